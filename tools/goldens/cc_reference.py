#!/usr/bin/env python3
"""Independent reference for the C-C method; regenerates tests/goldens/cc.json.

Run from the repository root:  python3 tools/goldens/cc_reference.py
Needs only numpy. The output is deterministic (fixed seeds), so re-running it gives the same file.

Written straight from the definitions (Kim, Eykholt & Salas, Physica D 127 (1999) 48-60; the seed
paper's Eq. 18-20; docs/design.md "Stage definitions"), brute force and readable rather than fast. It
shares no code or algorithm with src/model/cc.rs: it builds every embedded vector explicitly and
takes the full matrix of pairwise distances, where the Rust grows distances incrementally.

  C(m, N, r, t) = 2 / (M (M-1)) * #{ i < j : max_k |x_{i+kt} - x_{j+kt}| <= r },  M = N - (m-1) t
  S(m, r, t)    = (1/t) sum_{s=1..t} [ C_s(m, N/t, r, t) - C_s(1, N/t, r, t)^m ]
      sub-series s = {x_s, x_{s+t}, x_{s+2t}, ...} truncated to floor(N/t) samples, embedded with
      delay 1 inside it (= delay t in the original series); C_s(1) uses all floor(N/t) points.
  m = 2..5, r_j = j sigma / 2 (j = 1..4), sigma = population std (ddof = 0) of the whole series.
  dS(m, t) = max_j S - min_j S;  S_mean(t) = mean over (m, j);  dS_mean(t) = mean over m of dS;
  S_cor(t) = dS_mean(t) + |S_mean(t)|.
  tau: first t >= 2 with dS_mean(t-1) > dS_mean(t) <= dS_mean(t+1) ("first_local_minimum");
       else first t with S_mean(t) == 0 or a sign change between t-1 and t ("first_zero_crossing");
       else argmin dS_mean ("argmin_delta_s").  tau_w = argmin S_cor (first on ties).
  m = round(tau_w / tau) + 1 with halves rounded up, at least 2.

Pitfalls avoided (both are common in published C-C code, and the Rust test shows the golden would
catch them):
- self-pairs: only pairs i < j are counted, normalised by M(M-1)/2; counting i == j (and both
  orders, normalised by M^2) biases C upwards, most at small radii;
- the 2-norm: the distance is the sup-norm max_k |.|, not the Euclidean norm;
- the Heaviside step counts a distance equal to r (theta(0) = 1); the "ties" case has integer
  values with sigma = 1 exactly, so distances equal r_2 = 1 and r_4 = 2 and '<' would differ.

Floating-point order: sigma, C, the power C^m (repeated multiplication), the sums over s, (m, j)
and m are evaluated in plain left-to-right order, the same order as the Rust, so that the chosen
tau, tau_w and m cannot flip on rounding. Input series are multiples of 2^-10 (or small integers),
so that their JSON decimal form is read back exactly by any parser.
"""
import json
import os

import numpy as np

M_VALUES = (2, 3, 4, 5)
J_VALUES = (1, 2, 3, 4)


def population_std(x):
    """Population standard deviation, summing left to right in plain Python."""
    total = 0.0
    for v in x:
        total += float(v)
    mean = total / len(x)
    sq = 0.0
    for v in x:
        d = float(v) - mean
        sq += d * d
    return float(np.sqrt(sq / len(x)))


def correlation_integral(y, m, r):
    """C of series y embedded with dimension m, delay 1: sup-norm, pairs i < j only, d <= r."""
    big_m = len(y) - (m - 1)
    vectors = np.array([y[i:i + m] for i in range(big_m)])          # shape (M, m)
    dist = np.max(np.abs(vectors[:, None, :] - vectors[None, :, :]), axis=2)
    i_idx, j_idx = np.triu_indices(big_m, k=1)                       # i < j
    count = int(np.sum(dist[i_idx, j_idx] <= r))
    return 2.0 * count / (big_m * (big_m - 1))


def s_value(x, m, r, t):
    length = len(x) // t
    total = 0.0
    for s in range(t):
        sub = np.asarray(x[s::t][:length], dtype=float)
        c1 = correlation_integral(sub, 1, r)
        power = c1
        for _ in range(m - 1):
            power *= c1
        total += correlation_integral(sub, m, r) - power
    return total / t


def choose_tau(delta_s_mean, s_mean):
    n = len(delta_s_mean)
    for t in range(2, n):                       # t + 1 <= t_max
        if delta_s_mean[t - 2] > delta_s_mean[t - 1] <= delta_s_mean[t]:
            return t, "first_local_minimum"
    for t in range(1, n + 1):
        if s_mean[t - 1] == 0.0 or (t >= 2 and (s_mean[t - 2] < 0.0) != (s_mean[t - 1] < 0.0)):
            return t, "first_zero_crossing"
    return int(np.argmin(delta_s_mean)) + 1, "argmin_delta_s"


def cc_reference(x, t_max):
    sigma = population_std(x)
    radii = [j * sigma / 2.0 for j in J_VALUES]
    table, delta_s, s_mean, delta_s_mean, s_cor = [], [], [], [], []
    for t in range(1, t_max + 1):
        rows = [[s_value(x, m, r, t) for r in radii] for m in M_VALUES]
        total = 0.0
        delta_total = 0.0
        deltas = []
        for row in rows:
            for v in row:
                total += v
            deltas.append(max(row) - min(row))
            delta_total += deltas[-1]
        table.append(rows)
        delta_s.append(deltas)
        s_mean.append(total / 16.0)
        delta_s_mean.append(delta_total / 4.0)
        s_cor.append(delta_s_mean[-1] + abs(s_mean[-1]))
    tau, rule = choose_tau(delta_s_mean, s_mean)
    tau_w = int(np.argmin(s_cor)) + 1
    m = max(2, (2 * tau_w + tau) // (2 * tau) + 1)
    return {"sigma": sigma, "radii": radii, "t": list(range(1, t_max + 1)), "s": table,
            "delta_s": delta_s, "s_mean": s_mean, "delta_s_mean": delta_s_mean, "s_cor": s_cor,
            "tau": tau, "tau_w": tau_w, "m": m, "tau_rule": rule}


def quantise(x):
    """Round to multiples of 2^-10 so the JSON text is exact."""
    return np.round(np.asarray(x) * 1024.0) / 1024.0


def ar1_sine(rng, n):
    e = rng.standard_normal(n)
    x = np.zeros(n)
    for i in range(1, n):
        x[i] = 0.8 * x[i - 1] + 0.5 * e[i]
    return quantise(x + np.sin(2.0 * np.pi * np.arange(n) / 25.0))


def integer_ties(rng, n):
    """Integers -2..2 with mean 0 and variance exactly 1 (n/16 each of +-2, n/4 each of +-1, the
    rest 0), placed in the rank order of a smooth AR(1) series so the series has some memory."""
    assert n % 16 == 0
    values = np.array([-2] * (n // 16) + [-1] * (n // 4) + [0] * (3 * n // 8)
                      + [1] * (n // 4) + [2] * (n // 16), dtype=float)
    e = rng.standard_normal(n)
    z = np.zeros(n)
    for i in range(1, n):
        z[i] = 0.9 * z[i - 1] + e[i]
    x = np.empty(n)
    x[np.argsort(z, kind="stable")] = values
    return x


def main():
    rng = np.random.default_rng(19990048)
    cases = []
    base = ar1_sine(rng, 300)
    # The same series with a shorter t range exercises the fallback rules for tau: up to t = 6
    # dS_mean only falls but S_mean changes sign at t = 6; up to t = 4 neither happens.
    for name, x, t_max in (("ar1_sine", base, 8),
                           ("ar1_sine_tmax6", base, 6),
                           ("ar1_sine_tmax4", base, 4),
                           ("rounded_0.1", np.round(ar1_sine(rng, 240), 1), 8),
                           ("integer_ties", integer_ties(rng, 304), 8)):
        case = {"name": name, "n": len(x), "t_max": t_max, "x": [float(v) for v in x]}
        case.update(cc_reference(list(x), t_max))
        cases.append(case)
    assert cases[-1]["sigma"] == 1.0, "the ties case must have sigma exactly 1"
    assert [c["tau_rule"] for c in cases[1:3]] == ["first_zero_crossing", "argmin_delta_s"]
    out = {"generator": "tools/goldens/cc_reference.py", "numpy_version": np.__version__,
           "cases": cases}
    path = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "goldens", "cc.json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    for c in cases:
        print(f"{c['name']}: n={c['n']} sigma={c['sigma']:.6g} tau={c['tau']} ({c['tau_rule']}) "
              f"tau_w={c['tau_w']} m={c['m']}")


if __name__ == "__main__":
    main()
