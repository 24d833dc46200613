#!/usr/bin/env bash
# Every picture flexloop writes, rendered from small runs: each PNG exists, is a PNG of the stated
# size with something drawn in it, and gnuplot said nothing (flexloop passes on anything gnuplot
# prints as "warning: plot FILE: gnuplot: ..."). The metrology frame's (README) and another
# machine's. The hil histograms need the private namespace (root); without it they are skipped.
#   tests/cli/pictures.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checked=0

# run NAME COMMAND...: runs it, keeps its stderr, fails on a non-zero exit or a gnuplot remark.
run() {
  local name=$1
  shift
  "$@" >"$tmp/$name.out" 2>"$tmp/$name.err" || fail "$name: exit $? ($(cat "$tmp/$name.err"))"
  ! grep -q "gnuplot" "$tmp/$name.err" || fail "$name: gnuplot said: $(cat "$tmp/$name.err")"
}

# png FILE MIN_WIDTH MIN_HEIGHT: a PNG of at least that size, not a blank canvas.
png() {
  python3 - "$1" "$2" "$3" <<'PY' || fail "picture $1"
import struct, sys, zlib
path, w_min, h_min = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = open(path, "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
w, h = struct.unpack(">II", data[16:24])
assert w >= w_min and h >= h_min, f"{w}x{h} px, expected at least {w_min}x{h_min}"
# Inflate the image data: a drawn plot has many distinct scanlines, a blank one has one.
idat, i = b"", 8
while i < len(data):
    n, kind = struct.unpack(">I4s", data[i:i + 8])
    if kind == b"IDAT":
        idat += data[i + 8:i + 8 + n]
    i += 12 + n
raw = zlib.decompress(idat)
stride = len(raw) // h
rows = {raw[r * stride:(r + 1) * stride] for r in range(h)}
assert len(rows) > h // 10, f"only {len(rows)} distinct rows of {h}: nothing drawn"
PY
  checked=$((checked + 1))
}

metrology=$root/tools/scenes/metrology_frame.toml
run analyse_scene "$flexloop" analyse "$metrology" --out-dir "$tmp/analyse"
for p in singular_values transmissibility; do png "$tmp/analyse/$p.png" 1000 600; done
run analyse_model "$flexloop" analyse "$root/tools/models/cart.toml" -i acc:x.1 -O pos:x.2 \
  --out-dir "$tmp/cart"
png "$tmp/cart/bode.png" 1000 800
png "$tmp/cart/singular_values.png" 1000 600
for scene in "$metrology" "$root/tools/scenes/two_mass_chain.toml"; do
  name=$(basename "$scene" .toml)
  run "sim_$name" "$flexloop" sim "$scene" --duration 1 --plots "$tmp/sim_$name"
  png "$tmp/sim_$name/time_series.png" 1200 800
  png "$tmp/sim_$name/spectra.png" 1200 600
done
run tradeoff "$flexloop" tradeoff "$metrology" --methods zoh tustin --rates 2000 10000 \
  --reductions none --forms dense --scalars double --run 0.05 --bench-steps 200 --repeats 2 \
  --quiet --out-dir "$tmp/tradeoff"
png "$tmp/tradeoff/pareto_front.png" 800 500
if [[ $(id -u) -eq 0 ]]; then
  run hil "$flexloop" hil "$root/tools/scenes/two_mass_chain.toml" --netns --cpu -1 --priority 0 \
    --controller-cpu -1 --duration 1 --max-miss-share 100 --quiet --report "$tmp/hil/run.json"
  png "$tmp/hil/run_round_trip.png" 1000 500
  png "$tmp/hil/run_wakeup_lateness.png" 1000 500
else
  echo "not root: the hil histograms are not drawn here"
fi
echo "pictures: $checked drawn, no gnuplot remark"
