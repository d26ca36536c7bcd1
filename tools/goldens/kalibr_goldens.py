#!/usr/bin/env python3
# Golden values for `gyrocomp allan --format kalibr` (src/diag/kalibr.rs, tests/cli_allan.rs).
#
# Run from the crate root:   python3 tools/goldens/kalibr_goldens.py
# Writes tests/goldens/kalibr.json. Needs numpy and allantools (2024.06).
#
# The series is white noise plus a rate random walk, both driven by a 64-bit LCG whose uniform
# draws are exact in IEEE doubles, so the Rust test rebuilds the identical series from the
# parameters stored here (no data file in the repository):
#   state = state * 6364136223846793005 + 1442695040888963407 (mod 2^64)
#   u     = (state >> 11) / 2^53 - 0.5                        (one draw)
#   per sample: w = white * u(), walk += step * u(), x = bias + w + walk
# The reference is independent of gyrocomp's fit: allantools.oadev on the octave taus, then a
# weighted least-squares fit of only the two terms present, avar = N^2/tau + K^2 tau/3 (weights
# n/m on the relative residual, as in IEEE Std 952-1997 Annex C practice), converted to Kalibr's
# rad units. The true values (N = sigma_w * sqrt(dt), K = sigma_step / sqrt(dt), sigma = a/sqrt(12)
# for a uniform draw of width a) are stored too.

import json
import math
import os

import allantools
import numpy as np

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "goldens", "kalibr.json")
MASK = (1 << 64) - 1

SEED = 0x9E3779B97F4A7C15
RATE_HZ = 10.0
SAMPLES = 200_000
WHITE = 0.34641016151377546   # uniform width: sigma = 0.1 deg/s per sample
STEP = 3.0e-4                 # uniform width of the random-walk step
BIAS = 0.2


def series():
    state = SEED
    walk = 0.0
    x = []
    for _ in range(SAMPLES):
        state = (state * 6364136223846793005 + 1442695040888963407) & MASK
        w = WHITE * ((state >> 11) / 9007199254740992.0 - 0.5)
        state = (state * 6364136223846793005 + 1442695040888963407) & MASK
        walk += STEP * ((state >> 11) / 9007199254740992.0 - 0.5)
        x.append(BIAS + w + walk)
    return np.array(x)


def main():
    x = series()
    taus, adev, _, ns = allantools.oadev(x, rate=RATE_HZ, data_type="freq", taus="octave")
    m = np.round(taus * RATE_HZ)
    avar = adev**2
    basis = np.stack([1.0 / taus, taus / 3.0], axis=1)
    w = np.sqrt(ns / m) / avar  # relative residual, weight n/m
    coef, *_ = np.linalg.lstsq(basis * w[:, None], avar * w, rcond=None)
    n_fit, k_fit = math.sqrt(max(coef[0], 0.0)), math.sqrt(max(coef[1], 0.0))
    dt = 1.0 / RATE_HZ
    n_true = WHITE / math.sqrt(12.0) * math.sqrt(dt)
    k_true = STEP / math.sqrt(12.0) / math.sqrt(dt)
    rad = math.pi / 180.0
    doc = {
        "generator": {"seed": SEED, "rate_hz": RATE_HZ, "samples": SAMPLES, "white": WHITE, "step": STEP, "bias": BIAS},
        "reference": "allantools.oadev octave + 2-term WLS (N^2/tau + K^2 tau/3), rad units",
        "gyroscope_noise_density": n_fit * rad,
        "gyroscope_random_walk": k_fit * rad,
        "true_gyroscope_noise_density": n_true * rad,
        "true_gyroscope_random_walk": k_true * rad,
        "update_rate": RATE_HZ,
    }
    with open(OUT, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
