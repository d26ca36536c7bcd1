"""Oracle detectability of an injected effect (issue 16): how far the best possible test could see it.

An oracle knows the floor's exact noise model and the effect's exact form (its whole added signal,
or for a stochastic effect its spectrum); its evidence is an upper bound on what any diagnosis can
do with the recording. A miss below it is a miss of physics, not of the method. The diagnosis
knows neither, fits the effect on 70 % of the recording and checks it on the rest, and tests eight
effects at once (its own-null level is z 3.2 two-sided), so it needs more than the oracle does.

Evidence is reported as a standard score z (the oracle's test statistic in units of its own
null's standard deviation):

* A deterministic effect e(t) (warm-up, temperature, ramp, slow sinusoid, steps, triangle, chirp):
  the generalised-least-squares z of e's coefficient with an unknown constant bias beside it,
  z^2 = e'C^-1 e - (e'C^-1 1)^2 / (1'C^-1 1), on block means of the recording (at most
  MAX_BLOCKS blocks; C the exact covariance of the floor's block means: white noise, the
  Gauss-Markov bank, rate random walk).
* A fast one (a sinusoid above 0.05 Hz, spikes): the same GLS in the frequency domain on the
  first differences (the circulant approximation; the differenced floor is stationary), with every
  sample kept.
* A stochastic one (Gauss-Markov): the expected Whittle log-likelihood ratio between the floor
  with and without it, E[Lambda] = 2 sum_k (r_k - 1 - ln r_k), r_k = S1/S0 at the Fourier
  frequencies; z = sqrt(E[Lambda]). A noise burst: the same over its window, from the white floor.
* Quantization: none (a grid is seen in the values themselves, not against the floor).

**Fitted-levels oracle** (`fitted_oracle_z`): the diagnosis does not know the floor; it fits the
IEEE Std 952 terms to the recording, and what those terms can take in is no evidence for an
effect (a Gauss-Markov process of minutes is a rate random walk to a 4,000 s recording but for its
lowest few Fourier bins). This oracle still knows the effect's exact form, but of the floor only
its family, the IEEE terms the diagnosis fits: white noise, flicker (bias instability: a bank of
Gauss-Markov processes of equal variance, two per decade of correlation time, whose sum has a 1/f
spectrum over the span; FLICKER_TAUS) and rate random walk, each level free. Its evidence is the
expected likelihood ratio between that family with and without the effect (its amplitude free),
each at the levels closest to the truth in Kullback-Leibler divergence (the limit of maximum
likelihood under a misspecified model, White 1982, "Maximum likelihood estimation of misspecified
models", Econometrica 50):

  E[Lambda] = min_theta 2 KL(truth || null(theta)) - min_theta' 2 KL(truth || alternative(theta')),

on the block means (FITTED_BLOCKS of them) for a slow deterministic effect, where for Gaussian
block means with covariances C_t (truth) and C (model) and mean difference d
  2 KL = tr(C^-1 C_t) - n + ln det C - ln det C_t + d' P d,  P = C^-1 - C^-1 1 1' C^-1 / 1'C^-1 1
(the constant bias unknown), and with the Whittle form on the first differences for a fast or a
stochastic one, 2 KL = 2 sum_k ((S_t + P_k)/S - 1 - ln(S_t/S)). The floor's own Gauss-Markov bank
is outside the family; its misfit is in both terms and largely cancels. With the floor inside the
family this z is at most the known-floor oracle's (the null's minimum is at most its value at the
true levels); an effect that is itself an IEEE term (more rate random walk) has none. A miss at a low
fitted z is one no diagnosis that fits the floor's levels can be expected to avoid; the steps' z
here still knows their times, so for many small steps it remains an upper bound (their
second-order statistics are a rate random walk's; step_gaussianity.py measures what is left).
"""

import math
import os

# The fitted-levels oracle factors 200 x 200 matrices: BLAS threads only contend (two generators
# on two cores ran 10x slower with them). Before numpy is imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

MAX_BLOCKS = 1500
FAST_HZ = 0.05


def floor_block_covariance(floor, fs, n, length):
    """Covariance of the block means (blocks of `length` samples, n // length of them) of a floor
    {white_n, gm_bank: [[sigma, tau]], rrw_k} in deg/s units sampled at fs."""
    blocks = n // length
    dt = 1.0 / fs
    L = length
    idx = np.arange(blocks)
    d = np.abs(idx[:, None] - idx[None, :])
    cov = np.eye(blocks) * (floor["white_n"] ** 2 * fs) / L
    for sigma, tau in floor["gm_bank"]:
        phi = math.exp(-dt / tau)
        h = np.arange(1, L)
        same = sigma * sigma * (L + 2.0 * np.sum((L - h) * phi**h)) / (L * L)
        geo = (1.0 - phi**L) / (1.0 - phi)
        lag = np.maximum(d * L - (L - 1), 1).astype(float)  # the nearest samples of two blocks
        c = sigma * sigma * geo * geo * np.power(phi, lag) / (L * L)
        np.fill_diagonal(c, same)
        cov += c
    k2 = floor["rrw_k"] ** 2 * dt
    lo = np.minimum(idx[:, None], idx[None, :]).astype(float)
    rrw = k2 * (lo * L + (L + 1) / 2.0)
    rrw[idx, idx] = k2 * (idx * L + (L + 1) * (2 * L + 1) / (6.0 * L))
    return cov + rrw


def effect_blocks(effect, max_blocks):
    """The effect's means over at most max_blocks equal blocks, and the block length (samples)."""
    length = max(1, math.ceil(effect.size / max_blocks))
    blocks = effect.size // length
    return effect[: blocks * length].reshape(blocks, length).mean(axis=1), length


def projected_norm(chol, e):
    """e'Pe, P = C^-1 - C^-1 1 1' C^-1 / 1'C^-1 1 (C = chol chol'): the GLS norm of e with an
    unknown constant beside it."""
    we = np.linalg.solve(chol, e)
    w1 = np.linalg.solve(chol, np.ones(e.size))
    return we @ we - (we @ w1) ** 2 / (w1 @ w1)


def block_gls_z(effect, floor, fs):
    e, length = effect_blocks(effect, MAX_BLOCKS)
    cov = floor_block_covariance(floor, fs, e.size * length, length)
    z2 = projected_norm(np.linalg.cholesky(cov), e)
    return math.sqrt(max(z2, 0.0))


def differenced_floor_spectrum(floor, fs, omega):
    """Spectral density (per-sample variance, omega radians per sample) of the floor's first
    differences: 4 sin^2(omega/2) (white + Gauss-Markov bank) + K^2 dt."""
    dt = 1.0 / fs
    s2 = 4.0 * np.sin(0.5 * omega) ** 2
    stationary = np.full_like(omega, floor["white_n"] ** 2 * fs)
    for sigma, tau in floor["gm_bank"]:
        stationary += gauss_markov_spectrum(sigma, tau, dt, omega)
    return s2 * stationary + floor["rrw_k"] ** 2 * dt


def gauss_markov_spectrum(sigma, tau, dt, omega):
    """AR(1) point samples of variance sigma^2: sigma^2 (1 - phi^2) / |1 - phi e^(-i omega)|^2."""
    phi = math.exp(-dt / tau)
    return sigma * sigma * (1.0 - phi * phi) / (1.0 + phi * phi - 2.0 * phi * np.cos(omega))


def spectral_gls_z(effect, floor, fs):
    de = np.diff(effect)
    m = de.size
    spec = np.fft.rfft(de)
    omega = 2.0 * math.pi * np.arange(spec.size) / m
    weight = np.full(spec.size, 2.0)
    weight[0] = 1.0
    if m % 2 == 0:
        weight[-1] = 1.0
    s = differenced_floor_spectrum(floor, fs, omega)
    z2 = np.sum(weight[1:] * np.abs(spec[1:]) ** 2 / s[1:]) / m  # the constant bias is unknown
    return math.sqrt(z2)


def added_noise_z(extra, floor, fs, n):
    """sqrt E[Lambda] of the Whittle ratio for a stationary noise of spectral density `extra`
    (a function of omega) added to the floor, over the Fourier frequencies of n samples."""
    omega = 2.0 * math.pi * np.arange(1, n // 2) / n
    s2 = 4.0 * np.sin(0.5 * omega) ** 2
    r = 1.0 + s2 * extra(omega) / differenced_floor_spectrum(floor, fs, omega)
    return math.sqrt(2.0 * np.sum(r - 1.0 - np.log(r)))


def gauss_markov_z(sigma, tau, floor, fs, n):
    return added_noise_z(lambda omega: gauss_markov_spectrum(sigma, tau, 1.0 / fs, omega), floor, fs, n)


def oracle_z(kind, effect, info, floor, fs):
    """The oracle's z for an effect of `kind` whose added signal is `effect` (None for a stochastic
    one, then `info` holds its parameters); None where no oracle applies (quantisation)."""
    if kind == "quantization":
        return None
    if kind == "gauss_markov":
        return gauss_markov_z(info["sigma_dps"], info["time_scale_s"], floor, fs, effect.size)
    if kind == "noise_burst":
        inside = effect != 0.0
        extra = float(np.var(effect[inside])) if inside.any() else 0.0
        return added_noise_z(lambda omega: np.full_like(omega, extra), floor, fs, int(inside.sum()))
    fast = kind == "spikes" or (kind == "sinusoid" and info.get("frequency_hz", 0.0) > FAST_HZ)
    return spectral_gls_z(effect, floor, fs) if fast else block_gls_z(effect, floor, fs)


FITTED_BLOCKS = 200
FLICKER_TAUS = 10.0 ** np.arange(-1.0, 5.01, 0.5)


def nelder_mead(f, x0, step=1.0, iterations=600, tol=1e-8):
    """Minimises f over R^d by the Nelder-Mead simplex (Nelder & Mead 1965, standard
    coefficients 1, 2, 0.5, 0.5); (argmin, min). numpy only: the generator needs no scipy."""
    d = len(x0)
    pts = [np.asarray(x0, float)] + [np.asarray(x0, float) + step * np.eye(d)[i] for i in range(d)]
    vals = [f(p) for p in pts]
    for _ in range(iterations):
        order = np.argsort(vals)
        pts, vals = [pts[i] for i in order], [vals[i] for i in order]
        if abs(vals[-1] - vals[0]) <= tol * (1.0 + abs(vals[0])):
            break
        centre = np.mean(pts[:-1], axis=0)
        refl = centre + (centre - pts[-1])
        fr = f(refl)
        if fr < vals[0]:
            exp = centre + 2.0 * (centre - pts[-1])
            fe = f(exp)
            pts[-1], vals[-1] = (exp, fe) if fe < fr else (refl, fr)
        elif fr < vals[-2]:
            pts[-1], vals[-1] = refl, fr
        else:
            con = centre + 0.5 * (pts[-1] - centre)
            fc = f(con)
            if fc < vals[-1]:
                pts[-1], vals[-1] = con, fc
            else:
                pts = [pts[0]] + [pts[0] + 0.5 * (p - pts[0]) for p in pts[1:]]
                vals = [vals[0]] + [f(p) for p in pts[1:]]
    best = int(np.argmin(vals))
    return pts[best], vals[best]


def minimise(f, x0):
    """Nelder-Mead restarted from its own result until it stops improving (a simplex can stall
    on a ridge); (argmin, min)."""
    x, v = nelder_mead(f, x0, step=2.0)
    for _ in range(6):
        x2, v2 = nelder_mead(f, x, step=0.5)
        if v2 >= v - 1e-9 * (1.0 + abs(v)):
            break
        x, v = x2, v2
    return x, v


def family_block_covariances(fs, n, length):
    """Unit block-mean covariances of the IEEE family (white, flicker, rate random walk)."""
    white = floor_block_covariance(dict(white_n=1.0 / math.sqrt(fs), gm_bank=[], rrw_k=0.0), fs, n, length)
    flicker = floor_block_covariance(
        dict(white_n=0.0, gm_bank=[[1.0, tau] for tau in FLICKER_TAUS], rrw_k=0.0), fs, n, length
    )
    walk = floor_block_covariance(dict(white_n=0.0, gm_bank=[], rrw_k=math.sqrt(fs)), fs, n, length)
    return [white, flicker, walk]


def block_kl_terms(cov, truth, e):
    """(tr(C^-1 C_t) + ln det C, d'Pd) for block covariance C (module docs)."""
    try:
        chol = np.linalg.cholesky(cov)
    except np.linalg.LinAlgError:
        return math.inf, math.inf
    half = np.linalg.solve(chol, truth)
    trace = np.trace(np.linalg.solve(chol.T, half))
    logdet = 2.0 * np.sum(np.log(np.diag(chol)))
    return trace + logdet, projected_norm(chol, e)


def fitted_block_z(effect, floor, fs):
    """The fitted-levels oracle for a slow deterministic effect (module docs): block means."""
    e, length = effect_blocks(effect, FITTED_BLOCKS)
    blocks = e.size
    truth = floor_block_covariance(floor, fs, blocks * length, length)
    units = family_block_covariances(fs, blocks * length, length)
    scale = np.trace(truth) / blocks

    def cov(theta):
        return sum(math.exp(t) * u for t, u in zip(theta, units)) + 1e-12 * scale * np.eye(blocks)

    def alternative(theta):
        return block_kl_terms(cov(theta), truth, e)[0]

    def null(theta):
        a, b = block_kl_terms(cov(theta), truth, e)
        return a + b

    return fitted_evidence(null, alternative, np.log([scale / np.trace(u) * blocks / 3.0 for u in units]))


def family_spectra(fs, omega):
    """Unit spectral densities of the IEEE family's first differences (white, flicker, walk)."""
    dt = 1.0 / fs
    s2 = 4.0 * np.sin(0.5 * omega) ** 2
    flicker = sum(gauss_markov_spectrum(1.0, tau, dt, omega) for tau in FLICKER_TAUS)
    return [s2, s2 * flicker, np.full_like(omega, dt)]


def whittle_kl(truth, power, model):
    """2 KL in the Whittle form, sum over Fourier bins of 2((S_t + P)/S - 1 - ln(S_t/S))."""
    if np.any(model <= 0.0):
        return math.inf
    return 2.0 * np.sum((truth + power) / model - 1.0 - np.log(truth / model))


def fitted_spectral_z(floor, fs, n, added=None, effect=None, extra_unit=None):
    """The fitted-levels oracle in the Whittle form on first differences (module docs): for a
    deterministic `effect` (its periodogram P), or a stochastic one of differenced spectral
    density `added` (into the truth), whose unit shape `extra_unit` the alternative adds with a
    free level."""
    if effect is not None:
        de = np.diff(effect)
        n = de.size
        power = np.abs(np.fft.rfft(de)[1 : n // 2]) ** 2 / n
    omega = 2.0 * math.pi * np.arange(1, n // 2) / n
    truth = differenced_floor_spectrum(floor, fs, omega)
    if added is not None:
        truth = truth + added(omega)
        power = np.zeros_like(omega)
    units = family_spectra(fs, omega)
    scale = float(np.mean(truth))
    start = np.log([scale / np.mean(u) / 3.0 for u in units])

    def model(theta, cols):
        return sum(math.exp(t) * u for t, u in zip(theta, cols)) + 1e-12 * scale

    def null(theta):
        return whittle_kl(truth, power, model(theta, units))

    # Deterministic: the alternative fits the effect exactly, its divergence is the family's;
    # stochastic: the family plus the effect's shape at a free level.
    cols = units if extra_unit is None else units + [extra_unit(omega)]

    def alternative(theta):
        return whittle_kl(truth, 0.0, model(theta, cols))

    alt_start = np.append(start, [math.log(scale / np.mean(c) / 3.0) for c in cols[len(units) :]])
    return fitted_evidence(null, alternative, start, alt_start)


def fitted_evidence(null, alternative, start, alt_start=None):
    """sqrt(min null - min alternative) (module docs): the alternative minimised first (from
    alt_start when it has levels beyond the family's, else start), then the null from the
    alternative's family levels and from start, the lower kept."""
    at_alt, v_alt = minimise(alternative, start if alt_start is None else alt_start)
    v_null = min(minimise(null, at_alt[: len(start)])[1], minimise(null, start)[1])
    return math.sqrt(max(v_null - v_alt, 0.0))


def fitted_oracle_z(kind, effect, info, floor, fs):
    """The fitted-levels oracle's z (module docs) for an effect of `kind`, as `oracle_z`; None
    where no oracle applies (quantisation) or the effect is no stationary addition (a burst)."""
    if kind in ("quantization", "noise_burst"):
        return None
    dt = 1.0 / fs
    if kind == "gauss_markov":
        sigma, tau = info["sigma_dps"], info["time_scale_s"]

        def shape(omega):
            return 4.0 * np.sin(0.5 * omega) ** 2 * gauss_markov_spectrum(1.0, tau, dt, omega)

        return fitted_spectral_z(floor, fs, effect.size, added=lambda w: sigma * sigma * shape(w), extra_unit=shape)
    # An oscillation with fewer than four blocks per period is in the spectral form.
    block_s = math.ceil(effect.size / FITTED_BLOCKS) * dt
    fast = kind in ("spikes", "chirp") or (kind == "sinusoid" and info.get("frequency_hz", 0.0) * block_s > 0.25)
    return fitted_spectral_z(floor, fs, effect.size, effect=effect) if fast else fitted_block_z(effect, floor, fs)


def brute_block_covariance(floor, fs, n, length):
    """floor_block_covariance by summing the samples' covariance matrix over blocks (O(n^2); the
    self-check's independent reference)."""
    dt = 1.0 / fs
    i = np.arange(n)
    lag = np.abs(i[:, None] - i[None, :])
    cov = np.eye(n) * floor["white_n"] ** 2 * fs
    for sigma, tau in floor["gm_bank"]:
        cov = cov + sigma * sigma * np.exp(-lag * dt / tau)
    steps = np.minimum(i[:, None], i[None, :]) + 1.0  # the walk has taken k + 1 steps at sample k
    cov = cov + floor["rrw_k"] ** 2 * dt * steps
    blocks = n // length
    a = np.kron(np.eye(blocks), np.ones(length) / length)
    return a @ cov @ a.T


def selfcheck():
    """Closed forms the oracle must reproduce; raises AssertionError on a mismatch."""
    floor = dict(white_n=0.03, gm_bank=[[0.004, 8.0], [0.005, 90.0]], rrw_k=4e-5)
    fast = floor_block_covariance(floor, 10.0, 120, 8)
    slow = brute_block_covariance(floor, 10.0, 120, 8)
    assert np.allclose(fast, slow, rtol=1e-10, atol=0.0), np.max(np.abs(fast / slow - 1.0))
    white = dict(white_n=0.03, gm_bank=[], rrw_k=0.0)
    fs, n = 10.0, 40_000
    var = white["white_n"] ** 2 * fs
    t = np.arange(n)
    # A ramp of change D on white noise, constant bias unknown: z^2 = sum (e - mean e)^2 / var.
    ramp = 0.05 * t / n
    want = math.sqrt(np.sum((ramp - ramp.mean()) ** 2) / var)
    got = block_gls_z(ramp, white, fs)
    assert abs(got / want - 1.0) < 0.01, (got, want)
    # A sinusoid of amplitude A on white noise: z^2 = n A^2 / (2 var) (frequency domain, differenced).
    line = 0.01 * np.sin(2.0 * math.pi * 0.2 * t / fs)
    want = math.sqrt(n * 0.01**2 / (2.0 * var))
    got = spectral_gls_z(line, white, fs)
    assert abs(got / want - 1.0) < 0.01, (got, want)
    # A weak Gauss-Markov process: 2 sum (r - 1 - ln r) ~ sum (r - 1)^2 with r - 1 = S_gm / S_white.
    omega = 2.0 * math.pi * np.arange(1, n // 2) / n
    ratio = gauss_markov_spectrum(0.0005, 20.0, 1.0 / fs, omega) / var
    want = math.sqrt(np.sum(ratio**2))
    got = gauss_markov_z(0.0005, 20.0, white, fs, n)
    assert abs(got / want - 1.0) < 0.02, (got, want)
    # Fitted levels, floor inside the family: a ramp's evidence is at most the known floor's ...
    ramp_fitted = fitted_oracle_z("ramp", ramp, {}, white, fs)
    assert 0.0 < ramp_fitted <= 1.001 * block_gls_z(ramp, white, fs), ramp_fitted
    # ... a fast sinusoid's (nothing in the family looks like a line) about the same ...
    line_fitted = fitted_oracle_z("sinusoid", line, dict(frequency_hz=0.2), white, fs)
    assert abs(line_fitted / spectral_gls_z(line, white, fs) - 1.0) < 0.02, line_fitted
    # ... and more rate random walk, itself a term of the family, none although the known floor's
    # oracle sees it plainly.
    walk = dict(white_n=0.03, gm_bank=[], rrw_k=4e-5)
    more = (10.0 * walk["rrw_k"]) ** 2 / fs
    known = added_noise_z(lambda omega: np.full_like(omega, more) / (4.0 * np.sin(0.5 * omega) ** 2), walk, fs, n)
    unit = lambda omega: np.full_like(omega, 1.0 / fs)  # noqa: E731
    fitted = fitted_spectral_z(walk, fs, n, added=lambda omega: more * fs * unit(omega), extra_unit=unit)
    assert known > 10.0 and fitted < 0.5, (known, fitted)


if __name__ == "__main__":
    selfcheck()
    print("oracle self-check passed")
