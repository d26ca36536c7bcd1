#!/usr/bin/env python3
"""How low can the per-motion angle error go when the floor's noise model is known exactly? (issue 13)

On recordings of the independent generator (`tools/simgap/independent_cases.py`, whose manifest
lists each floor's exact terms) with injected motion (`tools/eval/motion_matrix.py --out DIR`),
it runs the *optimal* causal estimator of the drift: a Kalman filter whose model is the
generator's own floor, and which knows the publisher's flags (it updates on every static sample
and on no moving one). Among all estimators that see the same samples and flags, the Kalman filter
with the true model has the least mean-square error of the drift, so its per-motion angle error
is a bound no tracker can beat on average (a median can sit a little below it by chance).

State (one axis), the floor's terms in deg/s (IEEE Std 952; `floor_description` of the generator):

    b_k      = b_{k-1} + w_k,          Var w = K^2 dt          (constant bias + rate random walk)
    g_{i,k}  = phi_i g_{i,k-1} + v_ik, phi_i = exp(-dt/tau_i), Var v = sigma_i^2 (1 - phi_i^2)
    y_k      = b_k + sum_i g_{i,k} + n_k,  Var n = N^2 / dt    (white noise, static samples only)

with b_0 ~ N(0, 1) (the generator's constant bias is uniform in +-1 deg/s) and each g_i started
at its stationary variance. The drift subtracted from sample k is the one-step prediction
H x_{k|k-1}: it uses samples before k only. During a motion the filter only predicts, so the
Gauss-Markov parts decay towards zero and the random walk's variance grows, as they should.

Printed per recording x profile and pooled (median per-motion |sum (e - drift) dt|, e = gyro -
truth): the oracle, start-up bias-hold (mean of the first `--startup-s` s before the first motion,
as `gyrocomp eval --protocol motion`), last-static (the last 60 s of static samples), the
white-noise floor 0.674 N sqrt(T) with the exact N (the fitted one without a manifest), and the oracle's normalised innovation squared
over the static samples (about 1 when the model is the data's: the self-check of this bound).
With `--json` also one JSON line: the pooled medians, the root-mean-square angle errors (the
quantity the filter minimises in expectation, so the oracle's is the smallest) and the NIS of
every file.

With `--fitted` the same filter runs with a model *fitted to each file's own static samples*
instead of the manifest's: a non-negative least-squares fit of the Allan variance (octave blocks of
the static series, motion cut out) to white noise, rate random walk and Gauss-Markov processes at
fixed correlation times (FITTED_TAUS_S), on relative residuals. The fit sees the whole file, so it is
not causal: the figure says how close a multi-time-scale tracker whose model is measured on the unit
could come to the exact-model bound. With `--refit-s S` as well the fit is causal: the model is
refitted every S seconds of static samples on the static samples seen so far (Gauss-Markov states
at all of FITTED_TAUS_S, silent until a fit gives them noise; before the first fit white noise from
the first differences and no drift noise): the prototype of such a tracker.

Usage: tools/eval/oracle_tracker.py DIR [MANIFEST] [--profiles turns,mixed] [--column gx_dps]
                                    [--fitted [--refit-s 120]] [--json]
"""
import argparse
import glob
import json
import math
import os

import numpy as np

from per_turn_bound import motions

LAST_STATIC_S = 60.0
BIAS_PRIOR_VAR = 1.0
FITTED_TAUS_S = (3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)


def gm_avar(sigma2, tc, m, dt):
    """Allan variance at m-sample blocks of a sampled first-order Gauss-Markov process (AR(1),
    variance sigma2, phi = exp(-dt/tc)): Var(block mean) - Cov(adjacent block means), exactly."""
    phi = math.exp(-dt / tc)
    m = np.asarray(m, dtype=float)
    pm = phi ** m
    var = (m + 2.0 * phi * (m * (1.0 - phi) - (1.0 - pm)) / (1.0 - phi) ** 2) / m**2
    cov = phi * (1.0 - pm) ** 2 / (1.0 - phi) ** 2 / m**2
    return sigma2 * (var - cov)


def fitted_floor(e, moving, dt):
    """White noise, rate random walk and a Gauss-Markov bank fitted to the static samples' Allan variance."""
    from scipy.optimize import nnls

    y = e[~moving]
    taus, avars, counts = [], [], []
    m = 1
    while 8 * m <= y.size:
        means = y[: y.size // m * m].reshape(-1, m).mean(1)
        d = np.diff(means)
        taus.append(m * dt)
        avars.append(0.5 * float(np.mean(d * d)))
        counts.append(d.size)
        m *= 2
    tau = np.array(taus)
    av = np.array(avars)
    cols = [1.0 / tau, tau / 3.0] + [gm_avar(1.0, tc, tau / dt, dt) for tc in FITTED_TAUS_S]
    w = np.sqrt(np.array(counts)) / av
    A = np.column_stack(cols) * w[:, None]
    c, _ = nnls(A, av * w)
    bank = [[math.sqrt(v), tc] for v, tc in zip(c[2:], FITTED_TAUS_S) if v > 0]
    return dict(white_n=math.sqrt(c[0]), rrw_k=math.sqrt(c[1]), gm_bank=bank)


def model_noise(model, taus, dt):
    """Per-step process noise of the states [bias, Gauss-Markov at `taus`] and the white variance of
    a floor description (a Gauss-Markov term at a time constant not in `taus` is an error)."""
    q = np.zeros(1 + len(taus))
    q[0] = model["rrw_k"] ** 2 * dt
    for sigma, tau in model["gm_bank"]:
        q[1 + list(taus).index(tau)] = sigma * sigma * (1.0 - math.exp(-2.0 * dt / tau))
    return q, max(model["white_n"] ** 2 / dt, 1e-300)


def kalman_drift(e, moving, dt, taus, q, r, p0, refit=None):
    """One-step drift predictions H x_{k|k-1} of the filter with states [bias, Gauss-Markov at `taus`]
    (updated on static samples only), and its mean NIS. `refit(k)`, called before each static
    update, may return a new (q, r)."""
    phi = np.concatenate([[1.0], np.exp(-dt / np.asarray(taus, dtype=float))])
    F = np.diag(phi)
    Q = np.diag(q)
    x = np.zeros(phi.size)
    P = np.diag(p0)
    drift = np.empty(e.size)
    nis = 0.0
    updates = 0
    for k in range(e.size):
        if k:
            x = phi * x
            P = F @ P @ F.T + Q
        pred = x.sum()
        drift[k] = pred
        if moving[k]:
            continue
        new = refit(k) if refit is not None else None
        if new is not None:
            q, r = new
            Q = np.diag(q)
        hp = P.sum(axis=1)  # P H', H = [1, 1, ...]
        s = hp.sum() + r
        nu = e[k] - pred
        nis += nu * nu / s
        updates += 1
        gain = hp / s
        x = x + gain * nu
        P = P - np.outer(gain, hp)
    return drift, nis / max(updates, 1)


def oracle_drift(e, moving, dt, floor):
    """The filter with a fixed model (the manifest's exact floor, or one fitted in hindsight)."""
    taus = [tau for _, tau in floor["gm_bank"]]
    q, r = model_noise(floor, taus, dt)
    return kalman_drift(e, moving, dt, taus, q, r, [BIAS_PRIOR_VAR] + [s * s for s, _ in floor["gm_bank"]])


def causal_drift(e, moving, dt, refit_s):
    """The filter with its model refitted every `refit_s` seconds of static samples, on the static
    samples before the current one (the Gauss-Markov states at FITTED_TAUS_S, zero noise until a
    fit gives them some); before the first fit: white noise from the first differences, no drift
    noise (a growing mean)."""
    static = np.where(~moving)[0]
    first = e[static[:64]]
    q = np.zeros(1 + len(FITTED_TAUS_S))
    r = max(float(np.var(np.diff(first))) / 2.0, 1e-300)
    every = max(int(round(refit_s / dt)), 1)
    seen = np.cumsum(~moving)

    def refit(k):
        if seen[k] % every or seen[k] < 64:
            return None
        return model_noise(fitted_floor(e[:k], moving[:k], dt), FITTED_TAUS_S, dt)

    p0 = np.zeros(1 + len(FITTED_TAUS_S))
    p0[0] = BIAS_PRIOR_VAR
    return kalman_drift(e, moving, dt, FITTED_TAUS_S, q, r, p0, refit)


def angle_errors(e, drift, dt, segs):
    return [abs(float(np.sum(e[s:o] - drift[s:o]) * dt)) for s, o in segs]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("manifest", nargs="?", help="the generator's manifest.json (without it: --fitted, every file in DIR)")
    ap.add_argument("--profiles", default="turns,mixed")
    ap.add_argument("--column", default="gx_dps")
    ap.add_argument("--startup-s", type=float, default=60.0)
    ap.add_argument("--fitted", action="store_true", help="the filter's model fitted to each file's static samples")
    ap.add_argument("--refit-s", type=float, default=None,
                    help="with --fitted: refit causally every this many seconds of static samples")
    ap.add_argument("--json", action="store_true", help="print the pooled figures as one JSON line as well")
    a = ap.parse_args()
    if a.refit_s and not a.fitted:
        ap.error("--refit-s refits the fitted model: give --fitted as well")
    if a.manifest:
        with open(a.manifest) as f:
            manifest = json.load(f)
        floors = {os.path.splitext(c["file"])[0]: manifest["floors"][c["floor"]] for c in manifest["cases"]}
        names = {os.path.splitext(c["file"])[0]: f"{c['floor']} {c['rate_hz']:g} Hz" for c in manifest["cases"]}
    elif a.fitted:
        bases = {os.path.basename(p).rsplit("_", 2)[0] for p in glob.glob(os.path.join(a.dir, "*_s*.csv"))}
        floors = {b: None for b in bases}
        names = {b: "fitted" for b in bases}
    else:
        ap.error("without a manifest the floor is unknown: give MANIFEST or --fitted")
    nis_files = []
    models = ("oracle", "bias-hold", "last-static", "floor")
    pooled = {m: [] for m in models}
    print(f"{'recording':<20} {'floor':<20} {'profile':<6} {'motions':>7} {'oracle':>8} {'bias-hold':>9} "
          f"{'last-stat':>9} {'floor':>8} {'o/bh':>5} {'o/floor':>7} {'NIS':>5}")
    for profile in a.profiles.split(","):
        for base in sorted(floors):
            files = sorted(glob.glob(os.path.join(a.dir, f"{base}_{profile}_s*.csv")))
            if not files:
                continue
            cell = {m: [] for m in models}
            nis_all = []
            for path in files:
                e, moving, dt, segs = motions(path, a.column)
                fit = fitted_floor(e, moving, dt) if a.fitted else None
                if a.refit_s:
                    drift, nis = causal_drift(e, moving, dt, a.refit_s)
                else:
                    drift, nis = oracle_drift(e, moving, dt, fit or floors[base])
                floor = floors[base] or fit
                nis_all.append(nis)
                cell["oracle"] += angle_errors(e, drift, dt, segs)
                start = segs[0][0] if segs else e.size
                hold = e[: min(start, int(round(a.startup_s / dt)))].mean()
                cell["bias-hold"] += angle_errors(e, np.full(e.size, hold), dt, segs)
                static = np.where(~moving)[0]
                last = np.zeros(e.size)
                for s, o in segs:
                    past = static[static < s][-int(round(LAST_STATIC_S / dt)):]
                    last[s:o] = e[past].mean() if past.size else hold
                cell["last-static"] += angle_errors(e, last, dt, segs)
                cell["floor"] += [0.674 * floor["white_n"] * math.sqrt((o - s) * dt) for s, o in segs]
            med = {m: float(np.median(cell[m])) for m in models}
            print(f"{base:<20} {names[base]:<20} {profile:<6} {len(cell['floor']):>7} {med['oracle']:>8.4f} "
                  f"{med['bias-hold']:>9.4f} {med['last-static']:>9.4f} {med['floor']:>8.4f} "
                  f"{med['oracle'] / med['bias-hold']:>5.2f} {med['oracle'] / med['floor']:>7.2f} {np.mean(nis_all):>5.2f}")
            for m in models:
                pooled[m] += cell[m]
            nis_files += nis_all
    med = {m: float(np.median(pooled[m])) for m in models}
    print(f"\npooled over {len(pooled['floor'])} motions: floor median {med['floor']:.4f} deg")
    for m in models[:3]:
        print(f"  {m:<12} median {med[m]:.4f} deg = {med[m] / med['bias-hold']:.2f}x bias-hold, "
              f"{med[m] / med['floor']:.2f}x floor")
    if a.json:
        rms = {m: float(np.sqrt(np.mean(np.square(pooled[m])))) for m in models}
        print(json.dumps(dict(motions=len(pooled["floor"]), median_deg=med, rms_deg=rms, nis_mean_per_file=nis_files)))


if __name__ == "__main__":
    main()
