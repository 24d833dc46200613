# SPDX-License-Identifier: BSD-3-Clause
"""flexloop.sim and flexloop.campaign against the command line (issue 55, 3): the same runs and
samples, the same bits.

sim: the CLI's --log CSV (each number the shortest text that reads back to the same double) and
its --json (the RMS table's numbers as JSON numbers, which read back to the same doubles) against
the module's arrays and table, compared with ==. campaign: the CLI's samples.jsonl and
summary.json against the module's samples and summary, compared as parsed JSON with == (each
line's flexloop.build names the program that computed it: the module's file here).

Run by CTest with PYTHONPATH at the module and FLEXLOOP the command line program; the working
directory is the repository."""
import csv
import hashlib
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import flexloop

FRAME = "tools/scenes/metrology_frame.toml"
PASSIVE = "tools/scenes/metrology_frame_no_controller.toml"
UNCERTAIN = "tools/scenes/metrology_frame_uncertain.toml"


def cli_sim(tmp_path, loop, duration, *options):
    log, figures = tmp_path / "log.csv", tmp_path / "figures.json"
    run = subprocess.run([os.environ["FLEXLOOP"], "sim", loop, "--duration", str(duration),
                          "--log", str(log), "--json", str(figures), *options],
                         check=True, capture_output=True, text=True)
    with open(log, newline="") as f:
        rows = list(csv.reader(f))
    columns = {name: np.array([float(r[i]) for r in rows[1:]]) for i, name in enumerate(rows[0])}
    return columns, json.loads(figures.read_text()), run.stdout


def assert_same_run(py, columns, figures):
    assert np.array_equal(py.t, columns.pop("t_s"))
    assert list(py.signals) == list(columns)  # the log's columns, in its order
    for name, values in columns.items():
        assert np.array_equal(py.signals[name], values), name
    assert py.logged == figures["logged"]
    assert py.controlled == figures["controlled"]
    assert py.start_off == figures["start_off"] and py.start_on == figures["start_on"]
    assert list(py.rms) == [row["channel"] for row in figures["rms"]]
    for row in figures["rms"]:
        mine = py.rms[row["channel"]]
        assert mine["unit"] == row["unit"]
        for key in ("off", "on", "change_db"):
            if row[key] is None:  # no controller: no controller-on figure
                assert np.isnan(mine[key]), (row["channel"], key)
            else:
                assert mine[key] == row[key], (row["channel"], key)  # to the bit
    assert py.rms_command == {c["channel"]: c["on"] for c in figures["rms_command"]}


@pytest.mark.parametrize("options", [{}, {"controller": "off", "start": "rest"}])
def test_sim_of_a_scene_is_the_cli_to_the_bit(tmp_path, options):
    flags = [x for k, v in options.items() for x in (f"--{k}", v)]
    columns, figures, stdout = cli_sim(tmp_path, FRAME, 0.05, *flags)
    py = flexloop.sim(FRAME, 0.05, **options)
    assert py.t.shape == (500,)  # 0.05 s at 10 kHz
    assert len(py.signals) == 6 + 6 + 6 + 6 + 6  # floor, z, z sensed, sensors, commands
    assert_same_run(py, columns, figures)
    # The table sim prints is these numbers.
    first = figures["rms"][0]
    assert f"{first['off']:14.4e}" in stdout


def test_sim_of_a_loop_with_another_seed_is_the_cli_on_that_artefact(tmp_path):
    loop = flexloop.build(FRAME)
    artefact = tmp_path / "loop.json"
    loop.save(str(artefact))
    text = json.loads(artefact.read_text())
    assert text["floor"]["seed"] != 7
    text["floor"]["seed"] = 7
    (tmp_path / "seed7.json").write_text(json.dumps(text))
    columns, figures, _ = cli_sim(tmp_path, str(tmp_path / "seed7.json"), 0.03)
    py = flexloop.sim(loop, 0.03, seed=7)
    assert figures["floor_seed"] == 7
    assert_same_run(py, columns, figures)
    other = flexloop.sim(loop, 0.03)  # the loop's own seed: another floor
    assert not np.array_equal(other.signals[next(iter(other.signals))],
                              py.signals[next(iter(py.signals))])


def test_sim_without_a_controller_has_one_run(tmp_path):
    columns, figures, _ = cli_sim(tmp_path, PASSIVE, 0.02)
    py = flexloop.sim(PASSIVE, 0.02)
    assert not py.controlled and py.logged == "off" and py.rms_command == {}
    assert_same_run(py, columns, figures)


def test_sim_bad_input_raises_the_cli_message(tmp_path):
    with pytest.raises(flexloop.InputError, match="missing.toml"):
        flexloop.sim(str(tmp_path / "missing.toml"), 0.1)
    with pytest.raises(flexloop.InputError, match="controller"):
        flexloop.sim(FRAME, 0.1, controller="maybe")
    with pytest.raises(flexloop.InputError, match="duration"):
        flexloop.sim(FRAME, -1.0)
    bad = tmp_path / "bad.toml"
    model = pathlib.Path("tools/models/metrology_frame.toml").resolve()
    bad.write_text(open(FRAME).read().replace("rate_hz = 10000", "rate_hz = -5")
                   .replace('"../models/metrology_frame.toml"', f'"{model}"'))
    with pytest.raises(flexloop.InputError, match=r"bad\.toml:\d+") as e:  # file:line
        flexloop.sim(str(bad), 0.1)
    assert_cli_says(["sim", str(bad), "--duration", "0.1"], e.value)


def assert_cli_says(args, error):
    """The command line refuses the same input (exit 2) with the exception's message."""
    run = subprocess.run([os.environ["FLEXLOOP"], *args], capture_output=True, text=True)
    assert run.returncode == 2
    assert f"error: {error}" in run.stderr


def same(py, cli, path=""):
    """Every entry equal, every number to the bit (==)."""
    if isinstance(cli, dict):
        assert set(py) == set(cli), path
        for k in cli:
            same(py[k], cli[k], f"{path}/{k}")
    elif isinstance(cli, list):
        assert len(py) == len(cli), path
        for i, (a, b) in enumerate(zip(py, cli)):
            same(a, b, f"{path}[{i}]")
    else:
        assert py == cli, path


def sha16(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()[:16]


def test_campaign_is_the_cli_to_the_bit(tmp_path):
    out = tmp_path / "campaign"
    subprocess.run([os.environ["FLEXLOOP"], "campaign", FRAME, "-u", UNCERTAIN, "-n", "6",
                    "--design", "lhs", "--seed", "3", "--jobs", "2", "--worst", "0", "--quiet",
                    "--out-dir", str(out)], check=True, capture_output=True)
    cli_plan = json.loads((out / "plan.json").read_text())
    cli_samples = [json.loads(line) for line in (out / "samples.jsonl").read_text().splitlines()]
    cli_summary = json.loads((out / "summary.json").read_text())
    py = flexloop.campaign(FRAME, UNCERTAIN, 6, design="lhs", seed=3, jobs=2)
    same(py.plan, cli_plan)
    assert [s["index"] for s in py.samples] == list(range(6))
    assert len(py.samples) == len(cli_samples) == 6
    for p, c in zip(py.samples, cli_samples):
        # Who computed the line: the module's file, not python3's (the CLI: its executable).
        assert p["flexloop"]["build"] == sha16(flexloop.__file__)
        assert c["flexloop"]["build"] == sha16(os.environ["FLEXLOOP"])
        same({**p, "flexloop": c["flexloop"]}, c)
    same(py.summary, cli_summary)
    one = flexloop.campaign(FRAME, UNCERTAIN, 6, design="lhs", seed=3, jobs=1)
    assert one.samples == py.samples  # a sample is its index's, whatever thread computes it
    assert one.summary == py.summary


def test_campaign_bad_input_raises_the_cli_message(tmp_path):
    with pytest.raises(flexloop.InputError, match="nothing.toml"):
        flexloop.campaign(FRAME, str(tmp_path / "nothing.toml"), 4)
    with pytest.raises(flexloop.InputError):
        flexloop.campaign(FRAME, UNCERTAIN, 0)
    bad = tmp_path / "bad_uncertain.toml"
    bad.write_text('[[parameter]]\npath = "element.*.nothing"\ndistribution = "normal"\n'
                   'relative_sd = 0.05\n')
    with pytest.raises(flexloop.InputError, match=r"bad_uncertain\.toml:1:") as e:
        flexloop.campaign(FRAME, str(bad), 4)
    assert_cli_says(["campaign", FRAME, "-u", str(bad), "-n", "4", "--out-dir",
                     str(tmp_path / "c")], e.value)
