"""Warm-started finite differences: dJ*/dr of the paper's arm with motor dynamics (rotor
inertias, viscous friction, a torque-speed envelope) at 1 kg, by central differences started
cold and started from the solution at r, beside the exact sensitivity the solve reports.

Started cold, the solves at r +- h land in other local optima (J = 116.7 instead of 118.5), and
their difference is no derivative; started from the solution at r they stay on its branch.

    python3 examples/python/continuation.py      # writes continuation.svg beside this file
"""

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import codesign as cd  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
DESIGN = np.array([9.0, 5.62, 3.0, 1.8])
STEP = 1e-3
#: The ratios strictly inside their bounds (r1 = 9 and r3 = 3 are on theirs): r2 and r4.
INTERIOR = [1, 3]


def motor_task() -> cd.Task:
    """The built-in task with the motors' rotor inertia, friction and envelope."""
    return cd.Task.builtin().with_changes(
        motors={
            "rotor_inertia_kgm2": [2e-5, 2e-5, 1e-5, 1e-5],
            "viscous_friction_nm_s_per_rad": 1e-4,
            "no_load_speed_rad_s": 150.0,
        }
    )


def central(task: cd.Task, base: cd.Solution, index: int, start) -> float:
    """(J*(r + h e_i) - J*(r - h e_i)) / 2h, each solve from ``start``."""
    step = np.zeros(len(DESIGN))
    step[index] = STEP
    ends = [task.solve(payload=1.0, ratios=DESIGN + s * step, start=start) for s in (1, -1)]
    return (ends[0].cost - ends[1].cost) / (2 * STEP)


def differences(task: cd.Task):
    """The solution at r, and the cold and warm central differences of the interior ratios."""
    base = task.solve(payload=1.0, ratios=DESIGN)
    cold = np.array([central(task, base, i, None) for i in INTERIOR])
    warm = np.array([central(task, base, i, base) for i in INTERIOR])
    return base, cold, warm


def main() -> None:
    base, cold, warm = differences(motor_task())
    print(f"at r = {DESIGN.tolist()}: {base}")
    exact_interior = base.cost_gradient[INTERIOR]
    for i, exact, c, w in zip(INTERIOR, exact_interior, cold, warm):
        print(f"  dJ*/dr{i + 1}: exact {exact:+.6f}, cold {c:+.6f}, warm {w:+.6f} "
              f"(warm off by {abs(w - exact) / abs(exact):.1e} relative)")
    figure, axes = plt.subplots(figsize=(7, 4), constrained_layout=True)
    x = np.arange(len(INTERIOR))
    for offset, values, label in ((-0.25, exact_interior, "exact (envelope theorem)"),
                                  (0.0, warm, "central differences, warm start"),
                                  (0.25, cold, "central differences, cold start")):
        axes.bar(x + offset, values, width=0.25, label=label)
    axes.set_xticks(x, [f"r{i + 1}" for i in INTERIOR])
    axes.set(ylabel="dJ*/dr", title=f"sensitivity at r = {DESIGN.tolist()}, 1 kg, h = {STEP}")
    axes.axhline(0.0, color="k", linewidth=0.5)
    axes.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")
    plt.rcParams["svg.hashsalt"] = "codesign"
    figure.savefig(HERE / "continuation.svg", metadata={"Date": None})


if __name__ == "__main__":
    main()
