"""A task written in code from typed sections is the task read from JSON: the same hash, the
same solve."""

import math

import pytest

import codesign as cd
from codesign import sections as s
from conftest import ROOT


def built_in_from_sections(**changes) -> cd.Task:
    tool = s.PointOnLink("link_4", (0.0, 0.0, 0.15))
    parts = dict(
        robot=None,
        tcp=tool,
        payload=s.Payload(0.0, tool),
        motion=s.Motion(
            start=[0.0, 1.8849555921538759, 0.0, 0.0],
            goal=[-math.pi, -math.pi / 2, -math.pi / 2, 0.0],
            horizon_s=0.8,
            steps=50,
            ends=cd.Ends.PAPER,
        ),
        motors=s.Motors(torque_limit_nm=1.7, speed_limit_rad_s=100.0),
        transmission=s.TransmissionSpec(
            matrix=[["r1", 0, 0, 0], ["r2", "r2", 0, 0], [1, "r3", "r4", "r4"], [1, "r3", "r4", "-r4"]],
            original=[6.0, 3.0, 1.0, 1.0],
            bounds=[(1.0, 9.0), (1.0, 9.0), (1.0, 3.0), (1.0, 3.0)],
            order=["r3 <= r2", "r2 < r1"],
        ),
        cartesian_box=s.CartesianBox(
            y=s.SoftInterval((-1.0, 0.4), 1000.0), z=s.SoftInterval((-0.9, 0.6), 1000.0)
        ),
        limit_modes=s.LimitModes(cd.LimitMode.PAPER, cd.LimitMode.EXACT),
        solver={"tol": 1e-8, "max_iter": 3000, "options": {"mumps_pivot_order": 6}},
    )
    parts.update(changes)
    return cd.Task.from_sections(**parts)


def test_a_task_from_typed_sections_has_the_hash_of_the_same_task_read_from_json():
    typed = built_in_from_sections().solve(payload=1.0, steps=8)
    read = cd.Task.builtin().solve(payload=1.0, steps=8)
    assert typed.task_hash == read.task_hash
    assert typed.cost == read.cost


def test_a_section_out_of_range_is_refused_naming_its_field():
    with pytest.raises(cd.InputError, match="motors.torque_limit_nm"):
        built_in_from_sections(motors=s.Motors(torque_limit_nm=-1.0, speed_limit_rad_s=100.0))


def test_motors_chosen_from_a_catalogue_set_the_motor_figures():
    """The paper's ideal motor as a catalogue part is the built-in task: the same hash, the same
    solve; a field set against a part's value is refused naming both."""
    ideal = s.Part(str(ROOT / "tests" / "data" / "catalogue" / "ideal.json"), "ideal 1.7 N m")
    typed = built_in_from_sections(motors=s.Motors(parts=[ideal] * 4)).solve(payload=1.0, steps=8)
    read = cd.Task.builtin().solve(payload=1.0, steps=8)
    assert typed.task_hash == read.task_hash
    assert typed.cost == read.cost
    real = cd.Task.load(ROOT / "robots" / "tasks" / "pick_place_parts.json")
    with pytest.raises(cd.InputError, match=r"motors.torque_limit_nm = 1 conflicts with motors.parts\[0\]"):
        real.with_changes(motors={"torque_limit_nm": 1.0})


def test_carried_parts_pass_through_a_task_dict():
    """A task's ``carried`` parts read from its file, changed as a dict and given as sections:
    each solve records every part's mass at its design and the actuator mass, and the pulley's
    mass grows with the ratio its teeth follow."""
    path = ROOT / "robots" / "examples" / "planar_2dof" / "carried_pulley.json"
    task = cd.Task.load(path)
    document = task.to_dict()
    assert [part["link"] for part in document["carried"]] == ["upper_arm", "upper_arm"]
    small = task.solve(ratios=[50.0, 12.0], steps=8).to_dict()
    large = task.solve(ratios=[50.0, 24.0], steps=8).to_dict()
    assert [p["kind"] for p in small["carried"]] == ["pulley", "motor"]
    assert large["carried"][0]["mass_kg"] == pytest.approx(4 * small["carried"][0]["mass_kg"])
    assert small["actuator_mass_kg"] == pytest.approx(small["carried"][0]["mass_kg"] + 0.38)
    catalogue = str(ROOT / "robots" / "catalogue" / "parts.json")
    motor_only = [{"link": "upper_arm", "at": [0.05, 0.0, 0.0],
                   "motor": {"catalogue": catalogue, "name": "Allied Motion HT02501-A00"}}]
    changed = task.with_changes(carried=motor_only).solve(steps=8).to_dict()
    assert changed["actuator_mass_kg"] == pytest.approx(0.38)
    with pytest.raises(cd.InputError, match=r"carried\[0\]\.link = 'nowhere' is no link"):
        task.with_changes(carried=[dict(motor_only[0], link="nowhere")]).solve(steps=8)
