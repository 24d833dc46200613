#!/usr/bin/env bash
# `flexloop analyse MODEL` of a model without input channels (the cart of tools/models/cart.toml
# with its cart held fixed: no prescribed coordinate, no actuator, so no default input) writes the
# modal analysis, skips the pictures it cannot draw, says so in one line, and exits 0. The same
# model with an input named draws them.
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1
root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

sed -e 's/^prescribed = .*//' -e 's/^fixed = \["y.1", "y.2"\]/fixed = ["x.1", "y.1", "y.2"]/' \
  "$root/tools/models/cart.toml" >"$tmp/held_cart.toml"
grep -q '^fixed = \["x.1", "y.1", "y.2"\]' "$tmp/held_cart.toml" || fail "the fixture was not made"
grep -q '^prescribed' "$tmp/held_cart.toml" && fail "the fixture still has a prescribed coordinate"

out=$("$flexloop" analyse "$tmp/held_cart.toml" --points 20 --out-dir "$tmp/an" 2>&1); rc=$?
[[ $rc -eq 0 ]] || fail "analyse of a model without input channels: exit $rc ($out)"
[[ "$out" == *"mode  1"* ]] || fail "no modes printed: $out"
skipped=$(grep -c '^skipped ' <<<"$out")
[[ $skipped -eq 1 ]] || fail "expected one 'skipped' line, got $skipped: $out"
line=$(grep '^skipped ' <<<"$out")
[[ "$line" == *"bode.png"* && "$line" == *"singular_values.png"* && "$line" == *"no input channel"* &&
   "$line" == *"--input"* ]] || fail "the skipped line does not name the pictures and why: $line"
[[ "$out" == *"wrote $tmp/an/analysis.json"* ]] || fail "no 'wrote analysis.json' line: $out"
[[ "$out" != *"error"* ]] || fail "an error was printed: $out"
for f in bode.png singular_values.png frequency_response.csv singular_values.csv; do
  [[ ! -e "$tmp/an/$f" ]] || fail "$f written for a model without channels"
done
# The modal analysis: k = 800 N/m, m = 2 kg, one mode at sqrt(k/m)/(2 pi) = 3.18310 Hz, and the
# poles of the damped oscillator (d = 4 N s/m): -d/(2m) +- j sqrt(k/m - (d/2m)^2) = -1 +- j 19.975.
/usr/bin/python3 - "$tmp/an/analysis.json" <<'PY' || fail "analysis.json does not hold the modal analysis"
import json, math, sys
j = json.load(open(sys.argv[1]))
f = j["natural_frequencies_hz"]
assert len(f) == 1 and abs(f[0] - math.sqrt(400) / (2 * math.pi)) < 1e-9, f
assert j["state_space"]["inputs"] == [], j["state_space"]["inputs"]
poles = sorted(j["poles"], key=lambda p: p[1])
expected = [[-1.0, -math.sqrt(399)], [-1.0, math.sqrt(399)]]
assert all(abs(a - b) < 1e-9 for p, q in zip(poles, expected) for a, b in zip(p, q)), poles
assert len(j["mode_shapes"]) == 1, j["mode_shapes"]
PY

# With an input named, the same model has a response: every picture is drawn, nothing skipped.
out=$("$flexloop" analyse "$tmp/held_cart.toml" -i force:x.2 --points 20 --out-dir "$tmp/an_in" 2>&1) ||
  fail "analyse with an input: $out"
[[ "$out" != *"skipped"* ]] || fail "analyse with an input skipped something: $out"
for f in analysis.json bode.png singular_values.png frequency_response.csv singular_values.csv; do
  [[ -s "$tmp/an_in/$f" ]] || fail "analyse with an input did not write $f"
done
echo "analyse without channels: 2 checks passed"
