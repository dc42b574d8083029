"""A payload sweep of the paper's arm at its original gear ratios, in both spaces: the optimal
cost J and the peak motor torque against the payload, each solve warm-started from the last.

    python3 examples/python/payload_sweep.py      # writes payload_sweep.svg beside this file
"""

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import codesign as cd  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
PAYLOADS = np.arange(0.0, 3.01, 0.25)


def sweep(task: cd.Task, space: str):
    """J, feasibility and peak motor torque per payload, each solve started from the last."""
    costs, feasible, peaks, previous = [], [], [], None
    for payload in PAYLOADS:
        sol = task.solve(space=space, payload=float(payload), start=previous)
        costs.append(sol.cost)
        feasible.append(sol.feasible)
        peaks.append(np.abs(sol.tau_u).max())
        previous = sol if sol.feasible else None
        print(f"{space:9} {payload:4.2f} kg: {sol}")
    return np.array(costs), np.array(feasible), np.array(peaks)


def main() -> None:
    task = cd.Task.builtin()
    limit = task.to_dict()["motors"]["torque_limit_nm"]
    figure, (cost_axes, torque_axes) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for space, colour in (("actuation", "tab:blue"), ("joint", "tab:orange")):
        costs, feasible, peaks = sweep(task, space)
        cost_axes.plot(PAYLOADS[feasible], costs[feasible], "o-", color=colour, label=space)
        cost_axes.plot(PAYLOADS[~feasible], costs[~feasible], "x", color=colour,
                       label=f"{space}: infeasible")
        torque_axes.plot(PAYLOADS, peaks, "o-", color=colour, label=space)
    torque_axes.axhline(limit, color="k", linestyle="--", label=f"motor limit {limit} N m")
    cost_axes.set(xlabel="payload (kg)", ylabel="optimal cost J", yscale="log",
                  title=f"original design r = {tuple(task.to_dict()['transmission']['original'])}")
    torque_axes.set(xlabel="payload (kg)", ylabel="peak |motor torque| (N m)",
                    title="peak motor torque along the optimal motion")
    for axes in (cost_axes, torque_axes):
        axes.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")
    plt.rcParams["svg.hashsalt"] = "codesign"
    figure.savefig(HERE / "payload_sweep.svg", metadata={"Date": None})


if __name__ == "__main__":
    main()
