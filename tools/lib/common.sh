# Shared by tools/demo, tools/check and tools/bench: install what is missing, configure, build.
# Sourced, not run.

FLEXLOOP_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
FLEXLOOP_PACKAGES=(
  build-essential cmake git pkg-config clang-format
  libeigen3-dev liblcm-dev liblcm-bin libglib2.0-dev
  libboost-dev catch2 libbenchmark-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  libssl-dev iproute2 util-linux bsdutils rt-tests gnuplot-nox python3 python3-matplotlib valgrind
  libcjson-dev libmatio-dev python3-numpy python3-scipy python3-mpmath libslicot-dev liblapack-dev libblas-dev
  gfortran
)

say() { printf '\033[1m[flexloop]\033[0m %s\n' "$*"; }

# Install the Debian packages that are not installed yet (apt-get update only when needed).
ensure_packages() {
  local missing=()
  for p in "${FLEXLOOP_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]} == 0)); then
    say "dependencies: all ${#FLEXLOOP_PACKAGES[@]} packages present"
    return
  fi
  say "installing: ${missing[*]}"
  local sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# configure_and_build BUILD_DIR BUILD_TYPE [cmake options...]
configure_and_build() {
  local dir=$1 type=$2
  shift 2
  say "configure $dir ($type $*)"
  cmake -S "$FLEXLOOP_ROOT" -B "$FLEXLOOP_ROOT/$dir" -DCMAKE_BUILD_TYPE="$type" "$@" >/dev/null
  say "build $dir"
  cmake --build "$FLEXLOOP_ROOT/$dir" -j "$(nproc)" -- --no-print-directory
}
