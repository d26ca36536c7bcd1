#!/usr/bin/env python3
"""How low can a per-motion angle error go on these recordings? (issue 13, the per-turn target)

Reads motion-injected files (`gyrocomp motion` output: t_s, the gyro column, truth_dps, moving;
e.g. the files `tools/eval/motion_matrix.py --out DIR` leaves) and scores *predictors of the drift
that know the publisher's flags*, on the sensor error e = gyro - truth:

- the white-noise floor of each motion, 0.674 * N * sqrt(T), N from the static samples' first
  differences (sigma_diff / sqrt(2) * sqrt(dt));
- boxcar means of the last L seconds of static samples before each motion (L = 60 s is the
  `last-static` ZARU reference of `gyrocomp eval --protocol motion`);
- exponentially forgetting means over the static samples (the form of a random-walk Kalman
  tracker's weights), time constant tau;
- the least-squares linear predictor: weights (summing to one) on the 10 s block means of the last
  600 s of static samples, fitted to the motions' own mean errors (angle-weighted). Fitted
  **in-sample** it is an optimistic bound on every linear predictor of that history; the
  leave-one-recording-out figure beside it fits on the other recordings and scores on the held-out
  one.

Each figure is the pooled median per-motion angle error over the pooled median floor, as
`motion_matrix.py` prints it. What it shows: with the bias these units have, no linear causal
estimate from the static gyro history gets the per-turn error much below ~1.3x the floor.

Usage: tools/eval/per_turn_bound.py DIR [--profile turns] [--column gx_dps]
"""
import argparse
import glob
import os

import numpy as np

BLOCK_S = 10.0
HISTORY_BLOCKS = 60


def motions(path, column):
    """Sensor error, dt and the (start, end) index pairs of each flagged motion of one file."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    a = np.loadtxt(path, delimiter=",", skiprows=1)
    col = {name: i for i, name in enumerate(header)}
    e = a[:, col[column]] - a[:, col["truth_dps"]]
    moving = a[:, col["moving"]].astype(bool)
    dt = float(np.median(np.diff(a[:, col["t_s"]])))
    edges = np.diff(np.concatenate([[0], moving.astype(int), [0]]))
    return e, moving, dt, list(zip(np.where(edges == 1)[0], np.where(edges == -1)[0]))


def ratio(errors, floors):
    return float(np.nanmedian(errors) / np.median(floors))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--profile", default="turns")
    ap.add_argument("--column", default="gx_dps")
    a = ap.parse_args()
    files = sorted(glob.glob(os.path.join(a.dir, f"*_{a.profile}_s*.csv")))
    if not files:
        raise SystemExit(f"no *_{a.profile}_s*.csv files in {a.dir}")
    boxcars = (20, 40, 60, 100, 200, 600)
    taus = (15, 30, 45, 60, 90, 200)
    err_box = {L: [] for L in boxcars}
    floors = []
    hist = []  # per motion: recording, block means (newest first), mean error over the motion, T, floor
    for path in files:
        e, moving, dt, segs = motions(path, a.column)
        static = np.where(~moving)[0]
        n_white = np.std(np.diff(e[static])) / np.sqrt(2) * np.sqrt(dt)
        block = int(round(BLOCK_S / dt))
        recording = os.path.basename(path).split(f"_{a.profile}_")[0]
        for s, o in segs:
            T = (o - s) * dt
            floor = 0.674 * n_white * np.sqrt(T)
            floors.append(floor)
            past = static[static < s]
            for L in boxcars:
                p = past[-int(L / dt):]
                err_box[L].append(abs(np.sum(e[s:o] - e[p].mean()) * dt) if len(p) else np.nan)
            if len(past) >= block * HISTORY_BLOCKS:
                tail = e[past[-block * HISTORY_BLOCKS:]][::-1]
                hist.append((recording, tail.reshape(HISTORY_BLOCKS, block).mean(1), e[s:o].mean(), T, floor))
    print(f"{len(floors)} motions ({a.profile}) in {len(files)} files; floor median {np.median(floors):.4f} deg")
    print("boxcar of the last L s of static samples:  "
          + "  ".join(f"{L} s {ratio(err_box[L], floors):.3f}" for L in boxcars))
    rec = np.array([h[0] for h in hist])
    X = np.array([h[1] for h in hist])
    y = np.array([h[2] for h in hist])
    T = np.array([h[3] for h in hist])
    fl = np.array([h[4] for h in hist])
    print(f"on the {len(hist)} motions with {HISTORY_BLOCKS * BLOCK_S:.0f} s of static history:")
    exp_line = []
    for tau in taus:
        w = np.exp(-(np.arange(HISTORY_BLOCKS) + 0.5) * BLOCK_S / tau)
        exp_line.append(f"{tau} s {ratio(np.abs((y - X @ (w / w.sum())) * T), fl):.3f}")
    print("  exponential forgetting, tau:  " + "  ".join(exp_line))

    def fit(rows):
        A = (X[rows, 1:] - X[rows, :1]) * T[rows, None]
        w, *_ = np.linalg.lstsq(A, (y[rows] - X[rows, 0]) * T[rows], rcond=None)
        return np.concatenate([[1 - w.sum()], w])

    w_in = fit(np.ones(len(y), bool))
    print(f"  least-squares linear predictor, in-sample (optimistic): {ratio(np.abs((y - X @ w_in) * T), fl):.3f}")
    held = np.empty(len(y))
    for r in np.unique(rec):
        w = fit(rec != r)
        held[rec == r] = np.abs((y[rec == r] - X[rec == r] @ w) * T[rec == r])
    print(f"  least-squares linear predictor, leave one recording out: {ratio(held, fl):.3f}")
    print("  its weights, cumulative over the newest 10/30/60/100/300/600 s: "
          + " ".join(f"{c:.2f}" for c in np.cumsum(w_in)[[0, 2, 5, 9, 29, 59]]))


if __name__ == "__main__":
    main()
