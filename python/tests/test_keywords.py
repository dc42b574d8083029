"""Keywords (issue 57, items 6, 19 and 22): a keyword of the wrong type or out of its range is a
codesign.InputError that names it and says what it takes; numpy's scalars count as numbers; the
capacity search's settings are checked by the command line's rule; optimize's outputs and
progress are taken as given or refused."""

import subprocess

import numpy as np
import pytest

import codesign as cd
from conftest import PLANAR

TINY = dict(space="actuation", payload=1.0, population=8, generations=1, seed=0, workers=1,
            progress=False)


@pytest.mark.parametrize(
    "method, keywords, named",
    [
        ("solve", dict(steps=-1), "steps=-1: must not be negative"),
        ("solve", dict(steps=2**64), "steps=18446744073709551616: must be below 2**64"),
        ("optimize", dict(population=-1), "population=-1: must not be negative"),
        ("optimize", dict(seed=-1), "seed=-1: must not be negative"),
        ("optimize", dict(workers=-1), "workers=-1: must not be negative"),
        ("solve", dict(steps="10"), "steps='10': must be a whole number (an int), not str"),
        ("solve", dict(steps=10.0), "steps=10.0: must be a whole number (an int), not float"),
        ("solve", dict(payload="1"), "payload='1': must be a number, not str"),
        ("solve", dict(payload=True), "payload=True: must be a number, not bool"),
        ("solve", dict(space=1), "space=1: must be a str, not int"),
        ("solve", dict(elastic="yes"), "elastic='yes': must be True or False, not str"),
        ("capacity", dict(max="64"), "max='64': must be a number, not str"),
        ("optimize", dict(sigma=[1]), "sigma=[1]: must be a number, not list"),
        ("optimize", dict(resume=1), "resume=1: must be True or False, not int"),
        ("solve", dict(ratios="50,12"), "ratios='50,12': must be a list or a 1-D array of numbers"),
        ("solve", dict(ratios={50: 1, 12: 1}), "ratios={50: 1, 12: 1}: must be a list or"),
        ("check", dict(ratios=[50, 12 + 0j]), "ratios[1]=(12+0j): must be a number, not complex"),
        ("capacity", dict(ratios=np.array([50, 12], dtype=complex)), "ratios[0]=(50+0j): must"),
        ("solve", dict(ratios=np.ones((2, 1))), "ratios=array of shape (2, 1): must be a list"),
    ],
)
def test_a_keyword_of_the_wrong_type_or_sign_is_an_input_error_naming_it(
    planar, method, keywords, named
):
    with pytest.raises(cd.InputError) as raised:
        getattr(planar, method)(**keywords)
    assert str(raised.value).startswith(named), str(raised.value)


def test_numpy_scalars_are_numbers(planar):
    plain = planar.solve(payload=1.0, ratios=[50, 12], steps=10)
    numpy = planar.solve(payload=np.float32(1.0), ratios=np.array([50, 12], dtype=np.float32),
                         steps=np.int64(10))
    assert numpy.cost == plain.cost
    changed = planar.with_changes(payload=np.float32(2.0),
                                  motors={"torque_limit_nm": np.float64(0.8)},
                                  motion={"steps": np.int32(12)})
    assert changed.to_dict()["payload"]["mass_kg"] == 2.0
    assert changed.to_dict()["motion"]["steps"] == 12


def test_a_change_json_cannot_hold_names_its_keyword(planar):
    with pytest.raises(cd.InputError, match=r"^payload=nan: must be a finite number"):
        planar.with_changes(payload=float("nan"))
    with pytest.raises(cd.InputError, match=r"^motors.torque_limit_nm=inf: must be a finite"):
        planar.with_changes(motors={"torque_limit_nm": float("inf")})
    with pytest.raises(cd.InputError, match=r"^motion.steps=\{1, 2\}: JSON has no form for a set"):
        planar.with_changes(motion={"steps": {1, 2}})


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


def test_optimize_outputs_are_taken_as_given_or_refused(planar, tmp_path):
    with pytest.raises(cd.InputError, match=r"^out='': must name a file"):
        planar.optimize(**TINY, out="")
    with pytest.raises(cd.InputError, match=r"^log='': must name a file"):
        planar.optimize(**TINY, log="")
    hidden = tmp_path / ".log.jsonl"
    with pytest.raises(cd.InputError, match=r"^log=.*: an evaluation log is named NAME\.log"):
        planar.optimize(**TINY, log=hidden)
    assert list(tmp_path.iterdir()) == []
    run = planar.optimize(**TINY, out=tmp_path / "run.txt")
    assert run.result_file == str(tmp_path / "run.txt")
    assert run.log_file == str(tmp_path / "run.log.jsonl")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.log.jsonl", "run.txt"]


def test_progress_is_a_flag_or_a_callable(planar):
    for progress in (1, "yes", 0.0):
        with pytest.raises(cd.InputError, match=r"^progress=.*: must be True, False, None or"):
            planar.optimize(**dict(TINY, progress=progress))
