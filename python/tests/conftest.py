"""Fixtures of the Python package's tests: the repository's files and the command line."""

import os
import pathlib
import shutil

import pytest

import codesign as cd

ROOT = pathlib.Path(__file__).resolve().parents[2]
PLANAR = ROOT / "robots" / "examples" / "planar_2dof" / "task.json"


def codesign_binary() -> pathlib.Path:
    """The command line to compare with: $CODESIGN_BIN, else the newest build in target/."""
    named = os.environ.get("CODESIGN_BIN")
    if named:
        return pathlib.Path(named)
    built = [ROOT / "target" / kind / "codesign" for kind in ("release", "debug")]
    built = [path for path in built if path.exists()]
    if not built:
        found = shutil.which("codesign")
        assert found, "no codesign binary: run cargo build first, or set CODESIGN_BIN"
        return pathlib.Path(found)
    return max(built, key=lambda path: path.stat().st_mtime)


@pytest.fixture(scope="session")
def planar() -> cd.Task:
    """The planar 2-DOF example task."""
    return cd.Task.load(PLANAR)


@pytest.fixture(scope="session")
def binary() -> pathlib.Path:
    """The codesign binary."""
    return codesign_binary()
