"""The cost of driving codesign from Python: the wall time of Task.solve against the solve's own
time (IPOPT and the callbacks, as the result records it), median over repeated solves.

    pip install ./python && python3 benches/python_overhead.py
"""

import pathlib
import statistics
import time

import codesign as cd

ROOT = pathlib.Path(__file__).resolve().parents[1]
REPEATS = 40


def measure(label: str, task: cd.Task, **keywords) -> None:
    """Prints the median wall time, the in-process solve time, and the median of each call's
    own difference (paired, so that a loaded machine slows both sides of it alike)."""
    walls, solves = [], []
    for _ in range(REPEATS):
        started = time.perf_counter()
        sol = task.solve(**keywords)
        walls.append(time.perf_counter() - started)
        solves.append(sol.to_dict()["solve_seconds"]["total"])
    wall, solve = statistics.median(walls), statistics.median(solves)
    extra = statistics.median(w - s for w, s in zip(walls, solves))
    print(f"{label}: Python {wall * 1e3:.2f} ms, in-process solve {solve * 1e3:.2f} ms, "
          f"overhead per call {extra * 1e3:.2f} ms ({100 * extra / solve:.1f} %)")


def main() -> None:
    measure("built-in arm, actuation, 1 kg", cd.Task.builtin(), payload=1.0)
    measure("built-in arm, joint, 1 kg", cd.Task.builtin(), space="joint", payload=1.0)
    planar = cd.Task.load(ROOT / "robots" / "examples" / "planar_2dof" / "task.json")
    measure("planar 2-DOF, actuation, 1 kg", planar, payload=1.0, ratios=[50, 12])


if __name__ == "__main__":
    main()
