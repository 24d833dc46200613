#!/usr/bin/env python3
"""The fixture FMU scene (tests/fixtures/metrology_frame_fmu.toml) made runnable in DIR: a copy of
the FMU beside it, the model path absolute, and the built-in PI's designed gains, leak and limits
(read from LOOP.json, `flexloop build tools/scenes/metrology_frame.toml`) as the FMU's parameters.

  tests/fmu/fmu_scene.py SOURCE_DIR FMU LOOP.json DIR     # prints the scene's path
"""
import json
import pathlib
import shutil
import sys

root, fmu, loop, out = (pathlib.Path(a) for a in sys.argv[1:5])
pi = json.load(open(loop))["controller"]
assert pi["type"] == "pi_force_feedback", pi["type"]
shutil.copy(fmu, out / "pi_force_feedback.fmu")
text = (root / "tests/fixtures/metrology_frame_fmu.toml").read_text()
text = text.replace('"../../tools/models/metrology_frame.toml"',
                    json.dumps(str(root / "tools/models/metrology_frame.toml")))
lines = ["", "[controller.parameters]"]
for i in range(6):
    for j in range(6):
        lines.append(f"K_P_{i + 1}_{j + 1} = {pi['K_P'][i][j]!r}")
        lines.append(f"K_I_{i + 1}_{j + 1} = {pi['K_I'][i][j]!r}")
lines += [f"leak_rad_s = {pi['leak_rad_s']!r}", f"u_min = {pi['u_min'][0]!r}",
          f"u_max = {pi['u_max'][0]!r}"]
scene = out / "metrology_frame_fmu.toml"
scene.write_text(text + "\n".join(lines) + "\n")
print(scene)
