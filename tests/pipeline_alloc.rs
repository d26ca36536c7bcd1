//! The pipeline's hot path allocates nothing per sample: a counting global allocator (counting
//! only on the thread that runs the pipeline) watches thousands of static, moving, rejected and
//! gap samples with a fitted fixed-size CPSO-LSSVM model installed on every axis.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

use gyrocomp::config::Config;
use gyrocomp::model::Fit;
use gyrocomp::model::scaler::MinMaxScaler;
use gyrocomp::sim::{Generator, Preset};
use gyrocomp::stream::{FLAG_MOVING, InputSample, Pipeline};

struct Counting;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCS.with(|a| a.set(a.get() + 1));
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            ALLOCS.with(|a| a.set(a.get() + 1));
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn no_allocation_per_sample() {
    let mut c = Config::paper();
    c.input.rate_hz = gyrocomp::config::RateSetting::Hz(10.0);
    c.retrain.schedule.window = 1500;
    c.retrain.fit.cpso.candidates = 6;
    c.retrain.fit.cpso.particles = 3;
    c.retrain.fit.cpso.iterations = 2;
    let mut p = Pipeline::new(c.pipeline().unwrap()).unwrap();
    let mut sim = Preset::Paper.config();
    sim.duration_s = 800.0;
    let out = Generator::generate(&sim, 3).unwrap();
    let n = out.len();
    let input: Vec<InputSample> = (0..n)
        .map(|k| {
            let mut s = InputSample::new(k as u64, k as u64 * 100_000_000, std::array::from_fn(|a| out.axes[a].raw[k]));
            match k % 1000 {
                100..=149 => s.flags |= FLAG_MOVING,
                300 => s.rate_dps[1] = f64::NAN,
                400 => s.rate_dps[2] = 1e9,
                500 => s.rate_dps[0] += 0.9,
                600 => s.seq -= 1,
                _ => {}
            }
            s
        })
        .collect();
    let warm = 3000;
    for s in &input[..warm] {
        p.process(s);
    }
    let fit = c.cpso_lssvm().unwrap();
    for axis in 0..3 {
        let w = p.training_window(axis);
        let scaler = MinMaxScaler::fit(&w).unwrap();
        let scaled: Vec<f64> = w.iter().map(|&v| scaler.transform(v)).collect();
        p.install_model(axis, Arc::new(fit.fit(&scaled).unwrap()), scaler, 1).unwrap();
    }
    p.process(&input[warm]); // first load of the slots on this thread
    // The counter works: one allocation is seen.
    COUNTING.with(|c| c.set(true));
    drop(std::hint::black_box(vec![1u8]));
    COUNTING.with(|c| c.set(false));
    assert_eq!(ALLOCS.with(|a| a.replace(0)), 1);
    assert_eq!(p.model_version(), 1);
    COUNTING.with(|c| c.set(true));
    let gap = InputSample::new(n as u64 + 5, input[n - 1].t_ns + 1_000_000_000_000, [0.0; 3]);
    for s in &input[warm + 1..] {
        p.process(s);
    }
    p.process(&gap);
    COUNTING.with(|c| c.set(false));
    let allocs = ALLOCS.with(Cell::get);
    assert_eq!(allocs, 0, "{allocs} allocations over {} samples", n - warm);
    let s = p.stats();
    assert!(s.moving > 0 && s.rejected > 0 && s.gaps > 0, "{s:?}");
    let i = s.input;
    assert!(i.invalid > 0 && i.spikes > 0 && i.duplicates > 0 && i.seq_skipped > 0, "{i:?}");
}

/// The default path (Kalman tracker, statistical detector, rate from the timestamps): after the
/// period is measured and the windows sized (one allocation, within the first ten samples), no
/// sample allocates — static, flagged, rejected, detected motion or a gap.
#[test]
fn no_allocation_per_sample_on_the_default_path() {
    let mut p = Pipeline::new(Config::default().pipeline().unwrap()).unwrap();
    let mut sim = Preset::Adis16405.config();
    sim.duration_s = 1500.0;
    let out = Generator::generate(&sim, 3).unwrap();
    let n = out.len();
    let input: Vec<InputSample> = (0..n)
        .map(|k| {
            let mut s = InputSample::new(k as u64, k as u64 * 100_000_000, std::array::from_fn(|a| out.axes[a].raw[k]));
            match k % 2000 {
                100..=149 => s.flags |= FLAG_MOVING,
                300 => s.rate_dps[1] = f64::NAN,
                // A 20 s turn the detector has to find.
                700..=899 => s.rate_dps[0] += 30.0 * (std::f64::consts::PI * (k % 2000 - 700) as f64 / 200.0).sin(),
                1600 => s.seq -= 1,
                _ => {}
            }
            s
        })
        .collect();
    let warm = 50;
    for s in &input[..warm] {
        p.process(s);
    }
    assert_eq!(p.period_s(), Some(0.1));
    COUNTING.with(|c| c.set(true));
    let gap = InputSample::new(n as u64 + 5, input[n - 1].t_ns + 1_000_000_000_000, [0.0; 3]);
    for s in &input[warm..] {
        p.process(s);
    }
    p.process(&gap);
    COUNTING.with(|c| c.set(false));
    let allocs = ALLOCS.with(|a| a.replace(0));
    assert_eq!(allocs, 0, "{allocs} allocations over {} samples", n - warm);
    let s = p.stats();
    assert!(s.moving > 0 && s.rejected > 0 && s.gaps > 0 && s.committed > 0 && s.detector.onsets > 0, "{s:?}");
}
