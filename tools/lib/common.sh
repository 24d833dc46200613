# SPDX-License-Identifier: BSD-3-Clause
# Shared by tools/demo, tools/check and tools/bench: install what is missing, configure, build.
# Sourced, not run.

FLEXLOOP_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# What building and running the `flexloop` program needs (tools/demo installs only these).
FLEXLOOP_BUILD_PACKAGES=(
  build-essential cmake ninja-build ccache lld git pkg-config
  libeigen3-dev liblcm-dev liblcm-bin libglib2.0-dev
  libboost-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libssl-dev
  libcjson-dev libmatio-dev libnlopt-dev libspectra-dev libsuitesparse-dev libslicot-dev
  liblapack-dev libblas-dev libopenblas0-pthread gfortran libzip-dev libpugixml-dev gnuplot-nox
  libiceoryx-posh-dev libiceoryx-hoofs-dev libiceoryx-binding-c-dev iceoryx
)
# And what the tests, the sanitizers, the outside references and the engines need (tools/check).
FLEXLOOP_PACKAGES=(
  "${FLEXLOOP_BUILD_PACKAGES[@]}"
  clang-format catch2 libbenchmark-dev iproute2 util-linux bsdutils rt-tests python3
  python3-matplotlib valgrind python3-numpy python3-scipy python3-mpmath python3-openturns
  calculix-ccx gmsh clang libclang-rt-14-dev libxml2-utils help2man
  pybind11-dev python3-pybind11 python3-dev python3-pytest
  slurm-wlm slurmctld slurmd slurm-client munge universal-ctags
)

say() { printf '\033[1m[flexloop]\033[0m %s\n' "$*"; }

# Install the Debian packages that are not installed yet (apt-get update only when needed):
# every one the checks need, or with `build` only what building and running flexloop needs.
ensure_packages() {
  local -n wanted=FLEXLOOP_PACKAGES
  [[ "${1:-}" == build ]] && local -n wanted=FLEXLOOP_BUILD_PACKAGES
  local missing=()
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]} == 0)); then
    say "dependencies: all ${#wanted[@]} packages present"
    return
  fi
  say "installing: ${missing[*]}"
  local sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Compiler cache: objects are looked up by their preprocessed source, with paths under the
# repository taken relative to it, so a second clone or a build directory made anew reuses them.
export CCACHE_BASEDIR="$FLEXLOOP_ROOT"
export CCACHE_NOHASHDIR=true

# configure BUILD_DIR BUILD_TYPE [cmake options...]: Ninja (its log, .ninja_log, times every
# translation unit: tools/compile-times), ccache when present. A build directory that an older
# version configured with another generator is configured anew.
configure() {
  local dir=$1 type=$2
  shift 2
  local cache="$FLEXLOOP_ROOT/$dir/CMakeCache.txt"
  if [[ -f "$cache" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
    say "$dir was configured with another generator: configuring it anew"
    rm -rf "${FLEXLOOP_ROOT:?}/$dir/CMakeCache.txt" "${FLEXLOOP_ROOT:?}/$dir/CMakeFiles"
  fi
  # CMake keeps the compiler it first found: one configured with another ($CXX) starts anew.
  local compiler
  compiler=$(command -v "${CXX:-c++}")
  if [[ -f "$cache" ]] &&
    ! grep -qx "CMAKE_CXX_COMPILER:\(FILEPATH\|STRING\)=$compiler" "$cache"; then
    say "$dir was configured with another compiler: configuring it anew with $compiler"
    rm -rf "${FLEXLOOP_ROOT:?}/$dir/CMakeCache.txt" "${FLEXLOOP_ROOT:?}/$dir/CMakeFiles"
  fi
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  say "configure $dir ($type $*)"
  cmake -G Ninja -S "$FLEXLOOP_ROOT" -B "$FLEXLOOP_ROOT/$dir" -DCMAKE_BUILD_TYPE="$type" \
    "${launcher[@]}" "$@" >/dev/null
}

# build BUILD_DIR [targets...]: every target when none is named.
build() {
  local dir=$1
  shift
  say "build $dir${*:+ (}$*${*:+)}"
  cmake --build "$FLEXLOOP_ROOT/$dir" -j "$(nproc)" ${*:+--target "$@"}
}

# configure_and_build BUILD_DIR BUILD_TYPE [cmake options...]: configure, then build everything.
configure_and_build() {
  configure "$@"
  build "$1"
}
