"""A task's sections and a linkage's numbers at the edges, read as the command line reads them."""

import pytest

import codesign as cd
from conftest import ROOT

SCREW = ROOT / "robots" / "examples" / "planar_2dof" / "ball_screw.json"


def test_a_section_given_as_a_list_is_refused_naming_it(planar):
    # serde read a list as the section's fields in order: motors=[1, 2] was a torque limit of 1
    # and a speed limit of 2.
    sections = {
        "motors": [1, 2],
        "tcp": ["gripper", [0.05, 0.0, 0.0]],
        "payload": [0.0, {"link": "gripper", "point": [0.05, 0.0, 0.0]}],
        "weights": [0.001, 0.001, 10.0],
        "limit_modes": ["exact", "exact"],
    }
    for section, value in sections.items():
        with pytest.raises(cd.InputError, match=rf"{section} at line \d+: invalid type: an array"):
            planar.with_changes(**{section: value})


def test_a_tiny_screw_lead_is_an_input_error_not_a_panic():
    # A lead of 1e-300 m made G(q) infinite and raised PanicException from nalgebra's SVD, which
    # `except Exception` misses.
    screw = cd.Task.load(SCREW)
    matrix = screw.to_dict()["transmission"]["matrix"]
    matrix[1]["linear"]["lead_m"] = 1e-300
    with pytest.raises(cd.Error, match=r"lead_m = 1e-300 m is outside \[1e-6, 100\] m"):
        screw.with_changes(transmission={"matrix": matrix}).check()
