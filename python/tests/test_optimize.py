"""Co-design runs from Python: results, logs, resumption, progress and Ctrl-C."""

import json
import signal
import subprocess
import sys
import time

import pytest

import codesign as cd
from conftest import PLANAR

SMALL = dict(space="actuation", payload=1.0, population=8, generations=2, seed=0, workers=2)


def test_a_cmaes_run_writes_its_result_and_log_and_resumes(planar, tmp_path):
    log = tmp_path / "run.log.jsonl"
    seen = []
    run = planar.optimize(**SMALL, log=log, progress=lambda *p: seen.append(p))
    assert run.result_file == str(tmp_path / "run.json")
    assert json.loads((tmp_path / "run.json").read_text()) == run.to_dict()
    assert len(run.best_ratios) == 2 and run.best_cost < 1e6
    assert len(run.costs) == 8 * 3
    assert [done for done, _, _ in seen] == list(range(1, 25))
    assert all(total == 24 for _, total, _ in seen)
    again = planar.optimize(**SMALL, log=log, resume=True, progress=False)
    assert again.to_dict()["replayed"] == 24
    assert again.best_cost == run.best_cost
    with pytest.raises(cd.InputError, match="exists already"):
        planar.optimize(**SMALL, log=log, progress=False)


def test_a_run_without_files_and_the_gradient_method(planar):
    run = planar.optimize(**SMALL, progress=False)
    assert run.result_file == "" and run.log_file is None
    gradient = planar.optimize(space="actuation", payload=1.0, method="gradient",
                               gradient_iterations=3)
    assert gradient.best_cost < 1e6


def test_a_runs_best_design_is_a_solution_with_named_columns(planar):
    run = planar.optimize(**SMALL, progress=False)
    best = run.best
    assert isinstance(best, cd.Solution)
    assert best.cost == run.best_cost and list(best.ratios) == list(run.best_ratios)
    assert best.to_dict()["trajectory"] == run.best_result["trajectory"]
    assert best.joint_names == run.best_result["joints"] and len(best.motor_names) == 2
    assert best.q.shape[1] == len(best.joint_names)
    with pytest.raises(cd.InputError, match="keeps no point to start from"):
        planar.solve(space="actuation", payload=1.0, ratios=best.ratios, start=best)


def test_a_run_without_a_feasible_design_has_no_cost(planar):
    # Issue 57, item 8: no design of the planar arm holds 100 kg at rest.
    run = planar.optimize(space="actuation", payload=100.0, population=5, generations=0,
                          workers=1, progress=False)
    assert len(run.best_ratios) == 0
    assert run.best_cost is None and run.to_dict()["best_cost"] is None
    assert repr(run) == "<codesign.Run no feasible design>"


def test_run_settings_are_checked(planar, tmp_path):
    with pytest.raises(cd.InputError, match="method="):
        planar.optimize(method="annealing")
    with pytest.raises(cd.InputError, match="log="):
        planar.optimize(log=tmp_path / "run.txt")
    with pytest.raises(cd.InputError, match="choose one"):
        planar.optimize(**SMALL, log=tmp_path / "a.log.jsonl", resume=True, overwrite=True)
    # Worded with the keyword, not the command line's flag.
    with pytest.raises(cd.InputError, match="^population=1: must be 5 to"):
        planar.optimize(space="actuation", population=1, progress=False)
    with pytest.raises(cd.InputError, match="^sigma=-1: must be a positive number"):
        planar.optimize(space="actuation", sigma=-1.0, progress=False)
    # Issue 57, item 10: a step wider than the design box, up to samples that are no number.
    with pytest.raises(cd.InputError, match="^sigma=1e308: must be a positive number at most 1"):
        planar.optimize(space="actuation", sigma=1e308, progress=False)
    # Issue 57, item 20: a budget whose result `table` could not read (256 MiB).
    with pytest.raises(cd.InputError, match="^generations=30000: with population 10000 that is "
                       "300010000 evaluations"):
        planar.optimize(space="actuation", population=10000, generations=30000, progress=False)


def test_the_penalty_and_the_bounds_run_as_the_command_lines(planar, tmp_path, binary):
    # Python and the command line alike: --penalty graded --bounds map.
    run = planar.optimize(**SMALL, penalty="graded", bounds="map", out=tmp_path / "py.json",
                          progress=False)
    subprocess.run(
        [str(binary), "optimize", "--task", str(PLANAR), "--space", "actuation", "--payload",
         "1", "--population", "8", "--generations", "2", "--seed", "0", "--workers", "2",
         "--penalty", "graded", "--bounds", "map", "--out", str(tmp_path / "cli.json")],
        check=True, capture_output=True,
    )
    cli = json.loads((tmp_path / "cli.json").read_text())
    assert cli["inputs"]["grading"] == "graded" and cli["inputs"]["bounds"] == "map"
    assert run.to_dict()["inputs"] == cli["inputs"]
    assert list(run.best_ratios) == cli["best_ratios"] and run.best_cost == cli["best_cost"]
    with pytest.raises(cd.InputError, match='^penalty="steep": expected flat, graded or a'):
        planar.optimize(**SMALL, penalty="steep", progress=False)
    with pytest.raises(cd.InputError, match="^penalty=True: must be"):
        planar.optimize(**SMALL, penalty=True, progress=False)
    with pytest.raises(cd.InputError, match='^bounds="wrap": must be one of penalty, clip, map'):
        planar.optimize(**SMALL, bounds="wrap", progress=False)


def test_a_progress_callback_that_raises_stops_the_run(planar, tmp_path):
    def fail(done, total, best):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        planar.optimize(**SMALL, log=tmp_path / "r.log.jsonl", progress=fail)


# The child restores Python's own handler of INT: a shell without job control (a CI runner, a
# background job) starts its children with INT ignored, as no terminal can send it there.
RUN = """
import signal, sys, codesign as cd
signal.signal(signal.SIGINT, signal.default_int_handler)
task = cd.Task.load(sys.argv[1])
def progress(done, total, best):
    if done == 10:
        print("running", flush=True)
task.optimize(space="actuation", payload=1.0, population=8, generations=40, seed=1,
              workers=1, log=sys.argv[2], progress=progress)
print("finished", flush=True)
"""


def test_ctrl_c_stops_a_run_within_a_second_and_leaves_it_resumable(planar, tmp_path):
    log = tmp_path / "long.log.jsonl"
    child = subprocess.Popen(
        [sys.executable, "-c", RUN, str(PLANAR), str(log)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert child.stdout.readline().strip() == "running"
    child.send_signal(signal.SIGINT)
    sent = time.monotonic()
    child.wait(timeout=30)
    stopped = time.monotonic() - sent
    _, errors = child.communicate(timeout=30)
    assert stopped < 1.5, f"the run took {stopped:.1f} s to stop:\n{errors}"
    assert child.returncode != 0 and "KeyboardInterrupt" in errors
    kept = log.read_text().splitlines()
    assert len(kept) > 10
    run = planar.optimize(space="actuation", payload=1.0, population=8, generations=40, seed=1,
                          workers=1, log=log, resume=True, progress=False)
    assert run.to_dict()["replayed"] >= 10


def test_the_time_objective_shortens_the_motion(planar):
    task = planar.with_changes(motion={"steps": 20})
    run = task.optimize(space="actuation", payload=0.0, method="gradient", objective="time",
                        gradient_iterations=2)
    document = run.to_dict()
    assert document["inputs"]["objective"] == {"kind": "time"}
    assert run.best_cost <= document["original_cost"]
    assert run.best_result["cost"] == run.best_result["horizon_s"]
    with pytest.raises(cd.InputError, match='objective="speed"'):
        task.optimize(objective="speed")
