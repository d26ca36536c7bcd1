//! Criterion benchmarks of wavelet denoising (issue: foundation, item 7).
//!
//! - `batch/denoise_100k`: the paper's batch denoise (db4, 3 levels) of 100,000 samples, beside
//!   `batch/baseline_copy_sum_100k` (one pass over the same data) and `batch/wavedec_waverec_100k`
//!   (the allocating transform pair without thresholding) measured in the same run.
//! - `causal/push_w{64,256,1024}`: one `CausalDenoiser::push` with a full window (cost per sample),
//!   beside `causal/baseline_batch_w256` (one batch denoise of a 256-sample window, allocating).
//!
//! Run: `cargo bench --bench denoise`. Compare ratios, not absolute times: this machine is noisy.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::stream::{CausalConfig, CausalDenoiser};
use gyrocomp::wavelet::dwt::{wavedec, waverec};
use gyrocomp::wavelet::{DenoiseConfig, Denoiser, Wavelet, denoise_batch};

/// A deterministic gyro-like test signal: a slow random walk plus white noise.
fn signal(n: usize) -> Vec<f64> {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut walk = 0.0;
    (0..n)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            walk += 1e-3 * u;
            walk + 0.1 * u
        })
        .collect()
}

fn batch(c: &mut Criterion) {
    let x = signal(100_000);
    let mut group = c.benchmark_group("batch");
    group.sample_size(30);
    group.bench_function("baseline_copy_sum_100k", |b| b.iter(|| black_box(x.to_vec()).iter().sum::<f64>()));
    let w = Wavelet::db4();
    group.bench_function("wavedec_waverec_100k", |b| b.iter(|| waverec(&wavedec(black_box(&x), &w, 3), &w)));
    group.bench_function("denoise_100k", |b| b.iter(|| denoise_batch(black_box(&x), &DenoiseConfig::paper())));
    let mut planned = Denoiser::new(DenoiseConfig::paper(), x.len());
    let mut out = vec![0.0; x.len()];
    group.bench_function("denoise_100k_planned", |b| b.iter(|| planned.denoise_into(black_box(&x), &mut out)));
    group.finish();
}

fn causal(c: &mut Criterion) {
    let x = signal(50_000);
    let mut group = c.benchmark_group("causal");
    group.bench_function("baseline_batch_w256", |b| {
        b.iter(|| denoise_batch(black_box(&x[..256]), &DenoiseConfig::paper()))
    });
    for window in [64, 256, 1024] {
        let config = CausalConfig { denoise: DenoiseConfig::paper(), window, lag: 5 };
        let mut denoiser = CausalDenoiser::new(config).unwrap();
        for &v in &x[..window] {
            denoiser.push(v);
        }
        let mut i = window;
        group.bench_function(format!("push_w{window}"), |b| {
            b.iter(|| {
                i = if i + 1 < x.len() { i + 1 } else { window };
                denoiser.push(black_box(x[i]))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, batch, causal);
criterion_main!(benches);
