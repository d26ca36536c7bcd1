#!/usr/bin/env python3
"""Independent case generator for `gyrocomp simgap` (issue 16, item 1).

Written apart from src/diag/simgap (numpy only, its own parametrisation, its own noise floors), so
the diagnosis is measured on recordings it was not built around. Every case is one CSV recording
in the project's format (`t_s,gx_dps,temp_c`, as `gyrocomp sim` writes) plus an entry in
`manifest.json` saying what was injected: effect class, sub-class, magnitude (and its bin), time
scale, seed, noise floor, rate and duration, and how visible it is (oracle.py): `oracle_z` to a test
that knows the floor exactly, `oracle_z_fitted` to one that knows only the floor's IEEE family and
fits its levels, as the diagnosis must.

Noise floors (IEEE Std 952 terms, deg/s units; `s` below is the floor's scale: 0.1, 1 or 10):

    white N    = s * 0.03 deg/s/sqrt(Hz)          (angle random walk)
    GM bank    = s * sigma_i, tau_i: (0.004, 8 s), (0.005, 90 s), (0.004, 900 s)
                 (a bank of first-order Gauss-Markov processes; its Allan deviation is a flat-ish
                 bias instability B ~ s * 0.003 deg/s from ~10 s to ~1000 s)
    RRW K      = s * 4e-5 deg/s/sqrt(s)          (rate random walk)
    bias       = uniform(-1, 1) deg/s constant

`quiet` is s = 0.1, `nominal` s = 1, `noisy` s = 10; `nominal_flat` has no GM bank (white + RRW
only). Effect magnitudes scale with s, so the magnitude bins are signal-to-floor bins.

Floors of other shapes (s = 1, same white N; chosen only with --floors, so the default draws of
the floors above are unchanged):

    early_bias   GM bank (0.03, 2 s), (0.015, 20 s), (0.008, 200 s): bias instability from a
                 few seconds on (a consumer MEMS), RRW as nominal
    steep_rrw    the nominal GM bank, RRW K x10 (the Allan curve rising from ~10 min)
    white_only   white noise alone
    flicker      nine GM processes of sigma 0.005 at 0.3, 1, 3, ... 3000 s (1/f over four
                 decades, B ~ 0.006 deg/s), RRW as nominal

Effect classes (expected first named effect in brackets; the magnitude factor m is drawn
log-uniform in the class's range; its bin is the third of the log-range it falls in):

    warmup        A e^(-t/T), A = ±m * s, m in [0.03, 0.3]; T log-uniform 60 s .. duration/4
                  (sub-class long_warmup when T >= 900 s)                         [warmup]
    temperature   c * (temp - mean), temp = room drift + slow sine + steps, c = ±m*s/°C,
                  m in [0.003, 0.03]                                               [temperature]
    ramp          linear change of ±m * s over the run, m in [0.03, 0.5]          [ramp]
    sinusoid      m * s * sin(2 pi f t + phi), m in [0.005, 0.05], f log-uniform
                  10/duration .. min(1, rate/4) Hz                                 [sinusoid]
    bias_jumps    few_large: Poisson 1-6 /h, each N(0, (m s)^2), m in [0.02, 0.1];
                  many_small: 20-100 /h of m in [0.004, 0.02] (a fraction of the per-sample
                  noise, several sigma in 100 s means)                            [bias_jumps]
    bias_jumps_mid  between the two: Poisson 6-20 /h of m in [0.008, 0.04] (0.1-0.4 of the
                  per-sample noise, 3-13 white-noise sigma in 100 s means: the issue's "many
                  small steps"; added in the twenty-fourth session, after the classes above, so
                  their seeds draw the same cases as before)                      [bias_jumps]
    long_warmup   a warm-up as above with T log-uniform 900 s .. the recording's duration: the
                  issue's failure 4 ("a quarter of an hour or more"), which the warmup class
                  reaches only on its longest recordings; added in the fortieth session, after
                  the classes above                                                [warmup]
    spikes        Poisson 5-100 /h single-sample outliers of ±m*s*sqrt(rate/10 Hz), m in
                  [0.6, 3]: 6-30 sigma of the per-sample white noise at any rate  [spikes]
    quantization  output rounded to a grid of m*s deg/s, m in [0.02, 0.2]          [quantization]
    gauss_markov  sigma = m * s, m in [0.006, 0.04], correlation time log-uniform 5-300 s
                  (sub-class gm_1min when 30-120 s)                               [gauss_markov]
    dominant      a dominant effect (warmup, sinusoid or ramp at the top third of its range)
                  plus a small second effect of another kind (bottom of its range); the dominant
                  one must be named first                                          [its name]
    none          the floor only (pure IEEE terms)                                 [none]
    outside       an effect outside the catalogue: a chirp 0.01 -> 0.2 Hz, a noise burst (white
                  noise x2-4 over 10-30 % of the run) or a triangle wave of the bias  [outside]

Seeds: the TUNING ranges are 1000-1999 and 2000-2999 (the second opened in the twenty-first
session, when the first was used up), the REPORT ranges 1-999 and 3000-3999. Tune only on tuning seeds;
report figures only on report seeds, measured after tuning stopped. A case's seed is
`first_seed + index`, where cases are numbered class by class; the per-case generator is
numpy's PCG64 seeded with (seed, 16).

Usage:
    independent_cases.py OUT_DIR [--first-seed 1000] [--per-class 10] [--rates 10]
                         [--durations 3000,5000] [--floors quiet,nominal,noisy,nominal_flat]
                         [--classes warmup,...]
"""

import argparse
import json
import math
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: oracle.py says why
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from oracle import fitted_oracle_z, oracle_z

TUNING_RANGES = (range(1000, 2000), range(2000, 3000))
REPORT_RANGES = (range(1, 1000), range(3000, 4000))

FLOORS = {
    "quiet": 0.1,
    "nominal": 1.0,
    "noisy": 10.0,
    "nominal_flat": 1.0,
    "early_bias": 1.0,
    "steep_rrw": 1.0,
    "white_only": 1.0,
    "flicker": 1.0,
}
WHITE_N = 0.03
GM_BANK = [(0.004, 8.0), (0.005, 90.0), (0.004, 900.0)]
RRW_K = 4e-5
# The floors of other shapes (thirty-first session; not in the default --floors, so the seeds of
# earlier sets draw the same cases): bias instability from a few seconds on, as a consumer MEMS;
# a rate random walk 10x nominal (the Allan curve rising from ~10 min); white noise alone; and a
# 1/f flicker over four decades (equal-variance Gauss-Markov poles, two per decade, 0.3-3000 s).
EARLY_BANK = [(0.03, 2.0), (0.015, 20.0), (0.008, 200.0)]
FLICKER_BANK = [(0.005, 0.3 * 10 ** (k / 2)) for k in range(9)]
BANKS = {"nominal_flat": [], "white_only": [], "early_bias": EARLY_BANK, "flicker": FLICKER_BANK}
RRW_SCALE = {"steep_rrw": 10.0, "white_only": 0.0}

CLASSES = [
    "warmup",
    "temperature",
    "ramp",
    "sinusoid",
    "bias_jumps",
    "spikes",
    "quantization",
    "gauss_markov",
    "dominant",
    "none",
    "outside",
    "bias_jumps_mid",
    "long_warmup",
]


def ar1(rng, n, sigma, tau, dt):
    """Stationary first-order Gauss-Markov process (exact discretisation), vectorised in blocks."""
    phi = math.exp(-dt / tau)
    q = sigma * math.sqrt(1.0 - phi * phi)
    e = rng.standard_normal(n) * q
    out = np.empty(n)
    x0 = rng.standard_normal() * sigma
    # Within a block x_k = phi^k (x0 + sum_{j<=k} phi^-j e_j); blocks keep phi^-k below e^40.
    block = max(1, min(n, int(40.0 / max(dt / tau, 1e-12))))
    start = 0
    while start < n:
        stop = min(n, start + block)
        k = np.arange(stop - start)
        lp = k * math.log(phi)
        s = np.cumsum(e[start:stop] * np.exp(-lp))
        out[start:stop] = np.exp(lp) * (x0 * phi + s)
        x0 = out[stop - 1]
        start = stop
    return out


def floor_noise(rng, name, n, fs):
    s = FLOORS[name]
    dt = 1.0 / fs
    x = rng.standard_normal(n) * (s * WHITE_N * math.sqrt(fs))
    for sigma, tau in BANKS.get(name, GM_BANK):
        x += ar1(rng, n, s * sigma, tau, dt)
    x += np.cumsum(rng.standard_normal(n)) * (s * RRW_K * RRW_SCALE.get(name, 1.0) * math.sqrt(dt))
    return x


def temperature_profile(rng, t, duration):
    warm = rng.uniform(2.0, 6.0) * (1.0 - np.exp(-t / rng.uniform(600.0, 2400.0)))
    period = rng.uniform(1500.0, 6000.0)
    sine = rng.uniform(0.5, 2.0) * np.sin(2 * math.pi * t / period + rng.uniform(0, 2 * math.pi))
    steps = np.zeros_like(t)
    for _ in range(rng.integers(1, 4)):
        at = rng.uniform(0.1, 0.9) * duration
        steps += rng.uniform(-1.5, 1.5) * (1.0 / (1.0 + np.exp(-(t - at) / 60.0)))
    return rng.uniform(18.0, 30.0) + warm + sine + steps + rng.standard_normal(t.size) * 0.03


def log_uniform(rng, lo, hi):
    u = rng.uniform()
    return lo * (hi / lo) ** u, u


def bin_of(u):
    return "low" if u < 1 / 3 else ("mid" if u < 2 / 3 else "high")


def poisson_times(rng, rate_per_h, duration):
    count = rng.poisson(rate_per_h * duration / 3600.0)
    return np.sort(rng.uniform(0.0, duration, count))


def step_process(rng, t, duration, rate_per_h, draw_sizes):
    """Bias steps at Poisson times (at least one, placed in the first 10-60 % when none fall),
    sizes from draw_sizes(count); the summed step signal and the number of steps."""
    times = poisson_times(rng, rate_per_h, duration)
    if times.size == 0:
        times = np.array([rng.uniform(0.1, 0.6) * duration])
    x = np.zeros(t.size)
    for at, size in zip(times, draw_sizes(times.size)):
        x[t >= at] += size
    return x, int(times.size)


def add_effect(rng, kind, t, fs, duration, s, temp, strength=None):
    """Returns (signal to add, post-processing fn or None, description dict).

    strength: None to draw the magnitude over the whole range, "high"/"low" to force a third."""
    n = t.size

    def draw(lo, hi):
        if strength is None:
            return log_uniform(rng, lo, hi)
        u = rng.uniform(2 / 3, 1.0) if strength == "high" else rng.uniform(0.0, 1 / 3)
        return lo * (hi / lo) ** u, u

    sign = rng.choice([-1.0, 1.0])
    if kind in ("warmup", "long_warmup"):
        m, u = draw(0.03, 0.3)
        tau, _ = log_uniform(rng, 60.0, duration / 4.0) if kind == "warmup" else log_uniform(rng, 900.0, duration)
        sub = "long_warmup" if tau >= 900.0 else "warmup"
        return sign * m * s * np.exp(-t / tau), None, dict(sub=sub, m=m, u=u, amplitude_dps=sign * m * s, time_scale_s=tau)
    if kind == "temperature":
        m, u = draw(0.003, 0.03)
        c = sign * m * s
        return c * (temp - temp.mean()), None, dict(sub="temperature", m=m, u=u, dps_per_c=c, time_scale_s=None)
    if kind == "ramp":
        m, u = draw(0.03, 0.5)
        return sign * m * s * t / duration, None, dict(sub="ramp", m=m, u=u, change_dps=sign * m * s, time_scale_s=duration)
    if kind == "sinusoid":
        m, u = draw(0.005, 0.05)
        f, _ = log_uniform(rng, 10.0 / duration, min(1.0, fs / 4.0))
        phi = rng.uniform(0, 2 * math.pi)
        return m * s * np.sin(2 * math.pi * f * t + phi), None, dict(sub="sinusoid", m=m, u=u, amplitude_dps=m * s, frequency_hz=f, time_scale_s=1.0 / f)
    if kind == "bias_jumps":
        many = rng.uniform() < 0.5
        if many:
            rate = rng.uniform(20.0, 100.0)
            m, u = draw(0.004, 0.02)
        else:
            rate = rng.uniform(1.0, 6.0)
            m, u = draw(0.02, 0.1)
        if many:
            x, jumps = step_process(rng, t, duration, rate, lambda k: rng.choice([-1.0, 1.0], k) * m * s)
        else:
            x, jumps = step_process(rng, t, duration, rate, lambda k: rng.standard_normal(k) * m * s)
        return x, None, dict(sub="many_small_steps" if many else "few_large_steps", m=m, u=u, rate_per_h=rate, jumps=jumps, time_scale_s=3600.0 / rate)
    if kind == "bias_jumps_mid":
        rate = rng.uniform(6.0, 20.0)
        m, u = draw(0.008, 0.04)
        x, jumps = step_process(rng, t, duration, rate, lambda k: rng.choice([-1.0, 1.0], k) * m * s)
        return x, None, dict(sub="mid_steps", m=m, u=u, rate_per_h=rate, jumps=jumps, time_scale_s=3600.0 / rate)
    if kind == "spikes":
        m, u = draw(0.6, 3.0)
        rate = rng.uniform(5.0, 100.0)
        idx = np.unique(rng.integers(0, n, max(1, rng.poisson(rate * duration / 3600.0))))
        x = np.zeros(n)
        # In units of the per-sample white noise at 10 Hz: the same multiple of it at any rate
        # (the factor is exactly 1 at 10 Hz, so the default draws are unchanged).
        size = m * s * math.sqrt(fs / 10.0)
        x[idx] = rng.choice([-1.0, 1.0], idx.size) * size * rng.uniform(0.7, 1.3, idx.size)
        return x, None, dict(sub="spikes", m=m, u=u, rate_per_h=rate, spikes=int(idx.size), time_scale_s=None)
    if kind == "quantization":
        m, u = draw(0.02, 0.2)
        step = m * s

        def quantise(y):
            return np.round(y / step) * step

        return np.zeros(n), quantise, dict(sub="quantization", m=m, u=u, step_dps=step, time_scale_s=None)
    if kind == "gauss_markov":
        m, u = draw(0.006, 0.04)
        tau, _ = log_uniform(rng, 5.0, 300.0)
        sub = "gm_1min" if 30.0 <= tau <= 120.0 else "gauss_markov"
        return ar1(rng, n, m * s, tau, 1.0 / fs), None, dict(sub=sub, m=m, u=u, sigma_dps=m * s, time_scale_s=tau)
    if kind == "chirp":
        m, u = draw(0.01, 0.04)
        f0, f1 = 0.01, 0.2
        phase = 2 * math.pi * (f0 * t + 0.5 * (f1 - f0) * t * t / duration)
        return m * s * np.sin(phase), None, dict(sub="chirp", m=m, u=u, amplitude_dps=m * s, time_scale_s=None)
    if kind == "noise_burst":
        m, u = draw(2.0, 4.0)
        length = rng.uniform(0.1, 0.3) * duration
        at = rng.uniform(0.0, duration - length)
        inside = (t >= at) & (t < at + length)
        x = np.zeros(n)
        x[inside] = rng.standard_normal(inside.sum()) * s * WHITE_N * math.sqrt(fs) * math.sqrt(m * m - 1.0)
        return x, None, dict(sub="noise_burst", m=m, u=u, start_s=at, time_scale_s=length)
    if kind == "triangle":
        m, u = draw(0.01, 0.05)
        period, _ = log_uniform(rng, duration / 8.0, duration / 2.0)
        ph = (t / period + rng.uniform()) % 1.0
        return m * s * (4.0 * np.abs(ph - 0.5) - 1.0), None, dict(sub="triangle", m=m, u=u, amplitude_dps=m * s, time_scale_s=period)
    raise ValueError(kind)


def make_case(seed, klass, rates, durations, floors):
    rng = np.random.Generator(np.random.PCG64([seed, 16]))
    fs = float(rng.choice(rates))
    duration = float(round(rng.uniform(durations[0], durations[1])))
    floor = str(rng.choice(floors))
    s = FLOORS[floor]
    n = int(round(duration * fs))
    t = np.arange(n) / fs
    temp = temperature_profile(rng, t, duration)
    x = floor_noise(rng, floor, n, fs) + rng.uniform(-1.0, 1.0)
    post = []
    floor_model = floor_description(floor)
    oracle = fitted = None
    if klass == "none":
        expected, info = "none", dict(sub="none", m=None, u=None, time_scale_s=None)
    elif klass == "outside":
        kind = str(rng.choice(["chirp", "noise_burst", "triangle"]))
        add, p, info = add_effect(rng, kind, t, fs, duration, s, temp)
        x += add
        oracle = oracle_z(kind, add, info, floor_model, fs)
        fitted = fitted_oracle_z(kind, add, info, floor_model, fs)
        expected = "outside"
    elif klass == "dominant":
        main = str(rng.choice(["warmup", "sinusoid", "ramp"]))
        second = str(rng.choice([k for k in ["sinusoid", "spikes", "gauss_markov", "bias_jumps"] if k != main]))
        add, _, info = add_effect(rng, main, t, fs, duration, s, temp, strength="high")
        add2, _, info2 = add_effect(rng, second, t, fs, duration, s, temp, strength="low")
        x += add + add2
        oracle = oracle_z(main, add, info, floor_model, fs)
        fitted = fitted_oracle_z(main, add, info, floor_model, fs)
        expected = main
        info = dict(info, sub=f"{main}+small_{second}", second=dict(info2, kind=second))
    else:
        add, p, info = add_effect(rng, klass, t, fs, duration, s, temp)
        x += add
        if p is not None:
            post.append(p)
        expected = {"bias_jumps_mid": "bias_jumps", "long_warmup": "warmup"}.get(klass, klass)
        oracle = oracle_z(expected, add, info, floor_model, fs)
        fitted = fitted_oracle_z(expected, add, info, floor_model, fs)
    for p in post:
        x = p(x)
    return t, x, temp, dict(
        seed=seed,
        klass=klass,
        expected=expected,
        sub=info.pop("sub"),
        magnitude=info.pop("m"),
        magnitude_bin=None if info.get("u") is None else bin_of(info["u"]),
        time_scale_s=info.pop("time_scale_s", None),
        params={k: v for k, v in info.items() if k != "u"},
        oracle_z=oracle,
        oracle_z_fitted=fitted,
        floor=floor,
        floor_scale=s,
        rate_hz=fs,
        duration_s=duration,
        samples=n,
    )


def floor_description(name):
    """The floor's terms in deg/s units (the manifest's `floors` entry)."""
    s = FLOORS[name]
    bank = [[sg * s, tau] for sg, tau in BANKS.get(name, GM_BANK)]
    return dict(scale=s, white_n=WHITE_N * s, gm_bank=bank, rrw_k=RRW_K * RRW_SCALE.get(name, 1.0) * s)


def write_csv(path, t, x, temp):
    with open(path, "w") as f:
        f.write("t_s,gx_dps,temp_c\n")
        rows = np.column_stack([t, x, temp])
        np.savetxt(f, rows, fmt=["%.6f", "%.9e", "%.4f"], delimiter=",")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--first-seed", type=int, default=1000)
    ap.add_argument("--per-class", type=int, default=10)
    ap.add_argument("--rates", default="10")
    ap.add_argument("--durations", default="3000,5000")
    ap.add_argument("--floors", default="quiet,nominal,noisy,nominal_flat")
    ap.add_argument("--classes", default=",".join(CLASSES))
    a = ap.parse_args()
    rates = [float(r) for r in a.rates.split(",")]
    durations = [float(d) for d in a.durations.split(",")]
    floors = a.floors.split(",")
    classes = a.classes.split(",")
    for c in classes:
        if c not in CLASSES:
            ap.error(f"unknown class {c!r}; known: {', '.join(CLASSES)}")
    for f in floors:
        if f not in FLOORS:
            ap.error(f"unknown floor {f!r}; known: {', '.join(FLOORS)}")
    if "long_warmup" in classes and min(durations) < 900.0:
        # Its time constant is drawn from 900 s to the recording's length.
        ap.error(f"class long_warmup needs recordings of 900 s or more; --durations starts at {min(durations):g}")
    last = a.first_seed + len(classes) * a.per_class - 1
    tuning = any(a.first_seed in r and last in r for r in TUNING_RANGES)
    report = any(a.first_seed in r and last in r for r in REPORT_RANGES)
    if not (tuning or report):
        ap.error(
            f"seeds {a.first_seed}-{last} are not inside one range: tuning 1000-1999 or 2000-2999, "
            "report 1-999 or 3000-3999"
        )
    os.makedirs(a.out_dir, exist_ok=True)
    cases = []
    index = 0
    for klass in classes:
        for _ in range(a.per_class):
            seed = a.first_seed + index
            index += 1
            t, x, temp, entry = make_case(seed, klass, rates, durations, floors)
            name = f"case_{seed:04d}_{klass}.csv"
            write_csv(os.path.join(a.out_dir, name), t, x, temp)
            entry["file"] = name
            cases.append(entry)
    manifest = dict(
        generator="tools/simgap/independent_cases.py",
        seed_range="tuning" if tuning else "report",
        first_seed=a.first_seed,
        floors={f: floor_description(f) for f in floors},
        cases=cases,
    )
    with open(os.path.join(a.out_dir, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)
    print(f"{len(cases)} cases in {a.out_dir} (seeds {a.first_seed}-{last}, {manifest['seed_range']})")


if __name__ == "__main__":
    main()
