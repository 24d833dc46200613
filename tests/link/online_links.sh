#!/usr/bin/env bash
# The online programs link no offline code (doc/design.md §1-2): no symbol of the model, its
# parsers, the linearisation and analysis, the controller design, the scenes or the reports is
# defined in them, and their link lines name no offline library. The controller FMU loader
# (controller/fmu, with libzip and pugixml) is a leaf only the programs that run a controller FMU
# link: each program after --no-fmu defines no controller::fmu symbol and names none of the three
# on its link line or among its shared libraries; each after --fmu does all of it.
#   tests/link/online_links.sh BUILD_DIR [--fmu|--no-fmu] EXE... [--fmu|--no-fmu] EXE...
# SPDX-License-Identifier: BSD-3-Clause
set -euo pipefail
build=$1; shift
offline_ns='flexloop::(plant::model|plant::lti|controller::design|scene|report)::|(^| )toml::'
offline_libs='libflexloop_(plant_model|plant_lti|controller_design|scene|report)\.a'
fmu=""  # "yes", "no" or "" (not checked), from the last --fmu / --no-fmu
fail=0
programs=0
# The FMU loader in program $1 (symbols $2, link line $3) as $fmu says: its symbols, its library
# on the link line, libzip and pugixml on the link line and among the shared libraries it needs.
check_fmu() {
  local name=$1 symbols=$2 link=$3 found=()
  grep -qE 'flexloop::controller::fmu::' <<<"$symbols" && found+=("controller::fmu symbols")
  grep -qE 'libflexloop_controller_fmu\.a' <<<"$link" && found+=("libflexloop_controller_fmu.a")
  local needed
  needed=$(readelf -d "$exe" | grep NEEDED || true)
  grep -qE 'libzip\.|-lzip\b' <<<"$link$needed" && found+=(libzip)
  grep -qE 'pugixml' <<<"$link$needed" && found+=(pugixml)
  if [[ $fmu == no && ${#found[@]} -gt 0 ]]; then
    echo "$name runs no controller FMU but has: ${found[*]}"; fail=1
  elif [[ $fmu == no ]]; then
    echo "$name: no controller FMU loader, libzip or pugixml"
  elif [[ $fmu == yes && ${#found[@]} -lt 4 ]]; then
    echo "$name runs a controller FMU but has only: ${found[*]}"; fail=1
  elif [[ $fmu == yes ]]; then
    echo "$name: the controller FMU loader linked, with libzip and pugixml"
  fi
}
for exe in "$@"; do
  case $exe in
    --fmu) fmu=yes; continue ;;
    --no-fmu) fmu=no; continue ;;
  esac
  programs=$((programs + 1))
  name=$(basename "$exe")
  symbols=$(nm -C --defined-only "$exe")
  hits=$(grep -E "$offline_ns" <<<"$symbols" | head -5 || true)
  if [[ -n "$hits" ]]; then
    echo "$name defines offline symbols:"; echo "$hits"; fail=1
  fi
  # The link line: Ninja's command for the program (Makefile builds: its link.txt).
  if [[ -f "$build/build.ninja" ]]; then
    link=$(ninja -C "$build" -t commands "$(realpath --relative-to="$build" "$exe")" | tail -1)
  else
    link_txt=$(find "$build" -path "*/CMakeFiles/$name.dir/link.txt" | head -1)
    link=${link_txt:+$(cat "$link_txt")}
  fi
  if [[ -z "$link" ]]; then echo "$name: no link line found under $build"; fail=1; continue; fi
  libs=$(grep -oE "$offline_libs" <<<"$link" | sort -u || true)
  if [[ -n "$libs" ]]; then echo "$name links offline libraries: $libs"; fail=1; fi
  check_fmu "$name" "$symbols" "$link"
  # The check must look at a loop program: each one defines the artefact reader.
  if ! grep -q "flexloop::artefact::" <<<"$symbols"; then
    echo "$name: no flexloop::artefact symbol found; is this the right program?"; fail=1
  fi
done
if [[ $fail -eq 0 ]]; then echo "online programs link only online code: $programs"; fi
exit $fail
