#!/usr/bin/env bash
# `flexloop replay` on plant reports written here (no real-time run): without a miss the replay
# is sim's loop; a run of misses is replayed as the plant counts it (held, then safe from the
# --safe-after-th on); a bad report exits 2 naming file and key, a record that contradicts itself
# exits 1 saying why, and neither writes --json.
#   tests/cli/replay_contract.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cd "$tmp" || fail "cd $tmp"

"$flexloop" replay --help | grep -q "Example" || fail "replay --help has no example"
"$flexloop" build "$root/tools/scenes/metrology_frame_lqg.toml" -o loop.json >/dev/null ||
  fail "flexloop build metrology_frame_lqg"
"$flexloop" sim loop.json --duration 0.5 --start rest > sim.txt || fail "flexloop sim"

# Plant reports as `flexloop plant --json` writes them (the keys replay reads), 0.5 s at 10 kHz.
python3 - <<'PY' || fail "writing the plant reports"
import json
names = [c["name"] for c in json.load(open("loop.json"))["channels"]["performance"]]
def report(ranges, **changes):
    r = {"rate_hz": 10000.0, "samples": 5000, "safe_after": 10, "safe_ramp_s": 0.5,
         "start": "rest", "divergence": None,
         "unapplied_answers": {"ranges": ranges, "complete": True},
         "physical": {"performance": [{"name": n, "unit": "m/s^2", "rms": 1e-3} for n in names]}}
    r.update(changes)
    return r
json.dump(report([]), open("ideal.json", "w"))
json.dump(report([[100, 120]]), open("misses.json", "w"))
json.dump(report([[100, 120], [50, 60]]), open("unordered.json", "w"))
bad = report([])
del bad["start"]
json.dump(bad, open("no_start.json", "w"))
json.dump(report([], rate_hz=1000.0), open("other_rate.json", "w"))
json.dump({"unanswered_samples": {"ranges": [[200, 200]], "complete": True}},
          open("controller.json", "w"))
PY

"$flexloop" replay loop.json --plant-report ideal.json --json ideal_replay.json >/dev/null ||
  fail "replay of a run without misses"
"$flexloop" replay loop.json --plant-report misses.json --json misses_replay.json >/dev/null ||
  fail "replay of a run with misses"
python3 - <<'PY' || fail "replay figures: $(cat sim.txt ideal_replay.json misses_replay.json)"
import json, re
sim = [float(m.group(1)) for m in
       (re.match(r"\s+\S+ \[[^]]*\]\s+\S+\s+(\S+)\s+\S+ dB", l) for l in open("sim.txt")) if m]
ideal, misses = json.load(open("ideal_replay.json")), json.load(open("misses_replay.json"))
assert len(sim) == 6 and len(ideal["performance_rms"]) == 6, (sim, ideal)
# Without a miss, sim's ideal loop (printed to 5 digits; the replay's last cycle is one more).
for s, r in zip(sim, ideal["performance_rms"]):
    assert abs(r / s - 1) <= 2e-4, (r, s)
assert ideal["deadline_misses"] == 0 and ideal["safe_command_cycles"] == 0, ideal
# 21 answers not applied in a row: held for 9 cycles, safe from the 10th on (12 cycles).
assert misses["deadline_misses"] == 21 and misses["safe_command_cycles"] == 12, misses
assert misses["performance_rms"] != ideal["performance_rms"]
assert misses["run_performance_rms"] == [1e-3] * 6
PY

expect_input_error() {  # report, text the message must hold
  local out rc
  out=$("$flexloop" replay loop.json --plant-report "$1" --json out.json 2>&1); rc=$?
  [[ $rc -eq 2 && "$out" == *"$1"* && "$out" == *"$2"* ]] ||
    fail "replay $1: exit $rc, expected 2 naming '$2': $out"
  [[ ! -e out.json ]] || fail "replay $1 wrote out.json"
}
expect_input_error unordered.json "key 'unapplied_answers': key 'ranges' entry 2"
expect_input_error no_start.json "key 'start'"
expect_input_error other_rate.json "rate"

out=$("$flexloop" replay loop.json --plant-report ideal.json --controller-record controller.json \
  --json out.json 2>&1); rc=$?
[[ $rc -eq 1 && "$out" == *"did not answer"* && ! -e out.json ]] ||
  fail "a record that contradicts itself: exit $rc, expected 1: $out"
echo "replay contract: ok"
