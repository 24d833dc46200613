#!/usr/bin/env bash
# A controller FMU's statuses, a changed FMU and a hand-written closed-loop start through the
# command line (issue 46). The fixture PI (tools/fmu/pi_force_feedback, the designed gains as its
# parameters, fmu_scene.py) answers its step N with the status its parameters ask
# (tools/fmu/fixture_fmu.h):
#   1. fmi2Discard at step 500: `sim LOOP.json` exits 1 naming the FMU, fmi2Discard and sample 500
#      (with what the FMU says of itself: fmi2Terminated, fmi2LastSuccessfulTime 500 periods);
#   2. fmi2Pending at step 500: the same, naming fmi2Pending;
#   3. fmi2Warning at step 500: the run passes, its RMS figures those of the FMU without the
#      warning, and sim says the warning was returned once, with the call, sample and message;
#   4. the .fmu replaced after `flexloop build` by another valid archive (the same entries and one
#      more file): sim and the controller process exit 2 naming the file, both SHA-256 and
#      `flexloop build` again (analyse takes a scene, which it builds: the FMU hashed there);
#   5. an artefact of the FMU loop given a closed-loop start by hand: refused when read, exit 2,
#      naming the start and why.
#   tests/fmu/fmu_statuses_sim.sh FLEXLOOP FMU SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 fmu=$2 root=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

source "$root/tests/fmu/status_scenes.sh"
# The RMS lines of a sim print-out.
rms() { grep -E '^  (acc|stress)' <<<"$1"; }
"$flexloop" build "$scene" -o "$tmp/plain.json" >/dev/null || fail "build (plain)"
plain=$("$flexloop" sim "$tmp/plain.json" --duration 0.2 2>&1) || fail "sim (plain): $plain"

# 1., 2. fmi2Discard and fmi2Pending end the run: exit 1, nothing printed after.
dt=$(python3 -c 'print("%.9g" % (500 / 10000))')
for case in "2 discard fmi2Discard" "5 pending fmi2Pending"; do
  read -r code name status <<<"$case"
  build_with_status "$code" "$name" 500
  out=$("$flexloop" sim "$tmp/$name.json" --duration 0.2 2>&1); rc=$?
  [[ $rc -eq 1 && "$out" == *"pi_force_feedback.fmu: fmi2DoStep returned $status at sample 500 (t = $dt s)"* &&
     "$out" != *"RMS of the performance outputs"* ]] || fail "sim with $status: exit $rc ($out)"
  if [[ $status == fmi2Discard ]]; then
    [[ "$out" == *"fmi2Terminated: true, fmi2LastSuccessfulTime: $dt s"* ]] ||
      fail "fmi2Discard without the FMU's own statuses: $out"
  fi
done

# 3. fmi2Warning: counted, named, and the run unchanged.
build_with_status 1 warning 500
out=$("$flexloop" sim "$tmp/warning.json" --duration 0.2 2>&1) || fail "sim with fmi2Warning: $out"
[[ "$out" == *"pi_force_feedback.fmu: fmi2Warning returned 1 times; the first: fmi2DoStep returned fmi2Warning at sample 500: step 500 warned as its parameters asked"* ]] ||
  fail "the warning is not reported: $out"
[[ "$(rms "$out")" == "$(rms "$plain")" && -n "$(rms "$plain")" ]] ||
  fail "the warning changed the run: $(rms "$out") vs $(rms "$plain")"

# 4. The FMU replaced after the build by another valid archive.
built=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["controller"]["sha256"])' \
  "$tmp/plain.json")
python3 - "$tmp/pi_force_feedback.fmu" <<'PY' || fail "re-zip"
import sys, zipfile
path = sys.argv[1]
with zipfile.ZipFile(path) as z:
    entries = {n: z.read(n) for n in z.namelist()}
entries["documentation/index.html"] = b"<p>the same controller, one more file</p>"
with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
    for n, data in entries.items():
        z.writestr(n, data)
PY
now=$(sha256sum "$tmp/pi_force_feedback.fmu" | cut -d' ' -f1)
[[ "$now" != "$built" ]] || fail "the archive did not change"
check_refused() {
  [[ $1 -eq 2 && "$2" == *"pi_force_feedback.fmu: its SHA-256 is $now, but"*"$built"* &&
     "$2" == *'run `flexloop build` again'* ]] || fail "$3 of a changed FMU: exit $1 ($2)"
}
out=$("$flexloop" sim "$tmp/plain.json" --duration 0.2 2>&1); check_refused $? "$out" sim
out=$("$root/tools/netns-run" -- "$flexloop" controller "$tmp/plain.json" --cpu -1 --priority 0 \
  --duration 1 2>&1)
check_refused $? "$out" "the controller process"

# 5. A closed-loop start written into the FMU loop's artefact by hand.
python3 - "$tmp/frame.json" "$tmp/warning.json" "$tmp/closed_start.json" <<'PY' || fail "edit"
import json, sys
builtin, fmu = (json.load(open(f)) for f in sys.argv[1:3])
assert "unavailable" in fmu["start"]["closed_loop"], fmu["start"]["closed_loop"]
fmu["start"]["closed_loop"] = builtin["start"]["closed_loop"]
json.dump(fmu, open(sys.argv[3], "w"))
PY
out=$("$flexloop" sim "$tmp/closed_start.json" --duration 0.2 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"closed_start.json"*"closed_loop"* &&
   "$out" == *"the controller is an FMU, whose state cannot be set from outside"* ]] ||
  fail "closed-loop start of an FMU loop: exit $rc ($out)"
echo "fmu statuses in sim: 5 checks passed"
