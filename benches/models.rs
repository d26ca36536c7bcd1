//! Criterion benchmarks of the LS-SVM models at the paper's training size, n = 4000 PSR rows
//! (§4.3, first group; the paper reports 14.556 s for its CPSO-LSSVM training).
//!
//! - `n4000/baseline_psr_matrix`: building the 4000 × 3 PSR matrix (τ = 10, m = 3) — the floor;
//! - `n4000/baseline_kernel_fill`: one 4000 × 4000 kernel matrix fill (lower triangle, 8·10⁶ exp);
//! - `n4000/exact_fit`: one exact LS-SVM fit (kernel fill + blocked Cholesky + two solves);
//! - `n4000/nystrom_fit_mp100`: one fixed-size LS-SVM fit with 100 k-means++ prototypes;
//! - `n4000/cpso_lssvm_default`: the full CPSO-LSSVM tuning and final fit, default settings
//!   (target ≤ 0.5 s on the 2-core development machine).
//!
//! Data: the paper's first group (run 1, gx_dps, first 5021 samples, db4-denoised, scaled to
//! [−1, 1]) when ../shared/data/real is present, otherwise a simulated drift (random walk plus
//! white noise, same processing). Run: `cargo bench --bench models`. Compare ratios, not absolute
//! times: this machine is shared and noisy.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::model::Fit;
use gyrocomp::model::embed::Embedding;
use gyrocomp::model::lssvm::kernel::kernel_plus_ridge;
use gyrocomp::model::lssvm::{CpsoLssvm, LssvmConfig, NystromConfig};
use gyrocomp::model::scaler::MinMaxScaler;
use gyrocomp::wavelet::{DenoiseConfig, denoise_batch};

const SAMPLES: usize = 5021;

/// Raw gx_dps of the real recording, or a simulated drift when it is absent.
fn raw_series() -> Vec<f64> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data/real/adis16405_run1_10hz.csv");
    if let Ok(text) = std::fs::read_to_string(path) {
        let mut lines = text.lines();
        let col = lines.next().and_then(|h| h.split(',').position(|c| c == "gx_dps"));
        if let Some(col) = col {
            let raw: Vec<f64> = lines.take(SAMPLES).filter_map(|l| l.split(',').nth(col)?.parse().ok()).collect();
            if raw.len() == SAMPLES {
                eprintln!("models bench: real data {path}");
                return raw;
            }
        }
    }
    eprintln!("models bench: {path} absent, using a simulated drift");
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut walk = 0.0;
    (0..SAMPLES)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            walk += 2e-3 * u;
            walk + 0.2 * u
        })
        .collect()
}

/// The 4021 normalised training samples that give 4000 PSR rows.
fn training_series() -> Vec<f64> {
    let (mut x, _) = denoise_batch(&raw_series(), &DenoiseConfig::paper());
    let train_len = Embedding::PAPER.history() + 4000;
    x.truncate(train_len);
    let scaler = MinMaxScaler::fit(&x).expect("finite data");
    scaler.transform_in_place(&mut x);
    x
}

fn n4000(c: &mut Criterion) {
    let train = training_series();
    let emb = Embedding::PAPER;
    let rows = emb.embed(&train);
    assert_eq!(rows.rows(), 4000);
    let mut group = c.benchmark_group("n4000");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(5));
    group.bench_function("baseline_psr_matrix", |b| b.iter(|| emb.embed(black_box(&train))));
    group.bench_function("baseline_kernel_fill", |b| {
        b.iter(|| kernel_plus_ridge(black_box(&rows.inputs), 3, 83.162, 29.358))
    });
    let nystrom = NystromConfig { gamma: 29.358, sigma2: 83.162, embedding: emb, ..NystromConfig::default() };
    group.bench_function("nystrom_fit_mp100", |b| b.iter(|| nystrom.fit(black_box(&train)).unwrap()));
    let tuner = CpsoLssvm::default();
    group.bench_function("cpso_lssvm_default", |b| b.iter(|| tuner.fit(black_box(&train)).unwrap()));
    group.measurement_time(Duration::from_secs(20));
    let exact = LssvmConfig { gamma: 29.358, sigma2: 83.162, embedding: emb };
    group.bench_function("exact_fit", |b| b.iter(|| exact.fit(black_box(&train)).unwrap()));
    group.finish();
}

criterion_group!(benches, n4000);
criterion_main!(benches);
