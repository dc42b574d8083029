"""A search over a task's candidate parts (``codesign parts``)."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Optional, Union

from codesign import _native
from codesign._errors import InputError
from codesign._keywords import flag, number, path, penalty as penalty_text, text, whole
from codesign._task import Progress, _progress, _worker_command


def parts(
    task: Union[str, os.PathLike],
    space: str = "actuation",
    out: Union[str, os.PathLike, None] = None,
    payload: Optional[float] = None,
    *,
    objective: str = "cost",
    penalty: Union[str, float, None] = None,
    gradient_iterations: Optional[int] = None,
    workers: Optional[int] = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Progress = None,
    ends: Optional[str] = None,
    torque_mode: Optional[str] = None,
    speed_mode: Optional[str] = None,
    linear_solver: Optional[str] = None,
) -> Dict[str, Any]:
    """Every combination of the candidate motors of the task file ``task`` (its
    ``motors.parts[i].candidates``) co-designed in its ratios by the gradient method, as
    ``codesign parts --task TASK --out OUT`` runs it: one co-design result per combination in
    the folder ``out``, and ``pareto.json`` with its plot ``pareto.svg`` beside them.

    ``objective`` judges each combination's design: ``"cost"`` (J* at the payload),
    ``"time"`` (the least duration T*), or ``"capacity"`` (the payload capacity of the design
    co-designed for the cost). ``penalty`` scores the descents' infeasible designs: ``"flat"``
    (the default), ``"graded"`` (which descends from infeasible starts toward feasibility, the
    choice at the edge of feasibility) or a number. ``resume=True`` reads the combinations an interrupted search
    finished; ``overwrite=True`` runs them all again. ``progress(done, total, best)`` is called
    after each combination (by default a tqdm bar where tqdm is installed).

    Returns the front's document, ``pareto.json`` as a dict: ``points`` (the non-dominated
    combinations, by increasing actuator mass), ``dominated``, ``infeasible``, and ``axes``
    saying which way each is better.
    """
    folder, family = path("out", out), path("task", task)
    if folder is None or family is None:
        raise InputError("task= and out=: give the task file and the folder the search writes to")
    found = _native.parts(
        family,
        text("space", space),
        folder,
        _worker_command(),
        payload=number("payload", payload),
        ends=text("ends", ends),
        torque_mode=text("torque_mode", torque_mode),
        speed_mode=text("speed_mode", speed_mode),
        linear_solver=text("linear_solver", linear_solver),
        objective=text("objective", objective),
        penalty=penalty_text("penalty", penalty),
        gradient_iterations=whole("gradient_iterations", gradient_iterations),
        workers=whole("workers", workers),
        resume=flag("resume", resume),
        overwrite=flag("overwrite", overwrite),
        progress=_progress(progress),
    )
    return json.loads(found)
