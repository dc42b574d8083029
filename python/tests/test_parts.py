"""codesign.parts writes the same pareto.json as `codesign parts` (the planar arm, three
candidate shoulder motors, the least duration T*)."""

import json
import subprocess

import pytest

import codesign as cd
from conftest import ROOT

CATALOGUE = str(ROOT / "robots" / "catalogue" / "parts.json")
CANDIDATES = ["Allied Motion HT02502-A00", "Allied Motion HT02501-A00", "Allied Motion HT02003-A00"]


def family(folder):
    """The planar arm carrying its elbow pulley and a motor, 16 intervals, a small design box,
    its shoulder motor chosen among three candidates; written to ``folder/family.json``."""
    examples = ROOT / "robots" / "examples" / "planar_2dof"
    task = json.loads((examples / "carried_pulley.json").read_text())
    task["robot"] = str(examples / "robot.urdf")
    task["carried"][0]["pulley"]["catalogue"] = CATALOGUE
    task["carried"][1]["motor"]["catalogue"] = CATALOGUE
    task["motion"]["steps"] = 16
    task["transmission"]["bounds"] = [[10, 40], [4, 16]]
    task["transmission"]["original"] = [30, 10]
    task["motors"] = {
        "speed_limit_rad_s": 120,
        "parts": [
            {"catalogue": CATALOGUE, "candidates": CANDIDATES},
            {"catalogue": CATALOGUE, "name": "Allied Motion HT02501-A00"},
        ],
    }
    path = folder / "family.json"
    path.write_text(json.dumps(task))
    return path


def without_times(document):
    """The document without what differs between two runs: the wall times."""
    for key in ("points", "dominated", "infeasible"):
        for point in document[key]:
            point.pop("wall_seconds")
    return document


def test_parts_writes_the_command_lines_front(tmp_path, binary):
    task = family(tmp_path)
    seen = []
    found = cd.parts(
        task,
        out=tmp_path / "python",
        payload=0.5,
        objective="time",
        penalty="graded",
        gradient_iterations=1,
        progress=lambda done, total, best: seen.append((done, total)),
    )
    assert seen == [(1, 3), (2, 3), (3, 3)]
    written = json.loads((tmp_path / "python" / "pareto.json").read_text())
    assert written["points"] == found["points"] and found["points"]
    assert (tmp_path / "python" / "pareto.svg").exists()
    subprocess.run(
        [str(binary), "parts", "--task", str(task), "--payload", "0.5", "--objective", "time",
         "--penalty", "graded", "--gradient-iterations", "1", "--out", str(tmp_path / "cli")],
        check=True, capture_output=True,
    )
    command_line = json.loads((tmp_path / "cli" / "pareto.json").read_text())
    assert without_times(command_line) == without_times(written)
    with pytest.raises(cd.InputError, match='^penalty="steep": expected flat, graded or a'):
        cd.parts(task, out=tmp_path / "other", payload=0.5, penalty="steep")
    with pytest.raises(cd.InputError, match="holds .* of an earlier search"):
        cd.parts(task, out=tmp_path / "python", payload=0.5, objective="time")
