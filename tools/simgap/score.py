#!/usr/bin/env python3
"""Scores `gyrocomp simgap` on the cases of independent_cases.py (issue 16): runs the diagnosis on
every case of a manifest and prints the confusion matrix per effect class, per magnitude bin and
per sub-class (and, when the manifest has them, per bin of the oracles' evidence, oracle.py: the
known-floor oracle's `oracle_z` and the fitted-levels oracle's `oracle_z_fitted`).

Outcome of a case: the first chosen effect when the verdict is "explained" or "partly explained";
`none` for "no significant gap"; `unexplained` otherwise. It is right when it equals the case's
expected answer (an effect's name; `none` for the pure-IEEE control; `unexplained` for an effect
outside the catalogue).

With `--given-floor` the diagnosis is given the case's noise floor as its simulator
(`gyrocomp simgap --sim`) instead of fitting the IEEE Std 952 terms to the recording: the
sim-to-real use, where the simulator was set up before the recording was made. The floor's white
noise and rate random walk are written as they are; its Gauss-Markov bank, which the simulator
config has no form for, as the flicker floor with the bank's Allan level (`floor_sim_toml`); the
constant bias as the mean of the training part (a turn-on bias no simulator knows).

Usage:
    score.py CASE_DIR [--gyrocomp target/release/gyrocomp] [--jobs 1] [--extra "--threads 1"]
             [--results results.json] [--keep DIR] [--given-floor]
    score.py CASE_DIR --tables-from results.json   (the tables again, against the manifest as it is)
"""

import argparse
import collections
import concurrent.futures
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np

# The span of averaging times over which the Gauss-Markov bank's Allan deviation is taken as a
# flicker floor (independent_cases.py: "flat-ish from ~10 s to ~1000 s"), s.
FLICKER_SPAN_S = (10.0, 2000.0)
# IEEE Std 952: the flicker floor of the Allan deviation is sqrt(2 ln 2 / pi) B.
FLICKER_FLOOR = math.sqrt(2.0 * math.log(2.0) / math.pi)


def gauss_markov_avar(sigma, tau_c, tau):
    """Allan variance of a first-order Gauss-Markov process of stationary sigma and correlation
    time tau_c at averaging time tau (IEEE Std 952-1997, Annex C)."""
    r = tau / tau_c
    return 2.0 * sigma * sigma / r * (1.0 - (3.0 - 4.0 * np.exp(-r) + np.exp(-2.0 * r)) / (2.0 * r))


def floor_sim_toml(floor, rate_hz, duration_s, bias_dps):
    """A `gyrocomp sim` config (TOML) of a case's noise floor (manifest `floors` entry): white
    noise as angle random walk, rate random walk as it is, the Gauss-Markov bank as a flicker
    floor at the geometric mean of the bank's Allan deviation over FLICKER_SPAN_S."""
    lines = [
        f"rate_hz = {rate_hz!r}",
        f"duration_s = {duration_s!r}",
        "",
        "[axis]",
        f"bias_dps = {float(bias_dps)!r}",
        f"arw_deg_rt_h = {floor['white_n'] * 60.0!r}",
        f"rrw_deg_h_rt_h = {floor['rrw_k'] * 3600.0 * 60.0!r}",
    ]
    if floor["gm_bank"]:
        taus = np.geomspace(FLICKER_SPAN_S[0], FLICKER_SPAN_S[1], 25)
        avar = sum(gauss_markov_avar(sg, tc, taus) for sg, tc in floor["gm_bank"])
        level = float(np.exp(np.mean(np.log(np.sqrt(avar)))))
        lines += [
            "",
            "[axis.bias_instability]",
            'model = "flicker"',
            f"b_deg_h = {level / FLICKER_FLOOR * 3600.0!r}",
            f"floor_from_s = {FLICKER_SPAN_S[0]!r}",
            f"floor_to_s = {FLICKER_SPAN_S[1]!r}",
        ]
    return "\n".join(lines) + "\n"


def given_floor_args(case_dir, case, floors, sim_dir):
    """`--sim FILE` for a case: its floor as a simulator config, the bias from the training part
    (the first 70 %, gyrocomp simgap's default split)."""
    x = np.loadtxt(os.path.join(case_dir, case["file"]), delimiter=",", skiprows=1, usecols=1)
    bias = x[: int(round(0.7 * x.size))].mean()
    path = os.path.join(sim_dir, f"floor_{case['seed']}.toml")
    with open(path, "w") as f:
        f.write(floor_sim_toml(floors[case["floor"]], case["rate_hz"], case["duration_s"], bias))
    return ["--sim", path]


def outcome(doc):
    verdict = doc["verdict"]
    if verdict in ("explained", "partly_explained") and doc["chosen"]:
        return doc["chosen"][0]
    if verdict == "no_significant_gap":
        return "none"
    return "unexplained"


def expected_outcome(case):
    return "unexplained" if case["expected"] == "outside" else case["expected"]


def run_case(gyrocomp, case_dir, case, extra, keep=None, given=None):
    if given is not None:
        extra = extra + given_floor_args(case_dir, case, *given)
    cmd = [gyrocomp, "simgap", "--real", os.path.join(case_dir, case["file"]), "--json"] + extra
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.time() - start
    if proc.returncode != 0:
        return dict(seed=case["seed"], error=proc.stderr.strip()[-400:], seconds=seconds)
    doc = json.loads(proc.stdout)
    if keep:
        with open(os.path.join(keep, f"case_{case['seed']}.json"), "w") as f:
            f.write(proc.stdout)
    named = outcome(doc)
    return dict(
        seed=case["seed"],
        outcome=named,
        verdict=doc["verdict"],
        chosen=doc["chosen"],
        tried=doc["tried"],
        gap_before=[doc["gap_before_train"], doc["gap_before"]],
        gap_after=[doc["gap_after_train"], doc["gap_after"]],
        correct=named == expected_outcome(case),
        seconds=seconds,
    )


def oracle_bin(case, key="oracle_z", label="oracle"):
    """The case's oracle evidence (oracle.py) as a bin: below 5 a test that knows the floor and the
    effect exactly has less than a 5-sigma view of it. With key "oracle_z_fitted", the evidence of
    one that knows the effect and only the floor's family (its levels fitted, as the diagnosis's)."""
    z = case.get(key)
    if z is None:
        return f"{label} n/a"
    return f"{label} z < 5" if z < 5 else (f"{label} z 5-10" if z < 10 else f"{label} z >= 10")


def table(title, rows, key):
    groups = collections.OrderedDict()
    for case, res in rows:
        groups.setdefault(key(case), []).append(res)
    outcomes = sorted({r.get("outcome", "error") for _, r in rows})
    print(f"\n{title}")
    head = f"  {'':<34}{'right':>9}  " + " ".join(f"{o[:12]:>12}" for o in outcomes)
    print(head)
    for k, results in groups.items():
        counts = collections.Counter(r.get("outcome", "error") for r in results)
        right = sum(1 for r in results if r.get("correct"))
        print(f"  {k:<34}{right:>4}/{len(results):<4} " + " ".join(f"{counts.get(o, 0):>12}" for o in outcomes))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case_dir")
    ap.add_argument("--gyrocomp", default="target/release/gyrocomp")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--extra", default="", help="more gyrocomp simgap arguments")
    ap.add_argument("--results", help="write per-case results (JSON) here")
    ap.add_argument("--keep", help="keep every case's full diagnosis JSON in this folder")
    ap.add_argument("--only", help="comma-separated classes to run")
    ap.add_argument("--per-class", type=int, help="run only the first N cases of each class")
    ap.add_argument("--given-floor", action="store_true",
                    help="give the diagnosis each case's noise floor as its simulator (module docs)")
    ap.add_argument("--tables-from", metavar="RESULTS",
                    help="run nothing: print the tables of an earlier --results file against this "
                         "manifest's cases (e.g. after the manifest gained a field)")
    a = ap.parse_args()
    with open(os.path.join(a.case_dir, "manifest.json")) as f:
        manifest = json.load(f)
    cases = manifest["cases"]
    if a.only:
        keep = set(a.only.split(","))
        cases = [c for c in cases if c["klass"] in keep]
    if a.per_class is not None:
        seen = collections.Counter()
        kept = []
        for c in cases:
            seen[c["klass"]] += 1
            if seen[c["klass"]] <= a.per_class:
                kept.append(c)
        cases = kept
    if a.tables_from:
        rows = results_rows(cases, a.tables_from)
        print(f"{len(cases)} cases from {a.case_dir} ({manifest['seed_range']} seeds), results of {a.tables_from}")
        print_tables(rows)
        return 0
    extra = shlex.split(a.extra)
    if a.keep:
        os.makedirs(a.keep, exist_ok=True)
    sim_dir = tempfile.mkdtemp(prefix="simgap-floors-") if a.given_floor else None
    given = (manifest["floors"], sim_dir) if a.given_floor else None
    start = time.time()
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = [pool.submit(run_case, a.gyrocomp, a.case_dir, c, extra, a.keep, given) for c in cases]
        results = []
        for c, fut in zip(cases, futures):
            r = fut.result()
            results.append(r)
            mark = "ok " if r.get("correct") else "BAD"
            print(f"{mark} seed {c['seed']:>4} {c['klass']:<13} {c['sub']:<28} {c['floor']:<12} "
                  f"{c['rate_hz']:>5.0f} Hz {c['duration_s']:>6.0f} s bin {str(c['magnitude_bin']):<5} "
                  f"z {'-' if c.get('oracle_z') is None else format(c['oracle_z'], '.1f'):>5} "
                  f"fitted {'-' if c.get('oracle_z_fitted') is None else format(c['oracle_z_fitted'], '.1f'):>5} -> "
                  f"{r.get('outcome', 'ERROR')} ({r.get('verdict', r.get('error', ''))}; tried {r.get('tried')}) "
                  f"{r['seconds']:.1f} s", flush=True)
    rows = list(zip(cases, results))
    print(f"\n{len(cases)} cases from {a.case_dir} ({manifest['seed_range']} seeds), "
          f"{time.time() - start:.0f} s; extra arguments: {a.extra or '(none)'}"
          f"{'; baseline: the given floor (--given-floor)' if a.given_floor else ''}")
    print_tables(rows)
    if a.results:
        with open(a.results, "w") as f:
            json.dump(dict(manifest_dir=a.case_dir, seed_range=manifest["seed_range"],
                           cases=[dict(c, result=r) for c, r in rows]), f, indent=1)
    return 0


def results_rows(cases, path):
    """The manifest's cases paired with their results from an earlier --results file, by seed;
    a case the file lacks is an error (the file is of another manifest)."""
    with open(path) as f:
        earlier = {c["seed"]: c["result"] for c in json.load(f)["cases"]}
    missing = [c["seed"] for c in cases if c["seed"] not in earlier]
    if missing:
        raise SystemExit(f"{path}: no result for seeds {missing[:10]} of this manifest")
    return [(c, earlier[c["seed"]]) for c in cases]


def print_tables(rows):
    """The confusion tables of (case, result) rows and the count of right outcomes."""
    table("By effect class (rows: injected; columns: what was named first)", rows, lambda c: c["klass"])
    table("By effect class and magnitude bin", rows, lambda c: f"{c['klass']} {c['magnitude_bin'] or '-'}")
    table("By sub-class", rows, lambda c: c["sub"])
    table("By noise floor", rows, lambda c: c["floor"])
    cases = [c for c, _ in rows]
    if any("oracle_z" in c for c in cases):
        table("By effect class and oracle evidence (tools/simgap/oracle.py)", rows,
              lambda c: f"{c['klass']} {oracle_bin(c)}")
    if any("oracle_z_fitted" in c for c in cases):
        table("By effect class and fitted-levels oracle evidence (tools/simgap/oracle.py)", rows,
              lambda c: f"{c['klass']} {oracle_bin(c, 'oracle_z_fitted', 'fitted')}")
    right = sum(1 for _, r in rows if r.get("correct"))
    print(f"\nright: {right}/{len(rows)}")


if __name__ == "__main__":
    sys.exit(main())
