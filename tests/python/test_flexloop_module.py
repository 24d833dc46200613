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
