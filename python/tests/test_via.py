"""Via points, an upright link and a TCP goal (``motion.via``, ``motion.upright``,
``motion.goal``) from Python: typed sections and plain dicts give one task, ``check`` refuses a TCP
via point or goal out of reach naming its field, and a solve passes a reachable one within its
tolerance."""

import math

import pytest

import codesign as cd
from codesign import sections as s

THROUGH = s.ViaTcp(t_s=0.4, tcp=(0.0, -0.7, -0.1), tol_m=0.01)


def test_typed_via_points_are_the_task_file_s_and_a_solve_passes_through_them():
    task = cd.Task.builtin()
    typed = task.with_changes(motion={"via": [THROUGH]})
    plain = task.with_changes(
        motion={"via": [{"t_s": 0.4, "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01}]}
    )
    assert typed.to_dict()["motion"]["via"] == plain.to_dict()["motion"]["via"]
    assert typed.check().ok
    sol = typed.solve(payload=1.0, steps=20)
    assert sol.feasible
    node = sol.to_dict()["trajectory"]
    at = [node[axis][10] for axis in ("tcp_x", "tcp_y", "tcp_z")]
    assert math.dist(at, THROUGH.tcp) <= THROUGH.tol_m + 1e-6
    assert sol.to_dict()["violations"]["via_tcp"] <= 1e-6
    # Without it the TCP passes elsewhere at that node. (Its J is no bound on the constrained
    # one: each is a local optimum of a non-convex problem, and with the via point IPOPT lands
    # on a lower one here.)
    free = task.solve(payload=1.0, steps=20).to_dict()["trajectory"]
    elsewhere = [free[axis][10] for axis in ("tcp_x", "tcp_y", "tcp_z")]
    assert math.dist(elsewhere, THROUGH.tcp) > 10 * THROUGH.tol_m


def test_check_refuses_a_via_point_out_of_reach_and_an_unknown_upright_link():
    far = s.ViaTcp(t_s=0.4, tcp=(0.0, 1.5, 0.0), tol_m=0.01)
    upright = s.Upright(link="no_such_link", axis=(0.0, 0.0, 1.0), tol_rad=0.5)
    report = cd.Task.builtin().with_changes(motion={"via": [far], "upright": upright}).check()
    assert not report.ok
    problems = " ".join(report.problems)
    assert "motion.via[0].tcp lies" in problems
    assert "motion.upright.link: 'no_such_link'" in problems


def test_a_via_point_of_neither_kind_is_refused_naming_its_field():
    with pytest.raises(cd.InputError, match=r"motion.via\[0\]"):
        cd.Task.builtin().with_changes(motion={"via": [{"t_s": 0.4, "q": [0, 0, 0, 0]}]})


def test_a_via_point_within_a_window_is_passed_at_a_time_the_solve_chooses():
    within = s.ViaTcp(t_s=None, tcp=THROUGH.tcp, tol_m=0.01, window_s=(0.3, 0.5))
    task = cd.Task.builtin().with_changes(motion={"via": [within]})
    assert task.to_dict()["motion"]["via"] == [
        {"window_s": [0.3, 0.5], "tcp": [0.0, -0.7, -0.1], "tol_m": 0.01}
    ]
    sol = task.solve(payload=1.0, steps=20)
    assert sol.feasible
    (t,) = sol.via_times_s
    assert 0.3 <= t <= 0.5
    assert sol.to_dict()["trajectory"]["time"][10] == t
    overlapping = [within, s.ViaTcp(t_s=0.45, tcp=(0.0, -0.6, 0.0), tol_m=0.01)]
    report = cd.Task.builtin().with_changes(motion={"via": overlapping}).check()
    assert "motion.via[1].t_s = 0.45 must begin after motion.via[0] ends" in " ".join(
        report.problems
    )


def test_a_tcp_goal_ends_the_motion_inside_its_ball_and_check_flags_one_out_of_reach():
    task = cd.Task.builtin()
    goal = s.TcpGoal(tcp=(0.0, -0.25, 0.15), tol_m=0.005)
    typed = task.with_changes(motion={"goal": goal})
    plain = task.with_changes(motion={"goal": {"tcp": [0.0, -0.25, 0.15], "tol_m": 0.005}})
    assert typed.to_dict()["motion"]["goal"] == plain.to_dict()["motion"]["goal"]
    checked = typed.check()
    assert checked.ok and not any("motion.goal" in w for w in checked.warnings)
    sol = typed.solve(payload=1.0, steps=20)
    assert sol.feasible, sol.reason
    node = sol.to_dict()["trajectory"]
    end = [node[axis][-1] for axis in ("tcp_x", "tcp_y", "tcp_z")]
    assert math.dist(end, goal.tcp) <= goal.tol_m + 1e-6
    assert sol.goal_pose == pytest.approx(sol.q[-1])
    far = task.with_changes(motion={"goal": s.TcpGoal(tcp=(0.0, 1.5, 0.0), tol_m=0.01)})
    report = far.check()
    assert not report.ok
    assert any("motion.goal.tcp" in problem and "reach" in problem for problem in report.problems)
