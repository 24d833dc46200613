#!/usr/bin/env bash
# How a real-time run ends, as the user sees it (doc/cli.md "When a run fails"): the verdict and its
# exit code, the overrun policy, SIGINT / SIGTERM, and helper processes that fail. No timing is
# judged here (the loops run unpinned at normal priority); each check is on exit codes, messages
# and the written report.
#   1. `flexloop plant` with nobody answering: every cycle misses, exit 3, the share in words;
#      --max-miss-share 100 lets the same run pass; --stop-after-misses 5 stops it at the 5th miss.
#   2. `flexloop hil` under a terminal (script(1)) shows its live status line; SIGTERM to the hil
#      process alone ends plant and controller, writes the report marked partial, exit 130, and
#      leaves no process behind.
#   3. Ctrl-C (SIGINT to the whole process group) with --lcm-log: the same, and the log is kept.
#   4. an LCM log that cannot be created (or a report in a folder's place) is refused before
#      anything runs, exit 2, naming it; a log whose writes fail during the run (/dev/full) fails
#      the verdict (exit 3), saying why.
#   tests/hil/run_control.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d)
trap 'pkill -KILL -f "$tmp/" 2>/dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checks=0
ok() { checks=$((checks + 1)); }
no_leftovers() {
  sleep 0.2
  local left
  left=$(pgrep -af "$tmp/" | grep -v pgrep) && fail "$1: processes left behind: $left"
  ok
}
json() { python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(eval('(' + sys.argv[2] + ')'))" "$@"; }
unpinned=(--cpu -1 --priority 0)

"$flexloop" build "$root/tools/scenes/metrology_frame.toml" --rate 1000 -o "$tmp/loop.json" \
  >/dev/null || fail "flexloop build"

# 1. The verdict of a plant that nobody answers.
out=$("$root/tools/netns-run" -- "$flexloop" plant "$tmp/loop.json" "${unpinned[@]}" \
  --duration 0.5 --json "$tmp/alone.json" 2>&1); rc=$?
[[ $rc -eq 3 && "$out" == *"verdict fail; deadline misses 100 % of "*" cycles ("*"), above the limit of 1 %"* ]] ||
  fail "unanswered plant: exit $rc ($out)"
[[ $(json "$tmp/alone.json" 'r["verdict"]["result"], r["partial"]') == "('fail', False)" ]] ||
  fail "unanswered plant's figures: $(cat "$tmp/alone.json")"
ok
"$root/tools/netns-run" -- "$flexloop" plant "$tmp/loop.json" "${unpinned[@]}" --duration 0.2 \
  --max-miss-share 100 >/dev/null 2>&1 || fail "--max-miss-share 100: exit $?"
ok
out=$("$root/tools/netns-run" -- "$flexloop" plant "$tmp/loop.json" "${unpinned[@]}" \
  --duration 5 --stop-after-misses 5 --max-miss-share 100 --json "$tmp/stopped.json" 2>&1); rc=$?
[[ $rc -eq 3 && "$out" == *"overrun policy: stopped at the 5-th deadline miss, after "*" cycles"* ]] ||
  fail "--stop-after-misses 5: exit $rc ($out)"
[[ $(json "$tmp/stopped.json" 'r["cycles"] <= 7, r["partial"], r["verdict"]["ended"]') == \
  "(True, True, 'overrun policy')" ]] || fail "stopped plant's figures: $(cat "$tmp/stopped.json")"
ok

# 2. SIGTERM to hil alone, under a terminal.
hil_args=("$tmp/loop.json" --netns "${unpinned[@]}" --controller-cpu -1 --segments 2 --baseline-duration 0.4)
script -qfec "'$flexloop' hil ${hil_args[*]} --duration 30 --report '$tmp/term.json'" "$tmp/term.tty" \
  >/dev/null 2>&1 &
script_pid=$!
for _ in $(seq 150); do grep -q "cycles" "$tmp/term.tty" 2>/dev/null && break; sleep 0.1; done
grep -q "hil 1 kHz: .* cycles, .* misses (.* %), round trip p99 .* us, safe" "$tmp/term.tty" ||
  fail "no live status line under a terminal: $(cat "$tmp/term.tty")"
ok
hil_pid=$(pgrep -of "^$flexloop hil $tmp/loop.json") || fail "no hil process"
kill -TERM "$hil_pid"
wait "$script_pid"; rc=$?
[[ $rc -eq 130 ]] || fail "SIGTERM: exit $rc ($(cat "$tmp/term.tty"))"
grep -q "interrupted: interrupted (SIGINT/SIGTERM)" "$tmp/term.tty" ||
  fail "SIGTERM: no message ($(cat "$tmp/term.tty"))"
[[ $(json "$tmp/term.json" 'r["partial"], r["verdict"]["result"], 0 < r["cycles"] < 30000,
  r["controller"]["kind"], "physical" in r') == "(True, 'interrupted', True, 'pi_force_feedback', True)" ]] ||
  fail "SIGTERM: report $(head -c 600 "$tmp/term.json")"
ok
no_leftovers "SIGTERM"
# Captured first: with pipefail, `grep -q` closing the pipe early makes the writer die of SIGPIPE.
help=$("$flexloop" hil --help)
[[ "$help" == *"--quiet"* ]] || fail "hil --help has no --quiet"
ok

# 3. Ctrl-C: SIGINT to the whole group (setsid makes hil a group leader, as a shell job is).
setsid "$flexloop" hil "${hil_args[@]}" --duration 30 --report "$tmp/int.json" --lcm-log "$tmp/int.lcmlog" \
  >"$tmp/int.txt" 2>&1 &
hil_pid=$!
for _ in $(seq 150); do [[ $(stat -c %s "$tmp/int.lcmlog" 2>/dev/null || echo 0) -gt 100000 ]] && break; sleep 0.1; done
kill -INT -- "-$hil_pid"
wait "$hil_pid"; rc=$?
[[ $rc -eq 130 ]] || fail "Ctrl-C: exit $rc ($(cat "$tmp/int.txt"))"
[[ $(json "$tmp/int.json" 'r["partial"], r["verdict"]["result"], r["cycles"] > 0') == \
  "(True, 'interrupted', True)" ]] || fail "Ctrl-C: report $(head -c 600 "$tmp/int.json")"
[[ -s "$tmp/int.lcmlog" ]] || fail "Ctrl-C: the LCM log is gone"
ok
no_leftovers "Ctrl-C"

# 4. An LCM log that fails. One that cannot be created is bad input, refused before anything
# runs (exit 2, as every output that cannot be written); a report in a folder's place too.
mkdir "$tmp/a_directory"
out=$("$flexloop" hil "${hil_args[@]}" --duration 30 --report "$tmp/nolog.json" --lcm-log "$tmp/a_directory" 2>&1)
rc=$?
[[ $rc -eq 2 && "$out" == *"$tmp/a_directory: cannot be written: Is a directory"* && "$out" != *"cycles"* ]] ||
  fail "unopenable log: exit $rc ($out)"
[[ ! -e "$tmp/nolog.json" ]] || fail "unopenable log: a report was written"
out=$("$flexloop" hil "${hil_args[@]}" --duration 30 --report "$tmp/a_directory" 2>&1)
rc=$?
[[ $rc -eq 2 && "$out" == *"$tmp/a_directory: cannot be written: Is a directory"* && "$out" != *"cycles"* ]] ||
  fail "report in a folder's place: exit $rc ($out)"
ok
no_leftovers "unopenable log"
"$flexloop" hil "${hil_args[@]}" --duration 2 --report "$tmp/full.json" --lcm-log /dev/full >"$tmp/full.txt" 2>&1
rc=$?
[[ $rc -eq 3 ]] && grep -q "/dev/full: writing the LCM log failed (No space left on device)" "$tmp/full.txt" ||
  fail "log on a full device: exit $rc ($(cat "$tmp/full.txt"))"
[[ $(json "$tmp/full.json" 'r["verdict"]["result"], r["partial"]') == "('fail', False)" ]] ||
  fail "log on a full device: report $(head -c 600 "$tmp/full.json")"
ok
no_leftovers "log on a full device"
echo "run control: $checks checks passed"
