"""``Solution.plot()`` and ``Run.plot()``: the command line's charts drawn with matplotlib, which
is optional."""

import subprocess
import sys

import pytest

import codesign as cd
from conftest import ROOT

SCREW = ROOT / "robots" / "examples" / "planar_2dof" / "ball_screw.json"
RUN = ROOT / "results" / "runs" / "actuation-1kg-seed0.json"


def test_without_matplotlib_the_error_says_how_to_get_it(monkeypatch):
    sol = cd.Task.load(SCREW).solve(ratios=[50, 12])
    run = cd.Run(RUN.read_text(), str(RUN), None)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"Solution\.plot\(\).*pip install matplotlib"):
        sol.plot()
    with pytest.raises(ImportError, match=r"Run\.plot\(\).*pip install matplotlib"):
        run.plot()


def test_a_solution_draws_the_charts_of_solve_plot(binary, tmp_path):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    subprocess.run(
        [binary, "solve", "--task", SCREW, "--ratios", "50,12", "--plot", tmp_path],
        check=True,
        capture_output=True,
    )
    drawn = {path.stem for path in tmp_path.glob("*.svg")} - {"poses", "motion"}
    figures = cd.Task.load(SCREW).solve(ratios=[50, 12]).plot()
    assert set(figures) == drawn
    assert {"motor_1_torque_speed", "motor_2_torque_speed", "linkage_ratios"} <= drawn
    ratios = figures["linkage_ratios"].axes[0]
    assert [line.get_label() for line in ratios.get_lines()] == ["G[motor 2, elbow]"]
    torque_speed = figures["motor_2_torque_speed"].axes[0]
    legend = [text.get_text() for text in torque_speed.get_legend().get_texts()]
    assert any(text.startswith("speed limit") for text in legend), legend
    svg = (tmp_path / "motor_torques.svg").read_text()
    assert figures["motor_torques"].axes[0].get_title() in svg


def test_an_infeasible_solution_says_so_in_every_title():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    weak = cd.Task.load(SCREW).with_changes(motors={"torque_limit_nm": 0.05})
    sol = weak.solve(payload=1.0, ratios=[50, 12])
    assert not sol.feasible
    for name, figure in sol.plot().items():
        assert f"INFEASIBLE: {sol.reason}" in figure.axes[0].get_title(), name


def test_a_run_draws_its_cost_history():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    run = cd.Run(RUN.read_text(), str(RUN), None)
    ax = run.plot().axes[0]
    dots, best = ax.get_lines()[:2]
    feasible = [c for c in run.costs if 0 < c < 1e6]
    assert len(dots.get_xdata()) == len(feasible)
    assert min(best.get_ydata()) == pytest.approx(run.best_cost)
    assert ax.get_yscale() == "log"
    assert "actuation space, 1.0 kg" in ax.get_title()
