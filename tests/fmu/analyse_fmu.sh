#!/usr/bin/env bash
# `flexloop analyse` of a scene whose controller is an FMU: the sampled closed loop by simulation
# (an impulse per channel) in its print-out, analysis.json, the CSV and the plots; the same loop
# with an FMU that fails in the analysis's run (a sensor range it exceeds) exits 2 naming the FMU
# and the call.
#   tests/fmu/analyse_fmu.sh FLEXLOOP FMU SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 fmu=$2 root=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$flexloop" build "$root/tools/scenes/metrology_frame.toml" -o "$tmp/loop.json" >/dev/null ||
  fail "build"
scene=$(python3 "$root/tests/fmu/fmu_scene.py" "$root" "$fmu" "$tmp/loop.json" "$tmp") ||
  fail "fmu_scene.py"
out=$("$flexloop" analyse "$scene" --out-dir "$tmp/out" 2>&1) || fail "analyse: $out"
[[ "$out" == *"sampled loop by simulation: the responses settled"* ]] || fail "no settled loop: $out"
[[ "$out" == *"closed loop peak"* ]] || fail "no closed-loop peak: $out"
python3 - "$tmp/out" <<'PY' || fail "analysis files"
import csv, json, sys
d = sys.argv[1]
j = json.load(open(d + "/analysis.json"))
s = j["closed_loop_by_simulation"]
assert s["decayed"] and not s["diverged"], s
assert s["truncation_bound_over_peak"] < 1e-9, s
assert j["sigma_max_peak"]["closed_db"] < j["sigma_max_peak"]["open_db"] - 40, j["sigma_max_peak"]
header = next(csv.reader(open(d + "/transmissibility.csv")))
assert sum(1 for h in header if h.endswith("closed [dB]")) == 6, header
PY
for png in singular_values transmissibility; do
  [[ -s "$tmp/out/$png.png" ]] || fail "no $png.png"
done
# A sensor range of 1 mN: the impulse's response exceeds it and the fixture refuses the step.
echo 'y_max = 0.001' >> "$scene"
out=$("$flexloop" analyse "$scene" --out-dir "$tmp/bad" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"pi_force_feedback.fmu"* && "$out" == *"fmi2DoStep"* ]] ||
  fail "failing FMU: exit $rc ($out)"
echo "analyse of an FMU loop: ok"
