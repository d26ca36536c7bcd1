//! Criterion benchmark of the per-sample `Pipeline` (issue 5): cost of `Pipeline::process` for
//! three axes with a fitted fixed-size CPSO-LSSVM (retrain window 4000, m_p = 100, default CPSO)
//! installed on every axis, static samples (the model path: causal denoise + one direct
//! (L + 1)-step prediction per axis). Beside it, in the same run: `baseline_denoise_at_w256`, one
//! uncached `Denoiser::denoise_at` of a 256-sample window at lag 5 (what each push cost before
//! the finest-detail cache; a fixed yardstick for ratios), `denoise_push_w256`, one
//! `CausalDenoiser::push` (the default window), and `process_no_model` (bias-estimate path).
//!
//! After criterion, a plain loop times 200,000 single `process` calls and prints p50/p99/p99.9
//! per sample and per sample per axis (criterion reports means and medians only).
//!
//! `process_3axes_default_kalman_statistical` is the default path (issue 13: Kalman tracker behind
//! the statistical detector); `process_3axes_adaptive_statistical` the `adaptive` estimator (the
//! scalar and the multi-scale trackers side by side); the same p50/p99 loop runs for both.
//!
//! Run: `cargo bench --bench pipeline`. Targets: ≤ 5 µs p99 per sample per axis (CPSO-LSSVM),
//! ≤ 2 µs for the default path.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::config::Config;
use gyrocomp::model::Fit;
use gyrocomp::model::scaler::MinMaxScaler;
use gyrocomp::sim::{Generator, Preset};
use gyrocomp::stream::{CausalDenoiser, InputSample, Pipeline};
use gyrocomp::wavelet::{DenoiseConfig, Denoiser};

const PERIOD_NS: u64 = 100_000_000;

struct Setup {
    rates: Vec<[f64; 3]>,
    fitted: Pipeline,
    bare: Pipeline,
    /// The default path: Kalman tracker behind the statistical detector, rate from timestamps.
    default: Pipeline,
    /// The `adaptive` estimator behind the statistical detector.
    adaptive: Pipeline,
    next: u64,
}

fn setup() -> Setup {
    let mut c = Config::paper();
    c.input.rate_hz = gyrocomp::config::RateSetting::Hz(10.0);
    assert_eq!(c.retrain.schedule.window, 4000);
    let out = Generator::generate(&Preset::Paper.config(), 1).unwrap();
    let rates: Vec<[f64; 3]> = (0..out.len()).map(|k| std::array::from_fn(|a| out.axes[a].raw[k])).collect();
    let mut fitted = Pipeline::new(c.pipeline().unwrap()).unwrap();
    let mut bare = Pipeline::new(c.pipeline().unwrap()).unwrap();
    let mut default = Pipeline::new(Config::default().pipeline().unwrap()).unwrap();
    let mut adaptive_config = Config::default();
    adaptive_config.drift.kind = gyrocomp::stream::EstimatorKind::Adaptive;
    let mut adaptive = Pipeline::new(adaptive_config.pipeline().unwrap()).unwrap();
    let warm = 5000;
    for (k, r) in rates[..warm].iter().enumerate() {
        let s = InputSample::new(k as u64, k as u64 * PERIOD_NS, *r);
        fitted.process(&s);
        bare.process(&s);
        default.process(&s);
        adaptive.process(&s);
    }
    let fit = c.cpso_lssvm().unwrap();
    let started = Instant::now();
    for axis in 0..3 {
        let w = fitted.training_window(axis);
        let scaler = MinMaxScaler::fit(&w).unwrap();
        let scaled: Vec<f64> = w.iter().map(|&v| scaler.transform(v)).collect();
        let model = fit.fit(&scaled).unwrap();
        eprintln!(
            "axis {axis}: {} rows, solver {:?}, gamma {:.3}, sigma2 {:.3}",
            w.len(),
            model.solver,
            model.gamma,
            model.sigma2
        );
        fitted.install_model(axis, Arc::new(model), scaler, 1).unwrap();
    }
    eprintln!("three CPSO-LSSVM fits: {:.2} s", started.elapsed().as_secs_f64());
    Setup { rates, fitted, bare, default, adaptive, next: warm as u64 }
}

impl Setup {
    fn sample(&mut self) -> InputSample {
        let k = self.next;
        self.next += 1;
        InputSample::new(k, k * PERIOD_NS, self.rates[k as usize % self.rates.len()])
    }
}

fn bench(c: &mut Criterion) {
    let mut s = setup();
    let mut group = c.benchmark_group("pipeline");
    let mut denoiser = CausalDenoiser::new(Config::default().causal_denoise().unwrap()).unwrap();
    for r in &s.rates[..256] {
        denoiser.push(r[0]);
    }
    let rates = s.rates.clone();
    let column: Vec<f64> = rates.iter().map(|r| r[0]).collect();
    let mut uncached = Denoiser::new(DenoiseConfig::paper(), 256);
    let mut start = 0;
    group.bench_function("baseline_denoise_at_w256", |b| {
        b.iter(|| {
            start = if start + 257 < column.len() { start + 1 } else { 0 };
            uncached.denoise_at(black_box(&column[start..start + 256]), 250).0
        })
    });
    let mut i = 256;
    group.bench_function("denoise_push_w256", |b| {
        b.iter(|| {
            i = if i + 1 < rates.len() { i + 1 } else { 256 };
            denoiser.push(black_box(rates[i][0]))
        })
    });
    group.bench_function("process_3axes_cpso_lssvm_w4000", |b| {
        b.iter(|| {
            let x = s.sample();
            s.fitted.process(black_box(&x))
        })
    });
    group.bench_function("process_3axes_default_kalman_statistical", |b| {
        b.iter(|| {
            let x = s.sample();
            s.default.process(black_box(&x))
        })
    });
    group.bench_function("process_3axes_adaptive_statistical", |b| {
        b.iter(|| {
            let x = s.sample();
            s.adaptive.process(black_box(&x))
        })
    });
    group.bench_function("process_3axes_no_model", |b| {
        b.iter(|| {
            let x = s.sample();
            s.bare.process(black_box(&x))
        })
    });
    group.finish();
    assert_eq!(s.fitted.model_version(), 1);

    let n = 200_000;
    for (name, path) in
        [("CPSO-LSSVM w4000", 0), ("default: Kalman + statistical detector", 1), ("adaptive + statistical detector", 2)]
    {
        let mut times = Vec::with_capacity(n);
        for _ in 0..n {
            let x = s.sample();
            let p = match path {
                0 => &mut s.fitted,
                1 => &mut s.default,
                _ => &mut s.adaptive,
            };
            let t0 = Instant::now();
            black_box(p.process(black_box(&x)));
            times.push(t0.elapsed().as_nanos() as f64);
        }
        times.sort_by(f64::total_cmp);
        let q = |p: f64| times[((p * n as f64) as usize).min(n - 1)];
        eprintln!(
            "process (3 axes, {name}) over {n} samples: p50 {:.2} µs, p99 {:.2} µs, p99.9 {:.2} µs per sample; \
             per sample per axis p50 {:.2} µs, p99 {:.2} µs",
            q(0.5) / 1e3,
            q(0.99) / 1e3,
            q(0.999) / 1e3,
            q(0.5) / 3e3,
            q(0.99) / 3e3
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
