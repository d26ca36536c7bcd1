#!/usr/bin/env python3
"""Regenerates tests/goldens/wavelet.json from PyWavelets (the independent reference).

Run from the repository root:  python3 tools/goldens/wavelet_goldens.py
Needs numpy and PyWavelets 1.x (pip install numpy PyWavelets). The output is deterministic.

Contents:
- "cases": seeded test signals of odd and even lengths, with pywt.wavedec coefficients
  (db4, mode='symmetric', level 3) and the paper's denoised signal (universal soft threshold,
  sigma = median(|cD1|)/0.6745, T = sigma*sqrt(2 ln n), waverec truncated to n).
- "other_wavelets": wavedec of one signal for db1, db2, db6, db10 at level 2.
- "causal": for a short series, the causal denoiser's expected output once its window is full:
  at each time t >= window-1, the batch denoise of the window x[t-window+1 : t+1], read at
  position window-1-lag (the estimate of x[t-lag] made at time t).
"""
import json
import math
import os

import numpy as np
import pywt


def denoise(x, wavelet="db4", level=3):
    coeffs = pywt.wavedec(x, wavelet, mode="symmetric", level=level)
    sigma = np.median(np.abs(coeffs[-1])) / 0.6745
    t = sigma * math.sqrt(2.0 * math.log(len(x)))
    coeffs = [coeffs[0]] + [pywt.threshold(d, t, mode="soft") for d in coeffs[1:]]
    return pywt.waverec(coeffs, wavelet, mode="symmetric")[: len(x)], sigma, t


def signal(rng, n):
    walk = np.cumsum(rng.standard_normal(n)) * 0.002
    return walk + 0.05 * rng.standard_normal(n) + 0.01 * np.sin(np.arange(n) * 0.05)


def floats(a):
    return [float(v) for v in a]


def main():
    rng = np.random.default_rng(20171010)
    cases = []
    for n in (64, 101, 1000, 1001):
        x = signal(rng, n)
        coeffs = pywt.wavedec(x, "db4", mode="symmetric", level=3)
        den, sigma, t = denoise(x)
        cases.append({
            "n": n,
            "x": floats(x),
            "coeffs": [floats(c) for c in coeffs],
            "sigma": float(sigma),
            "threshold": float(t),
            "denoised": floats(den),
        })
    x = signal(rng, 257)
    others = [{"wavelet": w, "level": 2, "x": floats(x),
               "coeffs": [floats(c) for c in pywt.wavedec(x, w, mode="symmetric", level=2)]}
              for w in ("db1", "db2", "db6", "db10")]
    x = signal(rng, 300)
    causal = []
    for window, lag in ((64, 0), (64, 5), (100, 12)):
        expected = {}
        for t in range(window - 1, len(x)):
            den, _, _ = denoise(x[t - window + 1: t + 1])
            expected[t - lag] = float(den[window - 1 - lag])
        causal.append({"window": window, "lag": lag,
                       "target_index": sorted(expected), "value": [expected[k] for k in sorted(expected)]})
    out = {"pywt_version": pywt.__version__, "cases": cases, "other_wavelets": others,
           "causal_series": floats(x), "causal": causal}
    path = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "goldens", "wavelet.json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
