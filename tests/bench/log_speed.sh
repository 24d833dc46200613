#!/usr/bin/env bash
# A log at the disk's speed (issue 48, item 4), measured in one run: `flexloop sim` of a scene
# unlogged, logged to .mat and to .csv, and `dd` writing as many bytes with fsync into the same
# folder, interleaved, REPEATS times each; prints the medians of wall and CPU (user + sys) time
# and the ratio (logged - unlogged) / disk time against the target 1.3.
#   tests/bench/log_speed.sh FLEXLOOP [SCENE] [DURATION_S] [DIR] [REPEATS]
# DIR (default out/bench/log_speed) is where the logs go: the disk under test. The figures are
# wall time; on a shared machine read the CPU columns too (the load is printed).
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
flexloop=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=${2:-$root/tools/scenes/metrology_frame.toml}
duration=${3:-100}
dir=${4:-$root/out/bench/log_speed}
repeats=${5:-3}
mkdir -p "$dir"
times=$dir/times.txt
: >"$times"

# timed NAME COMMAND...: one line "NAME wall user sys" in $times.
timed() {
  local name=$1
  shift
  /usr/bin/time -f "$name %e %U %S" -a -o "$times" "$@" >/dev/null 2>&1 ||
    { echo "FAIL: $name: $*" >&2; exit 1; }
}
disk() {  # disk NAME BYTES: dd of BYTES zeros into $dir, fsync'ed before dd exits
  timed "$1" dd if=/dev/zero of="$dir/dd.bin" bs=4M count="$2" iflag=count_bytes conv=fsync
  rm -f "$dir/dd.bin"
}

echo "host: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "disk: $(df --output=source,fstype "$dir" | tail -1) under $dir"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "scene $(basename "$scene"), $duration s simulated, $repeats runs each"
for ((k = 0; k < repeats; ++k)); do
  timed unlogged "$flexloop" sim "$scene" --duration "$duration"
  timed mat "$flexloop" sim "$scene" --duration "$duration" --log "$dir/log.mat"
  disk disk_mat "$(stat -c %s "$dir/log.mat")"
  timed csv "$flexloop" sim "$scene" --duration "$duration" --log "$dir/log.csv"
  disk disk_csv "$(stat -c %s "$dir/log.csv")"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$times" "$dir/log.mat" "$dir/log.csv" <<'PY'
import os, statistics, sys
runs = {}
for line in open(sys.argv[1]):
    name, wall, user, sys_ = line.split()
    runs.setdefault(name, []).append((float(wall), float(user) + float(sys_)))
def med(name, k):
    return statistics.median(r[k] for r in runs[name])
print(f"{'run':10s} {'wall s':>8s} {'cpu s':>8s}   (medians of {len(runs['unlogged'])})")
for name in ("unlogged", "mat", "disk_mat", "csv", "disk_csv"):
    print(f"{name:10s} {med(name, 0):8.3f} {med(name, 1):8.3f}")
for fmt, path in (("mat", sys.argv[2]), ("csv", sys.argv[3])):
    extra, disk = med(fmt, 0) - med("unlogged", 0), med("disk_" + fmt, 0)
    ratio = extra / disk
    print(f"{fmt}: {os.path.getsize(path) / 1e6:.0f} MB, logged - unlogged = {extra:.3f} s wall, "
          f"disk {disk:.3f} s: ratio {ratio:.2f} (target <= 1.3: "
          f"{'met' if ratio <= 1.3 else 'NOT met'})")
PY
rm -f "$dir/log.mat" "$dir/log.csv"
