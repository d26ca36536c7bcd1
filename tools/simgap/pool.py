#!/usr/bin/env python3
"""Pools `score.py --results` files into the README's per-class table (issue 16).

Each results file holds one case set's outcomes (score.py). This prints, per generator class, how
many cases were named right over every case and over the cases the recording shows: the
fitted-levels oracle (oracle.py, `oracle_z_fitted`) at z >= 5, or, for bias steps, whose
second-order statistics are a rate random walk's and whose oracle knows the step times, the step
kurtosis at z >= 3.5 against phase-randomised surrogates (step_gaussianity.py). Controls, spikes
and the quantiser count as shown, as does a case without an oracle (a noise burst). The rows are
markdown, as the README's table has them.

Usage:
    pool.py RESULTS.json [RESULTS.json ...] [--min-z 5] [--min-step-z 3.5] [--misses]
"""

import argparse
import json
import os
from collections import Counter

import numpy as np

from independent_cases import CLASSES as GENERATOR_CLASSES
from step_gaussianity import gaussianity_z

# The generator's classes, each added later one beside the class it extends (the README's order).
LATER = {"long_warmup": "warmup", "bias_jumps_mid": "bias_jumps"}
CLASSES = [k for base in GENERATOR_CLASSES if base not in LATER for k in [base] + [c for c, p in LATER.items() if p == base]]
STEP_CLASSES = ("bias_jumps", "bias_jumps_mid")
ALWAYS_SHOWN = ("none", "spikes", "quantization")


def shown(case, case_dir, min_z, min_step_z):
    """Whether the recording shows the case's effect (module docs)."""
    klass = case["klass"]
    if klass in ALWAYS_SHOWN:
        return True
    if klass in STEP_CLASSES:
        x = np.loadtxt(os.path.join(case_dir, case["file"]), delimiter=",", skiprows=1, usecols=1)
        return gaussianity_z(x, case["rate_hz"], case["seed"]) >= min_step_z
    z = case.get("oracle_z_fitted")
    return z is None or z >= min_z


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", nargs="+")
    ap.add_argument("--min-z", type=float, default=5.0)
    ap.add_argument("--min-step-z", type=float, default=3.5)
    ap.add_argument("--misses", action="store_true", help="list every case named wrong")
    a = ap.parse_args()
    every, every_right, seen, seen_right = Counter(), Counter(), Counter(), Counter()
    misses = []
    for path in a.results:
        with open(path) as f:
            doc = json.load(f)
        for case in doc["cases"]:
            result = case.get("result", {})
            if "error" in result or "correct" not in result:
                raise SystemExit(f"{path}: case {case['seed']} has no outcome: {result.get('error', 'not run')}")
            klass, right = case["klass"], bool(result["correct"])
            every[klass] += 1
            every_right[klass] += right
            visible = shown(case, doc["manifest_dir"], a.min_z, a.min_step_z)
            if visible:
                seen[klass] += 1
                seen_right[klass] += right
            if not right:
                misses.append((case["seed"], case.get("sub"), case["floor"], case.get("oracle_z_fitted"),
                               result.get("outcome"), result.get("verdict"), visible))
    classes = [k for k in CLASSES if every[k]] + sorted(k for k in every if k not in CLASSES)

    def row(name, total, right):
        cells = [f"{right[k]}/{total[k]}" if total[k] else "" for k in classes]
        return f"| {name} | " + " | ".join(cells) + f" | {sum(right.values())}/{sum(total.values())} |"

    print("| | " + " | ".join(classes) + " | all |")
    print("|---" * (len(classes) + 2) + "|")
    print(row("every case", every, every_right))
    print(row("where the recording shows it", seen, seen_right))
    if a.misses:
        print()
        for seed, sub, floor, z, outcome, verdict, visible in sorted(misses):
            zs = "-" if z is None else f"{z:.1f}"
            print(f"{seed:>5} {sub:<26} {floor:<13} fitted z {zs:>5}  -> {outcome} ({verdict})"
                  f"{'' if visible else '  [not shown]'}")


if __name__ == "__main__":
    main()
