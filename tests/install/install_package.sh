#!/usr/bin/env bash
# `cmake --install` of a built tree into a temporary prefix gives a package a user can work with
# (doc/install.md):
#   - bin/ holds the four programs, and bin/flexloop runs from the prefix;
#   - include/flexloop/ the C controller library's headers (carrier, sample decoder, the lcm-gen C
#     types), which compile as C and, inside extern "C", as C++; lib/ the shared library, and
#     lib/flexloop/ the plant FMU's (for `flexloop export-fmu`);
#   - lib/pkgconfig/flexloop.pc and lib/cmake/flexloop/ (config, version, and the imported targets
#     flexloop::c_controller and flexloop::<program>);
#   - share/flexloop/ the scenes, models, controllers and the C example; share/man/man1/ a man page
#     per program (help2man, from --help);
#   - the installed C example builds out of tree against the prefix both with pkg-config and with
#     its CMake project (find_package(flexloop) -> flexloop::c_controller), and each build closes a
#     2-s loop on the installed LQG scene (at 1 kHz, its controller designed by the installed
#     design_lqg.py) against the installed `flexloop plant` inside a private loopback-only
#     namespace (tools/netns-run; the controller stopped by its pid, also on failure). Not a timing
#     test: an answer may be late; judged are that the controller answered at least half the
#     samples and that the plant dropped no message as undecodable;
#   - `cpack -G DEB` makes a .deb of the same tree under /usr whose dependencies include LCM, and
#     whose version (+native) and description say so when the build is native (-march=native).
#   tests/install/install_package.sh BUILD_DIR SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
build=$1 root=$2
tmp=$(mktemp -d)
prefix=$tmp/prefix
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checks=0
pass() { checks=$((checks + 1)); }

cmake --install "$build" --prefix "$prefix" > "$tmp/install.txt" 2>&1 ||
  fail "cmake --install: $(cat "$tmp/install.txt")"

programs=(flexloop flexloop-plant flexloop-controller flexloop-c-controller)
for program in "${programs[@]}"; do
  [[ -x $prefix/bin/$program ]] || fail "no bin/$program"
  man=$prefix/share/man/man1/$program.1
  [[ -f $man ]] || fail "no man page share/man/man1/$program.1"
  grep -q '^\.SH NAME' "$man" && grep -q '^\.TH' "$man" && (($(wc -l < "$man") > 20)) ||
    fail "$program.1 is not a man page"
done
"$prefix/bin/flexloop" version > "$tmp/version.txt" || fail "bin/flexloop version"
pass

# lib/ is lib or lib/<multiarch> (GNUInstallDirs): where the .pc is.
pc=$(find "$prefix" -name flexloop.pc)
[[ -n $pc ]] || fail "no flexloop.pc"
libdir=$(dirname "$(dirname "$pc")")
for f in cmake/flexloop/flexloopConfig.cmake cmake/flexloop/flexloopConfigVersion.cmake \
  cmake/flexloop/flexloopTargets.cmake libflexloop_c_controller.so flexloop/flexloop_plant.so; do
  [[ -e $libdir/$f ]] || fail "no ${libdir#"$prefix"/}/$f"
done
for target in c_controller "${programs[@]}"; do
  grep -q "^add_[a-z]*(flexloop::$target .*IMPORTED" "$libdir/cmake/flexloop/flexloopTargets.cmake" ||
    fail "find_package(flexloop) gives no imported target flexloop::$target"
done
for h in carrier.h sample_decode.h flexloop_msgs_sensor_sample_t.h flexloop_msgs_actuator_command_t.h; do
  [[ -f $prefix/include/flexloop/$h ]] || fail "no include/flexloop/$h"
done
for d in scenes/metrology_frame_lqg.toml models/metrology_frame.toml \
  controllers/metrology_frame_lqg.json examples/c_controller/state_space_controller.c \
  examples/c_controller/CMakeLists.txt; do
  [[ -f $prefix/share/flexloop/$d ]] || fail "no share/flexloop/$d"
done
# The Python module from the prefix (issue 55, 3): the cart linearised as bin/flexloop does.
"$prefix/bin/flexloop" linearise "$prefix/share/flexloop/models/cart.toml" --out "$tmp/cart.json" \
  > /dev/null || fail "bin/flexloop linearise"
PYTHONPATH=$prefix/lib/python3/dist-packages /usr/bin/python3 - "$prefix" "$tmp/cart.json" <<'PY' ||
import json, sys
import numpy as np
import flexloop
prefix, cli = sys.argv[1], json.load(open(sys.argv[2]))
assert flexloop.__file__.startswith(prefix), flexloop.__file__
lin = flexloop.linearise(prefix + "/share/flexloop/models/cart.toml")
for name in "ABCD":
    want = np.array(cli[name], dtype=float).reshape(getattr(lin, name).shape)
    assert np.allclose(getattr(lin, name), want, rtol=1e-12, atol=0), name
PY
  fail "import flexloop from the prefix: the cart is not the command line's"
# Nothing installed may need the build tree: the C programs find the library by $ORIGIN.
if readelf -d "$prefix/bin/flexloop-c-controller" | grep -q "$build"; then
  fail "bin/flexloop-c-controller's run path names the build tree"
fi
pass

export PKG_CONFIG_PATH=$libdir/pkgconfig
[[ $(pkg-config --modversion flexloop) == [0-9]* ]] || fail "pkg-config --modversion flexloop"
printf '#include <flexloop/carrier.h>\n#include <flexloop/sample_decode.h>\n' > "$tmp/headers.c"
for lang in c c++; do
  # shellcheck disable=SC2046
  cc -x "$lang" -fsyntax-only -Wall -Wextra $(pkg-config --cflags flexloop) "$tmp/headers.c" \
    > "$tmp/headers.txt" 2>&1 || fail "the headers as $lang: $(cat "$tmp/headers.txt")"
done
pass

example=$prefix/share/flexloop/examples/c_controller
# shellcheck disable=SC2046
cc -std=c11 -Wall -Wextra -Werror "$example/state_space_controller.c" \
  $(pkg-config --cflags --libs flexloop libcjson) -lm -Wl,-rpath,"$libdir" \
  -o "$tmp/pkg-config-controller" > "$tmp/cc.txt" 2>&1 ||
  fail "the example with pkg-config: $(cat "$tmp/cc.txt")"
pass
cmake -S "$example" -B "$tmp/example" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
  > "$tmp/cmake.txt" 2>&1 && cmake --build "$tmp/example" >> "$tmp/cmake.txt" 2>&1 ||
  fail "the example with find_package(flexloop): $(cat "$tmp/cmake.txt")"
ldd "$tmp/example/my-c-controller" | grep -q "$libdir/libflexloop_c_controller.so" ||
  fail "the CMake-built example does not link the installed library: $(ldd "$tmp/example/my-c-controller")"
pass

# The installed LQG scene at 1 kHz (gentle on a busy machine), its controller designed anew by the
# installed design_lqg.py, as tests/hil/external_c_controller.sh does from the source tree.
share=$prefix/share/flexloop rate=1000 duration=2
"$prefix/bin/flexloop" build "$share/scenes/metrology_frame.toml" --rate $rate -o "$tmp/frame.json" \
  > "$tmp/build.txt" 2>&1 || fail "installed flexloop build: $(cat "$tmp/build.txt")"
"$share/controllers/design_lqg.py" "$tmp/frame.json" -o "$tmp/lqg.json" > "$tmp/design.txt" 2>&1 ||
  fail "installed design_lqg.py: $(cat "$tmp/design.txt")"
sed -e "s|^rate_hz = .*|rate_hz = $rate|" -e "s|^file = .*|file = \"$tmp/lqg.json\"|" \
  -e "s|^model = .*|model = \"$share/models/metrology_frame.toml\"|" \
  "$share/scenes/metrology_frame_lqg.toml" > "$tmp/scene.toml"
"$prefix/bin/flexloop" build "$tmp/scene.toml" -o "$tmp/loop.json" > "$tmp/build.txt" 2>&1 ||
  fail "installed flexloop build (LQG, $rate Hz): $(cat "$tmp/build.txt")"
run_loop() {
  local controller=$1 name
  name=$(basename "$controller")
  "$root/tools/netns-run" -- bash -c "
    set -e
    '$controller' '$tmp/loop.json' --duration $((duration + 10)) > '$tmp/$name.txt' 2>&1 &
    pid=\$!
    trap 'kill -TERM \$pid 2>/dev/null || true' EXIT
    sleep 0.5
    '$prefix/bin/flexloop' plant '$tmp/loop.json' --duration $duration --max-miss-share 100 \\
      --start rest --json '$tmp/$name.json' > '$tmp/$name-plant.txt' 2>&1
    kill -TERM \$pid; wait \$pid" > "$tmp/netns.txt" 2>&1 ||
    fail "$name in the namespace: $(cat "$tmp/netns.txt" "$tmp/$name.txt" "$tmp/$name-plant.txt")"
  /usr/bin/python3 - "$tmp/$name.json" "$tmp/$name.txt" <<'PY' || fail "$name's loop: $(cat "$tmp/$name.txt")"
import json, re, sys
plant = json.load(open(sys.argv[1]))
answered = int(re.search(r"answered (\d+) samples", open(sys.argv[2]).read()).group(1))
cycles = plant["cycles"]
print(f"  {answered} of {cycles} samples answered, {plant['deadline_misses']} misses (not judged)")
assert cycles > 0 and answered >= cycles / 2, (answered, cycles)
assert plant["dropped_messages"]["decode_failure"] == 0
PY
  echo "loop closed with the installed package and $name"
}
run_loop "$tmp/pkg-config-controller"
pass
run_loop "$tmp/example/my-c-controller"
pass
# The .deb (cpack): the same tree under /usr, its dependencies read from the binaries, and a
# native build said to be one.
(cd "$build" && cpack -G DEB -B "$tmp/deb") > "$tmp/cpack.txt" 2>&1 || fail "cpack: $(cat "$tmp/cpack.txt")"
deb=$(find "$tmp/deb" -maxdepth 1 -name 'flexloop_*.deb')
[[ -n $deb ]] || fail "cpack made no flexloop_*.deb: $(cat "$tmp/cpack.txt")"
dpkg-deb -I "$deb" > "$tmp/control.txt" || fail "dpkg-deb -I"
grep -q "^ Depends:.*liblcm" "$tmp/control.txt" || fail "the .deb depends on no LCM: $(cat "$tmp/control.txt")"
if grep -q "^FLEXLOOP_NATIVE:BOOL=ON" "$build/CMakeCache.txt"; then
  grep -q "^ Version: .*+native" "$tmp/control.txt" && grep -q "march=native" "$tmp/control.txt" ||
    fail "a native build's .deb does not say so: $(cat "$tmp/control.txt")"
fi
dpkg-deb -c "$deb" > "$tmp/contents.txt" || fail "dpkg-deb -c"
for f in usr/bin/flexloop usr/include/flexloop/carrier.h usr/lib/pkgconfig/flexloop.pc \
  usr/lib/cmake/flexloop/flexloopConfig.cmake usr/share/flexloop/scenes/metrology_frame.toml \
  usr/share/man/man1/flexloop.1; do
  grep -q " \./${f//./\\.}\$" "$tmp/contents.txt" || fail "the .deb has no /$f"
done
pass
echo "install: $checks checks passed"
