# SPDX-License-Identifier: BSD-3-Clause
# shellcheck shell=bash disable=SC2154
# Shared by start-local-cluster and stop-local-cluster (sourced; $dir is the cluster's directory).

# The pid in FILE when it is alive, is the program NAME and was started on $dir's files.
live_pid() {
  local file=$1 name=$2 pid
  [[ -s $file ]] || return 1
  pid=$(tr -dc '0-9' 2>/dev/null < "$file") || return 1  # gone when the daemon exits
  [[ -n $pid && -r /proc/$pid/comm ]] || return 1
  [[ $(cat "/proc/$pid/comm" 2>/dev/null) == "$name" ]] || return 1
  [[ $(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null) != Z ]] || return 1  # exited, not reaped
  tr '\0' ' ' 2>/dev/null < "/proc/$pid/cmdline" | grep -qF "$dir/" || return 1
  echo "$pid"
}

# Every daemon of the cluster in $dir is alive.
all_daemons_live() {
  live_pid "$dir/munge/munged.pid" munged >/dev/null &&
    live_pid "$dir/run/slurmctld.pid" slurmctld >/dev/null &&
    live_pid "$dir/run/slurmd.pid" slurmd >/dev/null
}
