#!/usr/bin/env bash
# tests/campaign/slurm_campaign.sh FLEXLOOP REPO: a campaign through Slurm, for real (issue 47
# item 7). Starts a single-node Slurm (tools/slurm/start-local-cluster: root, loopback only), plans
# a small campaign over the three-mass fixture (three uncertain parameters, 240 samples, each
# also simulated for 0.2 s with --simulate: the runs' noise must be the same bytes too), and
#   1. submits it with --engine slurm (3 shards: an array of 3 elements) and with --engine local,
#      reports both, and checks that the merged samples.jsonl are byte-identical (cmp);
#   2. runs shard 1 alone, kills it with SIGKILL once its file has a line, runs it again, and
#      checks that the merge of it with the local engine's other shards is byte-identical too.
# The cluster is stopped, and checked to leave no process behind, on every exit path.
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
flexloop=$1 repo=$2
fail() { echo "slurm campaign: $*" >&2; exit 1; }
[[ $(id -u) -eq 0 ]] || fail "needs root (the local cluster's daemons run as root)"
"$flexloop" campaign submit --help >/dev/null 2>&1 || fail "$flexloop has no 'campaign submit'"
# submit waits for its shards; --wait says so where the command line has it.
wait_flag=()
if "$flexloop" campaign submit --help | grep -q -- '--wait'; then wait_flag=(--wait); fi

work=$(mktemp -d /tmp/flexloop-slurm-campaign.XXXXXX)
chmod 0711 "$work"  # the cluster's munge socket lies below it: every user must reach it
cluster="$work/cluster"
finish() {
  local rc=$?
  "$repo/tools/slurm/stop-local-cluster" "$cluster" || rc=1
  if pgrep -f -- "$cluster" >/dev/null; then
    pgrep -af -- "$cluster" >&2
    echo "slurm campaign: processes of the cluster left behind" >&2
    rc=1
  fi
  if [[ $rc -eq 0 ]]; then
    rm -rf "$work"
    echo "slurm campaign: ok"
  else
    echo "slurm campaign: failed; files kept in $work" >&2
  fi
  exit $rc
}
trap finish EXIT
cluster_env=$("$repo/tools/slurm/start-local-cluster" "$cluster") || fail "the local cluster did not start"
eval "$cluster_env"

cat > "$work/U.toml" <<'EOF'
[[parameter]]
path = "element.d.stiffness"
distribution = "uniform"
low = 1.2e5
high = 1.8e5

[[parameter]]
path = "node.*.mass"
distribution = "normal"
relative_sd = 0.05
draw = "each"

[[parameter]]
path = "effects.actuator.gain"
distribution = "uniform"
low = 0.8
high = 1.2
EOF
plan="$work/plan.json"
"$flexloop" campaign plan "$repo/tests/fixtures/three_masses.toml" --uncertain "$work/U.toml" \
  -n 240 --design lhs --seed 47 --simulate 0.2 -o "$plan"

# 1. The same plan through both engines, merged by `campaign report`.
"$flexloop" campaign submit "$plan" --engine slurm --shards 3 "${wait_flag[@]}" \
  --time-limit 10 --work-dir "$work/slurm"
"$flexloop" campaign submit "$plan" --engine local --shards 3 "${wait_flag[@]}" \
  --work-dir "$work/local"
ls "$work"/slurm/campaign-*_0.out >/dev/null || fail "no Slurm log in $work/slurm: not run by Slurm?"
"$flexloop" campaign report "$plan" "$work"/slurm/shard-*.jsonl --out-dir "$work/report-slurm"
"$flexloop" campaign report "$plan" "$work"/local/shard-*.jsonl --out-dir "$work/report-local"
[[ $(wc -l < "$work/report-local/samples.jsonl") -eq 240 ]] || fail "local merge has not 240 samples"
[[ $(grep -c '"status":"ran"' "$work/report-local/samples.jsonl") -gt 0 ]] || fail "no sample was simulated"
cmp "$work/report-slurm/samples.jsonl" "$work/report-local/samples.jsonl" ||
  fail "the Slurm engine's merged samples differ from the local engine's"

# 2. Shard 1 killed mid-way with SIGKILL, then run again to completion.
mkdir -p "$work/killed"
cp "$work/local/shard-0.jsonl" "$work/local/shard-2.jsonl" "$work/killed/"
shard="$work/killed/shard-1.jsonl"
"$flexloop" campaign run "$plan" --shard 1/3 -o "$shard" 2>/dev/null &
runner=$!
until [[ -s $shard ]] || ! kill -0 "$runner" 2>/dev/null; do :; done
kill -KILL "$runner" 2>/dev/null || fail "shard 1 ended before it could be killed"
wait "$runner" 2>/dev/null || true
lines=$(wc -l < "$shard")
full=$(wc -l < "$work/local/shard-1.jsonl")
((lines < full)) || fail "the killed shard holds all its $full samples: not killed mid-way"
echo "slurm campaign: shard 1 killed with $lines of $full samples written"
"$flexloop" campaign run "$plan" --shard 1/3 -o "$shard"
"$flexloop" campaign report "$plan" "$work"/killed/shard-*.jsonl --out-dir "$work/report-killed"
cmp "$work/report-killed/samples.jsonl" "$work/report-local/samples.jsonl" ||
  fail "the merge after a killed and rerun shard differs from the local engine's"
