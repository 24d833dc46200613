#!/usr/bin/env bash
# The shipped LQG as the state-space fixture FMU (tools/fmu/state_space_controller) through the
# command line (issue 33): `flexloop build tools/scenes/metrology_frame_lqg.toml`, its artefact's
# discrete matrices, D22, limits and anti-windup written into a scene by fmu_scene.py (the
# numbers through JSON and TOML, as a user would pass them), then `flexloop sim --start rest` of
# both scenes over 10 000 samples: the logs agree to 1e-12.
#   tests/fmu/fmu_lqg_sim.sh FLEXLOOP FMU SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 fmu=$2 root=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

cd "$root" || fail "cd $root"
"$flexloop" build tools/scenes/metrology_frame_lqg.toml -o "$tmp/lqg.json" >/dev/null ||
  fail "flexloop build metrology_frame_lqg"
scene=$(python3 tests/fmu/fmu_scene.py "$root" "$fmu" "$tmp/lqg.json" "$tmp") || fail "fmu_scene.py"
"$flexloop" sim tools/scenes/metrology_frame_lqg.toml --duration 1 --start rest \
  --log "$tmp/builtin.csv" >/dev/null || fail "sim (built-in)"
"$flexloop" sim "$scene" --duration 1 --start rest --log "$tmp/fmu.csv" >/dev/null ||
  fail "sim (FMU)"
python3 - "$tmp/builtin.csv" "$tmp/fmu.csv" <<'PY' || fail "the logs differ"
import csv, sys
(ha, *a), (hb, *b) = (list(csv.reader(open(f))) for f in sys.argv[1:3])
assert ha == hb and len(a) == len(b) == 10000, (len(a), len(b))
largest = max(abs(float(x) - float(y)) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
peak = max(abs(float(x)) for r in a for x in r[-6:])
print("sim LQG as the state-space FMU vs built-in, 10000 samples from rest: largest log "
      "difference %.3g (peak command %.3g N)" % (largest, peak))
sys.exit(0 if largest <= 1e-12 and peak > 0 else 1)
PY
echo "fmu lqg sim: ok"
