#!/usr/bin/env bash
# `flexloop baseline shm` and `flexloop baseline pingpong --transport iceoryx` as a user runs
# them, without timing judgement: they run and write their figures, leave no daemon, segment or
# socket behind, and refuse with a message naming iox-roudi when it is missing or already runs.
# Usage: cli_transport.sh FLEXLOOP
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
flexloop=$1
work=$(mktemp -d)
other_roudi=""
cleanup() {
  [[ -n "$other_roudi" ]] && kill -TERM "$other_roudi" 2>/dev/null && wait "$other_roudi" || true
  rm -rf "$work"
}
trap cleanup EXIT
checks=0
pass() { checks=$((checks + 1)); }
fail() { echo "FAIL: $*"; exit 1; }
nothing_of_roudi() {
  [[ "$(ls /dev/shm)" == "$shm_before" ]] || fail "/dev/shm changed: $(ls /dev/shm)"
  ! pgrep -x iox-roudi >/dev/null || fail "an iox-roudi is left: $(pgrep -a -x iox-roudi)"
  [[ ! -e /tmp/roudi && ! -e /tmp/iox-unique-roudi.lock ]] || fail "RouDi's socket or lock left"
}
gentle=(--priority 0 --no-mlock)
! pgrep -x iox-roudi >/dev/null || fail "an iox-roudi runs before the test (not ours to stop)"
shm_before=$(ls /dev/shm)

"$flexloop" baseline shm --round-trips 1000 "${gentle[@]}" --json "$work/shm.json" >"$work/out" ||
  fail "baseline shm: $(cat "$work/out")"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['round_trips']==1000 and j['round_trip_ns']['count']==1000 and j['kind']=='shm', j" "$work/shm.json" ||
  fail "baseline shm: the JSON"
nothing_of_roudi
pass

"$flexloop" baseline pingpong --transport iceoryx --duration 0.2 "${gentle[@]}" \
  --json "$work/pp.json" >"$work/out" 2>&1 || fail "pingpong iceoryx: $(cat "$work/out")"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['transport']=='iceoryx' and j['sent']==j['answered']+j['unanswered'] and j['round_trip_ns']['count']==j['answered'], j" "$work/pp.json" ||
  fail "pingpong iceoryx: the JSON"
nothing_of_roudi
pass

code=0
PATH=/nonexistent "$flexloop" baseline pingpong --transport iceoryx --duration 0.2 "${gentle[@]}" \
  >"$work/out" 2>&1 || code=$?
[[ $code == 1 ]] && grep -q "cannot run 'iox-roudi': No such file or directory" "$work/out" ||
  fail "no iox-roudi on PATH: exit $code, $(cat "$work/out")"
nothing_of_roudi
pass

iox-roudi >"$work/other.log" 2>&1 &
other_roudi=$!
for _ in $(seq 200); do grep -q "ready for clients" "$work/other.log" && break; sleep 0.01; done
code=0
"$flexloop" baseline pingpong --transport iceoryx --duration 0.2 "${gentle[@]}" \
  >"$work/out" 2>&1 || code=$?
[[ $code == 1 ]] && grep -q "iox-roudi already runs on this host (pid $other_roudi" "$work/out" ||
  fail "a RouDi already running: exit $code, $(cat "$work/out")"
kill -TERM "$other_roudi"
wait "$other_roudi" || true
other_roudi=""
nothing_of_roudi
pass

# Ctrl-C in the middle: SIGINT to the whole process group (python: a child with SIGINT at its
# default, which a shell's background job would not have). RouDi, in a group of its own, ends
# with its owner (PR_SET_PDEATHSIG) and cleans up; the runtimes remove their sockets.
python3 - "$flexloop" <<'PY' || fail "Ctrl-C: see above"
import os, signal, subprocess, sys, time
p = subprocess.Popen([sys.argv[1], "baseline", "pingpong", "--transport", "iceoryx", "--duration", "10",
                      "--priority", "0", "--no-mlock"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                     start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
deadline = time.time() + 10
while "iceoryx_mgmt" not in os.listdir("/dev/shm") and time.time() < deadline:
    time.sleep(0.01)
time.sleep(0.5)  # the ping-pong is running
os.killpg(p.pid, signal.SIGINT)
p.wait(timeout=20)
time.sleep(0.1)
deadline = time.time() + 10
while subprocess.run(["pgrep", "-x", "iox-roudi"], capture_output=True).returncode == 0 and time.time() < deadline:
    time.sleep(0.05)
left = [f for f in os.listdir("/tmp") if f.startswith(("flexloop_ping_", "flexloop_pong_"))]
assert p.returncode == -signal.SIGINT, p.returncode
assert not left, left
PY
nothing_of_roudi
pass

echo "iceoryx command line: $checks checks passed"
