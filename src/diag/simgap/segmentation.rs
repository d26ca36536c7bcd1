//! Two models of a slowly moving level seen through white noise, the pair the nested test of bias
//! jumps compares ([`super::nested_jumps`]):
//!
//! - **Piecewise constant** ([`segment_means`]): the segmentation of a series into constant-mean
//!   segments minimising RSS + β·(changes), found exactly by optimal partitioning with the PELT
//!   pruning (Killick, Fearnhead & Eckley 2012, "Optimal detection of changepoints with a linear
//!   computational cost", JASA 107: a start s is dropped once F(s) + C(s, t) > F(t), which is
//!   exact for a cost that does not grow when a segment is split, as the RSS).
//! - **Random walk** ([`local_level_m2ll`]): the local-level model y_k = μ_k + v_k,
//!   μ_k = μ_{k−1} + w_k, v ~ N(0, r), w ~ N(0, q), whose −2 log-likelihood is the Kalman filter's
//!   prediction-error decomposition (Durbin & Koopman 2012, *Time Series Analysis by State Space
//!   Methods*, §2.10), started at the first value with variance r.
//!
//! A step process makes the level move in a few sharp changes, a rate random walk in many small
//! ones; with the same variance per unit time the two have the same spectrum, so only such a
//! comparison of shapes, not of spectra, tells them apart.

/// The optimal segmentation of a series into constant-mean segments.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Index of the first value of every segment but the first, ascending.
    pub changes: Vec<usize>,
    /// The minimised RSS + β·`changes.len()`.
    pub cost: f64,
}

/// The segmentation of `y` minimising the residual sum of squares about each segment's mean plus
/// `beta` per change (module docs); one segment for fewer than two values.
pub fn segment_means(y: &[f64], beta: f64) -> Segmentation {
    let n = y.len();
    let mut sum = vec![0.0; n + 1];
    let mut sum2 = vec![0.0; n + 1];
    // Values about their mean, so that the prefix sums do not cancel catastrophically.
    let centre = if n > 0 { y.iter().sum::<f64>() / n as f64 } else { 0.0 };
    for (i, v) in y.iter().enumerate() {
        let d = v - centre;
        sum[i + 1] = sum[i] + d;
        sum2[i + 1] = sum2[i] + d * d;
    }
    let rss = |s: usize, t: usize| {
        let (a, b) = (sum[t] - sum[s], sum2[t] - sum2[s]);
        (b - a * a / (t - s) as f64).max(0.0)
    };
    // best[t]: the least cost of y[..t] plus beta (the first segment's beta is taken off at the
    // end); last[t]: where the last segment of that optimum starts.
    let mut best = vec![0.0; n + 1];
    let mut last = vec![0usize; n + 1];
    let mut starts: Vec<usize> = vec![0];
    for t in 1..=n {
        let (mut f, mut at) = (f64::INFINITY, 0);
        for &s in &starts {
            let v = best[s] + rss(s, t) + beta;
            if v < f {
                (f, at) = (v, s);
            }
        }
        best[t] = f;
        last[t] = at;
        starts.retain(|&s| best[s] + rss(s, t) <= f);
        starts.push(t);
    }
    let mut changes = Vec::new();
    let mut t = n;
    while t > 0 && last[t] > 0 {
        t = last[t];
        changes.push(t);
    }
    changes.reverse();
    Segmentation { cost: if n == 0 { 0.0 } else { best[n] - beta }, changes }
}

/// −2 log-likelihood of `y` under the local-level model with observation variance `r` and level
/// increment variance `q` (module docs); 0 for an empty series.
pub fn local_level_m2ll(y: &[f64], r: f64, q: f64) -> f64 {
    let Some((&first, rest)) = y.split_first() else { return 0.0 };
    let (mut level, mut p) = (first, r);
    let mut total = 0.0;
    for &v in rest {
        p += q;
        let s = p + r;
        let e = v - level;
        total += (2.0 * std::f64::consts::PI * s).ln() + e * e / s;
        let gain = p / s;
        level += gain * e;
        p -= gain * p;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::rng::{Stream, StreamId};

    /// A seeded stream of standard normal deviates.
    fn normals(seed: u64) -> Stream {
        Stream::new(seed, 0, StreamId::White)
    }

    /// The segmentation is the exhaustive optimum: on short series every set of changes is tried
    /// by brute force (2^(n−1) sets) and none costs less than what PELT returns.
    #[test]
    fn pelt_finds_the_exhaustive_optimum() {
        let mut rng = normals(5);
        for trial in 0..20 {
            let n = 9;
            let y: Vec<f64> =
                (0..n).map(|k| if k >= 4 { 2.0 } else { 0.0 } + rng.normal() * (0.3 + trial as f64 * 0.1)).collect();
            let beta = 1.0 + trial as f64 * 0.2;
            let got = segment_means(&y, beta);
            let mut exhaustive = f64::INFINITY;
            for mask in 0u32..(1 << (n - 1)) {
                let mut cost = 0.0;
                let mut start = 0;
                for end in 1..=n {
                    if end == n || mask & (1 << (end - 1)) != 0 {
                        let seg = &y[start..end];
                        let m = seg.iter().sum::<f64>() / seg.len() as f64;
                        cost += seg.iter().map(|v| (v - m) * (v - m)).sum::<f64>();
                        if end < n {
                            cost += beta;
                        }
                        start = end;
                    }
                }
                exhaustive = exhaustive.min(cost);
            }
            assert!((got.cost - exhaustive).abs() < 1e-9, "trial {trial}: {} against {exhaustive}", got.cost);
        }
    }

    /// Two clear steps are found where they are, and a constant series has none.
    #[test]
    fn finds_clear_steps_and_no_others() {
        let mut rng = normals(11);
        let y: Vec<f64> = (0..300)
            .map(|k| {
                let level = if k >= 200 {
                    -1.0
                } else if k >= 100 {
                    1.0
                } else {
                    0.0
                };
                level + 0.1 * rng.normal()
            })
            .collect();
        let beta = 2.0 * (300f64).ln() * 0.01;
        assert_eq!(segment_means(&y, beta).changes, vec![100, 200]);
        let flat: Vec<f64> = (0..300).map(|_| 0.1 * rng.normal()).collect();
        assert!(segment_means(&flat, beta).changes.is_empty());
    }

    /// The local-level likelihood is largest near the increment variance the series was made
    /// with (a random walk of q = 0.01 under white noise of r = 1, 20,000 values): the best q of a
    /// log grid lies within a factor 1.5 of it.
    #[test]
    fn the_local_level_likelihood_peaks_at_the_true_walk() {
        let mut rng = normals(3);
        let (r, q) = (1.0f64, 0.01f64);
        let mut level = 0.0;
        let y: Vec<f64> = (0..20_000)
            .map(|_| {
                level += q.sqrt() * rng.normal();
                level + r.sqrt() * rng.normal()
            })
            .collect();
        let grid: Vec<f64> = (0..41).map(|i| 1e-4 * 10f64.powf(i as f64 / 10.0)).collect();
        let best =
            grid.iter().copied().min_by(|a, b| local_level_m2ll(&y, r, *a).total_cmp(&local_level_m2ll(&y, r, *b)));
        let best = best.unwrap();
        assert!(best / q < 1.5 && q / best < 1.5, "best q {best}");
    }
}
