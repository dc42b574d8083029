"""The sections of a task as typed objects: a task written in code, field by field, with the
units in the names, as well as read from JSON (``Task.from_sections``).

Each section mirrors the core's type of the same name (``codesign_core::model::task``) and
becomes the JSON the task file would hold; the task is then checked as a file is, and its hash
is that of the same task read from JSON. Units: m, kg, s, rad, N m.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from enum import Enum
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from codesign._choices import Ends, LimitMode

Number = float
PerMotor = Union[float, Sequence[float]]


def _plain(value: Any) -> Any:
    """``value`` as JSON data: enums as their names, tuples as lists, None-valued keys dropped."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items() if item is not None}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if isinstance(value, Enum):
        return value.value
    return value


@dataclass
class PointOnLink:
    """A point fixed in a link's frame."""

    link: str
    point: Tuple[Number, Number, Number] = (0.0, 0.0, 0.0)


@dataclass
class Payload:
    """A point-mass payload: ``mass_kg`` at ``at``."""

    mass_kg: Number
    at: PointOnLink


@dataclass
class ViaJoints:
    """Joint angles the motion passes: each joint within ``tol_rad`` of ``q`` (rad, one per moving
    joint) at the node nearest ``t_s`` seconds, or, with ``t_s=None`` and ``window_s=(t_a,
    t_b)``, at a time the solve chooses within that window."""

    t_s: Optional[Number]
    q: Sequence[Number]
    tol_rad: Number
    window_s: Optional[Tuple[Number, Number]] = None


@dataclass
class ViaTcp:
    """A TCP position the motion passes: the TCP within ``tol_m`` of the world point ``tcp`` (m)
    at the node nearest ``t_s`` seconds, or, with ``t_s=None`` and ``window_s=(t_a, t_b)``, at a
    time the solve chooses within that window."""

    t_s: Optional[Number]
    tcp: Tuple[Number, Number, Number]
    tol_m: Number
    window_s: Optional[Tuple[Number, Number]] = None


@dataclass
class TcpGoal:
    """A goal given as a TCP position: the TCP within ``tol_m`` (m, at least 1e-6) of the world
    point ``tcp`` (m) at the last node, whose joint angles the solve chooses within the joint
    limits; the motion rests there."""

    tcp: Tuple[Number, Number, Number]
    tol_m: Number


@dataclass
class Upright:
    """``link``'s ``axis`` (in the link's frame) within ``tol_rad`` of the world's vertical at
    every node."""

    link: str
    axis: Tuple[Number, Number, Number]
    tol_rad: Number


@dataclass
class Motion:
    """The motion: from ``start`` to ``goal`` (joint positions, rad, or a :class:`TcpGoal`) in
    ``horizon_s`` seconds (or
    a free duration, ``{"free": [T_min, T_max]}``) on ``steps`` intervals, with what it asks at its
    ends, the points it passes (``via``: :class:`ViaJoints` or :class:`ViaTcp`, each at a time of
    a fixed duration) and a link it holds ``upright`` (:class:`Upright`)."""

    start: Sequence[Number]
    goal: Union[Sequence[Number], TcpGoal]
    horizon_s: Union[Number, Dict[str, Sequence[Number]]]
    steps: int = 50
    ends: Union[Ends, str] = Ends.HOLD
    via: List[Union[ViaJoints, ViaTcp]] = field(default_factory=list)
    upright: Optional[Upright] = None


@dataclass
class MotionEntry:
    """One motion of a task's several (``motions``): its ``name`` (unique), its ``weight`` in the
    task's score, its payload (``payload_kg``, kg) and the fields of :class:`Motion` it changes
    (its via points and upright link among them); a field left as None is the task's."""

    name: str
    weight: Number = 1.0
    payload_kg: Optional[Number] = None
    start: Optional[Sequence[Number]] = None
    goal: Union[None, Sequence[Number], TcpGoal] = None
    horizon_s: Union[None, Number, Dict[str, Sequence[Number]]] = None
    steps: Optional[int] = None
    ends: Union[None, Ends, str] = None
    via: Optional[List[Union[ViaJoints, ViaTcp]]] = None
    upright: Optional[Upright] = None


class MotionsScore(str, Enum):
    """How a task's motions make one score: ``SUM`` of w_i J_i (the default) or the ``WORST``."""

    SUM = "sum"
    WORST = "worst"


@dataclass
class Weights:
    """The weights of J: ``position`` per rad^2, ``velocity`` per (rad/s)^2, ``control`` per
    (N m)^2, ``time`` per s (the duration's term w_T T; 0 leaves it out)."""

    position: Number = 0.01
    velocity: Number = 0.01
    control: Number = 0.001
    time: Number = 0.0


@dataclass
class SoftInterval:
    """A soft interval [lower, upper] (m) on one world coordinate of the TCP, penalised by
    ``weight`` (per m^2) times the violation squared."""

    range: Tuple[Number, Number]
    weight: Number


@dataclass
class CartesianBox:
    """The soft box on the TCP, per world axis (an axis left out is free)."""

    x: Optional[SoftInterval] = None
    y: Optional[SoftInterval] = None
    z: Optional[SoftInterval] = None


@dataclass
class Part:
    """A motor of a catalogue (docs/guide/catalogue.md): the catalogue file, relative to the
    task's folder unless absolute, and the motor's ``name`` in it."""

    catalogue: str
    name: str


@dataclass
class Motors:
    """The motors, one value for all or one per motor (row of G): torque limits (N m) and speed
    limits (rad/s); the optional fields as the task file documents them. ``parts``, one
    catalogue motor per motor, sets the figures its motors' parts give (the limits among them,
    which may then be left out)."""

    torque_limit_nm: Optional[PerMotor] = None
    speed_limit_rad_s: Optional[PerMotor] = None
    rotor_inertia_kgm2: Optional[PerMotor] = None
    viscous_friction_nm_s_per_rad: Optional[PerMotor] = None
    no_load_speed_rad_s: Optional[PerMotor] = None
    torque_constant_nm_per_a: Optional[PerMotor] = None
    resistance_ohm: Optional[PerMotor] = None
    efficiency: Optional[PerMotor] = None
    names: Optional[List[str]] = None
    parts: Optional[List[Part]] = None


@dataclass
class TransmissionSpec:
    """G(r): ``matrix`` rows of numbers, ``"r<i>"``, ``"-r<i>"`` or ``"k*r<i>"`` (or linkage
    rows, as dicts), the ``original`` design, its ``bounds`` and ``order`` constraints."""

    matrix: List[List[Any]]
    original: Sequence[Number]
    bounds: Sequence[Tuple[Number, Number]]
    order: List[str] = field(default_factory=list)


@dataclass
class LimitModes:
    """How the motors' limits become joint limits: ``torque`` and ``speed`` modes."""

    torque: Union[LimitMode, str] = LimitMode.PAPER
    speed: Union[LimitMode, str] = LimitMode.EXACT


def task_document(
    robot: Optional[str],
    tcp: PointOnLink,
    payload: Payload,
    motion: Motion,
    motors: Motors,
    transmission: TransmissionSpec,
    weights: Weights,
    cartesian_box: CartesianBox,
    limit_modes: LimitModes,
    gravity: Tuple[Number, Number, Number],
    solver: Optional[Dict[str, Any]],
    motions: Optional[Sequence[MotionEntry]] = None,
    motions_score: Union[None, MotionsScore, str] = None,
    carried: Optional[Sequence[Dict[str, Any]]] = None,
) -> Dict[str, Any]:
    """The task file's JSON data of these sections (``motions``, ``motions_score`` and
    ``carried`` written only where given)."""
    document = {
        "robot": robot,
        "gravity": list(gravity),
        "tcp": asdict(tcp),
        "payload": asdict(payload),
        "motion": asdict(motion),
        "weights": asdict(weights),
        "cartesian_box": asdict(cartesian_box),
        "motors": asdict(motors),
        "transmission": asdict(transmission),
        "limit_modes": asdict(limit_modes),
    }
    if motions is not None:
        document["motions"] = [asdict(entry) for entry in motions]
    if motions_score is not None:
        document["motions_score"] = motions_score
    if carried is not None:
        document["carried"] = [dict(part) for part in carried]
    document = _plain(document)
    if not document["motion"]["via"]:
        del document["motion"]["via"]
    document["robot"] = robot
    if solver is not None:
        document["solver"] = solver
    return document
