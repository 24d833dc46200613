#!/usr/bin/env bash
# `flexloop campaign` as a user runs it (doc/campaign.md): the all-in-one command and its parts
# give the same samples.jsonl byte for byte (one shard, three shards through the local engine, a
# shard killed mid-line and rerun); bad input exits 2 with its place (N = 0, an unknown path with
# the nearest names, a shard of another plan, missing samples); the worst samples are scenes
# `analyse` runs as they are; every part has --help with an example; --simulate's samples are the
# same bytes however sharded, and bad --simulate values exit 2.
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1
root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checks=0
pass() { checks=$((checks + 1)); }

scene=$root/tests/fixtures/one_strut_campaign.toml
u=$root/tests/fixtures/one_strut_uncertain.toml

for part in "" plan run submit report worst; do
  out=$("$flexloop" campaign $part --help 2>&1) || fail "campaign $part --help: exit $?"
  [[ "$out" == *"Example:"* ]] || fail "campaign $part --help has no example"
done
pass

out=$("$flexloop" campaign plan "$scene" -u "$u" -n 0 -o "$tmp/p0.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"-n: a campaign needs at least one sample"* ]] || fail "N = 0: exit $rc ($out)"
[[ ! -e "$tmp/p0.json" ]] || fail "N = 0 left a plan"
pass

printf '[[parameter]]\npath = "node.mass.mass"\ndistribution = "normal"\nrelative_sd = 0.01\n\n[[parameter]]\npath = "element.strut.stifness"\ndistribution = "uniform"\nlow = 1e6\nhigh = 2e6\n' >"$tmp/typo.toml"
out=$("$flexloop" campaign plan "$scene" -u "$tmp/typo.toml" -n 4 -o "$tmp/p1.json" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"typo.toml:6:"* && "$out" == *"nearest valid names: element.strut.stiffness"* ]] ||
  fail "unknown path: exit $rc ($out)"
pass

"$flexloop" campaign plan "$scene" -u "$u" -n 12 --design lhs --seed 7 -o "$tmp/plan.json" >/dev/null ||
  fail "campaign plan"
"$flexloop" campaign plan "$scene" -u "$u" -n 12 --design lhs --seed 8 -o "$tmp/other.json" >/dev/null ||
  fail "campaign plan (seed 8)"
# The plan holds its inputs by absolute path: relative paths from elsewhere make the same plan.
(cd "$root/tests" && "$flexloop" campaign plan fixtures/one_strut_campaign.toml \
  -u fixtures/one_strut_uncertain.toml -n 12 --design lhs --seed 7 -o "$tmp/relative.json" >/dev/null) ||
  fail "campaign plan with relative paths"
cmp -s "$tmp/plan.json" "$tmp/relative.json" || fail "the plan depends on how its paths were given"
pass

# One shard, run whole; the same shard killed in its fifth line and run again: the same bytes.
"$flexloop" campaign run "$tmp/plan.json" --shard 0/1 -o "$tmp/whole.jsonl" -q || fail "run 0/1"
[[ $(wc -l <"$tmp/whole.jsonl") -eq 12 ]] || fail "run 0/1 wrote $(wc -l <"$tmp/whole.jsonl") lines"
head -c "$(( $(head -n 4 "$tmp/whole.jsonl" | wc -c) + 40 ))" "$tmp/whole.jsonl" >"$tmp/killed.jsonl"
"$flexloop" campaign run "$tmp/plan.json" --shard 0/1 -o "$tmp/killed.jsonl" -q || fail "rerun"
cmp -s "$tmp/whole.jsonl" "$tmp/killed.jsonl" || fail "a killed shard rerun differs from the whole run"
pass

out=$("$flexloop" campaign run "$tmp/other.json" --shard 0/1 -o "$tmp/whole.jsonl" -q 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"whole.jsonl:1: this line belongs to another plan"* ]] ||
  fail "shard of another plan: exit $rc ($out)"
pass

"$flexloop" campaign submit "$tmp/plan.json" --engine local --shards 3 --jobs 2 -q \
  --work-dir "$tmp/shards" >/dev/null || fail "submit --engine local"
out=$("$flexloop" campaign report "$tmp/plan.json" "$tmp/shards/shard-0.jsonl" "$tmp/shards/shard-2.jsonl" \
  --out-dir "$tmp/partial" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"4 of 12 samples missing: 1, 4, 7, 10"* ]] || fail "missing samples: exit $rc ($out)"
out=$("$flexloop" campaign report "$tmp/plan.json" "$tmp/whole.jsonl" "$tmp/other_shard.jsonl" \
  --out-dir "$tmp/r" 2>&1); rc=$?
[[ $rc -eq 2 ]] || fail "report of a file that does not exist: exit $rc"
pass

"$flexloop" campaign report "$tmp/plan.json" "$tmp"/shards/shard-*.jsonl --out-dir "$tmp/three" \
  --worst 2 >/dev/null || fail "report of three shards"
"$flexloop" campaign report "$tmp/plan.json" "$tmp/whole.jsonl" --out-dir "$tmp/one" --worst 0 \
  >/dev/null || fail "report of one shard"
cmp -s "$tmp/three/samples.jsonl" "$tmp/one/samples.jsonl" || fail "samples.jsonl depends on the sharding"
"$flexloop" campaign run "$tmp/other.json" --shard 0/1 -o "$tmp/other_whole.jsonl" -q || fail "run other"
out=$("$flexloop" campaign report "$tmp/plan.json" "$tmp/whole.jsonl" "$tmp/other_whole.jsonl" \
  --out-dir "$tmp/mixed" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"other_whole.jsonl:1: this line belongs to another plan"* ]] ||
  fail "report of a shard of another plan: exit $rc ($out)"
pass

# The worst samples run as they are.
n_worst=$(find "$tmp/three/worst" -name "sample-*_model.toml" | wc -l)
[[ $n_worst -eq 2 ]] || fail "expected 2 worst samples, found $n_worst"
for s in "$tmp"/three/worst/sample-[0-9]*.toml; do
  [[ "$s" == *_model.toml ]] && continue
  head -n 1 "$s" | grep -q "^# flexloop campaign: sample [0-9]* of plan " || fail "$s has no header"
  "$flexloop" analyse "$s" --points 20 --out-dir "$tmp/an" >/dev/null 2>&1 || fail "analyse $s"
done
pass

# The whole campaign in one command: the same samples as its parts (the same plan).
"$flexloop" campaign "$scene" -u "$u" -n 12 --design lhs --seed 7 --jobs 2 -q --out-dir "$tmp/all" \
  >/dev/null || fail "campaign (all-in-one)"
cmp -s "$tmp/all/plan.json" "$tmp/plan.json" || fail "the all-in-one plan differs"
cmp -s "$tmp/all/samples.jsonl" "$tmp/one/samples.jsonl" || fail "the all-in-one samples differ"
pass

# --simulate S: a value that is not a finite number > 0, or a run whose log would not fit in 1 GB,
# exits 2 naming the option and writes no
# plan; the simulated samples are the same bytes from one shard and from two (each sample's noise
# seeds depend on the plan and its index only); the report compares them with the Lyapunov RMS;
# a shard of the plan with another S is refused (S is in the plan, so in its plan_id).
sim_scene=$root/tests/fixtures/one_strut_saturating.toml
sim_u=$root/tests/fixtures/one_strut_simulate_uncertain.toml
for bad in 0 -1 abc 1e6; do
  out=$("$flexloop" campaign plan "$sim_scene" -u "$sim_u" -n 4 --simulate "$bad" -o "$tmp/bad.json" 2>&1); rc=$?
  [[ $rc -eq 2 && "$out" == *"--simulate"* ]] || fail "--simulate $bad: exit $rc ($out)"
  [[ ! -e "$tmp/bad.json" ]] || fail "--simulate $bad left a plan"
done
for part in "" plan; do
  "$flexloop" campaign $part --help 2>&1 | grep -q -- "--simulate" || fail "campaign $part --help has no --simulate"
done
pass

"$flexloop" campaign plan "$sim_scene" -u "$sim_u" -n 6 --simulate 0.5 -o "$tmp/sim.json" >/dev/null ||
  fail "campaign plan --simulate 0.5"
"$flexloop" campaign plan "$sim_scene" -u "$sim_u" -n 6 --simulate 1 -o "$tmp/sim1.json" >/dev/null ||
  fail "campaign plan --simulate 1"
"$flexloop" campaign run "$tmp/sim.json" --shard 0/1 -o "$tmp/sim_whole.jsonl" -q || fail "run --simulate"
[[ $(grep -c '"status":"ran"' "$tmp/sim_whole.jsonl") -eq 6 ]] ||
  fail "not every simulated sample ran: $(head -c 600 "$tmp/sim_whole.jsonl")"
"$flexloop" campaign submit "$tmp/sim.json" --engine local --shards 2 --jobs 2 -q \
  --work-dir "$tmp/sim_shards" >/dev/null || fail "submit --simulate"
"$flexloop" campaign report "$tmp/sim.json" "$tmp/sim_whole.jsonl" --out-dir "$tmp/sim_one" --worst 0 \
  >/dev/null || fail "report of the simulated shard"
"$flexloop" campaign report "$tmp/sim.json" "$tmp"/sim_shards/shard-*.jsonl --out-dir "$tmp/sim_two" \
  --worst 0 >/dev/null || fail "report of two simulated shards"
cmp -s "$tmp/sim_one/samples.jsonl" "$tmp/sim_two/samples.jsonl" || fail "simulated samples depend on the sharding"
grep -q "## Simulated runs against the Lyapunov RMS" "$tmp/sim_one/report.md" || fail "report.md has no simulated section"
out=$("$flexloop" campaign run "$tmp/sim1.json" --shard 0/1 -o "$tmp/sim_whole.jsonl" -q 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"sim_whole.jsonl:1: this line belongs to another plan"* ]] ||
  fail "a shard of the plan with another --simulate: exit $rc ($out)"
pass

# An open-loop campaign: a scene without a controller, the passive fleet (issue 54, 3.1).
open_scene=$root/tests/fixtures/one_strut_open_loop.toml
out=$("$flexloop" campaign "$open_scene" -u "$u" -n 10 --simulate 0.2 --out-dir "$tmp/open" --worst 1 -q 2>&1) ||
  fail "open-loop campaign: $out"
[[ "$out" == *"controller none: open loop"* ]] || fail "the open-loop plan does not say so: $out"
/usr/bin/python3 - "$tmp/open/summary.json" <<'PY' || fail "open-loop summary"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["loop"] == "open", s["loop"]
assert s["counts"]["stable"] == 10, s["counts"]
order = s["figure_order"]
assert "rms_open.acc:y.mass" in order and "peak_sigma" in order and "natural_frequency_1_hz" in order, order
assert not any(f.startswith("rms.") or f.startswith("disk_margin") for f in order), order
assert s["simulation"]["ran"] == 10, s["simulation"]
PY
grep -q '^\*\*Open loop:\*\*' "$tmp/open/report.md" || fail "report.md does not say the campaign is open loop"
pass

# The worst machine in the box (issue 54, 3.3): worst.json and worst.toml, the scene analyse runs;
# a figure that is not one exits 2 naming the choices and writes nothing.
"$flexloop" campaign worst "$scene" -u "$u" --figure peak_sigma -n 16 --evaluations 60 \
  --out-dir "$tmp/worst_box" -q >/dev/null || fail "campaign worst"
[[ -s "$tmp/worst_box/worst.json" && -s "$tmp/worst_box/worst_model.toml" ]] || fail "campaign worst wrote no worst.json"
"$flexloop" analyse "$tmp/worst_box/worst.toml" --out-dir "$tmp/worst_box/analysis" >/dev/null ||
  fail "analyse of worst.toml"
out=$("$flexloop" campaign worst "$scene" -u "$u" --figure gain --out-dir "$tmp/worst_bad" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--figure: 'gain' is not one of spectral_radius, largest_inner_radius, disk_margin_db"* ]] ||
  fail "campaign worst --figure gain: exit $rc ($out)"
[[ ! -e "$tmp/worst_bad" ]] || fail "a refused worst search left $tmp/worst_bad"
pass

echo "campaign cli: $checks checks passed"
