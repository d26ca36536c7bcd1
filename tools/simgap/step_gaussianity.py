#!/usr/bin/env python3
"""How far a recording's bias steps stand out from a Gaussian process of the same spectrum (issue 16).

A bias that jumps at Poisson times by +-m has the second-order statistics of a rate random walk of
K^2 = rate * m^2: its Allan curve and spectrum are a random walk's, so fitted IEEE terms take it in
and the fitted-levels oracle (oracle.py) cannot see it beyond that. What is left to a test that
does not know the step times is the steps' non-Gaussianity. This measures it without a model: the
kurtosis of the window differences of the 1 s means (the jump detector's statistic,
d[i] = mean(y[i..i+W]) - mean(y[i-W..i]), geometric mean over W of 30, 60, 120 and 240 s), against
the same statistic on phase-randomised surrogates of the recording (Theiler et al. 1992, "Testing
for nonlinearity in time series: the method of surrogate data", Physica D 58): the Fourier phases
of the 1 s means' increments drawn anew, amplitudes kept, so every surrogate is Gaussian with the
recording's own spectrum. z is the recording's statistic in standard deviations of the surrogates'.

A z near zero says the steps are, to this statistic, a Gaussian random walk: no diagnosis that fits
the floor's levels can be expected to name them. A z of several says they are visible as steps.

Usage:
    step_gaussianity.py CASE_DIR [--classes bias_jumps,bias_jumps_mid] [--surrogates 40]
"""

import argparse
import json
import os

import numpy as np

WINDOWS_S = (30, 60, 120, 240)


def second_means(x, fs):
    per = int(round(fs))
    n = x.size // per
    return x[: n * per].reshape(n, per).mean(axis=1)


def window_differences(y, w):
    c = np.concatenate([[0.0], np.cumsum(y)])
    i = np.arange(w, y.size - w + 1)
    return (c[i + w] - c[i]) / w - (c[i] - c[i - w]) / w


def step_kurtosis(y):
    """Geometric mean over WINDOWS_S of the kurtosis of the window differences."""
    logs = []
    for w in WINDOWS_S:
        d = window_differences(y, w)
        d = d - d.mean()
        logs.append(np.log(np.mean(d**4) / np.mean(d**2) ** 2))
    return float(np.exp(np.mean(logs)))


def surrogate(y, rng):
    """A Gaussian series with y's increment spectrum: increments' Fourier phases randomised."""
    dy = np.diff(y)
    spec = np.fft.rfft(dy - dy.mean())
    phase = np.exp(2j * np.pi * rng.uniform(size=spec.size))
    phase[0] = 1.0
    if dy.size % 2 == 0:
        phase[-1] = 1.0
    inc = np.fft.irfft(spec * phase, n=dy.size) + dy.mean()
    return np.concatenate([[y[0]], y[0] + np.cumsum(inc)])


def gaussianity_z(x, fs, seed, surrogates=40):
    y = second_means(x, fs)
    rng = np.random.default_rng(seed)
    null = np.array([step_kurtosis(surrogate(y, rng)) for _ in range(surrogates)])
    return (step_kurtosis(y) - null.mean()) / null.std()


def selfcheck():
    """Steps of 10 sigma every ~10 min stand out; a Gaussian random walk does not."""
    rng = np.random.default_rng(5)
    fs, n = 10.0, 40_000
    white = rng.standard_normal(n) * 0.03 * np.sqrt(fs)
    steps = np.cumsum(np.where(rng.uniform(size=n) < 1.0 / 6000.0, rng.choice([-0.05, 0.05], n), 0.0))
    walk = np.cumsum(rng.standard_normal(n)) * 4e-4 * np.sqrt(1.0 / fs)
    assert gaussianity_z(white + steps, fs, 1) > 5.0
    assert abs(gaussianity_z(white + walk, fs, 2)) < 3.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case_dir", nargs="?")
    ap.add_argument("--classes", default="bias_jumps,bias_jumps_mid")
    ap.add_argument("--surrogates", type=int, default=40)
    ap.add_argument("--selfcheck", action="store_true")
    a = ap.parse_args()
    if a.selfcheck or a.case_dir is None:
        selfcheck()
        print("step gaussianity self-check passed")
        return
    with open(os.path.join(a.case_dir, "manifest.json")) as f:
        cases = json.load(f)["cases"]
    keep = set(a.classes.split(","))
    for c in cases:
        if c["klass"] not in keep:
            continue
        x = np.loadtxt(os.path.join(a.case_dir, c["file"]), delimiter=",", skiprows=1, usecols=1)
        z = gaussianity_z(x, c["rate_hz"], c["seed"], a.surrogates)
        print(f"{c['seed']:>5} {c['sub']:<18} {c['floor']:<13} m {c['magnitude']:.4f} "
              f"every {c['time_scale_s']:5.0f} s  oracle z {c['oracle_z']:5.1f}  surrogate z {z:6.2f}", flush=True)


if __name__ == "__main__":
    main()
