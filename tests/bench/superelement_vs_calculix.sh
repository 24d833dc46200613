#!/usr/bin/env bash
# Superelements at size (issue 58), measured side by side in one run: a 1 m steel bar of
# 0.05 m x 0.05 m section, clamped at x = 0, meshed by gmsh in tet10 (tools/models/
# superelement_bar.geo, element size CLMAX), given to CalculiX (tests/fixtures/
# make_calculix_bar.py) twice: its own 6-mode *FREQUENCY solve, and *FREQUENCY,
# SOLVER=MATRIXSTORAGE for K, M and the row map. flexloop then reads them, reduces the bar by
# Craig-Bampton to its free end's four corners with the fixed-interface modes below CUT_HZ and
# takes the reduced model's eigenvalues (the hidden [.bench] case of test_superelement).
# Wall time and peak RSS of each (/usr/bin/time), one thread each (OMP/OpenBLAS), the load
# before each; the reduced model's six lowest frequencies against CalculiX's.
#   tests/bench/superelement_vs_calculix.sh TEST_SUPERELEMENT [CLMAX] [CUT_HZ] [DIR]
# TEST_SUPERELEMENT: build/check/tests/test_superelement; CLMAX 0.008 (m); CUT_HZ 4000;
# DIR out/bench/superelement_CLMAX.
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
bench=$(realpath "$1")
root=$(cd "$(dirname "$0")/../.." && pwd)
clmax=${2:-0.008}
cut=${3:-4000}
dir=${4:-$root/out/bench/superelement_$clmax}
mkdir -p "$dir"
cd "$dir"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1

# timed NAME COMMAND...: its output in NAME.log, "NAME wall_s peak_MiB load" in times.txt.
timed() {
  local name=$1 load
  shift
  load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%e %M" -o "$name.time" "$@" >"$name.log" 2>&1 ||
    { echo "FAIL: $name: $* (see $dir/$name.log)" >&2; exit 1; }
  read -r wall kb <"$name.time"
  printf '%-22s %8.2f s  %7.0f MiB  load %s\n' "$name" "$wall" "$((kb / 1024))" "$load" | tee -a times.txt
}

echo "host: $(nproc --all) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "date: $(date -u '+%F %T UTC'), load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "ccx: $(ccx -v 2>/dev/null | grep -m1 -o 'Version [0-9.]*'), gmsh $(gmsh --version 2>&1)"
: >times.txt
timed gmsh gmsh -3 -format inp -clmax "$clmax" "$root/tools/models/superelement_bar.geo" -o mesh.inp
/usr/bin/python3 "$root/tests/fixtures/make_calculix_bar.py" --gmsh-inp mesh.inp --modes 6 -o .
timed ccx_frequency_6 ccx -i bar_f
timed ccx_matrixstorage ccx -i bar_k
FLEXLOOP_BENCH_DIR=$dir FLEXLOOP_BENCH_CUT_HZ=$cut timed flexloop_import_cb "$bench" '[.bench]'
grep -E '^(dofs|dof map|\+|mode|worst)' flexloop_import_cb.log
