#!/usr/bin/env bash
# The loop's stationary start under several OpenBLAS kernels (issue 57): `flexloop build` of the
# metrology frame, the shipped flexible arm and a generated 50-beam arm with OPENBLAS_CORETYPE set
# to each kernel this CPU can run (and unset: OpenBLAS's own choice). Every artefact is read back
# by `flexloop sim`; every start covariance is positive semidefinite to 1e-12 of its largest
# eigenvalue; and the covariances of one loop agree across kernels to max(1e-10, 10 s), s the
# sensitivity the artefact states (eps |A| over the slowest mode's distance to the unit circle:
# plant/lti/stable_covariance.hpp). The agreement each loop reaches is printed.
#   tests/hard_cases/blas_kernels.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

blas=$(readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3)
case "$blas" in
*openblas*) ;;
*) echo "SKIP: libblas.so.3 is $blas, not OpenBLAS (tools/lib/common.sh installs it)"; exit 77 ;;
esac
# A kernel only where the CPU has its instructions (an unsupported one dies of SIGILL).
flags=$(grep -m1 '^flags' /proc/cpuinfo)
kernels=(native Prescott)
[[ $flags == *" avx "* ]] && kernels+=(Sandybridge)
[[ $flags == *" avx2 "* ]] && kernels+=(Haswell Zen)
[[ $flags == *" avx512f "* && $flags == *" avx512bw "* ]] && kernels+=(SkylakeX)

# with_kernel KERNEL COMMAND...: COMMAND on one BLAS thread with that kernel (native: OpenBLAS's own).
with_kernel() {
  local k=$1
  shift
  if [[ $k == native ]]; then
    env -u OPENBLAS_CORETYPE OPENBLAS_NUM_THREADS=1 "$@"
  else
    OPENBLAS_CORETYPE=$k OPENBLAS_NUM_THREADS=1 "$@"
  fi
}

/usr/bin/python3 "$root/tools/models/make_flexible_arm.py" --elements 50 -o "$tmp/arm50" \
  >/dev/null || fail "make_flexible_arm.py --elements 50"
declare -A scenes=([metrology_frame]="$root/tools/scenes/metrology_frame.toml"
  [flexible_arm]="$root/tools/scenes/flexible_arm.toml" [arm50]="$tmp/arm50/scene.toml")
for name in metrology_frame flexible_arm arm50; do
  for k in "${kernels[@]}"; do
    out="$tmp/${name}_$k.json"
    with_kernel "$k" "$flexloop" build "${scenes[$name]}" -o "$out" >"$tmp/build.txt" 2>&1 ||
      fail "$name, kernel $k: build: $(cat "$tmp/build.txt")"
    with_kernel "$k" "$flexloop" sim "$out" --duration 0.01 >"$tmp/sim.txt" 2>&1 ||
      fail "$name, kernel $k: sim refuses the artefact: $(cat "$tmp/sim.txt")"
  done
done

/usr/bin/python3 - "$tmp" "${kernels[@]}" <<'PY' || fail "the kernels disagree (above)"
import json, sys
import numpy as np
tmp, kernels = sys.argv[1], sys.argv[2:]
bad = 0
for name in ("metrology_frame", "flexible_arm", "arm50"):
    loops = {k: json.load(open(f"{tmp}/{name}_{k}.json"))["start"] for k in kernels}
    for which in ("open_loop", "closed_loop"):
        starts = {k: s.get(which) for k, s in loops.items()}
        if any(s is None or "covariance" not in s for s in starts.values()):
            print(f"{name} {which}: no stationary start")
            continue
        P = {k: np.array(s["covariance"], float) for k, s in starts.items()}
        sensitivity = max(s.get("sensitivity", 0.0) for s in starts.values())
        worst_psd = min(np.linalg.eigvalsh(p)[0] / np.linalg.eigvalsh(p)[-1] for p in P.values())
        ref = P["native"]
        spread = max(np.linalg.norm(p - ref) / np.linalg.norm(ref) for p in P.values())
        bound = max(1e-10, 10 * sensitivity)
        ok = spread <= bound and worst_psd >= -1e-12
        bad += not ok
        print(f"{name} {which}: {ref.shape[0]} states, kernels agree to {spread:.1e} relative "
              f"(bound {bound:.1e}, stated sensitivity {sensitivity:.1e}); smallest eigenvalue "
              f"{worst_psd:.1e} of the largest{'' if ok else '  <-- FAIL'}")
sys.exit(1 if bad else 0)
PY
echo "blas kernels: ${#kernels[@]} kernels (${kernels[*]}), 3 loops agree"
