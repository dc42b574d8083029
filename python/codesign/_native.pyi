"""The native module of codesign (pyo3): tasks and what they do, answered as the command line's
JSON documents. Use it through :mod:`codesign`."""

import pathlib
from typing import Callable, List, Optional, Tuple

import numpy

class NativeSolution:
    @staticmethod
    def of_run_best(text: str) -> Optional[NativeSolution]: ...
    def joint_names(self) -> List[str]: ...
    def motor_names(self) -> List[str]: ...
    """One solve's document, kept native, and where it ended (to warm-start another)."""

    def json(self) -> str: ...
    def feasible(self) -> bool: ...
    def reason(self) -> Optional[str]: ...
    def cost(self) -> float: ...
    def cost_terms(self) -> Optional[Tuple[float, float, float, float]]: ...
    def cost_gradient(self) -> Optional[List[float]]: ...
    def figures(self) -> Optional[str]: ...
    def summary(self) -> Tuple[str, int, List[float], float, str, str]: ...
    def arrays(self) -> Tuple[numpy.ndarray, Tuple[numpy.ndarray, ...]]: ...
    def linkage_arrays(self) -> Optional[Tuple[numpy.ndarray, numpy.ndarray]]: ...
    def resample(self, rate: float) -> Tuple[List[str], List[numpy.ndarray]]: ...
    def charts(self) -> List[Tuple[str, str]]: ...

class NativeTask:
    """A task: built in, read from a file, or given as JSON text."""

    @staticmethod
    def load(path: str) -> NativeTask: ...
    @staticmethod
    def builtin() -> NativeTask: ...
    @staticmethod
    def given(text: str, label: str, folder: str) -> NativeTask: ...
    def label(self) -> str: ...
    def check(
        self,
        payload: Optional[float] = None,
        ends: Optional[str] = None,
        ratios: Optional[List[float]] = None,
    ) -> Tuple[str, str, List[str], List[str]]: ...
    def solve(
        self,
        space: str,
        payload: Optional[float] = None,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        ratios: Optional[List[float]] = None,
        duration: Optional[List[float]] = None,
        steps: Optional[int] = None,
        elastic: bool = False,
        start: Optional[NativeSolution] = None,
        motion: Optional[str] = None,
    ) -> NativeSolution: ...
    def capacity(
        self,
        space: str,
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        ratios: Optional[List[float]] = None,
        resolution: Optional[float] = None,
        first_step: Optional[float] = None,
        max: Optional[float] = None,
        duration: Optional[float] = None,
    ) -> str: ...
    def tradeoff(
        self,
        space: str,
        durations: List[float],
        ends: Optional[str] = None,
        torque_mode: Optional[str] = None,
        speed_mode: Optional[str] = None,
        linear_solver: Optional[str] = None,
        ratios: Optional[List[float]] = None,
        resolution: Optional[float] = None,
        first_step: Optional[float] = None,
        max: Optional[float] = None,
        out: Optional[str] = None,
    ) -> str: ...

def optimize(
    task: NativeTask,
    space: str,
    out: str,
    worker_command: str,
    payload: Optional[float] = None,
    ends: Optional[str] = None,
    torque_mode: Optional[str] = None,
    speed_mode: Optional[str] = None,
    linear_solver: Optional[str] = None,
    method: str = "cmaes",
    objective: str = "cost",
    penalty: Optional[str] = None,
    bounds: Optional[str] = None,
    population: Optional[int] = None,
    generations: Optional[int] = None,
    seed: Optional[int] = None,
    sigma: Optional[float] = None,
    gradient_iterations: Optional[int] = None,
    warm_start: Optional[bool] = None,
    workers: Optional[int] = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Optional[Callable[[int, int, float], object]] = None,
) -> str: ...
def parts(
    task: str,
    space: str,
    out: str,
    worker_command: str,
    payload: Optional[float] = None,
    ends: Optional[str] = None,
    torque_mode: Optional[str] = None,
    speed_mode: Optional[str] = None,
    linear_solver: Optional[str] = None,
    objective: str = "cost",
    penalty: Optional[str] = None,
    gradient_iterations: Optional[int] = None,
    workers: Optional[int] = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Optional[Callable[[int, int, float], object]] = None,
) -> str: ...
def log_beside(out: str) -> pathlib.Path: ...
def serve_worker() -> None: ...
def task_text(path: Optional[str] = None) -> str: ...
def versions() -> Tuple[str, str]: ...

class NativeRobot:
    @staticmethod
    def from_urdf(path: str) -> NativeRobot: ...
    @staticmethod
    def of_task(task: NativeTask, payload: Optional[float] = None) -> NativeRobot: ...
    def joint_names(self) -> List[str]: ...
    def position_limits(self) -> List[Tuple[float, float]]: ...
    def payload(self) -> float: ...
    def rnea(self, q: List[float], v: List[float], a: List[float]) -> numpy.ndarray: ...
    def mass_matrix(self, q: List[float]) -> numpy.ndarray: ...
    def tcp(self, q: List[float]) -> Tuple[numpy.ndarray, numpy.ndarray]: ...
    def design(self) -> Optional[Tuple[List[float], List[Tuple[float, float]]]]: ...
    def ratio_matrix(self, ratios: List[float], q: List[float]) -> numpy.ndarray: ...
