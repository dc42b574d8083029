"""The results of a task's methods: each wraps the document the command line writes as JSON
(``to_dict()``, ``to_json()``), with its main figures as attributes and its trajectories as numpy
arrays. The fields are documented in ``docs/results.md``."""

from __future__ import annotations

import json
import math
from typing import Any, Dict, List, Optional

import numpy as np

from codesign import _native, _plot


class _Document:
    """A result document: the same JSON object as the command line's ``--out`` file."""

    def __init__(self, text: str) -> None:
        self._text = text
        self._document: Dict[str, Any] = json.loads(text)

    def to_dict(self) -> Dict[str, Any]:
        """The document as a dict (a deep copy: changing it changes nothing here)."""
        return json.loads(self._text)

    def to_json(self) -> str:
        """The document as JSON text, as the command line writes it (without the final newline)."""
        return self._text

    @property
    def schema(self) -> str:
        """The kind of document, e.g. ``codesign/solve``."""
        return self._document["schema"]

    @property
    def version(self) -> int:
        """The version of its schema."""
        return self._document["version"]


_TERMS = ("position", "velocity", "control", "cartesian_box")


class Solution:
    """One solve of the trajectory problem (``codesign solve --out``).

    Node arrays have N+1 rows (nodes k = 0..N, times ``t``); interval arrays have N rows (the
    controls and accelerations of the intervals k = 0..N-1, constant over each). n is the number
    of joints, m the number of motors (m = n). The document stays in the native module until
    ``to_dict()`` or ``to_json()`` asks for it.
    """

    def __init__(self, native: "_native.NativeSolution") -> None:
        self._native = native
        self._text: Optional[str] = None
        t, (q, v, a, tau, tau_u, motor_speed, tcp) = native.arrays()
        self.t: np.ndarray = t
        """Node times, s, shape (N+1,)."""
        self.q: np.ndarray = q
        """Joint positions, rad, shape (N+1, n)."""
        self.v: np.ndarray = v
        """Joint speeds, rad/s, shape (N+1, n)."""
        self.a: np.ndarray = a
        """Joint accelerations per interval, rad/s^2, shape (N, n)."""
        self.tau: np.ndarray = tau
        """Joint torques per interval, N m, shape (N, n)."""
        self.tau_u: np.ndarray = tau_u
        """Motor torques per interval, N m, shape (N, m)."""
        self.motor_speed: np.ndarray = motor_speed
        """Motor speeds per node, rad/s, shape (N+1, m)."""
        self.tcp: np.ndarray = tcp
        """TCP position in the world frame per node, m, shape (N+1, 3)."""
        linkage = native.linkage_arrays()
        self.motor_position: Optional[np.ndarray] = None
        """Each motor's angle per node, rad, shape (N+1, m), where a row of G is a linkage
        (gamma_i(q); G_i q for a constant row); None for a constant transmission."""
        self.ratio: Optional[np.ndarray] = None
        """G(q) per node, shape (N+1, m, n), where a row of G is a linkage; None otherwise."""
        if linkage is not None:
            self.motor_position, flat = linkage
            self.ratio = flat.reshape(len(t), motor_speed.shape[1], q.shape[1])
        status, iterations, ratios, payload, space, task_hash = native.summary()
        self.status: str = status
        """IPOPT's return status of the solve that gave the verdict."""
        self.iterations: int = iterations
        """IPOPT iterations, summed over every start the rule tried."""
        self.ratios: np.ndarray = np.asarray(ratios, dtype=float)
        """The design r solved."""
        self.payload: float = payload
        """The payload, kg."""
        self.space: str = space
        """``joint`` or ``actuation``."""
        self.task_hash: str = task_hash
        """The hash of the task solved (payload aside): equal hashes, equal problems."""
        self.joint_names: List[str] = native.joint_names()
        """The joints' names, the columns of the joint arrays (base outward)."""
        self.motor_names: List[str] = native.motor_names()
        """The motors' names, the columns of the motor arrays (rows of G)."""

    def to_json(self) -> str:
        """The document as JSON text, as ``codesign solve --out`` writes it (without the final
        newline)."""
        if self._text is None:
            self._text = self._native.json()
        return self._text

    def to_dict(self) -> Dict[str, Any]:
        """The document as a dict (a new one at each call)."""
        return json.loads(self.to_json())

    @property
    def schema(self) -> str:
        """``codesign/solve``."""
        return "codesign/solve"

    @property
    def version(self) -> int:
        """The version of the solve schema."""
        return self.to_dict()["version"]

    @property
    def feasible(self) -> bool:
        """Whether the design moves the payload within every limit (one rule: docs/model.md, 8)."""
        return self._native.feasible()

    @property
    def reason(self) -> Optional[str]:
        """Why the design is infeasible; None when feasible."""
        return None if self.feasible else self._native.reason()

    @property
    def cost(self) -> float:
        """The optimal cost J of the trajectory found (a local optimum; meaningful when
        ``feasible``: an infeasible solve's cost is that of the point IPOPT stopped at)."""
        return self._native.cost()

    @property
    def cost_terms(self) -> Optional[Dict[str, float]]:
        """J by term: ``position``, ``velocity``, ``control``, ``cartesian_box``."""
        terms = self._native.cost_terms()
        return None if terms is None else dict(zip(_TERMS, terms))

    @property
    def via_times_s(self) -> List[float]:
        """Each via point's time on the solved grid, s, in the order of ``motion.via`` (empty
        without via points): for a via point with a window (``window_s``), the time the solve
        chose within it."""
        return self.to_dict().get("via_times_s", [])

    @property
    def figures(self) -> Optional[Dict[str, Any]]:
        """Physical figures per motor (``motors[i]``) and in total: int tau_u^2 dt, RMS and peak
        torque, peak speed, peak power and work (docs/results.md, section 3)."""
        text = self._native.figures()
        return None if text is None else json.loads(text)

    @property
    def goal_pose(self) -> Optional[np.ndarray]:
        """The last node's joint angles q_N the solve chose, rad, shape (n,), where the task's
        goal is a TCP position (:class:`codesign.sections.TcpGoal`); None for a joint goal."""
        pose = self.to_dict().get("goal_pose")
        return None if pose is None else np.asarray(pose, dtype=float)

    @property
    def cost_gradient(self) -> Optional[np.ndarray]:
        """dJ*/dr, the exact sensitivity of the optimal cost to each ratio; None when infeasible."""
        gradient = self._native.cost_gradient()
        return None if gradient is None else np.asarray(gradient, dtype=float)

    def resample(self, rate: float) -> Dict[str, np.ndarray]:
        """The trajectory at ``rate`` samples per second (Hz), as ``codesign solve --export
        FILE.csv --rate HZ`` writes it: a dict from each column's name (``time_s``,
        ``q_<joint>_rad``, ..., ``tau_u_<motor>_Nm``, and ``i_u_<motor>_A`` where the task gives
        the motors' torque constants), in the CSV's order, to its values, shape (rows,).

        Rows at t = i / rate from 0 to the motion's end. Between the nodes the speeds follow
        v_k + s a_k and the positions q_k + s v_k+1 (the integration rows, each exact over its
        interval); accelerations, torques and currents are held over each interval; the motors'
        angles and speeds follow the joints through G(q). At the nodes every column is the
        solution's own value (docs/guide/results.md, "Exporting a trajectory for a
        controller"). Raises ``InputError`` for a rate that is not finite and positive or that
        gives more than 200 000 rows, and for a run's best solution, which keeps no robot to
        resample with (solve its design instead)."""
        names, columns = self._native.resample(float(rate))
        return dict(zip(names, columns))

    def plot(self) -> Dict[str, Any]:
        """The charts ``codesign solve --plot`` draws, as matplotlib Figures by the name of the
        file it writes (without ``.svg``): ``joint_positions``, ``joint_torques``,
        ``motor_torques``, ``tcp_path``, ``motor_1_torque_speed``, ... (one per motor), and
        ``linkage_ratios`` where a row of G is a linkage; the same curves, limits, colours and
        titles (an infeasible design's say so, and why). The arm's poses and animation are the
        command line's alone. Needs matplotlib (``ImportError`` saying so without it); raises
        ``InputError`` for a run's best solution, which keeps no robot (solve its design)."""
        plt = _plot.pyplot("Solution.plot()")
        charts = self._native.charts()
        return {
            file[: -len(".svg")]: _plot.draw_chart(plt, json.loads(chart))
            for file, chart in charts
        }

    def __repr__(self) -> str:
        verdict = "feasible" if self.feasible else f"infeasible: {self.reason}"
        return (f"<codesign.Solution {self.space} r={self.ratios.tolist()} "
                f"J={self.cost:.6g} {verdict}>")


class Capacity(_Document):
    """The payload capacity of a design (``codesign capacity --out``)."""

    @property
    def capacity_kg(self) -> Optional[float]:
        """The largest payload found feasible, kg; None when even 0 kg is infeasible."""
        return self._document.get("capacity_kg")

    @property
    def limited_by(self) -> Optional[str]:
        """What bounds the capacity: ``trajectory``, ``hold`` or ``search`` (the largest payload tried)."""
        return self._document.get("limited_by")

    @property
    def hold_kg(self) -> Optional[float]:
        """The most the motors hold at rest at both ends, kg."""
        return self._document.get("hold_kg")

    @property
    def first_infeasible_kg(self) -> Optional[float]:
        """The lightest payload found infeasible, kg; None when the search reached ``max``."""
        return self._document.get("first_infeasible_kg")

    @property
    def ratios(self) -> np.ndarray:
        """The design searched."""
        return np.asarray(self._document["inputs"]["ratios"], dtype=float)

    @property
    def probes(self) -> List[Dict[str, Any]]:
        """Each payload solved, in order, with its verdict."""
        return self._document["probes"]

    def __repr__(self) -> str:
        return f"<codesign.Capacity {self.capacity_kg} kg (limited by {self.limited_by})>"


class Run(_Document):
    """A co-design run (``codesign optimize --out``)."""

    def __init__(self, text: str, result: str, log: Optional[str]) -> None:
        super().__init__(text)
        self.result_file: str = result
        """Where the document was written."""
        self.log_file: Optional[str] = log
        """Its evaluation log (CMA-ES), which ``resume=True`` continues."""

    @property
    def best_ratios(self) -> np.ndarray:
        """The best design found; empty when none was feasible."""
        return np.asarray(self._document["best_ratios"], dtype=float)

    @property
    def best_cost(self) -> Optional[float]:
        """Its fitness (J*, or minus the capacity); None when no design was feasible."""
        return self._document["best_cost"]

    @property
    def costs(self) -> np.ndarray:
        """The fitness of every evaluation, in order."""
        return np.asarray(self._document["costs"], dtype=float)

    @property
    def generations(self) -> List[Dict[str, Any]]:
        """Per CMA-ES generation: its best, mean and spread."""
        return self._document["generations"]

    @property
    def best_result(self) -> Optional[Dict[str, Any]]:
        """The best design's solve, as in a solve document."""
        return self._document.get("best_result")

    @property
    def motion_costs(self) -> Optional[Dict[str, Any]]:
        """For a task with several motions: ``score`` (``"sum"`` or ``"worst"``), and ``best`` and
        ``original``, each motion's ``name``, ``weight``, ``payload_kg``, ``feasible``, ``cost``
        (J_i), ``status`` and full ``result`` at that design; None for a task of one motion."""
        return self._document.get("motion_costs")

    @property
    def best(self) -> Optional[Solution]:
        """The best design's solve as the run made it, a :class:`Solution` (None when no design
        was feasible). It keeps no point to start another solve from: solve its ``ratios`` for
        that."""
        native = _native.NativeSolution.of_run_best(self.to_json())
        return None if native is None else Solution(native)

    def plot(self) -> Any:
        """The cost of every evaluation as a matplotlib Figure: the feasible ones as dots and the
        best so far as a line on a log axis, the penalised ones (infeasible or invalid designs)
        counted in the legend, as the command line's ``cost_evolution`` plots. Needs matplotlib
        (``ImportError`` saying so without it)."""
        plt = _plot.pyplot("Run.plot()")
        inputs = self._document["inputs"]
        costs = [math.inf if c is None else c for c in self._document["costs"]]
        title = (
            f"Cost per evaluation: {inputs['space']} space, {inputs['payload_kg']} kg, "
            f"{inputs.get('method', 'cmaes')}"
            + (f", seed {inputs['seed']}" if "seed" in inputs else "")
        )
        return _plot.cost_history(plt, costs, inputs.get("penalty", math.inf), title)

    def __repr__(self) -> str:
        if self.best_cost is None:
            return "<codesign.Run no feasible design>"
        return f"<codesign.Run best r={self.best_ratios.tolist()} J={self.best_cost:.6g}>"


class CheckReport(_Document):
    """What ``codesign check`` finds before any solve: the joints, the static torques, the hold."""

    def __init__(self, text: str, words: str, problems: List[str], warnings: List[str]) -> None:
        self._text = text
        self._document = json.loads(text)
        self.text: str = words
        """The report as ``codesign check`` prints it."""
        self.problems: List[str] = problems
        """Every error found (what a solve refuses or cannot make sense of); empty when none."""
        self.warnings: List[str] = warnings
        """Every warning found (a solve runs through it); empty when none."""

    @property
    def ok(self) -> bool:
        """Whether no error was found (``codesign check`` exits 0): warnings may remain."""
        return not self.problems

    @property
    def schema(self) -> str:
        """The inspection has no envelope: ``codesign/check``."""
        return "codesign/check"

    @property
    def version(self) -> int:
        """1."""
        return 1

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return (
            f"<codesign.CheckReport {len(self.problems)} problem(s), "
            f"{len(self.warnings)} warning(s)>"
        )
