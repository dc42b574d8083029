"""The keywords of the task's methods read into what the native module takes: each of the type it
must be, else an :class:`InputError` that names the keyword, shows its value and says what it
takes. Numpy's scalars count as the Python numbers they hold. The ranges are the native module's
(the command line's) to check."""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
from collections.abc import Sequence
from enum import Enum
from typing import Any, List, Optional

import numpy as np

from codesign._errors import InputError

#: The longest value an error message shows, in characters.
SHOWN = 60


def shown(value: Any) -> str:
    """``value`` as an error message shows it: Python's repr, a numpy scalar as its number, an
    array by its shape; cut to :data:`SHOWN` characters."""
    if isinstance(value, np.ndarray):
        return f"array of shape {value.shape}"
    text = str(value) if isinstance(value, np.generic) else repr(value)
    return text if len(text) <= SHOWN else text[: SHOWN - 3] + "..."


def _refused(name: str, value: Any, takes: str) -> InputError:
    """The error of keyword ``name`` given ``value``, which is not what it ``takes``."""
    return InputError(f"{name}={shown(value)}: must be {takes}, not {type(value).__name__}")


def _is_bool(value: Any) -> bool:
    return isinstance(value, (bool, np.bool_))


def number(name: str, value: Any) -> Optional[float]:
    """None, or ``value`` (an int or a float, Python's or numpy's; not a bool) as a float."""
    if value is None:
        return None
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise _refused(name, value, "a number")
    try:
        return float(value)
    except OverflowError:
        raise InputError(f"{name}={shown(value)}: too large for a number of 64 bits") from None


def penalty(name: str, value: Any) -> Optional[str]:
    """None; ``"flat"`` (the paper's), ``"graded"``; or a number, a flat penalty of that value:
    as the command line's ``--penalty`` spells it."""
    if value is None or isinstance(value, str):
        return value
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise _refused(name, value, '"flat", "graded" or a number')
    return repr(float(value))


def duration(name: str, value: Any) -> Optional[List[float]]:
    """None; a number of seconds as ``[T]`` (a fixed duration); or a pair ``(T_min, T_max)`` as
    ``[T_min, T_max]`` (a free duration)."""
    if value is None:
        return None
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise _refused(name, value, "a duration in s or a pair (T_min, T_max) in s")
        return [number(f"{name}[{i}]", v) for i, v in enumerate(value)]  # type: ignore[misc]
    return [number(name, value)]  # type: ignore[list-item]


def whole(name: str, value: Any) -> Optional[int]:
    """None, or ``value`` (an int, Python's or numpy's; not a bool) as an int from 0 to
    2**64 - 1."""
    if value is None:
        return None
    if _is_bool(value) or not isinstance(value, numbers.Integral):
        raise _refused(name, value, "a whole number (an int)")
    value = int(value)
    if value < 0:
        raise InputError(f"{name}={shown(value)}: must not be negative")
    if value >= 2**64:
        raise InputError(f"{name}={shown(value)}: must be below 2**64")
    return value


def text(name: str, value: Any) -> Optional[str]:
    """None, or ``value``, a str."""
    if value is None or isinstance(value, str):
        return value
    raise _refused(name, value, "a str")


def flag(name: str, value: Any) -> bool:
    """``value``, True or False (Python's or numpy's)."""
    if _is_bool(value):
        return bool(value)
    raise _refused(name, value, "True or False")


def optional_flag(name: str, value: Any) -> Optional[bool]:
    """None, or :func:`flag`."""
    return None if value is None else flag(name, value)


def design(name: str, value: Any) -> Optional[List[float]]:
    """None, or the gear ratios ``value`` (a list, a tuple or a 1-D numpy array of numbers) as a
    list of floats."""
    if value is None:
        return None
    array = isinstance(value, np.ndarray) and value.ndim == 1
    listed = isinstance(value, Sequence) and not isinstance(value, (str, bytes))
    if not (array or listed):
        raise _refused(name, value, "a list or a 1-D array of numbers")
    return [number(f"{name}[{index}]", ratio) for index, ratio in enumerate(value)]


def path(name: str, value: Any) -> Optional[str]:
    """None, or ``value`` (a str or an os.PathLike) as a str that names a file."""
    if value is None:
        return None
    if not isinstance(value, (str, os.PathLike)):
        raise _refused(name, value, "a file's path (a str or an os.PathLike)")
    value = os.fspath(value)
    if not isinstance(value, str) or value == "":
        raise InputError(f"{name}={shown(value)}: must name a file")
    return value


def plain(name: str, value: Any) -> Any:
    """``value`` as JSON holds it: dicts with str keys, lists, str, bool, None and finite
    numbers, numpy's as Python's; anything else an error naming where it lies in ``name``
    (``motors.torque_limit_nm``). A section's dataclass (``codesign.sections``) counts as the
    dict of its fields, those that are None left out."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = dataclasses.asdict(value).items()
        value = {key: item for key, item in fields if item is not None}
    if isinstance(value, Enum):
        return value.value
    if isinstance(value, dict):
        for key in value:
            if not isinstance(key, str):
                raise InputError(f"{name}: the key {shown(key)} must be a str")
        return {key: plain(f"{name}.{key}", item) for key, item in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [plain(f"{name}[{index}]", item) for index, item in enumerate(value)]
    if value is None or isinstance(value, str):
        return value
    if _is_bool(value):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        if not math.isfinite(value):
            raise InputError(
                f"{name}={shown(value)}: must be a finite number (JSON has no NaN or infinity)"
            )
        return float(value)
    raise InputError(f"{name}={shown(value)}: JSON has no form for a {type(value).__name__}")
