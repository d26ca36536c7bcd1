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
"""

import math

import numpy as np

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


def block_gls_z(effect, floor, fs):
    n = effect.size
    length = max(1, math.ceil(n / MAX_BLOCKS))
    blocks = n // length
    e = effect[: blocks * length].reshape(blocks, length).mean(axis=1)
    cov = floor_block_covariance(floor, fs, blocks * length, length)
    chol = np.linalg.cholesky(cov)
    we = np.linalg.solve(chol, e)
    w1 = np.linalg.solve(chol, np.ones(blocks))
    z2 = we @ we - (we @ w1) ** 2 / (w1 @ w1)
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


if __name__ == "__main__":
    selfcheck()
    print("oracle self-check passed")
