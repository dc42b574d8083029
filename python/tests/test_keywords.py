"""Keywords (issue 57, items 6, 19 and 22): a keyword of the wrong type or out of its range is a
codesign.InputError that names it and says what it takes; numpy's scalars count as numbers; the
capacity search's settings are checked by the command line's rule; optimize's outputs and
progress are taken as given or refused."""

import subprocess

import pytest

import codesign as cd
from conftest import PLANAR


def test_capacity_settings_are_checked_as_the_command_line_checks_them(planar, binary):
    for keywords, flag, value in [
        (dict(max=1e308, first_step=1e300), "--first-step", "1e300"),
        (dict(max=1e308), "--max", "1e308"),
        (dict(max=5e-324), "--max", "5e-324"),
        (dict(first_step=5e-324), "--first-step", "5e-324"),
    ]:
        with pytest.raises(cd.InputError) as raised:
            planar.capacity(ratios=[50, 12], **keywords)
        keyword, rule = str(raised.value).split(": ", 1)
        assert keyword == f"{flag[2:].replace('-', '_')}={value}"
        assert rule.startswith("must be a mass from 0.000001 kg")
        printed = subprocess.run(
            [binary, "capacity", "--task", PLANAR, "--ratios", "50,12", flag, value],
            capture_output=True,
            text=True,
        )
        assert printed.returncode == 2, printed.stderr
        assert f"{flag} {value}: {rule}" in printed.stderr
