"""Derives the older-version fixtures of `codesign migrate` from current documents.

Usage: python3 derive.py SOLVE CAPACITY OPTIMIZE NONE LOG TABLE

SOLVE, CAPACITY, OPTIMIZE: current results of the planar example (robots/examples/planar_2dof)
at 4 steps; NONE: a co-design run of it that found no feasible design (payload 40 kg); LOG: the
evaluation log of OPTIMIZE; TABLE: the table `codesign table SOLVE OPTIMIZE NONE` wrote. Each fixture
removes or moves what its version did not write (docs/results.md, section 1; the writers' git
history): see README.md.
"""

import json
import sys


def load(path):
    with open(path) as f:
        return json.load(f)


def save(name, value):
    with open(name, "w") as f:
        json.dump(value, f, indent=2)
        f.write("\n")


def envelope(document, version):
    """The document with its envelope at `version`, or none for version 0."""
    body = {k: v for k, v in document.items() if k not in ("schema", "version")}
    if version == 0:
        return body
    return {"schema": document["schema"], "version": version, **body}


def result_v1(result):
    """A trajectory result as version 1 wrote it: no reason when feasible, no motor peaks and
    margins, no physical figures."""
    if result.get("reason") is None:
        result.pop("reason", None)
    for key in ("torque_peak_nm", "speed_peak_rad_s", "torque_margin_nm", "speed_margin_rad_s"):
        result["motors_execute"].pop(key)
    result.pop("figures", None)


def result_v0(result):
    """Older still: the static hold neither judged nor toleranced, no TCP x."""
    result_v1(result)
    result["static_hold"].pop("judged")
    result["static_hold"].pop("tolerance_nm")
    result["trajectory"].pop("tcp_x")


def tool_v0(document):
    """The tool as version 0 wrote it: named `codesign`, no linear solver (only MUMPS)."""
    document["tool"]["name"] = "codesign"
    document["tool"].pop("linear_solver")


def main(solve, capacity, optimize, none, log, table):
    for version, shape in ((1, result_v1), (0, result_v0)):
        document = load(solve)
        document.pop("start_point", None)
        shape(document)
        if version == 0:
            tool_v0(document)
        save(f"solve-v{version}.json", envelope(document, version))

        document = load(capacity)
        inputs = document.pop("inputs")
        if version == 0:
            inputs.pop("ends")
            tool_v0(document)
        flat = {"tool": document.pop("tool"), **inputs, **document}
        save(f"capacity-v{version}.json", envelope({"schema": "codesign/capacity", **flat}, version))

        document = load(optimize)
        for key in ("best_result", "original_result"):
            shape(document[key])
        if version == 0:
            tool_v0(document)
            for key in ("linear_solver", "verdict_rule", "warm_start"):
                document["inputs"].pop(key)
            document.pop("solves")
            document.pop("solve_seconds_total")
            document.pop("verdicts", None)
        save(f"optimize-v{version}.json", envelope(document, version))

    document = load(none)
    document["best_cost"] = document["inputs"]["penalty"]
    save("optimize-v2.json", envelope(document, 2))

    document = load(table)
    for row in document["rows"]:
        after = row.get("after")
        if after and after["best"] is None:
            after["per_seed"] = [[seed, 1e6] for seed, _ in after["per_seed"]]
    save("table-v1.json", envelope(document, 1))

    with open(log) as f:
        lines = [json.loads(line) for line in f]
    header = lines[0]
    header.pop("checksums")
    for key in ("linear_solver", "verdict_rule", "warm_start"):
        header["run"].pop(key)
    entries = []
    for entry in lines[1:]:
        entry.pop("check")
        entry.pop("run_seconds")
        entries.append(entry)
    with open("unchecked.log.jsonl", "w") as f:
        for line in [header] + entries:
            f.write(json.dumps(line, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
