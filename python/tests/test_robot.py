"""The robot and its transmission, mirrored from the core: equal to the command line's
`codesign dynamics` at random states, and G at a design and a pose."""

import json
import subprocess

import numpy as np
import pytest

import codesign as cd
from conftest import ROOT, codesign_binary


def dynamics_cli(q, v, a):
    """`codesign dynamics` of the built-in task's robot at (q, v, a)."""
    text = lambda x: ",".join(repr(float(value)) for value in x)
    out = subprocess.run(
        [str(codesign_binary()), "dynamics", "--q", text(q), "--v", text(v), "--a", text(a)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out)


def test_rnea_mass_matrix_and_tcp_equal_the_command_line_at_random_states():
    robot = cd.Task.builtin().robot()
    assert robot.dof == 4 and robot.joint_names[0] == "joint_arm_1"
    rng = np.random.default_rng(7)
    for _ in range(5):
        q, v, a = (rng.uniform(-1.5, 1.5, 4) for _ in range(3))
        expected = dynamics_cli(q, v, a)
        assert np.allclose(robot.rnea(q, v, a), expected["tau"], rtol=0, atol=1e-12)
        assert np.allclose(robot.mass_matrix(q), expected["mass_matrix"], rtol=0, atol=1e-12)
        position, jacobian = robot.tcp(q)
        assert np.allclose(position, expected["tcp_position"], rtol=0, atol=1e-12)
        assert np.allclose(jacobian, expected["tcp_jacobian"], rtol=0, atol=1e-12)


def test_a_robot_from_a_urdf_alone_and_its_errors():
    robot = cd.Robot.from_urdf(ROOT / "robots" / "belt_arm.urdf")
    assert robot.position_limits.shape == (4, 2)
    tau = robot.rnea(np.zeros(4), np.zeros(4), np.zeros(4))
    assert np.all(np.isfinite(tau))
    with pytest.raises(cd.InputError, match="q: 3 values for a robot of 4 joints"):
        robot.mass_matrix([0.0, 0.0, 0.0])
    with pytest.raises(cd.InputError, match=r"v\[1\]"):
        robot.rnea(np.zeros(4), [0.0, float("nan"), 0.0, 0.0], np.zeros(4))


def test_the_transmission_gives_g_at_a_design_and_a_pose():
    transmission = cd.Task.builtin().transmission
    assert list(transmission.original) == [6.0, 3.0, 1.0, 1.0]
    g = transmission.matrix([6.0, 3.0, 1.0, 1.0])
    expected = [[6, 0, 0, 0], [3, 3, 0, 0], [1, 1, 1, 1], [1, 1, 1, -1]]
    assert np.array_equal(g, np.array(expected, dtype=float))
    with pytest.raises(cd.InputError, match="ratios"):
        transmission.matrix([2.0, 3.0, 1.0, 1.0])


def test_enums_stand_for_their_names():
    task = cd.Task.load(ROOT / "robots" / "examples" / "planar_2dof" / "task.json")
    by_name = task.solve(space="actuation", payload=0.5, steps=10)
    by_enum = task.solve(space=cd.Space.ACTUATION, payload=0.5, steps=10, ends=cd.Ends.HOLD)
    by_text = task.solve(space="actuation", payload=0.5, steps=10, ends="hold")
    assert by_enum.cost == by_text.cost
    assert str(cd.Space.JOINT) == "joint" and cd.Method.GRADIENT == "gradient"
    assert by_name.feasible == by_enum.feasible
