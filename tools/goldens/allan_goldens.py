#!/usr/bin/env python3
# Golden values for the overlapping Allan deviation (src/diag/allan.rs, tests/allan.rs).
#
# Run from the crate root:   python3 tools/goldens/allan_goldens.py
# Writes tests/goldens/allan.json. Needs numpy and allantools (2024.06). The inputs are generated
# from fixed seeds, so re-running produces the same file byte for byte.
#
# Each case holds the input rate series ("x", deg/s), the sample rate, and the results of
# allantools.oadev(x, rate=rate, data_type="freq", taus=...) (tau_s, adev, ns, and adev_bits: the
# IEEE-754 bit patterns of adev as integers, for an exact comparison) for taus="octave" and, for the
# short cases only, taus="all".
#
# The inputs are rounded to 15 significant digits before use and stored with repr(), so they
# round-trip exactly through any JSON reader: serde_json (without its float_roundtrip feature) parses
# a 16-17 digit number with up to 1 ulp of error, but a number of at most 15 digits exactly.

import json
import os
import struct
import sys

import allantools
import numpy as np

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "goldens", "allan.json")


def series(seed, n, white, walk, bias):
    """White noise (std `white`) + random walk (step std `walk`) + constant `bias`."""
    rng = np.random.default_rng(seed)
    x = bias + white * rng.standard_normal(n) + np.cumsum(walk * rng.standard_normal(n))
    return [float(f"{v:.15g}") for v in x]


# (name, seed, length, rate Hz, white, walk, bias, include taus="all")
CASES = [
    ("short_37", 11, 37, 7.0, 0.1, 0.01, 0.3, True),
    ("wn_rw_1000", 12, 1000, 10.0, 0.12, 0.002, 0.5, False),
    ("wn_rw_1001_bias", 13, 1001, 100.0, 0.05, 0.001, 250.0, True),
    ("wn_rw_5000", 14, 5000, 3.3, 0.2, 0.004, -0.7, False),
]


def oadev(x, rate, taus):
    tau, adev, _err, ns = allantools.oadev(x, rate=rate, data_type="freq", taus=taus)
    return {
        "tau_s": [float(v) for v in tau],
        "adev": [float(v) for v in adev],
        "ns": [int(v) for v in ns],
        "adev_bits": [struct.unpack("<Q", struct.pack("<d", float(v)))[0] for v in adev],
    }


def dump(value):
    return json.dumps(value, separators=(",", ":"))


def main():
    lines = ["{"]
    lines.append(f' "generator":{dump("tools/goldens/allan_goldens.py")},')
    lines.append(f' "allantools":{dump(allantools.__version__)},')
    lines.append(' "cases":[')
    for i, (name, seed, n, rate, white, walk, bias, with_all) in enumerate(CASES):
        x = series(seed, n, white, walk, bias)
        lines.append("  {")
        lines.append(f'   "name":{dump(name)},')
        lines.append(f'   "rate_hz":{dump(rate)},')
        lines.append(f'   "x":{dump(x)},')
        lines.append(f'   "octave":{dump(oadev(np.array(x), rate, "octave"))},')
        lines.append(f'   "all":{dump(oadev(np.array(x), rate, "all") if with_all else None)}')
        lines.append("  }" + ("," if i + 1 < len(CASES) else ""))
    lines.append(" ]")
    lines.append("}")
    with open(OUT, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {os.path.normpath(OUT)} ({os.path.getsize(OUT)} bytes)", file=sys.stderr)


if __name__ == "__main__":
    main()
