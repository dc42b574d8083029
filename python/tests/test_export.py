"""``Solution.resample``: the command line's ``solve --export`` from Python, to the last bit."""

import csv
import subprocess

import numpy as np
import pytest

import codesign as cd
from conftest import ROOT

SCREW = ROOT / "robots" / "examples" / "planar_2dof" / "ball_screw.json"


def read_csv(path):
    """The CSV's columns by name, as floats, in the header's order."""
    with open(path, newline="") as file:
        rows = list(csv.reader(file))
    names, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(names)}


def test_resample_is_the_command_lines_export(binary, tmp_path):
    out = tmp_path / "t.csv"
    subprocess.run(
        [binary, "solve", "--task", SCREW, "--ratios", "50,12", "--export", out, "--rate", "1000"],
        check=True,
        capture_output=True,
    )
    cli = read_csv(out)
    sol = cd.Task.load(SCREW).solve(space="actuation", ratios=[50, 12])
    python = sol.resample(1000)
    assert list(python) == list(cli)
    for name, column in cli.items():
        assert np.array_equal(python[name], column), name


def test_the_resampled_nodes_are_the_solutions():
    sol = cd.Task.load(SCREW).solve(space="actuation", ratios=[50, 12])
    table = sol.resample(1000)
    rows = np.searchsorted(table["time_s"], sol.t - 1e-9)
    assert np.allclose(table["time_s"][rows], sol.t, rtol=0.0, atol=1e-12)
    held = np.minimum(np.arange(len(sol.t)), len(sol.t) - 2)
    for j, joint in enumerate(sol.joint_names):
        np.testing.assert_allclose(table[f"q_{joint}_rad"][rows], sol.q[:, j], atol=1e-12, rtol=0)
        np.testing.assert_allclose(table[f"v_{joint}_rad_s"][rows], sol.v[:, j], atol=1e-12, rtol=0)
        accelerations = table[f"a_{joint}_rad_s2"][rows]
        np.testing.assert_allclose(accelerations, sol.a[held, j], atol=1e-12, rtol=0)
    for i, motor in enumerate(name.replace(" ", "_") for name in sol.motor_names):
        np.testing.assert_allclose(
            table[f"q_u_{motor}_rad"][rows], sol.motor_position[:, i], atol=1e-12, rtol=0
        )
        np.testing.assert_allclose(
            table[f"v_u_{motor}_rad_s"][rows], sol.motor_speed[:, i], atol=1e-12, rtol=0
        )
        np.testing.assert_allclose(
            table[f"tau_u_{motor}_Nm"][rows], sol.tau_u[held, i], atol=1e-12, rtol=0
        )


def test_currents_where_the_task_gives_torque_constants():
    task = cd.Task.load(SCREW).with_changes(
        motors={"torque_constant_nm_per_a": [0.1, 0.05], "resistance_ohm": 1.0}
    )
    table = task.solve(space="actuation", ratios=[50, 12]).resample(200)
    np.testing.assert_array_equal(table["i_u_motor_1_A"], table["tau_u_motor_1_Nm"] / 0.1)
    np.testing.assert_array_equal(table["i_u_motor_2_A"], table["tau_u_motor_2_Nm"] / 0.05)
    assert "i_u_motor_1_A" not in cd.Task.load(SCREW).solve(ratios=[50, 12]).resample(200)


def test_bad_rates_and_a_runs_best_are_refused():
    sol = cd.Task.load(SCREW).solve(space="actuation", ratios=[50, 12])
    for rate in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(cd.InputError, match="rate="):
            sol.resample(rate)
    with pytest.raises(cd.InputError, match="200000"):
        sol.resample(1e9)
    path = ROOT / "results" / "runs" / "actuation-1kg-seed0.json"
    best = cd.Run(path.read_text(), str(path), None).best
    with pytest.raises(cd.InputError, match="solve its design first"):
        best.resample(100)
