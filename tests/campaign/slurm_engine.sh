#!/usr/bin/env bash
# tests/campaign/slurm_engine.sh TEST_CAMPAIGN REPO: the Slurm engine on a real Slurm. Starts a
# single-node cluster (tools/slurm/start-local-cluster, root, loopback only), runs the hidden
# cluster cases of test_campaign ([slurm_cluster]: an array of a stand-in program through
# submit_slurm, a failing element, the resubmission, an element that requeues itself), then stops
# the cluster on every exit path and checks that no process of it is left.
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
test_campaign=$1 repo=$2
dir=$(mktemp -d /tmp/flexloop-slurm-test.XXXXXX)
finish() {
  local rc=$?
  "$repo/tools/slurm/stop-local-cluster" "$dir" || rc=1
  if pgrep -f -- "$dir" >/dev/null; then
    echo "slurm engine: processes of the cluster left behind:" >&2
    pgrep -af -- "$dir" >&2
    rc=1
  fi
  [[ ! -e $dir ]] || { echo "slurm engine: $dir left behind" >&2; rc=1; }
  [[ $rc -eq 0 ]] && echo "slurm engine: ok"
  exit $rc
}
trap finish EXIT
cluster_env=$("$repo/tools/slurm/start-local-cluster" "$dir") || exit 1
eval "$cluster_env"
"$test_campaign" "[slurm_cluster]"
