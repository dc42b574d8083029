"""The paper's co-design loop on the paper's stack: pygmo's CMA-ES over the gear ratios, each
design's trajectory problem solved by IPOPT through CasADi (`ocp.py`), in one process. The
comparison point of `cargo bench --bench codesign`.

    python3 benches/paper_stack/codesign.py [--seed 0] [--population 16] [--generations 8]
        [--sigma 0.3] [--payload 1] [--ftol 0] [--json]
    python3 benches/paper_stack/codesign.py --agree RUN.log.jsonl [--designs 8]

The outer problem is docs/model.md section 10 with the crate's defaults (`codesign optimize
--space actuation --payload 1`, `--penalty flat`, `--bounds penalty`):

    F(r) = J*(r)  if r is valid and its trajectory problem is feasible,  1e6 otherwise,

judged as the crate judges it, cheapest test first:
- invalid: outside the bounds or the order constraints (r3 <= r2 < r1) of the task's
  `transmission`, or G(r) singular; nothing is solved (pygmo's `force_bounds` is off, as the
  crate's default `--bounds penalty`: samples are evaluated as drawn);
- where the task's `motion.ends` judge the hold (`hold`, `rest`; not the built-in task's
  `paper`), the load not held at rest (docs/model.md section 6, the crate's
  `Static_Hold_Failed`): the motor torques G^-T g(q) that hold the arm and payload still at the
  start or the goal exceed the torque limit (`TrajectoryOCP.static_hold`, RNEA at v = a = 0);
  nothing is solved;
- otherwise one IPOPT solve from the standard initial guess: feasible when IPOPT reports
  Solve_Succeeded or Solved_To_Acceptable_Level.

The NLP is built once with the ratios as its parameter (`TrajectoryOCP(parametric=True)`); each
design is one call of the same `nlpsol`.

CMA-ES is `pygmo.cmaes(gen, sigma0, ftol, xtol=1e-6, memory=False, force_bounds=False,
seed)` evolving `pygmo.population(problem, size=population, seed=seed)`: population + population
x generations evaluations, as the crate. pagmo ends a run when the fitness spread of the last
population is under ftol, also when every design of it scored the penalty (spread 0); the crate
skips that test after a generation with no feasible design (docs/model.md section 10). With
`--ftol 0` (the default here) pygmo does the crate's work: where a generation has a feasible
design its spread is at least 1e6 - J, far above the crate's 1e-6. The output says at which
generation pagmo's own ftol (1e-6) would have ended the run. pygmo draws its designs from its
own random stream (Mersenne twister), so the same seed gives other designs than the crate's.

`--agree LOG` checks this stack against a crate run instead: it judges the designs of the
crate's evaluation log (`codesign optimize ... --out RUN.json` writes `RUN.log.jsonl`) and
compares validity, the static hold, and, for the first `--designs` the crate solved,
feasibility and the cost (to 1e-6 relative); exit status 1 on any disagreement.
"""

import argparse
import json
import math
import os
import re
import statistics
import sys
import time

sys.dont_write_bytecode = True  # no __pycache__ beside the sources (not git-ignored)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import casadi  # noqa: E402
import numpy as np  # noqa: E402
import ocp  # noqa: E402

PENALTY = 1e6
ORDER = re.compile(r"^\s*r(\d+)\s*(<=|<)\s*r(\d+)\s*$")


class Judge:
    """Validity, static hold and solve of designs of one trajectory problem (built once)."""

    def __init__(self, payload_kg):
        self.ocp = ocp.TrajectoryOCP(space="actuation", payload_kg=payload_kg, parametric=True)
        # Under the task's `motion.ends` "paper" (the built-in task's) the hold at rest is no
        # condition of feasibility; under "hold" and "rest" it is (docs/model.md, section 6).
        self.judges_hold = self.ocp.task["motion"].get("ends", "paper") in ("hold", "rest")
        transmission = self.ocp.task["transmission"]
        self.lower = [b[0] for b in transmission["bounds"]]
        self.upper = [b[1] for b in transmission["bounds"]]
        self.order = []
        for text in transmission.get("order", []):
            m = ORDER.match(text)
            if m is None:
                raise ValueError(f"transmission.order: cannot read {text!r}")
            self.order.append((int(m.group(1)) - 1, m.group(2), int(m.group(3)) - 1))

    def valid(self, r):
        """Whether r is in the design space: finite, in the bounds, the order constraints, G(r)
        invertible (the crate's `Transmission::check_design`)."""
        if not all(math.isfinite(v) for v in r):
            return False
        if any(not (lo <= v <= hi) for v, lo, hi in zip(r, self.lower, self.upper)):
            return False
        for a, op, b in self.order:
            if not (r[a] <= r[b] if op == "<=" else r[a] < r[b]):
                return False
        G = ocp.transmission_matrix(self.ocp.task, r)
        return np.linalg.matrix_rank(G) == G.shape[0]

    def judge(self, r):
        """One evaluation: a dict with `kind` (invalid, unheld, feasible, infeasible), `fitness`,
        and for a solve its `status`, `iterations`, `cost` and `seconds`."""
        r = [float(v) for v in r]
        if not self.valid(r):
            return {"kind": "invalid", "fitness": PENALTY}
        if self.judges_hold:
            holds, _ = self.ocp.static_hold(r)
            if not holds:
                return {"kind": "unheld", "fitness": PENALTY}
        t = time.perf_counter()
        res = self.ocp.solve_design(r)
        seconds = time.perf_counter() - t
        return {"kind": "feasible" if res["success"] else "infeasible",
                "fitness": res["cost"] if res["success"] else PENALTY,
                "status": res["status"], "iterations": res["iterations"], "cost": res["cost"],
                "seconds": seconds}


class CodesignProblem:
    """The outer problem as a pygmo user-defined problem; keeps every evaluation in order."""

    def __init__(self, judge, started):
        self.judge = judge
        self.started = started
        self.evaluations = []

    def fitness(self, x):
        e = self.judge.judge(x)
        e["at_seconds"] = time.perf_counter() - self.started
        self.evaluations.append(e)
        return [e["fitness"]]

    def get_bounds(self):
        return (self.judge.lower, self.judge.upper)

    def get_name(self):
        return "gear ratios of the belt arm (paper's stack)"


def first_flat_generation(evaluations, population):
    """The first generation g >= 1 before which pagmo's own ftol (1e-6) would have ended the run:
    the population it was drawn from (generation g - 1, all replaced each generation) scored
    within 1e-6, i.e. all the penalty. None if there is none."""
    groups = [evaluations[i:i + population] for i in range(0, len(evaluations), population)]
    for g in range(1, len(groups) + 1):
        f = [e["fitness"] for e in groups[g - 1]]
        if len(f) == population and max(f) - min(f) < 1e-6:
            return g
    return None


def run(args):
    import pygmo

    t0 = time.perf_counter()
    judge = Judge(args.payload)
    build = time.perf_counter() - t0
    t = time.perf_counter()
    prob = pygmo.problem(CodesignProblem(judge, t0))
    pop = pygmo.population(prob, size=args.population, seed=args.seed)
    algo = pygmo.algorithm(pygmo.cmaes(gen=args.generations, sigma0=args.sigma, ftol=args.ftol,
                                       xtol=1e-6, memory=False, force_bounds=False,
                                       seed=args.seed))
    pop = algo.evolve(pop)
    evolve = time.perf_counter() - t
    udp = pop.problem.extract(CodesignProblem)
    ev = udp.evaluations
    solved = [e for e in ev if "status" in e]
    count = lambda kind: sum(e["kind"] == kind for e in ev)
    best = float(pop.champion_f[0])
    # When the champion was first evaluated, s from the start (the NLP's build included).
    best_at = next((e["at_seconds"] for e in ev if e["fitness"] == best), None)
    return {
        "seed": args.seed, "payload_kg": args.payload, "population": args.population,
        "generations": args.generations, "sigma0": args.sigma, "ftol": args.ftol,
        "evaluations": len(ev), "fevals": pop.problem.get_fevals(),
        "generations_run": (len(ev) - args.population) // args.population,
        "pagmo_ftol_stop_generation": first_flat_generation(ev, args.population),
        "solves": len(solved), "feasible": count("feasible"), "infeasible": count("infeasible"),
        "invalid": count("invalid"), "unheld": count("unheld"),
        "iterations": sum(e["iterations"] for e in solved),
        "solve_seconds": sum(e["seconds"] for e in solved),
        "median_solve_ms": 1e3 * statistics.median([e["seconds"] for e in solved]) if solved else None,
        "build_seconds": build, "evolve_seconds": evolve,
        "best_ratios": [float(v) for v in pop.champion_x], "best_cost": best,
        "best_seconds": best_at,
        "casadi": casadi.__version__, "pygmo": pygmo.__version__,
    }


def agree(args):
    """Judges the designs of a crate run's evaluation log and compares the verdicts."""
    with open(args.agree) as fh:
        lines = [json.loads(line) for line in fh if line.strip()]
    header, records = lines[0], lines[1:]
    payload = header["run"]["payload_kg"]
    if header["run"].get("space") != "actuation":
        raise SystemExit("--agree: the log is not of an actuation-space run")
    judge = Judge(payload)
    solved = 0
    bad = {"validity or hold": 0, "feasibility": 0, "cost": 0}
    for rec in records:
        r, status = rec["ratios"], rec["status"]
        valid = judge.valid(r)
        held = valid and (not judge.judges_hold or judge.ocp.static_hold(r)[0])
        ours_valid = status != "Invalid_Design"
        ours_held = ours_valid and status != "Static_Hold_Failed"
        verdict = f"valid {valid}/{ours_valid}, held {held}/{ours_held}"
        problem = None if (valid, held) == (ours_valid, ours_held) else "validity or hold"
        if problem is None and held and solved < args.designs:
            solved += 1
            e = judge.judge(r)
            feasible = e["kind"] == "feasible"
            if feasible != rec["feasible"]:
                problem = "feasibility"
            elif feasible and abs(e["cost"] - rec["cost"]) > 1e-6 * abs(rec["cost"]):
                problem = "cost"
            verdict += (f", feasible {feasible}/{rec['feasible']}, J {e['cost']:.9f}/"
                        f"{rec['cost']:.9f}, {e['iterations']}/{rec['iterations']} iterations")
        if problem is not None:
            bad[problem] += 1
        if problem is not None or args.verbose:
            print(f"{'ok  ' if problem is None else 'DIFF'} r = {r}: {verdict} (this stack/crate)")
    solver = header["run"].get("linear_solver", "mumps")
    print(f"agreement with {args.agree} (the crate with {solver}): {len(records)} designs "
          f"compared on validity and the static hold, {solved} solved by both on feasibility and "
          f"J (1e-6 relative); disagreements: "
          + ", ".join(f"{kind} {n}" for kind, n in bad.items()))
    if bad["cost"] and solver != "mumps":
        print("(a cost that differs with the crate's ldl is another local optimum along another "
              "iteration path; the crate with --linear-solver mumps takes this stack's path)")
    bad = sum(bad.values())
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=0, help="seed of pygmo's population and cmaes")
    ap.add_argument("--population", type=int, default=16, help="designs per generation (16)")
    ap.add_argument("--generations", type=int, default=8, help="generations after the first (8)")
    ap.add_argument("--sigma", type=float, default=0.3, help="sigma0 (0.3)")
    ap.add_argument("--payload", type=float, default=1.0, help="payload, kg (1)")
    ap.add_argument("--ftol", type=float, default=0.0,
                    help="pagmo's ftol (0: the crate's rule, see above; pagmo's default is 1e-6)")
    ap.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    ap.add_argument("--agree", metavar="LOG", help="compare with a crate run's evaluation log")
    ap.add_argument("--designs", type=int, default=8, help="--agree: solved designs to compare")
    ap.add_argument("--verbose", action="store_true", help="--agree: print every design")
    args = ap.parse_args()
    if args.agree:
        sys.exit(agree(args))
    row = run(args)
    if args.json:
        print(json.dumps(row))
        return
    print(f"pygmo {row['pygmo']} cmaes over CasADi {row['casadi']} + IPOPT (MUMPS), actuation "
          f"space, {row['payload_kg']:g} kg, seed {row['seed']}: best J = {row['best_cost']:.6f} at "
          f"r = {tuple(round(v, 4) for v in row['best_ratios'])}; {row['evaluations']} evaluations "
          f"({row['generations_run']} generations), {row['solves']} solves ({row['feasible']} "
          f"feasible), {row['invalid']} invalid, {row['unheld']} not holding the load; "
          f"{row['iterations']} IPOPT iterations, solves {row['solve_seconds']:.2f} s (median "
          f"{row['median_solve_ms'] or 0:.1f} ms); build {row['build_seconds']:.2f} s, evolve "
          f"{row['evolve_seconds']:.2f} s; pagmo's ftol 1e-6 would have stopped at generation "
          f"{row['pagmo_ftol_stop_generation']}")


if __name__ == "__main__":
    main()
