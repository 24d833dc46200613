# SPDX-License-Identifier: BSD-3-Clause
"""tools/controllers/design_lqg.py (issue 55, 3; issue 58, 5): it reads the loop through the
module, reproduces the shipped controller, and designs for a plant with floor states -- the
gravity-preloaded metrology frame, whose floor positions and velocities the actuators cannot move
-- a controller whose closed loop `flexloop analyse` judges stable.

Run by CTest with PYTHONPATH at the module and FLEXLOOP the command line program; the working
directory is the repository."""
import importlib.util
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest
import scipy.linalg

import flexloop

SCRIPT = "tools/controllers/design_lqg.py"
FRAME = "tools/scenes/metrology_frame.toml"
LQG_SCENE = "tools/scenes/metrology_frame_lqg.toml"
MODEL = str(pathlib.Path("tools/models/metrology_frame.toml").resolve())


def design(loop, out):
    run = subprocess.run(["/usr/bin/python3", SCRIPT, str(loop), "-o", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return json.loads(pathlib.Path(out).read_text()), run.stdout


def scene_copy(source, path, **replace):
    """The scene with its model by absolute path and the given `key = value` lines replaced."""
    lines = []
    for line in pathlib.Path(source).read_text().splitlines():
        key = line.split("=")[0].strip()
        if key == "model":
            line = f'model = "{MODEL}"'
        elif key in replace:
            line = f"{key} = {replace[key]}"
        lines.append(line)
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_shipped_design_is_reproduced(tmp_path):
    artefact = tmp_path / "frame.json"
    subprocess.run([os.environ["FLEXLOOP"], "build", FRAME, "-o", str(artefact)], check=True,
                   capture_output=True)
    mine, _ = design(artefact, tmp_path / "lqg.json")
    shipped = json.loads(pathlib.Path("tools/controllers/metrology_frame_lqg.json").read_text())
    for k in ("Ad", "Bd", "Cd", "Dd"):  # as tests/hil/external_c_controller.sh: CPUs differ
        a, b = np.array(mine[k]), np.array(shipped[k])
        assert a.shape == b.shape, k
        assert np.abs(a - b).max(initial=0) <= 1e-8 * np.linalg.norm(b) + 1e-12, k
    for k in ("states", "inputs", "outputs", "method", "dt"):
        assert mine[k] == shipped[k], k
    assert "separated" not in mine["provenance"]  # every state reachable: designed as before


def test_a_plant_with_floor_states_gets_a_stable_loop(tmp_path):
    # The frame under gravity preload (a leak of 1 Hz keeps its PI loop, which build checks,
    # stable): the floor's positions and velocities are plant states.
    preloaded = scene_copy(FRAME, tmp_path / "preloaded.toml", gravity_preload="true",
                           leak_hz="1.0")
    loop = flexloop.build(str(preloaded))
    channels = [d.removeprefix("acc:") for d in loop.disturbances]
    floor = [s for s in loop.states if s.split(":", 1)[1] in channels]
    assert len(floor) == 12, loop.states  # pos: and vel: of the six floor channels
    # The design as it was, on all states, has no LQR: (A, B2) is not stabilisable.
    nw, nz = len(loop.disturbances), len(loop.performance)
    B2, C1, D12 = loop.B[:, nw:], loop.C[:nz], loop.D[:nz, nw:]
    with pytest.raises((np.linalg.LinAlgError, ValueError)):
        scipy.linalg.solve_discrete_are(loop.A, B2, C1.T @ C1, D12.T @ D12 + 1e-10 * np.eye(6),
                                        s=C1.T @ D12)

    controller, said = design(preloaded, tmp_path / "lqg_preloaded.json")
    separated = controller["provenance"]["separated"]
    assert separated["uncontrollable_states"] == 12 and separated["controllable_states"] == 12
    assert "12 states the actuators cannot move separated" in said
    assert controller["spectral_radius"] < 1

    scene = scene_copy(LQG_SCENE, tmp_path / "lqg_preloaded.toml", gravity_preload="true",
                       file=f'"{tmp_path / "lqg_preloaded.json"}"')
    out = tmp_path / "analyse"
    subprocess.run([os.environ["FLEXLOOP"], "analyse", str(scene), "--out-dir", str(out)],
                   check=True, capture_output=True)
    analysis = json.loads((out / "analysis.json").read_text())
    assert analysis["closed_loop_stable"] is True
    assert analysis["static_stability"]["preloaded"] is True


def test_the_staircase_finds_what_the_actuators_reach():
    spec = importlib.util.spec_from_file_location("design_lqg", SCRIPT)
    lqg = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(lqg)
    # Two masses on springs, only the first pushed, and a third free mass nothing reaches.
    dt = 1e-3
    Ac = np.zeros((6, 6))
    Ac[:3, 3:] = np.eye(3)
    Ac[3:5, :2] = [[-2.0, 1.0], [1.0, -1.0]]
    A = scipy.linalg.expm(Ac * dt)
    B = np.zeros((6, 1))
    B[3, 0] = dt
    V, Vu = lqg.controllable_basis(A, B)
    assert V.shape == (6, 4) and Vu.shape == (6, 2)
    assert np.allclose(V.T @ V, np.eye(4)) and np.allclose(V.T @ Vu, 0)
    assert np.abs(Vu.T @ A @ V).max() < 1e-12  # block triangular: u never reaches Vu
    free = np.zeros(6)
    free[[2, 5]] = 1
    assert np.linalg.norm(V.T @ free) < 1e-12  # the free mass is the unreachable part
