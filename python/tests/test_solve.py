"""Tasks, checks, solves and capacities from Python, against the command line's documents."""

import json
import subprocess
import threading

import numpy as np
import pytest

import codesign as cd
from conftest import PLANAR, ROOT


def without_times(document):
    """A document without its wall times, which no two runs share."""
    document = dict(document)
    document.pop("solve_seconds", None)
    return document


def test_versions_are_this_build():
    assert cd.__version__ == "0.1.0"
    assert cd.IPOPT_VERSION.startswith("3.")


def test_tasks_load_from_files_and_the_built_in_one(planar):
    assert planar.label == str(PLANAR)
    assert planar.to_dict()["transmission"]["original"] == [50.0, 12.0]
    built_in = cd.Task.builtin()
    assert built_in.label == "built-in"
    assert built_in.to_dict()["robot"] is None
    assert json.loads(built_in.to_json()) == built_in.to_dict()


def test_a_missing_or_broken_task_file_is_an_input_error(tmp_path):
    with pytest.raises(cd.InputError, match="missing.json"):
        cd.Task.load(tmp_path / "missing.json")
    broken = tmp_path / "broken.json"
    broken.write_text('{"motion": ')
    with pytest.raises(ValueError, match="broken.json"):
        cd.Task.load(broken)


def test_changes_are_checked_as_a_file_is(planar):
    heavier = planar.with_changes(payload=2.0, motors={"torque_limit_nm": 0.8})
    assert heavier.to_dict()["payload"]["mass_kg"] == 2.0
    assert heavier.to_dict()["motors"]["torque_limit_nm"] == 0.8
    assert heavier.to_dict()["motors"]["speed_limit_rad_s"] == planar.to_dict()["motors"][
        "speed_limit_rad_s"
    ]
    assert "with motors, payload changed" in heavier.label
    with pytest.raises(cd.InputError, match="motion.steps"):
        planar.with_changes(motion={"steps": "ten"})
    with pytest.raises(cd.InputError, match="unknown field"):
        planar.with_changes(motor={"torque_limit_nm": 1.0})
    # The original is untouched.
    assert planar.to_dict()["motors"]["torque_limit_nm"] != 0.8


def test_check_reports_what_the_command_line_prints(planar, binary):
    report = planar.check(payload=1.0)
    assert report.ok and report.problems == []
    printed = subprocess.run(
        [binary, "check", "--task", PLANAR, "--payload", "1"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert report.text.strip() == printed.strip()
    overloaded = planar.check(payload=200.0)
    assert not overloaded.ok and overloaded.problems


def test_check_reports_the_problems_and_warnings_of_the_command_line(tmp_path, binary):
    """Python's check and ``codesign check --json`` list the same errors and warnings, the
    linkages' readings and the limit modes among them (issue 57, items 13 and 14): a four-bar
    whose loop opens within the joint limits (warnings: exit 0), one whose loop does not close
    at the start (an error), and one under the box modes a solve refuses."""
    example = ROOT / "robots" / "examples" / "planar_2dof"
    four_bar = cd.Task.load(example / "four_bar.json")
    matrix = four_bar.to_dict()["transmission"]["matrix"]
    short_rod = [matrix[0], {"crank_rod": dict(matrix[1]["crank_rod"], rod_m=0.15)}]
    cases = {
        "opens": four_bar.with_changes(
            transmission={"matrix": short_rod}, motion={"start": [0.1515, 0.5]}
        ),
        "open_at_start": four_bar.with_changes(transmission={"matrix": short_rod}),
        "paper": four_bar.with_changes(limit_modes={"torque": "paper", "speed": "paper"}),
    }
    for name, task in cases.items():
        report = task.check()
        document = dict(task.to_dict(), robot=str(example / "robot.urdf"))
        path = tmp_path / f"{name}.json"
        path.write_text(json.dumps(document))
        printed = subprocess.run(
            [binary, "check", "--task", path, "--json"], capture_output=True, text=True
        )
        found = json.loads(printed.stdout)
        assert report.problems == found["problems"], name
        assert report.warnings == found["warnings"], name
        assert printed.returncode == (0 if report.ok else 1), name
        assert report.to_dict()["linkages"] == found["linkages"], name
    assert cases["opens"].check().ok
    assert any("the loop does not close at" in w for w in cases["opens"].check().warnings)
    assert "design: at the start" in cases["open_at_start"].check().problems[0]
    assert 'limit_modes.torque = "paper" and limit_modes.speed = "paper"' in (
        cases["paper"].check().problems[0]
    )


def test_a_long_design_is_echoed_in_a_short_message(planar):
    """A design of a million ratios is refused naming its length, not echoing every value
    (issue 57, item 21)."""
    with pytest.raises(cd.InputError) as refused:
        planar.solve(payload=1.0, ratios=[50] * 10**6)
    message = str(refused.value)
    assert "... (1000000 values): invalid design: the design has 1000000 ratios" in message
    assert len(message) < 500, len(message)


def test_a_solve_gives_arrays_of_documented_shapes(planar):
    sol = planar.solve(space="actuation", payload=1.0, ratios=[50, 12])
    steps = planar.to_dict()["motion"]["steps"]
    assert sol.feasible and sol.reason is None
    assert sol.t.shape == (steps + 1,)
    for nodes in (sol.q, sol.v, sol.motor_speed):
        assert nodes.shape == (steps + 1, 2)
    for intervals in (sol.a, sol.tau, sol.tau_u):
        assert intervals.shape == (steps, 2)
    assert sol.tcp.shape == (steps + 1, 3)
    assert sol.cost_gradient.shape == (2,)
    assert sol.cost == pytest.approx(sum(sol.cost_terms.values()))
    document = sol.to_dict()
    assert document["version"] == 2 and document["reason"] is None
    motors = document["motors_execute"]
    limits = planar.to_dict()["motors"]
    np.testing.assert_allclose(motors["torque_peak_nm"], np.abs(sol.tau_u).max(axis=0))
    np.testing.assert_allclose(motors["speed_peak_rad_s"], np.abs(sol.motor_speed).max(axis=0))
    np.testing.assert_allclose(
        motors["torque_margin_nm"],
        limits["torque_limit_nm"] - np.asarray(motors["torque_peak_nm"]),
    )
    # The task's G(r) = [[r1, 0], [r2, 2 r2]]: motor speeds are G v at every node.
    G = np.array([[50.0, 0.0], [12.0, 24.0]])
    np.testing.assert_allclose(sol.motor_speed, sol.v @ G.T, rtol=1e-12, atol=1e-12)
    assert sol.motor_position is None and sol.ratio is None


def test_a_ball_screws_motor_follows_its_geometry():
    screw = cd.Task.load(ROOT / "robots" / "examples" / "planar_2dof" / "ball_screw.json")
    sol = screw.solve(space="actuation", ratios=[50, 12])
    assert sol.feasible
    steps = screw.to_dict()["motion"]["steps"]
    assert sol.motor_position.shape == (steps + 1, 2)
    assert sol.ratio.shape == (steps + 1, 2, 2)
    # The screw's length from the planar arm's geometry (robots/README.md): L^2 = 0.0325 -
    # 0.03 sin q; its motor turns 2 pi per 12 mm of it.
    elbow = sol.q[:, 1]
    length = np.sqrt(0.0325 - 0.03 * np.sin(elbow))
    np.testing.assert_allclose(sol.motor_position[:, 1], 2 * np.pi * length / 0.012, rtol=1e-12)
    ratio = -2 * np.pi / 0.012 * 0.015 * np.cos(elbow) / length
    np.testing.assert_allclose(sol.ratio[:, 1, 1], ratio, rtol=1e-9)
    np.testing.assert_allclose(sol.ratio[:, 1, 0], 0.0, atol=0.0)
    # Motor speeds are G(q) v, node by node.
    speeds = np.einsum("kij,kj->ki", sol.ratio, sol.v)
    np.testing.assert_allclose(sol.motor_speed, speeds, rtol=1e-12, atol=1e-12)


def test_a_solve_is_the_command_lines_to_the_last_bit(planar, binary, tmp_path):
    out = tmp_path / "solve.json"
    subprocess.run(
        [binary, "solve", "--task", PLANAR, "--payload", "1", "--ratios", "50,12", "--out", out],
        check=True,
        capture_output=True,
    )
    cli = json.loads(out.read_text())
    python = planar.solve(space="actuation", payload=1.0, ratios=[50, 12]).to_dict()
    assert without_times(python) == without_times(cli)


def test_an_infeasible_design_says_why_and_has_no_gradient(planar):
    weak = planar.with_changes(motors={"torque_limit_nm": 0.05})
    sol = weak.solve(payload=1.0, ratios=[50, 12])
    assert not sol.feasible
    assert isinstance(sol.reason, str) and sol.reason
    assert sol.cost_gradient is None


def test_a_warm_start_continues_to_a_nearby_payload(planar):
    first = planar.solve(payload=1.0, ratios=[50, 12])
    warm = planar.solve(payload=1.2, ratios=[50, 12], start=first)
    cold = planar.solve(payload=1.2, ratios=[50, 12])
    assert warm.feasible and cold.feasible
    assert warm.iterations < cold.iterations
    assert warm.cost == pytest.approx(cold.cost, rel=1e-6)


def test_a_start_that_does_not_fit_is_refused(planar):
    actuation = planar.solve(payload=1.0, ratios=[50, 12])
    with pytest.raises(cd.InputError, match="joint space"):
        planar.solve(space="joint", payload=1.0, ratios=[50, 12], start=actuation)
    with pytest.raises(cd.InputError, match="another task"):
        planar.with_changes(weights={"control": 0.5}).solve(payload=1.0, start=actuation)
    with pytest.raises(cd.InputError, match="elastic"):
        planar.solve(payload=1.0, elastic=True, start=actuation)


def test_bad_keywords_name_themselves(planar):
    with pytest.raises(cd.InputError, match="space=.*joint, actuation"):
        planar.solve(space="motor")
    with pytest.raises(cd.InputError, match="payload=-1"):
        planar.solve(payload=-1.0)
    with pytest.raises(cd.InputError, match="ratios="):
        planar.solve(ratios=[500, 12])
    with pytest.raises(cd.InputError, match="steps=0"):
        planar.solve(steps=0)
    with pytest.raises(cd.InputError, match="ends="):
        planar.solve(ends="stop")


def test_solves_in_threads_agree_with_solves_in_turn(planar):
    designs = [[50, 12], [40, 10], [60, 14], [45, 20]]
    alone = [planar.solve(payload=1.0, ratios=r).to_dict() for r in designs]
    together = [None] * len(designs)

    def solve(index):
        together[index] = planar.solve(payload=1.0, ratios=designs[index]).to_dict()

    threads = [threading.Thread(target=solve, args=(i,)) for i in range(len(designs))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert [without_times(d) for d in together] == [without_times(d) for d in alone]


def test_capacity_brackets_the_payload(planar):
    cap = planar.capacity(ratios=[50, 12], resolution=0.05)
    assert cap.capacity_kg > 0
    assert cap.first_infeasible_kg - cap.capacity_kg <= 0.05 + 1e-12
    assert cap.limited_by in ("trajectory", "hold", "search")
    assert cap.to_dict()["schema"] == "codesign/capacity"
    assert cap.ratios.tolist() == [50.0, 12.0]
    assert cap.to_dict()["inputs"]["task_file"] == str(PLANAR)
    with pytest.raises(cd.InputError, match="resolution"):
        planar.capacity(resolution=-1.0)
    slow = planar.capacity(ratios=[50, 12], resolution=0.2, duration=2.0)
    assert slow.to_dict()["inputs"]["duration_s"] == 2.0
    assert "duration_s" not in cap.to_dict()["inputs"]
    with pytest.raises(cd.InputError, match="duration"):
        planar.capacity(duration=0.0)


def test_a_tradeoff_is_the_capacity_within_each_duration(planar, tmp_path):
    out = tmp_path / "tradeoff.json"
    data = planar.tradeoff([1.0, 2.0], ratios=[50, 12], resolution=0.2, out=out)
    assert data["schema"] == "codesign/tradeoff" and data["version"] == 1
    assert data["inputs"]["durations_s"] == [1.0, 2.0]
    assert json.loads(out.read_text()) == data
    assert "<svg" in (tmp_path / "tradeoff.svg").read_text()
    alone = planar.capacity(ratios=[50, 12], resolution=0.2, duration=2.0)
    assert [p["duration_s"] for p in data["points"]] == [1.0, 2.0]
    assert data["points"][1]["capacity_kg"] == alone.capacity_kg
    with pytest.raises(cd.InputError, match="durations"):
        planar.tradeoff([])


def test_a_time_curve_is_the_minimum_time_solve_at_each_payload(planar, tmp_path):
    """T* against payload (``tradeoff(payloads=)``): each point is the pure minimum-time solve
    at its payload, T* does not fall as the payload grows, and the compared design has its own
    curve."""
    out = tmp_path / "curve.json"
    data = planar.tradeoff(payloads=[0.0, 0.5], ratios=[50, 12], compare=[[60, 10]], out=out)
    assert data["schema"] == "codesign/time_curve" and data["version"] == 1
    assert json.loads(out.read_text()) == data
    assert "<svg" in (tmp_path / "curve.svg").read_text()
    assert [c["ratios"] for c in data["curves"]] == [[50.0, 12.0], [60.0, 10.0]]
    lo, hi = data["inputs"]["horizon_s"]["free"]
    no_box = {axis: None for axis in planar.to_dict()["cartesian_box"]}
    fastest = planar.with_changes(
        weights={"position": 0, "velocity": 0, "control": 0, "time": 1}, cartesian_box=no_box)
    times = [p["minimum_time_s"] for p in data["curves"][0]["points"]]
    assert times == sorted(times) and None not in times
    for point in data["curves"][0]["points"]:
        sol = fastest.solve(payload=point["payload_kg"], ratios=[50, 12], duration=(lo, hi))
        assert sol.feasible
        assert point["minimum_time_s"] == pytest.approx(sol.to_dict()["horizon_s"], rel=1e-9)
    with pytest.raises(cd.InputError, match="payloads"):
        planar.tradeoff(payloads=[1.0, 0.5])
    with pytest.raises(cd.InputError, match="durations= and payloads="):
        planar.tradeoff([1.0], payloads=[0.5])


def test_the_built_in_task_solves_in_both_spaces():
    task = cd.Task.builtin()
    for space in ("joint", "actuation"):
        sol = task.solve(space=space, payload=0.0, steps=20)
        assert sol.space == space and sol.q.shape == (21, 4)
        assert ROOT.exists()


def test_physical_figures_match_a_hand_computation(planar):
    """Controls constant over each interval, speeds at the nodes: power is linear in each."""
    sol = planar.solve(payload=1.0, ratios=[50, 12])
    h = np.diff(sol.t)
    tau, w = sol.tau_u, sol.motor_speed
    figures = sol.figures
    for i, motor in enumerate(figures["motors"]):
        p0, p1 = tau[:, i] * w[:-1, i], tau[:, i] * w[1:, i]
        assert motor["torque_squared_integral"] == pytest.approx(np.sum(h * tau[:, i] ** 2))
        assert motor["rms_torque_nm"] == pytest.approx(
            np.sqrt(np.sum(h * tau[:, i] ** 2) / (sol.t[-1] - sol.t[0])))
        assert motor["peak_torque_nm"] == pytest.approx(np.abs(tau[:, i]).max())
        assert motor["peak_speed_rad_s"] == pytest.approx(np.abs(w[:, i]).max())
        assert motor["peak_power_w"] == pytest.approx(np.maximum(abs(p0), abs(p1)).max())
        assert motor["work_j"] == pytest.approx(np.sum(h * (p0 + p1) / 2))
        fine = np.linspace(0, 1, 2001)

        def positive(a, b, step):
            """int max(p, 0) dt by the trapezoid rule on a fine grid of the interval."""
            p = np.maximum(a + (b - a) * fine, 0.0)
            return np.sum((p[1:] + p[:-1]) / 2) * step / (len(fine) - 1)

        driving = sum(positive(a, b, step) for a, b, step in zip(p0, p1, h))
        assert motor["positive_work_j"] == pytest.approx(driving, rel=1e-4)
    assert figures["work_j"] == pytest.approx(sum(m["work_j"] for m in figures["motors"]))


def test_a_free_duration_is_the_command_lines_free_horizon(binary, tmp_path):
    """duration=(T_min, T_max) frees T as the task file's {"free": [T_min, T_max]} does: the
    same optimum to the bit, with the chosen T as horizon_s (issue 52)."""
    document = json.loads((ROOT / "robots" / "tasks" / "pick_place.json").read_text())
    document["robot"] = str(ROOT / "robots" / "belt_arm.urdf")
    document["weights"] = {"position": 0, "velocity": 0, "control": 0, "time": 1}
    document["cartesian_box"] = {}
    fixed, free, out = tmp_path / "fixed.json", tmp_path / "free.json", tmp_path / "out.json"
    fixed.write_text(json.dumps(document))
    document["motion"]["horizon_s"] = {"free": [0.3, 1.2]}
    free.write_text(json.dumps(document))
    python = cd.Task.load(fixed).solve(duration=(0.3, 1.2)).to_dict()
    assert python["feasible"] and python["horizon_s"] == python["cost"] < 0.8
    subprocess.run([binary, "solve", "--task", free, "--out", out], check=True, capture_output=True)
    cli = json.loads(out.read_text())
    for key in ["cost", "horizon_s", "cost_terms", "trajectory", "cost_gradient"]:
        assert python[key] == cli[key], key
    assert python["inputs"]["task"] == cli["inputs"]["task"]
    for bad, words in [((1.2, 0.3), "T_min must be below T_max"), ((0.3,), "a pair")]:
        with pytest.raises(cd.InputError, match=words):
            cd.Task.load(fixed).solve(duration=bad)


def test_the_minimum_time_problem_is_the_command_lines(binary, tmp_path):
    """minimum_time=True solves the task's pure minimum-time problem as `solve --minimum-time`
    does, to the bit; free_horizon="descend" shortens it (issue 52), and a search of another
    name is refused naming the keyword."""
    task = cd.Task.builtin()
    out = tmp_path / "out.json"
    for search in ["local", "descend"]:
        python = task.solve(steps=10, minimum_time=True, free_horizon=search).to_dict()
        assert python["feasible"] and python["horizon_s"] == python["cost"]
        subprocess.run(
            [binary, "solve", "--steps", "10", "--minimum-time", "--free-horizon", search,
             "--out", out],
            check=True,
            capture_output=True,
        )
        cli = json.loads(out.read_text())
        for key in ["cost", "horizon_s", "trajectory", "cost_gradient", "iterations"]:
            assert python[key] == cli[key], (search, key)
        if search == "local":
            local = python["cost"]
    assert python["cost"] <= local
    with pytest.raises(cd.InputError, match="free_horizon="):
        task.solve(steps=10, minimum_time=True, free_horizon="shortest")
