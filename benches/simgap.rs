//! Criterion benchmark of the sim-to-real diagnosis (issue 8: under 60 s for a 10,000 s, 10 Hz
//! recording in release mode on the project's 2-core machine).
//!
//! - `simgap/diagnose_100k_e32`: `gyrocomp simgap` on 100,000 samples (a 10,000 s, 10 Hz
//!   self-test recording with a warm-up, temperature recorded) with the default settings:
//!   ensembles of 32, one thread. Every candidate effect is fitted and its ensemble run, so
//!   this is the whole command minus reading the CSV.
//! - `simgap/member_100k`: the baseline of the comparison: one ensemble member, i.e. simulating the
//!   100,000 samples of the baseline model and computing the statistics of both parts. A diagnosis
//!   runs 32 × (1 + candidates + combinations) of them plus the effect fits and refits.
//!
//! Run: `cargo bench --bench simgap` (about three minutes). Compare ratios: the machine is noisy.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::diag::simgap::baseline::fit_noise_terms;
use gyrocomp::diag::simgap::model::simulate;
use gyrocomp::diag::simgap::selftest::{Injected, RATE_HZ, synthesize};
use gyrocomp::diag::simgap::stats::StatLayout;
use gyrocomp::diag::simgap::{Baseline, EffectKind, Recording, Settings, diagnose};

const DURATION_S: f64 = 10_000.0;

fn bench(c: &mut Criterion) {
    let (rate, temp, _) = synthesize(Injected::Effect(EffectKind::Warmup), DURATION_S, 1.0, 7).unwrap();
    let recording = Recording { rate: &rate, rate_hz: RATE_HZ, temp_c: Some(&temp) };
    let settings = Settings::default();
    let mut group = c.benchmark_group("simgap");
    group.sample_size(10);

    let n_train = (0.7 * rate.len() as f64).round() as usize;
    let terms = fit_noise_terms(&rate[..n_train], RATE_HZ, DURATION_S, false).unwrap();
    let model = terms.to_model(RATE_HZ, DURATION_S, 0.0);
    let train = StatLayout::new(n_train, RATE_HZ, 0.0, None, true).unwrap();
    let hold = StatLayout::new(rate.len() - n_train, RATE_HZ, n_train as f64 / RATE_HZ, None, true).unwrap();
    group.bench_function("member_100k", |b| {
        b.iter(|| {
            let x = simulate(black_box(&model), RATE_HZ, rate.len(), Some(&temp), 3).unwrap();
            let a = train.compute(&x[..n_train], Some(&temp[..n_train])).unwrap();
            let b = hold.compute(&x[n_train..], Some(&temp[n_train..])).unwrap();
            black_box((a, b))
        })
    });
    group.bench_function("diagnose_100k_e32", |b| {
        b.iter(|| black_box(diagnose(black_box(&recording), &Baseline::Fitted, &settings).unwrap().ensembles_run))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
