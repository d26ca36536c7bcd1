#!/usr/bin/env python3
# Golden values for the Welch power spectral density (src/diag/psd.rs, tests/psd_goldens.rs).
#
# Run from the crate root:   python3 tools/goldens/psd_goldens.py
# Writes tests/goldens/psd.json. Needs numpy and scipy. The inputs come from fixed seeds, so
# re-running produces the same file byte for byte.
#
# Each case holds the input series "x" (rounded to 15 significant digits, so it round-trips exactly
# through serde_json), the sample rate, the segment length, and the result of
# scipy.signal.welch(x, fs, window="hann", nperseg=L, noverlap=L//2, detrend="constant",
# scaling="density") (freq_hz, density).

import json
import os

import numpy as np
import scipy
import scipy.signal

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "goldens", "psd.json")


def rounded(v):
    return [float(f"{x:.15g}") for x in v]


def case(name, seed, n, fs, segment, kind):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    if kind == "white+walk":
        x = 0.1 * rng.standard_normal(n) + np.cumsum(0.002 * rng.standard_normal(n)) + 0.4
    elif kind == "sine+white":
        x = 0.02 * np.sin(2 * np.pi * 0.37 * t + 0.4) + 0.05 * rng.standard_normal(n) - 0.2
    else:
        raise ValueError(kind)
    x = np.array(rounded(x))
    f, p = scipy.signal.welch(x, fs, window="hann", nperseg=segment, noverlap=segment // 2,
                              detrend="constant", scaling="density")
    return {"name": name, "rate_hz": fs, "segment": segment, "x": x.tolist(),
            "freq_hz": f.tolist(), "density": p.tolist()}


def main():
    cases = [
        case("white_walk_10hz_l256", 1, 3000, 10.0, 256, "white+walk"),
        case("sine_white_100hz_l64", 2, 1000, 100.0, 64, "sine+white"),
        case("odd_length_l128", 3, 1337, 10.0, 128, "white+walk"),
    ]
    doc = {"generator": f"scipy {scipy.__version__}, numpy {np.__version__}", "cases": cases}
    with open(OUT, "w") as fh:
        json.dump(doc, fh, indent=None, separators=(",", ":"))
        fh.write("\n")


if __name__ == "__main__":
    main()
