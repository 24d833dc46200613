#!/usr/bin/env bash
# `flexloop export-fmu` as a user runs it: --help with an example; a scene and an artefact give an
# FMU with its description, library, artefact and GUID; bad input exits 2 naming what is wrong,
# with nothing written.
#   tests/fmu/export_fmu.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

out=$("$flexloop" export-fmu --help) || fail "--help"
[[ "$out" == *"Example"* ]] || fail "--help has no example: $out"
"$flexloop" export-fmu "$root/tools/scenes/cart.toml" -o "$tmp/cart.fmu" > "$tmp/out.txt" ||
  fail "export a scene: $(cat "$tmp/out.txt")"
"$flexloop" build "$root/tools/scenes/two_mass_chain.toml" --form modal -o "$tmp/chain.json" \
  >/dev/null || fail "build"
"$flexloop" export-fmu "$tmp/chain.json" -o "$tmp/chain.fmu" >/dev/null || fail "export an artefact"
python3 - "$tmp/cart.fmu" "$tmp/chain.fmu" <<'PY' || fail "archive contents"
import json, sys, zipfile, xml.etree.ElementTree as ET
for f in sys.argv[1:]:
    z = zipfile.ZipFile(f)
    names = set(z.namelist())
    assert names == {"modelDescription.xml", "resources/loop.json", "resources/guid.txt",
                     "binaries/linux64/flexloop_plant.so"}, names
    d = ET.fromstring(z.read("modelDescription.xml"))
    assert d.get("fmiVersion") == "2.0"
    assert d.get("guid") == z.read("resources/guid.txt").decode().strip()
    loop = json.loads(z.read("resources/loop.json"))
    step = float(d.find("DefaultExperiment").get("stepSize"))
    assert abs(step * loop["rate_hz"] - 1) < 1e-12, (step, loop["rate_hz"])
    inputs = [v.get("name") for v in d.iter("ScalarVariable") if v.get("causality") == "input"]
    assert len(inputs) == len(loop["channels"]["actuators"]), inputs
PY
out=$("$flexloop" export-fmu "$root/tools/scenes/cart.toml" -o "$tmp/no/such/dir/p.fmu" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"$tmp/no/such/dir/p.fmu"* ]] || fail "unwritable output: exit $rc ($out)"
out=$("$flexloop" export-fmu "$root/tools/scenes/cart.toml" --form sparse -o "$tmp/x.fmu" 2>&1); rc=$?
[[ $rc -eq 2 && ! -e "$tmp/x.fmu" ]] || fail "bad --form: exit $rc ($out)"
[[ $(ls "$tmp") == $'cart.fmu\nchain.fmu\nchain.json\nout.txt' ]] || fail "left behind: $(ls "$tmp")"
echo "export-fmu: ok"
