#!/usr/bin/env bash
# The online programs link no offline code (doc/design.md §1-2): no symbol of the model, its
# parsers, the linearisation and analysis, the controller design, the scenes or the reports is
# defined in them, and their link lines name no offline library.
#   tests/link/online_links.sh BUILD_DIR EXE...
set -euo pipefail
build=$1; shift
offline_ns='flexloop::(plant::model|plant::lti|controller::design|scene|report)::|(^| )toml::'
offline_libs='libflexloop_(plant_model|plant_lti|controller_design|scene|report)\.a'
fail=0
for exe in "$@"; do
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
  # The check must look at a loop program: each one defines the artefact reader.
  if ! grep -q "flexloop::artefact::" <<<"$symbols"; then
    echo "$name: no flexloop::artefact symbol found; is this the right program?"; fail=1
  fi
done
if [[ $fail -eq 0 ]]; then echo "online programs link only online code: $#"; fi
exit $fail
