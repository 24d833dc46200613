#!/usr/bin/env bash
# Two hosts on one machine: the plant and the controller in two network namespaces joined by a
# veth pair with private addresses (10.231.0.1/30 and 10.231.0.2/30, multicast routed to the
# veth), LCM across the link with ttl=1 (the lowest TTL that crosses one link; nothing is
# forwarded beyond it). Shows the loop closes (or, after a stall of one side, closes again) and
# reports its latency (a run that did not close is repeated once); removes the namespaces (and with them the veth pair) on every exit. The
# veth is created inside the namespaces, never in the caller's. Exit 77 (ctest SKIP_RETURN_CODE)
# when namespaces cannot be created.
#
#   tests/hil/veth_loop.sh build/release/tools/flexloop tools/scenes/metrology_frame.toml [RATE_HZ] [DURATION_S]
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
flexloop=$(realpath "$1"); scene=$(realpath "$2"); rate=${3:-1000}; duration=${4:-3}
skip() { echo "SKIP: $*"; exit 77; }
[[ $(id -u) == 0 ]] || skip "needs root to create network namespaces"
command -v ip >/dev/null || skip "no ip command (iproute2)"

ns_plant=flexloop-plant-$$; ns_ctrl=flexloop-ctrl-$$
veth_plant=flv$$p; veth_ctrl=flv$$c
work=$(mktemp -d); ctrl_pid=
cleanup() {
  [[ -n $ctrl_pid ]] && kill "$ctrl_pid" 2>/dev/null && wait "$ctrl_pid" 2>/dev/null
  ip netns del "$ns_plant" 2>/dev/null || true
  ip netns del "$ns_ctrl" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

ip netns add "$ns_plant" 2>/dev/null || skip "cannot create a network namespace"
ip netns add "$ns_ctrl" 2>/dev/null || skip "cannot create a network namespace"
ip -n "$ns_plant" link add "$veth_plant" type veth peer name "$veth_ctrl" netns "$ns_ctrl" \
  2>/dev/null || skip "cannot create a veth pair"
setup() {  # namespace interface address
  ip -n "$1" link set lo up
  ip -n "$1" addr add "$3" dev "$2"
  ip -n "$1" link set "$2" multicast on up
  ip -n "$1" route add 224.0.0.0/4 dev "$2"
}
setup "$ns_plant" "$veth_plant" 10.231.0.1/30
setup "$ns_ctrl" "$veth_ctrl" 10.231.0.2/30
url="udpm://239.255.76.67:7667?ttl=1"

# One run: controller, then plant, then the judgement (its exit status).
attempt() {
ip netns exec "$ns_ctrl" "$flexloop" controller "$scene" --rate "$rate" --cpu 1 \
  --link "$veth_ctrl" --url "$url" >"$work/controller.log" 2>&1 &
ctrl_pid=$!
for _ in $(seq 50); do grep -q "^controller:" "$work/controller.log" && break; sleep 0.1; done
grep -q "^controller:" "$work/controller.log" || { cat "$work/controller.log"; exit 1; }

ip netns exec "$ns_plant" "$flexloop" plant "$scene" --rate "$rate" --duration "$duration" \
  --cpu 0 --link "$veth_plant" --url "$url" --max-miss-share 100 --json "$work/plant.json" \
  >"$work/plant.log" 2>&1 ||
  { cat "$work/plant.log" "$work/controller.log"; exit 1; }
kill -TERM "$ctrl_pid"; wait "$ctrl_pid" || true; ctrl_pid=
cat "$work/plant.log"; cat "$work/controller.log"

python3 - "$work/plant.json" "$work/controller.log" <<'PY'
import json, re, sys
r = json.load(open(sys.argv[1]))
resumes = re.search(r"bumpless resumes (\d+)", open(sys.argv[2]).read())
rtt = r["round_trip_ns"]
cycles, misses = r["cycles"], r["deadline_misses"]
answered = rtt["count"]
print(f"veth loop: {cycles} cycles at {r['rate_hz']:g} Hz, {answered} answered in time, "
      f"{misses} deadline misses; round trip p50 {rtt['p50']/1e3:.1f} us, "
      f"p99 {rtt['p99']/1e3:.1f} us, max {rtt['max']/1e3:.1f} us")
# The loop closes when nearly every sample is answered in time across the link. A shared VM can
# stall one side for tens of periods (its vCPU not scheduled); the plant then applies its safe
# command, and the loop has closed again only if the controller resumed bumplessly afterwards.
safe = r["safe_command_cycles"]
recovered = safe == 0 or (resumes is not None and int(resumes.group(1)) >= 1)
if safe:
    print(f"veth loop: a stall engaged the safe command for {safe} periods; "
          f"the controller {'resumed bumplessly' if recovered else 'did NOT resume'}")
ok = cycles > 0 and answered >= 0.95 * cycles and safe <= 0.05 * cycles and recovered
print("veth loop closed" if ok else "veth loop did NOT close")
sys.exit(0 if ok else 1)
PY
}
# This VM stalls in bursts (a vCPU unscheduled for a hundred periods and more, the link's softirq
# with it): a run that did not close is repeated once, as the timing tests do; a link that cannot
# carry the loop fails both.
attempt || { echo "veth loop: not closed once; running again"; attempt; }
