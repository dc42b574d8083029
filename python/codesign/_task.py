"""The task: a robot, a motion and its motors, and what can be asked of it."""

from __future__ import annotations

import copy
import json
import os
import shlex
import sys
import tempfile
from typing import Any, Callable, Dict, Optional, Sequence, Union

from codesign import _native
from codesign._errors import InputError
from codesign._results import Capacity, CheckReport, Run, Solution

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


def _ratios(ratios: Optional[Sequence[float]]) -> Optional[list]:
    """The design as a list of floats (from any sequence or numpy array)."""
    return None if ratios is None else [float(r) for r in ratios]


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
    (``None``), or nothing (``False``)."""
    if callable(progress):
        return progress
    if progress is False:
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

    @property
    def label(self) -> str:
        """How results name this task: its file, ``built-in``, or what it was changed from."""
        return self._native.label()

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
        if isinstance(changes.get("payload"), (int, float)):
            changes["payload"] = {"mass_kg": float(changes["payload"])}
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
        text, words, problems, warnings = self._native.check(payload, ends, _ratios(ratios))
        return CheckReport(text, words, problems, warnings)

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
        duration: Optional[float] = None,
        steps: Optional[int] = None,
        elastic: bool = False,
    ) -> Solution:
        """Solves the trajectory problem of design ``ratios`` (default: the task's original).

        ``space`` is ``"actuation"`` (the paper's method) or ``"joint"``. ``start`` warm-starts
        from an earlier solution of the same task, space and kind (its point and multipliers;
        the payload may differ). The GIL is released while IPOPT runs; Ctrl-C stops it.
        """
        native_start = None if start is None else start._native
        native = self._native.solve(
            space,
            payload,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
            _ratios(ratios),
            duration,
            steps,
            elastic,
            native_start,
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
    ) -> Capacity:
        """The largest payload design ``ratios`` moves through the task, kg (``codesign
        capacity``): bracketed by doubling from ``first_step``, then bisected to ``resolution``."""
        text = self._native.capacity(
            space,
            ends,
            torque_mode,
            speed_mode,
            linear_solver,
            _ratios(ratios),
            resolution,
            first_step,
            max,
        )
        return Capacity(text)

    def optimize(
        self,
        space: str = "actuation",
        payload: Optional[float] = None,
        *,
        method: str = "cmaes",
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

        The result is written to ``out`` and a CMA-ES run's evaluation log to ``log``
        (``NAME.log.jsonl`` beside ``NAME.json``; give either); ``resume=True`` continues an
        interrupted run from its log. Without either the run goes to a temporary folder.
        ``progress`` is called as ``progress(done, total, best)`` after each evaluation; by
        default a tqdm bar shows where tqdm is installed (``False``: nothing).
        """
        result, log_file = self._outputs(out, log)
        with tempfile.TemporaryDirectory(prefix="codesign-") as folder:
            target = result or os.path.join(folder, "run.json")
            text = _native.optimize(
                self._native,
                space,
                target,
                _worker_command(),
                payload=payload,
                ends=ends,
                torque_mode=torque_mode,
                speed_mode=speed_mode,
                linear_solver=linear_solver,
                method=method,
                population=population,
                generations=generations,
                seed=seed,
                sigma=sigma,
                gradient_iterations=gradient_iterations,
                warm_start=warm_start,
                workers=workers,
                resume=resume,
                overwrite=overwrite,
                progress=_progress(progress),
            )
        return Run(text, result or "", log_file)

    @staticmethod
    def _outputs(out, log):
        """The result file and the log file of ``out=`` and ``log=`` (each derived from the
        other), or (None, None) for a run in a temporary folder."""
        if out is not None and log is not None:
            raise InputError("out= and log=: give one; the log lies beside the result")
        if log is not None:
            log = os.fspath(log)
            if not log.endswith(LOG_SUFFIX):
                raise InputError(f"log={log!r}: an evaluation log is named NAME{LOG_SUFFIX}")
            return log[: -len(LOG_SUFFIX)] + ".json", log
        if out is not None:
            out = os.fspath(out)
            stem = out[:-5] if out.endswith(".json") else out
            return out, stem + LOG_SUFFIX
        return None, None

    def __repr__(self) -> str:
        return f"<codesign.Task {self.label}>"
