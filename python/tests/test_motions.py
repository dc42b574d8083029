"""Several motions per design: a task with a ``motions`` list written from typed sections, each
motion solved by name, and a co-design run listing each motion's cost."""

import pytest

import codesign as cd
from codesign import sections as s

from conftest import PLANAR, ROOT

THREE_PICKS = ROOT / "robots" / "examples" / "planar_2dof" / "three_picks.json"


def planar_with_motions(**changes) -> cd.Task:
    """The planar example written from sections, with a low and a high pick."""
    planar = cd.Task.load(PLANAR).to_dict()
    tool = s.PointOnLink("gripper", (0.05, 0.0, 0.0))
    parts = dict(
        robot=str(PLANAR.parent / "robot.urdf"),
        tcp=tool,
        payload=s.Payload(0.0, tool),
        motion=s.Motion(**planar["motion"]),
        motors=s.Motors(torque_limit_nm=0.6, speed_limit_rad_s=250.0),
        transmission=s.TransmissionSpec(**planar["transmission"]),
        weights=s.Weights(**planar["weights"]),
        limit_modes=s.LimitModes("exact", "exact"),
        motions=[
            s.MotionEntry("low", weight=2.0),
            s.MotionEntry("high", start=[1.3918, -1.543], payload_kg=0.2, steps=20),
        ],
        motions_score=s.MotionsScore.WORST,
    )
    parts.update(changes)
    return cd.Task.from_sections(**parts)


def test_a_task_from_sections_solves_each_motion_by_name():
    task = planar_with_motions()
    assert task.motions == ["low", "high"]
    assert task.to_dict()["motions_score"] == "worst"
    assert task.to_dict()["motions"][0] == {"name": "low", "weight": 2.0}
    high = task.solve(motion="high")
    assert high.feasible
    inputs = high.to_dict()["inputs"]["task"]
    assert inputs["payload"]["mass_kg"] == 0.2 and inputs["motion"]["steps"] == 20
    with pytest.raises(cd.InputError, match=r"motion=: the task lists 2 motions \(low, high\)"):
        task.solve()
    with pytest.raises(cd.InputError, match="motion=top: the task has no motion of that name"):
        task.solve(motion="top")
    with pytest.raises(cd.InputError, match="motion=low: the task has no `motions` list"):
        cd.Task.load(PLANAR).solve(motion="low")
    with pytest.raises(cd.InputError, match="heaviest payload of one motion"):
        task.capacity()


def test_a_bad_motions_list_is_refused_naming_its_field():
    with pytest.raises(cd.InputError, match=r"motions\[1\].name"):
        planar_with_motions(motions=[s.MotionEntry("a"), s.MotionEntry("a")])
    with pytest.raises(cd.InputError, match=r"motions\[0\].weight = -1"):
        planar_with_motions(motions=[s.MotionEntry("a", weight=-1.0)])


def test_a_run_lists_each_motions_cost(tmp_path):
    task = cd.Task.load(THREE_PICKS)
    run = task.optimize(
        method="gradient", gradient_iterations=1, out=str(tmp_path / "run.json")
    )
    costs = run.motion_costs
    assert costs["score"] == "sum"
    assert [c["name"] for c in costs["original"]] == ["low", "middle", "high"]
    single = task.solve(motion="middle")
    assert costs["original"][1]["cost"] == single.cost
    weighted = sum(c["weight"] * c["cost"] for c in costs["best"])
    assert run.best_cost == pytest.approx(weighted, rel=1e-6)
    assert run.best_cost < sum(c["weight"] * c["cost"] for c in costs["original"])
