#!/usr/bin/env bash
# The plant FMUs `flexloop export-fmu` writes for shipped scenes against an outside validator:
# each modelDescription.xml validates with xmllint against the FMI 2.0 standard's own schema
# (tests/fixtures/fmi2_schema, unchanged from modelica/fmi-standard v2.0.5), which refuses a
# description with a fault put in; every real variable has the SI unit of its channel (a table of
# the project's units written here, not the exporter's parser), the log categories the FMU logs
# under are declared, and the model structure lists every output. An artefact whose channel unit
# does not read is refused (exit 2, naming the file and the unit, nothing written).
#   tests/fmu/plant_fmu_schema.sh FLEXLOOP SOURCE_DIR
# SPDX-License-Identifier: BSD-3-Clause
set -uo pipefail
flexloop=$1 root=$2
schema=$root/tests/fixtures/fmi2_schema/fmi2ModelDescription.xsd
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v xmllint >/dev/null || fail "xmllint is not installed (Debian: libxml2-utils)"

# check NAME: $tmp/NAME.fmu's description validates and its units, categories and structure hold.
check() {
  local name=$1 out
  python3 - "$tmp/$name.fmu" "$tmp/$name" <<'PY' || fail "unpack $name"
import sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
open(sys.argv[2] + ".xml", "wb").write(z.read("modelDescription.xml"))
open(sys.argv[2] + ".json", "wb").write(z.read("resources/loop.json"))
PY
  out=$(xmllint --noout --schema "$schema" "$tmp/$name.xml" 2>&1) ||
    fail "$name: modelDescription.xml does not validate against the FMI 2.0 schema: $out"
  python3 - "$tmp/$name.xml" "$tmp/$name.json" <<'PY' || fail "$name: units, categories, structure"
import json, sys, xml.etree.ElementTree as ET
d = ET.parse(sys.argv[1]).getroot()
loop = json.load(open(sys.argv[2]))
# The units the project's scenes give a channel: the Modelica name and the SI base exponents.
table = {"m": ("m", {"m": 1}), "m/s": ("m/s", {"m": 1, "s": -1}),
         "m/s^2": ("m/s2", {"m": 1, "s": -2}), "rad": ("rad", {"rad": 1}),
         "rad/s": ("rad/s", {"rad": 1, "s": -1}), "rad/s^2": ("rad/s2", {"rad": 1, "s": -2}),
         "N": ("N", {"kg": 1, "m": 1, "s": -2}), "N m": ("N.m", {"kg": 1, "m": 2, "s": -2})}
units = {}
for u in d.find("UnitDefinitions"):
    assert u.get("name") not in units, u.get("name")
    base = u.find("BaseUnit")
    units[u.get("name")] = {k: int(v) for k, v in base.attrib.items()} if base is not None else {}
channel = {}
for kind, prefix in (("actuators", "actuator."), ("sensors", "sensor."),
                     ("performance", "performance.")):
    for c in loop["channels"][kind]:
        channel[prefix + c["name"]] = c["unit"]
variables = list(d.find("ModelVariables"))
seen = set()
for v in variables:
    real = v.find("Real")
    if real is None:
        continue
    want = channel.pop(v.get("name"))
    name, exponents = table[want]
    assert real.get("unit") == name, (v.get("name"), real.get("unit"), want)
    assert units[name] == exponents, (name, units[name], exponents)
    seen.add(want)
assert not channel, channel
assert {c.get("name") for c in d.find("LogCategories")} == {"logStatusError", "logEvents"}
outputs = [str(i + 1) for i, v in enumerate(variables) if v.get("causality") == "output"]
for part in ("Outputs", "InitialUnknowns"):
    listed = [u.get("index") for u in d.find("ModelStructure").find(part)]
    assert listed == outputs, (part, listed, outputs)
print(" ".join(sorted(seen)))
PY
}

for scene in metrology_frame metrology_frame_all_effects payload_bipods; do
  "$flexloop" export-fmu "$root/tools/scenes/$scene.toml" -o "$tmp/$scene.fmu" >/dev/null ||
    fail "export $scene"
  check "$scene"
done
# The shipped scenes give N and m/s^2 only: the bipods' artefact with its channels in turn in each
# unit the project's scenes can give (rotations, moments, velocities, positions).
"$flexloop" build "$root/tools/scenes/payload_bipods.toml" -o "$tmp/units.json" >/dev/null ||
  fail "build the bipods"
python3 - "$tmp/units.json" <<'PY' || fail "edit units"
import json, sys
a = json.load(open(sys.argv[1]))
units = ["N", "N m", "m", "m/s", "m/s^2", "rad", "rad/s", "rad/s^2"]
channels = [c for k in ("actuators", "sensors", "performance") for c in a["channels"][k]]
for i, c in enumerate(channels):
    c["unit"] = units[i % len(units)]
json.dump(a, open(sys.argv[1], "w"))
PY
"$flexloop" export-fmu "$tmp/units.json" -o "$tmp/units.fmu" >/dev/null || fail "export the units"
[[ $(check units) == "N N m m m/s m/s^2 rad rad/s rad/s^2" ]] || fail "units: $(check units)"

# The validator has teeth: the same description without its guid, or with its log categories after
# the default experiment, does not validate.
sed 's/ guid="[^"]*"//' "$tmp/metrology_frame.xml" > "$tmp/no_guid.xml"
xmllint --noout --schema "$schema" "$tmp/no_guid.xml" 2>/dev/null && fail "a description without a guid validates"
python3 - "$tmp/metrology_frame.xml" "$tmp/moved.xml" <<'PY' || fail "move"
import sys, xml.etree.ElementTree as ET
t = ET.parse(sys.argv[1]); d = t.getroot()
c = d.find("LogCategories"); d.remove(c); d.insert(list(d).index(d.find("DefaultExperiment")) + 1, c)
t.write(sys.argv[2])
PY
xmllint --noout --schema "$schema" "$tmp/moved.xml" 2>/dev/null && fail "a misplaced <LogCategories> validates"

# A unit the exporter cannot declare: refused before anything is written.
"$flexloop" build "$root/tools/scenes/two_mass_chain.toml" -o "$tmp/chain.json" >/dev/null || fail "build"
python3 - "$tmp/chain.json" <<'PY' || fail "edit"
import json, sys
a = json.load(open(sys.argv[1])); a["channels"]["sensors"][0]["unit"] = "furlong/s"
json.dump(a, open(sys.argv[1], "w"))
PY
out=$("$flexloop" export-fmu "$tmp/chain.json" -o "$tmp/chain.fmu" 2>&1); rc=$?
[[ $rc -eq 2 && "$out" == *"chain.json"* && "$out" == *'"furlong"'* && ! -e "$tmp/chain.fmu" ]] ||
  fail "a unit that does not read: exit $rc ($out)"
echo "plant FMU schema: ok"
