"""The example notebooks (examples/notebooks/): numbered in their reading order, stored without
outputs, listed in the guide. `.ci/notebooks.py` runs them in `.ci/run`."""

import json
import re

from conftest import ROOT

FOLDER = ROOT / "examples" / "notebooks"
NOTEBOOKS = sorted(FOLDER.glob("*.ipynb"))


def test_the_notebooks_are_numbered_in_their_reading_order():
    names = [path.name for path in NOTEBOOKS]
    found = [re.fullmatch(r"(\d\d)_[a-z0-9_]+\.ipynb", name) for name in names]
    assert names and all(found), f"{names}: each named NN_words.ipynb"
    assert [int(match.group(1)) for match in found] == list(range(1, len(names) + 1)), names


def test_no_notebook_is_stored_with_outputs():
    for path in NOTEBOOKS:
        for i, cell in enumerate(json.loads(path.read_text())["cells"]):
            if cell["cell_type"] == "code":
                assert cell["outputs"] == [] and cell["execution_count"] is None, (
                    f"{path.name}, cell {i}: clear the outputs before committing "
                    "(jupyter nbconvert --clear-output --inplace, or Clear All Outputs)"
                )


def test_the_guide_lists_every_notebook():
    guide = (ROOT / "docs" / "guide" / "README.md").read_text()
    for path in NOTEBOOKS:
        assert f"examples/notebooks/{path.name}" in guide, f"docs/guide/README.md: {path.name}"
