#!/usr/bin/env bash
# `flexloop campaign SCENE -u U.toml -n N --method subset` as a user runs it (doc/campaign.md
# "Rare failures"): --help shows it with an example; it writes summary.json with p_unstable
# {estimate, cov, lo, hi, evaluations, method "subset"} and the levels, report.md and one line
# per evaluated machine in samples.jsonl; the same seed gives the same bytes; bad input exits 2
# with its place (n not a multiple of 10, a --design, --simulate; --margin without subset).
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
printf '[campaign]\ncontroller = "frozen"\n\n[[parameter]]\npath = "effects.actuator.gain"\ndistribution = "lognormal"\nrelative_sd = 0.2\n' >"$tmp/gain.toml"

out=$("$flexloop" campaign --help 2>&1) || fail "campaign --help: exit $?"
[[ "$out" == *"--method"* && "$out" == *"--method subset"* ]] || fail "--help shows no subset example"
pass

for run in a b; do
  "$flexloop" campaign "$scene" -u "$tmp/gain.toml" -n 200 --method subset --seed 4 \
    --out-dir "$tmp/$run" -q >"$tmp/$run.out" || fail "campaign --method subset ($run)"
done
[[ $(cat "$tmp/a.out") == "P(unstable) = "*"subset simulation"* ]] || fail "stdout: $(cat "$tmp/a.out")"
cmp -s "$tmp/a/summary.json" "$tmp/b/summary.json" || fail "the same seed gave another summary"
cmp -s "$tmp/a/samples.jsonl" "$tmp/b/samples.jsonl" || fail "the same seed gave other samples"
pass

/usr/bin/python3 - "$tmp/a" <<'PY' || fail "summary.json"
import json, sys
d = sys.argv[1]
s = json.load(open(d + "/summary.json"))
p = s["p_unstable"]
assert s["method"] == "subset" and p["method"] == "subset", s["method"]
assert 0 < p["lo"] < p["estimate"] < p["hi"] < 1, p
assert 0 < p["cov"] < 1, p
lines = open(d + "/samples.jsonl").read().splitlines()
assert p["evaluations"] == len(lines) == s["counts"]["total"], (p["evaluations"], len(lines))
assert sum(l["evaluations"] for l in s["levels"]) == p["evaluations"]
assert s["levels"][0]["evaluations"] == 200 and s["levels"][-1]["threshold"] == 0
estimate = 1.0
for l in s["levels"]:
    estimate *= l["fraction"]
assert abs(estimate - p["estimate"]) <= 1e-12 * estimate, (estimate, p["estimate"])
assert all("margin" in json.loads(l) for l in lines)
assert "P(unstable) by subset simulation" in open(d + "/report.md").read()
PY
pass

out=$("$flexloop" campaign "$scene" -u "$tmp/gain.toml" -n 95 --method subset --out-dir "$tmp/c" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"-n: subset simulation needs a multiple of 10"* ]] || fail "n = 95: exit $rc ($out)"
out=$("$flexloop" campaign "$scene" -u "$tmp/gain.toml" -n 100 --method subset --design lhs --out-dir "$tmp/c" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--design"* ]] || fail "--design with subset: exit $rc ($out)"
out=$("$flexloop" campaign "$scene" -u "$tmp/gain.toml" -n 100 --method subset --simulate 1 --out-dir "$tmp/c" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--simulate"* ]] || fail "--simulate with subset: exit $rc ($out)"
out=$("$flexloop" campaign "$scene" -u "$tmp/gain.toml" -n 100 --margin disk --out-dir "$tmp/c" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"--margin"*"--method subset"* ]] || fail "--margin without subset: exit $rc ($out)"
pass

echo "subset cli: $checks checks passed"
