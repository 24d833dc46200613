# SPDX-License-Identifier: BSD-3-Clause
"""The Python module against the command line (issue 55, 3): the same computation, the same bits.

Run by CTest with PYTHONPATH at the module and FLEXLOOP the command line program; the working
directory is the repository."""
import json
import os
import subprocess

import numpy as np
import pytest

import flexloop

CART = "tools/models/cart.toml"


def cli_linearise(tmp_path, model, inputs=(), outputs=()):
    out = tmp_path / "lin.json"
    args = [os.environ["FLEXLOOP"], "linearise", model, "--out", str(out)]
    for i in inputs:
        args += ["-i", i]
    for o in outputs:
        args += ["-O", o]
    subprocess.run(args, check=True, capture_output=True)
    return json.loads(out.read_text())


@pytest.mark.parametrize("channels", [((), ()), (("acc:x.1",), ("pos:x.2",))])
def test_linearise_is_the_cli_to_the_bit(tmp_path, channels):
    inputs, outputs = channels
    cli = cli_linearise(tmp_path, CART, inputs, outputs)
    py = flexloop.linearise(CART, list(inputs) or None, list(outputs) or None)
    for name in "ABCD":
        got = getattr(py, name)
        assert isinstance(got, np.ndarray)
        want = np.array(cli[name], dtype=float).reshape(got.shape)
        assert np.array_equal(got, want), name  # bit for bit: the JSON round-trips doubles
    assert py.states == cli["states"]
    assert py.inputs == cli["inputs"]
    assert py.outputs == cli["outputs"]
    assert np.array_equal(py.natural_frequencies_hz, np.array(cli["natural_frequencies_hz"]))


def test_the_metrology_frame_has_its_six_modes():
    lin = flexloop.linearise("tools/models/metrology_frame.toml")
    f = lin.natural_frequencies_hz
    assert f.shape == (6,)
    assert np.all(np.diff(f) >= 0)
    assert 10 < f[0] < 20


def test_bad_input_raises_the_cli_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[model]\nname = 'x'\ndim = 4\n")
    with pytest.raises(flexloop.InputError) as e:
        flexloop.linearise(str(bad))
    assert "bad.toml" in str(e.value)
    assert isinstance(e.value, ValueError)
    with pytest.raises(flexloop.InputError, match="not-there.toml"):
        flexloop.linearise(str(tmp_path / "not-there.toml"))
    with pytest.raises(flexloop.InputError, match="acc:x.99"):
        flexloop.linearise(CART, ["acc:x.99"])


FRAME = "tools/scenes/metrology_frame.toml"


def test_build_is_flexloop_build_and_loads_back(tmp_path):
    cli_file = tmp_path / "cli.json"
    subprocess.run([os.environ["FLEXLOOP"], "build", FRAME, "-o", str(cli_file)], check=True,
                   capture_output=True)
    cli = json.loads(cli_file.read_text())
    loop = flexloop.build(FRAME)
    assert loop.rate_hz == cli["rate_hz"]
    assert loop.controller == "pi_force_feedback"
    assert loop.form == "dense"
    assert loop.sensors == [c["name"] for c in cli["channels"]["sensors"]]
    py_file = tmp_path / "py.json"
    loop.save(str(py_file))
    saved = json.loads(py_file.read_text())
    saved.pop("provenance"), cli.pop("provenance")  # who built it, and when
    assert saved == cli
    back = flexloop.load(str(py_file))
    for name in "ABCD":
        assert np.array_equal(getattr(back, name), getattr(loop, name)), name
    modal = flexloop.build(FRAME, rate_hz=5000, form="modal")
    assert modal.rate_hz == 5000 and modal.form == "modal"


def agree(py, cli, path=""):
    """Every entry the same, every number to the bit (==). Until the disk margin's complex SVD
    had one copy (controller/design/disk_margins.cpp), its last bits and the disk margin's
    frequency differed here (doc/python.md)."""
    if isinstance(cli, dict):
        assert set(py) == set(cli), path
        for k in cli:
            if k != "flexloop_git":  # the module's build may be of a tree with changes
                agree(py[k], cli[k], f"{path}/{k}")
    elif isinstance(cli, list):
        assert len(py) == len(cli), path
        for i, (a, b) in enumerate(zip(py, cli)):
            agree(a, b, f"{path}[{i}]")
    else:
        assert py == cli, path


def test_analyse_is_analysis_json(tmp_path):
    out = tmp_path / "analyse"
    subprocess.run([os.environ["FLEXLOOP"], "analyse", FRAME, "--out-dir", str(out)], check=True,
                   capture_output=True)
    cli = json.loads((out / "analysis.json").read_text())
    py = flexloop.analyse(FRAME)
    assert py["natural_frequencies_hz"] == cli["natural_frequencies_hz"]
    agree(py, cli)
    with pytest.raises(flexloop.InputError, match="nothing.toml"):
        flexloop.analyse(str(tmp_path / "nothing.toml"))
