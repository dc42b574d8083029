"""The robot: its joints, its dynamics and, for a task's robot, its transmission.

It mirrors the core's ``Robot`` and ``Dynamics`` (``codesign_core::model::Robot``,
``codesign_core::dynamics::Dynamics``), in Pinocchio's spirit: a model loaded once, then free
evaluations at a state. Units are SI: q in rad (m for a prismatic joint), v in rad/s, a in
rad/s^2, torques in N m, positions in m; joint vectors in the chain's order, base outward.
"""

from __future__ import annotations

import os
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

from codesign import _native
from codesign._keywords import design


class Robot:
    """A serial robot: kinematics and mass properties from a URDF, with gravity, a tool centre
    point (TCP) and a payload.

    >>> robot = Robot.from_urdf("robots/belt_arm.urdf")
    >>> robot.rnea(q, v, a)            # joint torques, N m
    """

    def __init__(self, native: "_native.NativeRobot"):
        self._native = native

    @classmethod
    def from_urdf(cls, path: Union[str, os.PathLike]) -> "Robot":
        """The URDF at ``path`` alone: gravity 9.81 m/s^2 down world z, the TCP at the origin of
        its chain's tip link, no payload and no transmission."""
        return cls(_native.NativeRobot.from_urdf(os.fspath(path)))

    @property
    def joint_names(self) -> List[str]:
        """The moving joints' names, base outward."""
        return self._native.joint_names()

    @property
    def dof(self) -> int:
        """The number of moving joints."""
        return len(self.joint_names)

    @property
    def position_limits(self) -> np.ndarray:
        """Each joint's (lower, upper) position limits, shape (n, 2), rad (m if prismatic)."""
        return np.array(self._native.position_limits(), dtype=float).reshape(-1, 2)

    @property
    def payload(self) -> float:
        """The payload carried at the task's payload point, kg."""
        return self._native.payload()

    def rnea(self, q: Sequence[float], v: Sequence[float], a: Sequence[float]) -> np.ndarray:
        """Inverse dynamics tau = M(q) a + b(q, v), N m, shape (n,)."""
        return self._native.rnea(design("q", q), design("v", v), design("a", a))

    def mass_matrix(self, q: Sequence[float]) -> np.ndarray:
        """The joint-space mass matrix M(q), kg m^2, shape (n, n)."""
        return self._native.mass_matrix(design("q", q))

    def tcp(self, q: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
        """The TCP's world position p(q), m, shape (3,), and its Jacobian dp/dq, shape (3, n)."""
        return self._native.tcp(design("q", q))


class Transmission:
    """A task's transmission G(q; r): motor angles q_u = gamma(q), speeds G v, joint torques
    G^T tau_u. Rows are motors, columns joints; ratios are the design parameters r."""

    def __init__(self, native: "_native.NativeRobot"):
        self._native = native
        original, bounds = native.design()
        self._original = np.array(original, dtype=float)
        self._bounds = np.array(bounds, dtype=float).reshape(-1, 2)

    @property
    def original(self) -> np.ndarray:
        """The task's original design r, shape (ratios,)."""
        return self._original.copy()

    @property
    def bounds(self) -> np.ndarray:
        """Each ratio's (lower, upper) bounds, shape (ratios, 2)."""
        return self._bounds.copy()

    def matrix(
        self, ratios: Optional[Sequence[float]] = None, q: Optional[Sequence[float]] = None
    ) -> np.ndarray:
        """G at the design ``ratios`` (default: the original) and the pose ``q`` (rad; default:
        the zero pose), shape (motors, joints). A constant G does not depend on q."""
        ratios = self._original if ratios is None else ratios
        q = np.zeros(self._native_dof()) if q is None else q
        return self._native.ratio_matrix(design("ratios", ratios), design("q", q))

    def _native_dof(self) -> int:
        return len(self._native.joint_names())
