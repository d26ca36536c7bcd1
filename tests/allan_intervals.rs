//! The confidence intervals of the Allan noise-term fit (`diag::fit_intervals::fit_intervals`, the
//! `fit_ci` of `gyrocomp allan --format json`): on simulated white noise + rate random walk with
//! known N and K, the 95 % intervals hold the true values in most runs, and N's shrink as the
//! recording grows. Coverage and widths are printed (`cargo test -- --nocapture`).

use gyrocomp::diag::allan::{Taus, oadev};
use gyrocomp::diag::fit_intervals::{FitIntervals, fit_intervals};
use gyrocomp::diag::noise_fit::{Weighting, fit_allan};
use gyrocomp::sim::{AxisConfig, Generator, SimConfig};

const RATE_HZ: f64 = 100.0;
/// ARW 2.4 deg/√h and RRW 600 deg/h/√h: the −½ and +½ lines cross at τ = √3·N/K ≈ 25 s, so the
/// 2^17-sample recordings (1311 s) show K over more than five octaves.
const ARW_DEG_RT_H: f64 = 2.4;
const RRW_DEG_H_RT_H: f64 = 600.0;

/// The intervals of every axis of seeds 1..=`seeds` at `samples` samples.
fn intervals(samples: usize, seeds: u64) -> Vec<FitIntervals> {
    let axis =
        AxisConfig { arw_deg_rt_h: Some(ARW_DEG_RT_H), rrw_deg_h_rt_h: Some(RRW_DEG_H_RT_H), ..AxisConfig::default() };
    let cfg = SimConfig::with_axis(RATE_HZ, samples as f64 / RATE_HZ, axis);
    let mut out = Vec::new();
    for seed in 1..=seeds {
        for a in &Generator::generate(&cfg, seed).unwrap().axes {
            let allan = oadev(&a.raw, RATE_HZ, &Taus::Octave).unwrap();
            let fit = fit_allan(&allan, Weighting::IndependentTerms).unwrap();
            out.push(fit_intervals(&allan, Weighting::IndependentTerms, &fit, 0.95, 60, 952).unwrap());
        }
    }
    out
}

#[test]
fn intervals_cover_the_true_n_and_k_and_shrink_with_length() {
    let (n_true, k_true) = (ARW_DEG_RT_H / 60.0, RRW_DEG_H_RT_H / 216_000.0);
    let long = intervals(1 << 17, 4);
    let inside = |get: fn(&FitIntervals) -> [f64; 2], truth: f64, runs: &[FitIntervals]| {
        runs.iter().filter(|ci| get(ci)[0] <= truth && truth <= get(ci)[1]).count()
    };
    let (n_in, k_in) = (inside(|c| c.n, n_true, &long), inside(|c| c.k, k_true, &long));
    println!("2^17 samples: true N inside {n_in}/12, true K inside {k_in}/12 of the 95 % intervals");
    // 12 runs at 95 %: 10 or more inside has probability ≈ 0.98 for honest intervals.
    assert!(n_in >= 10 && k_in >= 10, "N {n_in}/12, K {k_in}/12: {long:#?}");
    assert!(long.iter().all(|c| c.fits == c.draws), "every replicate refits");

    let short = intervals(1 << 14, 4);
    let width = |runs: &[FitIntervals], get: fn(&FitIntervals) -> [f64; 2]| {
        runs.iter().map(|c| get(c)[1] - get(c)[0]).sum::<f64>() / runs.len() as f64
    };
    let (wn, wk) = ((width(&short, |c| c.n), width(&long, |c| c.n)), (width(&short, |c| c.k), width(&long, |c| c.k)));
    let (n_short, k_short) = (inside(|c| c.n, n_true, &short), inside(|c| c.k, k_true, &short));
    println!("2^14 samples: true N inside {n_short}/12, true K inside {k_short}/12");
    println!("mean width, 2^14 → 2^17 samples: N {:.3e} → {:.3e}, K {:.3e} → {:.3e}", wn.0, wn.1, wk.0, wk.1);
    // Eight times the data: about √8 ≈ 2.8 times narrower; at least 2 asked for. K is not held
    // to it: over 2^14 samples (164 s) K shows over three octaves only, the fit often sets it to
    // zero and the interval then hugs zero (the boundary case of the method, module docs of
    // diag::fit_intervals), so its width does not measure its precision there.
    assert!(wn.1 * 2.0 < wn.0, "N widths {wn:?}");
    assert!(long.iter().all(|c| c.k[1].is_finite() && c.k[1] > 0.0), "K bounded above: {long:#?}");
}
