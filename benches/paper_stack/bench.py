"""Wall time of trajectory solves with the paper's stack (CasADi + IPOPT + MUMPS), the comparison
point of `cargo bench --bench solve`.

    python3 benches/paper_stack/bench.py [--runs 7] [--warm-up 1] [--quick] [--jit] [--json FILE]

For each case the problem is built once (CasADi expressions, nlpsol with its derivative
functions); then `warm-up` unmeasured solves and `runs` measured solves from the standard initial
guess, each timed around the `solver(...)` call only. Printed per case: status, iterations, cost,
the median wall time of the solve, and CasADi's own split of that time into the NLP callbacks
(function and derivative evaluations) and the rest (IPOPT with MUMPS).

Cases: the default problem (actuation space, 0 kg, r = (6, 3, 1, 1)); the joint-space problem at
0 kg; actuation at 1 kg, original ratios; and the infeasible actuation problem at 3 kg, original
ratios (fewer runs, it takes hundreds of iterations). `--quick` runs only the default problem.
"""

import argparse
import json
import os
import statistics
import sys
import time

sys.dont_write_bytecode = True  # no __pycache__ beside the sources (not git-ignored)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import casadi  # noqa: E402
import ocp  # noqa: E402

CALLBACK_TIMERS = ("nlp_f", "nlp_g", "nlp_grad_f", "nlp_jac_g", "nlp_hess_l", "nlp_grad")


def measure(name, runs, warm_up, jit, **problem):
    t0 = time.perf_counter()
    p = ocp.TrajectoryOCP(jit=jit, **problem)
    build = time.perf_counter() - t0
    for _ in range(warm_up):
        p.solver(**p.args)
    walls, callbacks, results = [], [], []
    for _ in range(runs):
        t = time.perf_counter()
        sol = p.solver(**p.args)
        walls.append(time.perf_counter() - t)
        stats = p.solver.stats()
        callbacks.append(sum(stats.get("t_wall_" + k, 0.0) for k in CALLBACK_TIMERS))
        results.append(p.result(sol))
    r = results[0]
    assert all(x["iterations"] == r["iterations"] and x["status"] == r["status"] for x in results)
    wall = statistics.median(walls)
    cb = statistics.median(callbacks)
    row = {
        "case": name, "space": p.space, "payload_kg": p.payload_kg, "ratios": p.ratios,
        "status": r["status"], "iterations": r["iterations"], "cost": r["cost"],
        "runs": runs, "median_solve_ms": 1e3 * wall, "min_solve_ms": 1e3 * min(walls),
        "max_solve_ms": 1e3 * max(walls), "median_callbacks_ms": 1e3 * cb,
        "build_ms": 1e3 * build, "ms_per_iteration": 1e3 * wall / max(r["iterations"], 1),
    }
    print(f"{name}: {p.space} space, {p.payload_kg:g} kg, r = {tuple(p.ratios)}: {r['status']} "
          f"({r['iterations']} iterations, J = {r['cost']:.6f}); median of {runs}: "
          f"solve {row['median_solve_ms']:.1f} ms (min {row['min_solve_ms']:.1f}, max "
          f"{row['max_solve_ms']:.1f}), callbacks {row['median_callbacks_ms']:.1f} ms "
          f"({100 * cb / wall:.0f}%), {row['ms_per_iteration']:.2f} ms/iteration; "
          f"build {row['build_ms']:.0f} ms", flush=True)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=7, help="measured solves per case (default 7)")
    ap.add_argument("--heavy-runs", type=int, default=3, help="measured solves of the 3 kg case (default 3)")
    ap.add_argument("--warm-up", type=int, default=1, help="unmeasured solves first (default 1)")
    ap.add_argument("--quick", action="store_true", help="only the default problem")
    ap.add_argument("--jit", action="store_true",
                    help="compile the NLP's functions to C first (CasADi jit, needs a C compiler)")
    ap.add_argument("--json", help="also write the rows to this file")
    args = ap.parse_args()

    print(f"CasADi {casadi.__version__}, IPOPT via nlpsol, linear solver MUMPS, "
          f"{'jit-compiled' if args.jit else 'SX virtual machine'} callbacks", flush=True)
    rows = [measure("default", args.runs, args.warm_up, args.jit,
                    space="actuation", payload_kg=0.0, ratios=[6, 3, 1, 1])]
    if not args.quick:
        rows.append(measure("joint", args.runs, args.warm_up, args.jit,
                            space="joint", payload_kg=0.0, ratios=[6, 3, 1, 1]))
        rows.append(measure("1 kg", args.runs, args.warm_up, args.jit,
                            space="actuation", payload_kg=1.0, ratios=[6, 3, 1, 1]))
        rows.append(measure("3 kg (infeasible)", args.heavy_runs, min(args.warm_up, 1), args.jit,
                            space="actuation", payload_kg=3.0, ratios=[6, 3, 1, 1]))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
