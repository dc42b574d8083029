"""codesign: co-design of the transmission and the motion of robots with parallel
transmissions, on IPOPT.

>>> import codesign as cd
>>> task = cd.Task.builtin()
>>> sol = task.solve(space="actuation", payload=1.0)
>>> sol.feasible, sol.cost, sol.q.shape

Every result converts to the document the command line writes (``to_dict()``, ``to_json()``);
every failure raises a :class:`codesign.Error` (:class:`InputError` for a bad input, a
``ValueError``; :class:`SolverError` when the work fails, a ``RuntimeError``).
"""

from codesign._choices import Ends, LimitMode, LinearSolver, Method, Space
from codesign._errors import Error, InputError, SolverError
from codesign._native import versions as _versions
from codesign._parts import parts
from codesign._results import Capacity, CheckReport, Run, Solution
from codesign._robot import Robot, Transmission
from codesign import _sections as sections
from codesign._task import Task

__version__, IPOPT_VERSION = _versions()

__all__ = [
    "Capacity",
    "CheckReport",
    "Ends",
    "Error",
    "InputError",
    "IPOPT_VERSION",
    "LimitMode",
    "LinearSolver",
    "Method",
    "Robot",
    "Run",
    "Solution",
    "SolverError",
    "Space",
    "Task",
    "Transmission",
    "__version__",
    "parts",
    "sections",
]
