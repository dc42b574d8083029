"""The closed sets of names the keywords take, as enums: ``Space.ACTUATION`` where
``"actuation"`` is written. Each member is its name as a string too, so either may be given
and a member compares equal to its name."""

from enum import Enum


class _Choice(str, Enum):
    """A name of a closed set; ``str()`` gives the name as the command line spells it."""

    def __str__(self) -> str:
        return self.value


class Space(_Choice):
    """The controls: joint torques (the baseline) or motor torques (the paper's method)."""

    JOINT = "joint"
    ACTUATION = "actuation"


class LimitMode(_Choice):
    """How the motors' limits become joint limits in the joint space."""

    PAPER = "paper"
    INTERVAL = "interval"
    EXACT = "exact"


class Ends(_Choice):
    """What the motion asks at its ends beyond the start and goal states."""

    PAPER = "paper"
    HOLD = "hold"
    REST = "rest"


class Method(_Choice):
    """The co-design's outer method."""

    CMAES = "cmaes"
    GRADIENT = "gradient"


class LinearSolver(_Choice):
    """The sparse solver inside IPOPT."""

    LDL = "ldl"
    MUMPS = "mumps"
