#!/usr/bin/env python3
"""Pooled motion-injected evaluation (issue 13): static recordings x profiles x seeds.

For each static recording, profile and seed it runs `gyrocomp motion` and then
`gyrocomp eval --protocol motion --json` (default config unless --config), collects the per-motion
angle errors of every model and the white-noise floor of every motion, and prints:
- per recording x profile: median per-motion error of each model, its ratio to bias-hold, the
  ratio of gyrocomp's median to the floor, and the whole-run error;
- per recording x profile, pooled over the seeds: the same medians and ratios (the cells of
  issue 13's "<= 1.0x bias-hold on every recording x profile");
- gyrocomp's motion judgement against the truth (`detection` of the eval JSON, issue 13 item 3):
  motions missed, detection delay (median, p95), moving samples leaked as static and the angle
  they carry, false alarms per hour, per recording x profile and pooled;
- pooled over everything: the median per-motion error of each model / bias-hold's, and the
  whole-run error summed / bias-hold's.

Usage: tools/eval/motion_matrix.py --gyrocomp target/release/gyrocomp --out /tmp/mm \
          --profiles turns,mixed --seeds 1,2,3 REC.csv [REC.csv ...] [--column gx_dps]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{r.stderr}")
    return r.stdout


def empty_detection():
    """An accumulator of gyrocomp's `detection` figures (eval JSON) over runs."""
    return dict(motions=0, missed=0, delays=[], moving=0, leaked=0, leaked_deg=[], false_alarms=0, hours=0.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("recordings", nargs="+")
    ap.add_argument("--gyrocomp", default="target/release/gyrocomp")
    ap.add_argument("--out", default="/tmp/motion_matrix")
    ap.add_argument("--profiles", default="turns,mixed")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--column", default="gx_dps")
    ap.add_argument("--config", default=None)
    ap.add_argument("--models", default="gyrocomp,gyrocomp-flagged,bias-hold,last-static")
    ap.add_argument("--json", action="store_true", help="print the pooled figures as JSON")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    models = a.models.split(",")
    pooled = {m: [] for m in models}
    run_err = {m: 0.0 for m in models}
    floors = []
    rows = []
    cells = {}
    det = {}  # (recording, profile) -> pooled detection figures of gyrocomp
    for rec in a.recordings:
        base = os.path.splitext(os.path.basename(rec))[0]
        for prof in a.profiles.split(","):
            for seed in a.seeds.split(","):
                path = os.path.join(a.out, f"{base}_{prof}_s{seed}.csv")
                run([a.gyrocomp, "motion", rec, "--profile", prof, "--seed", seed, "--columns", a.column, "-o", path])
                cmd = [a.gyrocomp, "eval", path, "--protocol", "motion", "--column", a.column, "--models", a.models, "--json"]
                if a.config:
                    cmd += ["--config", a.config]
                out = json.loads(run(cmd))
                by = {m["name"]: m for m in out["models"]}
                floor = out["data"]["white_floor_deg_segments"]
                floors += floor
                cell = cells.setdefault((base, prof), {"floor": [], **{m: [] for m in models}})
                cell["floor"] += floor
                row = {"recording": base, "profile": prof, "seed": seed, "floor": statistics.median(floor) if floor else None}
                d = by.get("gyrocomp", {}).get("detection")
                if d:
                    acc = det.setdefault((base, prof), empty_detection())
                    acc["motions"] += d["motions"]
                    acc["missed"] += d["missed"]
                    acc["delays"] += d["delays_s"]
                    acc["moving"] += d["moving_samples"]
                    acc["leaked"] += d["leaked_samples"]
                    acc["leaked_deg"] += d["leaked_angle_deg_segments"]
                    acc["false_alarms"] += d["false_alarms"]
                    acc["hours"] += out["data"]["samples"] / out["data"]["rate_hz"] / 3600.0
                for m in models:
                    seg = by[m]["angle_err_deg_segments"]
                    pooled[m] += seg
                    cell[m] += seg
                    run_err[m] += by[m]["angle_err_deg_run"]
                    row[m] = (statistics.median(seg) if seg else None, by[m]["angle_err_deg_run"])
                rows.append(row)
    print(f"{'recording':<28} {'profile':<6} {'seed':>4} " + " ".join(f"{m:>18}" for m in models) + "   floor  g/floor  g/bh   run g/bh")
    for r in rows:
        bh = r["bias-hold"][0]
        g = r["gyrocomp"][0]
        print(f"{r['recording']:<28} {r['profile']:<6} {r['seed']:>4} "
              + " ".join(f"{r[m][0]:>18.4f}" for m in models)
              + f"  {r['floor']:.4f}  {g / r['floor']:.2f}    {g / bh:.2f}   {r['gyrocomp'][1] / r['bias-hold'][1]:.2f}")
    print(f"\nper recording x profile, seeds {a.seeds} pooled:")
    print(f"{'recording':<28} {'profile':<6} {'motions':>7} " + " ".join(f"{m:>18}" for m in models) + "   g/floor  g/bh")
    for (base, prof), cell in cells.items():
        med = {m: statistics.median(cell[m]) for m in models}
        print(f"{base:<28} {prof:<6} {len(cell['floor']):>7} " + " ".join(f"{med[m]:>18.4f}" for m in models)
              + f"    {med['gyrocomp'] / statistics.median(cell['floor']):.2f}   {med['gyrocomp'] / med['bias-hold']:.2f}")
    if det:
        print("\ngyrocomp's motion judgement against the truth (delay: first sample judged moving; leaked: moving samples judged static):")
        print(f"{'recording':<28} {'profile':<6} {'missed':>10} {'delay med s':>11} {'delay p95 s':>11} {'leaked':>8} {'leaked deg/motion':>17} {'false alarms/h':>14}")
        pooled_det = {}  # ("pooled", profile) and ("pooled", "all")
        for (base, prof), acc in det.items():
            for key in (("pooled", prof), ("pooled", "all")):
                total = pooled_det.setdefault(key, empty_detection())
                for k in total:
                    total[k] += acc[k]
        for key, acc in list(det.items()) + list(pooled_det.items()):
            q = statistics.quantiles(acc["delays"], n=20)[-1] if len(acc["delays"]) > 1 else float("nan")
            print(f"{key[0]:<28} {key[1]:<6} {acc['missed']:>4}/{acc['motions']:<5} {statistics.median(acc['delays']) if acc['delays'] else float('nan'):>11.2f} {q:>11.2f} "
                  f"{acc['leaked'] / max(acc['moving'], 1):>7.1%} {statistics.median(acc['leaked_deg']):>17.3f} {acc['false_alarms'] / acc['hours']:>14.2f}")
    bh = statistics.median(pooled["bias-hold"])
    summary = {m: {"median_deg": statistics.median(pooled[m]), "ratio_to_bias_hold": statistics.median(pooled[m]) / bh,
                   "run_deg_sum": run_err[m], "run_ratio_to_bias_hold": run_err[m] / run_err["bias-hold"]} for m in models}
    summary["floor_median_deg"] = statistics.median(floors)
    summary["motions"] = len(floors)
    print(f"\npooled over {len(floors)} motions: floor median {summary['floor_median_deg']:.4f} deg")
    for m in models:
        s = summary[m]
        print(f"  {m:<18} median {s['median_deg']:.4f} deg = {s['ratio_to_bias_hold']:.2f}x bias-hold, "
              f"{s['median_deg'] / summary['floor_median_deg']:.2f}x floor; whole-run sum {s['run_deg_sum']:.1f} deg = {s['run_ratio_to_bias_hold']:.2f}x bias-hold")
    if a.json:
        print(json.dumps(summary))


if __name__ == "__main__":
    main()
