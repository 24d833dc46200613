#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""A fixture FMU scene made runnable in DIR from a built loop artefact LOOP.json: a copy of the FMU
beside it, the model path absolute, and the built-in controller's numbers as the FMU's
[controller.parameters].

- pi_force_feedback (`flexloop build tools/scenes/metrology_frame.toml`): the scene
  tests/fixtures/metrology_frame_fmu.toml, the designed gains, leak and limits as the parameters
  of tools/fmu/pi_force_feedback.
- state_space (e.g. `flexloop build tools/scenes/metrology_frame_lqg.toml`): the artefact's own
  scene (its provenance, from SOURCE_DIR) with its [controller] table replaced by the FMU, the
  channels mapped to y1.., u1.., the discrete A, B, C, D, the feedthrough D22 and its delay, the
  limits and the anti-windup as the parameters of tools/fmu/state_space_controller (of the design's size).

  tests/fmu/fmu_scene.py SOURCE_DIR FMU LOOP.json DIR     # prints the scene's path
"""
import json
import pathlib
import re
import shutil
import sys

root, fmu, loop, out = (pathlib.Path(a) for a in sys.argv[1:5])
artefact = json.load(open(loop))
c = artefact["controller"]
shutil.copy(fmu, out / fmu.name)
lines = ["", "[controller.parameters]"]


def matrix(name, rows):
    for i, row in enumerate(rows):
        for j, value in enumerate(row):
            lines.append(f"{name}_{i + 1}_{j + 1} = {value!r}")


if c["type"] == "pi_force_feedback":
    text = (root / "tests/fixtures/metrology_frame_fmu.toml").read_text()
    text = text.replace('"../../tools/models/metrology_frame.toml"',
                        json.dumps(str(root / "tools/models/metrology_frame.toml")))
    for i in range(6):
        for j in range(6):
            lines.append(f"K_P_{i + 1}_{j + 1} = {c['K_P'][i][j]!r}")
            lines.append(f"K_I_{i + 1}_{j + 1} = {c['K_I'][i][j]!r}")
    lines += [f"leak_rad_s = {c['leak_rad_s']!r}", f"u_min = {c['u_min'][0]!r}",
              f"u_max = {c['u_max'][0]!r}"]
    scene = out / "metrology_frame_fmu.toml"
else:
    assert c["type"] == "state_space", c["type"]
    source = root / artefact["provenance"]["scene"]
    text = source.read_text()
    model = re.search(r'^model = "(.*)"', text, re.M)
    text = (text[:model.start(1)] + str((source.parent / model.group(1)).resolve()) +
            text[model.end(1):])
    sensors = [s["name"] for s in artefact["channels"]["sensors"]]
    actuators = [a["name"] for a in artefact["channels"]["actuators"]]
    table = [f'[controller]\ntype = "fmu"\nfile = "{fmu.name}"\n\n[controller.map.sensors]']
    table += [f'"{s}" = "y{i + 1}"' for i, s in enumerate(sensors)]
    table += ["", "[controller.map.actuators]"]
    table += [f'"{a}" = "u{i + 1}"' for i, a in enumerate(actuators)]
    # The [controller] table, up to the next table not under it.
    text = re.sub(r"^\[controller\]\n(?:(?!\[(?!controller[.\]])).*\n)*",
                  "\n".join(table) + "\n\n", text, count=1, flags=re.M)
    for name in ("A", "B", "C", "D"):
        matrix(name, c[name])
    matrix("D22", c["feedthrough"])
    for limit in ("u_min", "u_max"):
        if c[limit]:
            lines += [f"{limit}_{i + 1} = {c[limit][i if len(c[limit]) > 1 else 0]!r}"
                      for i in range(len(actuators))]
    lines.append(f"anti_windup = {1 if c['anti_windup'] == 'hold' else 0}")
    lines.append(f"feedthrough_delay = {c['feedthrough_delay']}")
    scene = out / (source.stem + "_fmu.toml")
scene.write_text(text + "\n".join(lines) + "\n")
print(scene)
