#!/usr/bin/env python3
"""Independent reference for the exact LS-SVM; regenerates tests/goldens/lssvm.json.

Run from the repository root:  python3 tools/goldens/lssvm_reference.py
Needs only numpy. Deterministic (fixed seed, values on a 2^-16 grid), so re-running it gives the
same file.

Written straight from the definitions (Suykens & Vandewalle 1999; LS-SVMlab conventions; the seed
paper's Eq. 7-8 and 15-16), brute force and readable rather than fast. It shares no algorithm with
src/model/lssvm: it builds the full (n+1) x (n+1) bordered matrix and calls np.linalg.solve
(LU), where the Rust factors only the SPD block by Cholesky; and it computes leave-one-out
residuals by n refits on n-1 rows, where the Rust uses the closed form of Cawley & Talbot (2004).

  K(x, y) = exp(-||x - y||^2 / sig2)                       (Eq. 8, sig2 = LS-SVMlab's sig2)
  [ 0   1^T           ] [ b     ]   [ 0 ]
  [ 1   Omega + I/gam ] [ alpha ] = [ y ],  Omega_ij = K(x_i, x_j)     (Eq. 7, Suykens form)
  f(x) = sum_i alpha_i K(x, x_i) + b
  PSR (Eq. 15-16): row k = [s_k, s_{k+tau}, ..., s_{k+(m-1)tau}], target s_{k+(m-1)tau+1}.

Fixture: a noisy logistic-map series (seeded), tau = 2, m = 3; the first 60 rows train, the
next 10 are test rows.
"""
import json
import os

import numpy as np

TAU, DIM, N_TRAIN, N_TEST = 2, 3, 60, 10
CASES = [(10.0, 0.5), (1000.0, 5.0), (0.5, 0.05)]


def series(length):
    rng = np.random.default_rng(20170417)
    z, out = 0.3, []
    for _ in range(length):
        z = 3.9 * z * (1.0 - z)
        out.append(z - 0.5 + 0.05 * rng.standard_normal())
    # Multiples of 2^-16: their JSON decimal form is read back exactly by any parser.
    return [round(v * 65536.0) / 65536.0 for v in out]


def embed(s):
    hist = (DIM - 1) * TAU + 1
    rows = [[s[k + j * TAU] for j in range(DIM)] for k in range(len(s) - hist)]
    return np.array(rows), np.array(s[hist:])


def kernel(a, b, sig2):
    d = ((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)
    return np.exp(-d / sig2)


def fit(x, y, gam, sig2):
    n = len(y)
    a = np.zeros((n + 1, n + 1))
    a[0, 1:] = 1.0
    a[1:, 0] = 1.0
    a[1:, 1:] = kernel(x, x, sig2) + np.eye(n) / gam
    sol = np.linalg.solve(a, np.concatenate([[0.0], y]))
    return sol[1:], sol[0]


def predict(x_train, alpha, b, x, sig2):
    return kernel(x, x_train, sig2) @ alpha + b


def main():
    s = series(N_TRAIN + N_TEST + (DIM - 1) * TAU + 1)
    x, y = embed(s)
    assert len(y) == N_TRAIN + N_TEST
    xtr, ytr, xte = x[:N_TRAIN], y[:N_TRAIN], x[N_TRAIN:]
    cases = []
    for gam, sig2 in CASES:
        alpha, b = fit(xtr, ytr, gam, sig2)
        loo = []
        for i in range(N_TRAIN):
            keep = np.arange(N_TRAIN) != i
            a_i, b_i = fit(xtr[keep], ytr[keep], gam, sig2)
            loo.append(float(ytr[i] - predict(xtr[keep], a_i, b_i, xtr[i:i + 1], sig2)[0]))
        cases.append({
            "gamma": gam,
            "sigma2": sig2,
            "alpha": alpha.tolist(),
            "b": float(b),
            "test_predictions": predict(xtr, alpha, b, xte, sig2).tolist(),
            "loo_residuals": loo,
        })
    out = {
        "generator": "tools/goldens/lssvm_reference.py",
        "tau": TAU,
        "dim": DIM,
        "n_train": N_TRAIN,
        "n_test": N_TEST,
        "series": s,
        "cases": cases,
    }
    path = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "goldens", "lssvm.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
