#!/usr/bin/env python3
# Golden values for the χ² upper quantile (src/model/normal.rs `chi2_upper`, test
# `chi_square_quantiles_match_scipy`; the Allan confidence band in src/diag/allan.rs and the
# spike-dispersion limit in src/diag/simgap/fit_events.rs use the same function).
#
# Run from the crate root:   python3 tools/goldens/chi_square_goldens.py
# Prints (k, alpha, scipy.stats.chi2.isf(alpha, k)) with repr, the form the Rust test holds.

from scipy.stats import chi2

CASES = [
    (1.0, 1e-12), (1.0, 0.025), (1.0, 0.999),
    (2.0, 1e-6), (2.0, 0.975),
    (3.0, 1e-12), (3.0, 0.5), (3.0, 0.999),
    (4.5, 1e-6), (4.5, 0.975),
    (9.0, 0.001), (9.0, 0.999),
    (19.0, 1e-12), (19.0, 1e-6), (19.0, 0.025),
    (40.0, 0.5), (40.0, 0.975),
    (199.0, 1e-12), (199.0, 0.001), (199.0, 0.5), (199.0, 0.999),
]

if __name__ == "__main__":
    for k, alpha in CASES:
        print(f"({k!r}, {alpha!r}, {float(chi2.isf(alpha, k))!r}),")
    # Used beside the table: the spike-dispersion limit and an Allan band point.
    print("isf(1e-4, 9) =", repr(float(chi2.isf(1e-4, 9))))
    a = (1.0 - 0.683) / 2.0
    print("isf(0.1585, 15) =", repr(float(chi2.isf(a, 15))), " isf(0.8415, 15) =", repr(float(chi2.isf(1.0 - a, 15))))
