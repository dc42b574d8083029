"""A co-design of the planar 2-DOF example at 1 kg: CMA-ES (population 16, 10 generations, two
worker processes) and the gradient method on the exact dJ*/dr, with the history plotted.

    python3 examples/python/codesign_history.py   # writes codesign_history.svg beside this file
"""

import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import codesign as cd  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def main() -> None:
    task = cd.Task.load(ROOT / "robots" / "examples" / "planar_2dof" / "task.json")
    with tempfile.TemporaryDirectory() as folder:
        run = task.optimize(space="actuation", payload=1.0, method="cmaes", population=16,
                            generations=10, seed=0, workers=2,
                            log=pathlib.Path(folder) / "run.log.jsonl", progress=False)
    gradient = task.optimize(space="actuation", payload=1.0, method="gradient")
    original = task.solve(space="actuation", payload=1.0)
    print(f"original {original}\nCMA-ES   {run}\ngradient {gradient}")
    costs = run.costs
    feasible = costs < 1e6  # the penalty of an infeasible design
    best = np.minimum.accumulate(np.where(feasible, costs, np.inf))
    figure, axes = plt.subplots(figsize=(8, 4), constrained_layout=True)
    evaluations = np.arange(1, len(costs) + 1)
    axes.plot(evaluations[feasible], costs[feasible], ".", color="0.6", label="feasible design")
    axes.plot(evaluations, best, "-", color="tab:blue", label="CMA-ES best so far")
    axes.axhline(gradient.best_cost, color="tab:green", linestyle="--",
                 label=f"gradient method: J = {gradient.best_cost:.3f}")
    axes.axhline(original.cost, color="tab:red", linestyle=":",
                 label=f"original design: J = {original.cost:.3f}")
    axes.set(xlabel="evaluation", ylabel="optimal cost J (infeasible designs left out)",
             yscale="log", title="co-design of the planar 2-DOF arm, 1 kg, actuation space")
    axes.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")
    plt.rcParams["svg.hashsalt"] = "codesign"
    figure.savefig(HERE / "codesign_history.svg", metadata={"Date": None})


if __name__ == "__main__":
    main()
