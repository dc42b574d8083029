"""The task: a robot, a motion and its motors, and what can be asked of it."""

from __future__ import annotations

import copy
import json
import os
import shlex
import sys
import tempfile
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from codesign import _native
from codesign._errors import InputError
from codesign._keywords import (
    design,
    duration as duration_of,
    flag,
    number,
    optional_flag,
    path,
    penalty as penalty_text,
    plain,
    shown,
    text,
    whole,
)
from codesign._results import Capacity, CheckReport, Run, Solution
from codesign._robot import Robot, Transmission
from codesign._sections import (
    CartesianBox,
    LimitModes,
    Motion,
    MotionEntry,
    MotionsScore,
    Motors,
    Payload,
    PointOnLink,
    TransmissionSpec,
    Weights,
    task_document,
)

#: The suffix of an evaluation log, beside its result ``NAME.json``.
LOG_SUFFIX = ".log.jsonl"

Progress = Union[None, bool, Callable[[int, int, float], Any]]


def _merge(base: Dict[str, Any], changes: Dict[str, Any]) -> Dict[str, Any]:
    """``base`` with ``changes`` merged in: dicts merge key by key, other values replace."""
    merged = copy.deepcopy(base)
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = copy.deepcopy(value)
    return merged


def _worker_command() -> str:
    """The shell command that starts one worker: this interpreter running codesign.worker, with
    this package's folder first on its path (so that a source folder in the working directory
    never stands in for it)."""
    folder = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    program = (
        f"import sys; sys.path.insert(0, {folder!r}); "
        "from codesign.worker import main; main()"
    )
    return f"{shlex.quote(sys.executable)} -c {shlex.quote(program)}"


def _progress(progress: Progress) -> Optional[Callable[[int, int, float], Any]]:
    """The callable behind ``progress=``: the caller's, a tqdm bar where tqdm is installed
    (``None`` or ``True``), or nothing (``False``)."""
    if callable(progress):
        return progress
    if progress is not None and not isinstance(progress, (bool, np.bool_)):
        raise InputError(
            f"progress={shown(progress)}: must be True, False, None or a callable "
            "progress(done, total, best)"
        )
    if progress is False or progress is np.False_:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    bar = None

    def show(done: int, total: int, best: float) -> None:
        nonlocal bar
        if bar is None:
            bar = tqdm(total=total, desc="co-design", unit="solve")
        bar.update(done - bar.n)
        bar.set_postfix(best=f"{best:.4g}")
        if done >= total:
            bar.close()

    return show


class Task:
    """A co-design task: robot, motion, motors, transmission and solver settings.

    Load one with :meth:`load` or :meth:`builtin`, change it with :meth:`with_changes` (checked
    as a file is), and ask it what the command line answers: :meth:`check`, :meth:`solve`,
    :meth:`capacity` and :meth:`optimize`.
    """

    def __init__(self, native: "_native.NativeTask", document: Dict[str, Any], folder: str):
        self._native = native
        self._document = document
        self._folder = folder

    @classmethod
    def load(cls, path: Union[str, os.PathLike]) -> "Task":
        """The task file at ``path`` (JSON; see ``codesign task --help``)."""
        path = os.fspath(path)
        native = _native.NativeTask.load(path)
        document = json.loads(_native.task_text(path))
        return cls(native, document, os.path.dirname(os.path.abspath(path)))

    @classmethod
    def builtin(cls) -> "Task":
        """The paper's pick-and-place task on the built-in 4-DOF belt arm."""
        document = json.loads(_native.task_text(None))
        return cls(_native.NativeTask.builtin(), document, os.getcwd())

    @classmethod
    def from_sections(
        cls,
        *,
        robot: Optional[Union[str, os.PathLike]],
        tcp: "PointOnLink",
        payload: "Payload",
        motion: "Motion",
        motors: "Motors",
        transmission: "TransmissionSpec",
        weights: Optional["Weights"] = None,
        cartesian_box: Optional["CartesianBox"] = None,
        limit_modes: Optional["LimitModes"] = None,
        gravity: Sequence[float] = (0.0, 0.0, -9.81),
        solver: Optional[Dict[str, Any]] = None,
        folder: Optional[Union[str, os.PathLike]] = None,
        motions: Optional[Sequence["MotionEntry"]] = None,
        motions_score: Union[None, "MotionsScore", str] = None,
        carried: Optional[Sequence[Dict[str, Any]]] = None,
    ) -> "Task":
        """A task written in code from its typed sections (``codesign.sections``), checked as a
        file is: ``robot`` is the URDF's path (relative to ``folder``, default the working
        folder), or None for the built-in arm. Sections left out take their defaults (the
        paper's weights, no box, limit modes ``paper`` and ``exact``). ``motions`` makes one
        design serve several motions (each a :class:`~codesign.sections.MotionEntry` changing
        ``motion``), scored by ``motions_score``: ``"sum"`` (the default) or ``"worst"``.
        ``carried`` lists parts fixed to links, as the task file's ``carried`` entries (dicts:
        ``link``, ``at`` and one of ``pulley``, ``motor``, ``gearbox``; docs/guide/catalogue.md),
        their catalogues relative to ``folder``."""
        document = task_document(
            None if robot is None else os.fspath(robot),
            tcp,
            payload,
            motion,
            motors,
            transmission,
            weights or Weights(),
            cartesian_box or CartesianBox(),
            limit_modes or LimitModes(),
            tuple(gravity),
            solver,
            motions,
            motions_score,
            carried,
        )
        folder = os.getcwd() if folder is None else os.path.abspath(os.fspath(folder))
        native = _native.NativeTask.given(json.dumps(document), "a task from sections", folder)
        return cls(native, document, folder)

    @property
    def label(self) -> str:
        """How results name this task: its file, ``built-in``, or what it was changed from."""
        return self._native.label()

    def robot(self, payload: Optional[float] = None) -> Robot:
        """The task's robot (its URDF, gravity, TCP and payload; ``payload`` kg instead where
        given), with its dynamics."""
        return Robot(_native.NativeRobot.of_task(self._native, payload))

    @property
    def motions(self) -> List[str]:
        """The names of the task's several motions (``motions``), in order; empty for a task of
        one motion."""
        return [entry["name"] for entry in self._document.get("motions", [])]

    @property
    def transmission(self) -> Transmission:
        """The task's transmission: its design space and G at a design and a pose."""
        return Transmission(_native.NativeRobot.of_task(self._native, None))

    def to_dict(self) -> Dict[str, Any]:
        """The task as the dict of its JSON file (a copy)."""
        return copy.deepcopy(self._document)

    def to_json(self) -> str:
        """The task as JSON text."""
        return json.dumps(self._document, indent=2)

    def with_changes(self, **changes: Any) -> "Task":
        """A new task with ``changes`` merged into this one's sections and checked as a file is.

        Each keyword is a section of the task file; a dict merges into it key by key, any other
        value replaces it. ``payload=2.0`` is short for ``payload={"mass_kg": 2.0}``. A relative
        ``robot`` path is taken from the folder of the task file this one was loaded from.
        Example: ``task.with_changes(payload=2.0, motors={"torque_limit_nm": 0.8})``.
        """
        changes = {key: plain(key, value) for key, value in changes.items()}
        payload = changes.get("payload")
        if isinstance(payload, (int, float)) and not isinstance(payload, bool):
            changes["payload"] = {"mass_kg": float(payload)}
        document = _merge(self._document, changes)
        label = f"{self.label} with {', '.join(sorted(changes))} changed"
        native = _native.NativeTask.given(json.dumps(document), label, self._folder)
        return Task(native, document, self._folder)

    def check(
        self,
        payload: Optional[float] = None,
        ratios: Optional[Sequence[float]] = None,
        ends: Optional[str] = None,
    ) -> CheckReport:
        """What ``codesign check`` finds before any solve: joints, static torques, the hold, the
        limit modes, the linkages; its errors in ``problems``, its warnings in ``warnings``."""
        found, words, problems, warnings = self._native.check(
            number("payload", payload), text("ends", ends), design("ratios", ratios)
        )
        return CheckReport(found, words, problems, warnings)

    def solve(
        self,
        space: str = "actuation",
        payload: Optional[float] = None,
        ratios: Optional[Sequence[float]] = None,
        *,
        start: Optional[Solution] = None,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        duration: Union[None, float, Tuple[float, float]] = None,
        steps: Optional[int] = None,
        elastic: bool = False,
        motion: Optional[str] = None,
        minimum_time: bool = False,
        free_horizon: Optional[str] = None,
    ) -> Solution:
        """Solves the trajectory problem of design ``ratios`` (default: the task's original).

        ``space`` is ``"actuation"`` (the paper's method) or ``"joint"``. ``start`` warm-starts
        from an earlier solution of the same task, space and kind (its point and multipliers;
        the payload may differ). A task with several motions (:attr:`motions`) solves the one
        ``motion`` names (``solve --motion``). ``minimum_time=True`` solves the task's pure
        minimum-time problem instead (``solve --minimum-time``: J* = T*, s), and
        ``free_horizon`` (``"local"`` or ``"descend"``) chooses how a free horizon is searched
        (``solve --free-horizon``). The GIL is released while IPOPT runs; Ctrl-C stops it.
        """
        if start is not None and not isinstance(start, Solution):
            raise InputError(
                f"start={shown(start)}: must be a Solution of an earlier solve, not "
                f"{type(start).__name__}"
            )
        native_start = None if start is None else start._native
        native = self._native.solve(
            text("space", space),
            number("payload", payload),
            text("ends", ends),
            text("torque_mode", torque_mode),
            text("speed_mode", speed_mode),
            text("linear_solver", linear_solver),
            design("ratios", ratios),
            duration_of("duration", duration),
            whole("steps", steps),
            flag("elastic", elastic),
            native_start,
            text("motion", motion),
            flag("minimum_time", minimum_time),
            text("free_horizon", free_horizon),
        )
        return Solution(native)

    def capacity(
        self,
        space: str = "actuation",
        ratios: Optional[Sequence[float]] = None,
        *,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        resolution: Optional[float] = None,
        first_step: Optional[float] = None,
        max: Optional[float] = None,
        duration: Optional[float] = None,
    ) -> Capacity:
        """The largest payload design ``ratios`` moves through the task, kg (``codesign
        capacity``): bracketed by doubling from ``first_step``, then bisected to ``resolution``;
        each payload moved in ``duration`` s where given (``--duration``), else the task's."""
        found = self._native.capacity(
            text("space", space),
            text("ends", ends),
            text("torque_mode", torque_mode),
            text("speed_mode", speed_mode),
            text("linear_solver", linear_solver),
            design("ratios", ratios),
            number("resolution", resolution),
            number("first_step", first_step),
            number("max", max),
            number("duration", duration),
        )
        return Capacity(found)

    def tradeoff(
        self,
        durations: Optional[Sequence[float]] = None,
        space: str = "actuation",
        ratios: Optional[Sequence[float]] = None,
        *,
        payloads: Optional[Sequence[float]] = None,
        compare: Optional[Sequence[Sequence[float]]] = None,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        resolution: Optional[float] = None,
        first_step: Optional[float] = None,
        max: Optional[float] = None,
        out: Optional[Union[str, os.PathLike]] = None,
    ) -> Dict[str, Any]:
        """The payload capacity of design ``ratios`` against the duration of its motion
        (``codesign tradeoff``): at each of ``durations`` (s), the heaviest payload moved within
        it, as :meth:`capacity` with ``duration=`` finds it. Returns the document's data (a
        dict: ``inputs`` with ``durations_s``, and ``points``, one per duration, each with its
        ``duration_s``, ``capacity_kg`` and search); given ``out`` (``NAME.json``), writes it
        there with its plot beside it (``NAME.svg``).

        Given ``payloads`` (kg, increasing) instead of ``durations``, the other way round
        (``codesign tradeoff --payloads``): the least duration T* of design ``ratios`` and of
        each design of ``compare`` at each payload, each its pure minimum-time problem solved as
        :meth:`solve` solves it; the first payload a design cannot move within T_max ends its
        curve. Returns the document's data: ``inputs`` with ``payloads_kg`` and ``horizon_s``,
        and ``curves``, one per design, each with its ``ratios``, its ``points`` (each with
        ``payload_kg``, ``feasible``, ``minimum_time_s``) and ``ends_at_kg``."""
        if payloads is not None:
            return self._time_curve(
                durations, space, ratios, payloads, compare, ends, torque_mode, speed_mode,
                linear_solver, (resolution, first_step, max), out
            )
        if compare is not None:
            raise InputError("compare=: only with payloads=")
        listed = design("durations", durations)
        if listed is None:
            raise InputError("durations=None: must be a list of durations in s, or give payloads=")
        found = self._native.tradeoff(
            text("space", space),
            listed,
            text("ends", ends),
            text("torque_mode", torque_mode),
            text("speed_mode", speed_mode),
            text("linear_solver", linear_solver),
            design("ratios", ratios),
            number("resolution", resolution),
            number("first_step", first_step),
            number("max", max),
            path("out", out),
        )
        return json.loads(found)

    def _time_curve(
        self, durations, space, ratios, payloads, compare, ends, torque_mode, speed_mode,
        linear_solver, search, out
    ) -> Dict[str, Any]:
        """:meth:`tradeoff` with ``payloads``: T* against payload."""
        if durations is not None:
            raise InputError("durations= and payloads=: give one, the trade-off's axis")
        if any(value is not None for value in search):
            raise InputError("resolution=, first_step=, max=: capacity searches, not with payloads=")
        listed = design("payloads", payloads)
        if listed is None:
            raise InputError("payloads=None: must be a list of payloads in kg")
        designs = None
        if ratios is not None or compare is not None:
            first = design("ratios", ratios) if ratios is not None else None
            if first is None:
                first = self.to_dict()["transmission"]["original"]
            others = [design(f"compare[{i}]", each) for i, each in enumerate(compare or [])]
            designs = [first] + others
        found = self._native.time_curve(
            text("space", space),
            listed,
            text("ends", ends),
            text("torque_mode", torque_mode),
            text("speed_mode", speed_mode),
            text("linear_solver", linear_solver),
            designs,
            path("out", out),
        )
        return json.loads(found)

    def optimize(
        self,
        space: str = "actuation",
        payload: Optional[float] = None,
        *,
        method: str = "cmaes",
        objective: str = "cost",
        penalty: Union[str, float, None] = None,
        bounds: Optional[str] = None,
        population: Optional[int] = None,
        generations: Optional[int] = None,
        seed: Optional[int] = None,
        sigma: Optional[float] = None,
        gradient_iterations: Optional[int] = None,
        warm_start: Optional[bool] = None,
        workers: Optional[int] = None,
        log: Optional[Union[str, os.PathLike]] = None,
        out: Optional[Union[str, os.PathLike]] = None,
        resume: bool = False,
        overwrite: bool = False,
        progress: Progress = None,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
    ) -> Run:
        """A co-design run (``codesign optimize``): CMA-ES (``method="cmaes"``, its designs
        solved by ``workers`` worker processes) or the gradient method on dJ*/dr (its
        candidate starts and its descents solved on ``workers`` threads).

        ``objective`` is what the run minimises: ``"cost"``, the trajectory cost J;
        ``"energy"``, the motors' copper losses; or ``"time"``, the least duration T* of the
        motion (each design solves the task's pure minimum-time problem, J* = T*, and the
        gradient method descends on the exact dT*/dr).

        ``penalty`` scores an infeasible design: ``"flat"`` (the paper's 1e6, the default),
        ``"graded"`` (by how far the design is from feasibility, through the elastic problem)
        or a number (a flat penalty of that value). ``bounds`` says what CMA-ES does with a
        sample outside the design space: ``"penalty"`` (the paper's rule, the default),
        ``"clip"`` or ``"map"`` (every sample drawn in the unit box and mapped onto the space).

        The result is written to ``out`` and a CMA-ES run's evaluation log to ``log``
        (``NAME.log.jsonl`` beside ``NAME.json``; give either); ``resume=True`` continues an
        interrupted run from its log. Without either the run goes to a temporary folder.
        ``progress`` is called as ``progress(done, total, best)`` after each evaluation, and
        stops the run by raising; by default (``None`` or ``True``) a tqdm bar shows where tqdm
        is installed (``False``: nothing).
        """
        result, log_file = self._outputs(path("out", out), path("log", log))
        keywords = dict(
            payload=number("payload", payload),
            ends=text("ends", ends),
            torque_mode=text("torque_mode", torque_mode),
            speed_mode=text("speed_mode", speed_mode),
            linear_solver=text("linear_solver", linear_solver),
            method=text("method", method),
            objective=text("objective", objective),
            penalty=penalty_text("penalty", penalty),
            bounds=text("bounds", bounds),
            population=whole("population", population),
            generations=whole("generations", generations),
            seed=whole("seed", seed),
            sigma=number("sigma", sigma),
            gradient_iterations=whole("gradient_iterations", gradient_iterations),
            warm_start=optional_flag("warm_start", warm_start),
            workers=whole("workers", workers),
            resume=flag("resume", resume),
            overwrite=flag("overwrite", overwrite),
            progress=_progress(progress),
        )
        space = text("space", space)
        with tempfile.TemporaryDirectory(prefix="codesign-") as folder:
            target = result or os.path.join(folder, "run.json")
            found = _native.optimize(self._native, space, target, _worker_command(), **keywords)
        return Run(found, result or "", log_file)

    @staticmethod
    def _outputs(out: Optional[str], log: Optional[str]):
        """The result file and the log file of ``out=`` and ``log=`` (the log where the run
        keeps it, beside the result; the result ``NAME.json`` of a log ``NAME.log.jsonl``), or
        (None, None) for a run in a temporary folder."""
        if out is not None and log is not None:
            raise InputError("out= and log=: give one; the log lies beside the result")
        if out is not None:
            return out, os.fspath(_native.log_beside(out))
        if log is None:
            return None, None
        name = os.path.basename(log)
        if not name.endswith(LOG_SUFFIX) or name == LOG_SUFFIX:
            raise InputError(
                f"log={log!r}: an evaluation log is named NAME{LOG_SUFFIX}, NAME not empty"
            )
        result = log[: -len(LOG_SUFFIX)] + ".json"
        beside = os.fspath(_native.log_beside(result))
        if beside != log:
            raise InputError(
                f"log={log!r}: the run's result {result!r} keeps its log at {beside!r}; give "
                f"out={result!r} instead"
            )
        return result, log

    def __repr__(self) -> str:
        return f"<codesign.Task {self.label}>"
