//! Pipeline snapshots: the installed model of each axis and the pipeline state it reads, as one
//! self-checking byte string (no file or thread code here; the daemon writes and reads the
//! files, `crate::daemon::state`).
//!
//! A snapshot lets a restarted daemon compensate with its last model from the first sample: per
//! axis it holds the model ([`ModelState`]: kernel expansion, embedding, γ, σ², solver), the
//! scaler of its training window (paper Eq. 21), its version, and the warm state
//! ([`AxisWarm`]: the causal denoiser's raw window, the static denoised history the model reads
//! and retrains on, the bias estimate and the held drift). The restored history is concatenated
//! with the samples after the restart exactly as the pipeline concatenates across a gap.
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 0..8 | magic `GYROSNAP` |
//! | 8..12 | format version ([`FORMAT_VERSION`]) |
//! | 12..20 | payload length n |
//! | 20..28 | FNV-1a 64 checksum of the payload (detects accidental corruption, not tampering) |
//! | 28..28+n | payload: [`Snapshot`] in bincode 2 `standard()` encoding |
//!
//! Decoding trusts nothing: header, length, checksum, a size-limited decode with no trailing
//! bytes, then [`Snapshot::validate`]; [`Snapshot::restore_into`] also checks the running
//! configuration against [`Compat`] before it changes the pipeline.
//!
//! Files: this one holds the content (the types, [`Compat`], [`Snapshot::validate`]);
//! `format.rs` the bytes ([`Snapshot::encode`], [`Snapshot::decode`]); `restore.rs` the capture
//! from and the checked restore into a pipeline; the warm state itself is [`super::warm`].

mod format;
mod restore;

use serde::{Deserialize, Serialize};

use super::pipeline::PipelineConfig;
use super::warm::{AxisWarm, StreamWarm};
use crate::model::embed::Embedding;
use crate::model::scaler::MinMaxScaler;
use crate::model::snapshot::ModelState;

/// First bytes of every snapshot.
pub const MAGIC: [u8; 8] = *b"GYROSNAP";
/// Version of the layout and payload written by this build (the only one it reads).
pub const FORMAT_VERSION: u32 = 7;
/// Largest payload accepted, bytes (a 1,000,000-sample history of three axes is 24 MB).
pub const MAX_PAYLOAD: usize = 256 << 20;
/// Bytes before the payload.
pub const HEADER_LEN: usize = 28;

/// The settings a stored model and its warm state depend on; a snapshot made under other values
/// is refused.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Compat {
    /// `denoise.wavelet`.
    pub wavelet: String,
    /// `denoise.level`.
    pub level: usize,
    /// `denoise.window`.
    pub denoise_window: usize,
    /// `denoise.lag` (sets how far the model forecasts).
    pub lag: usize,
    /// `embedding.tau`, `embedding.dim`.
    pub embedding: Embedding,
    /// Nominal sample period from `input.rate_hz`, ns (0: "auto").
    pub period_ns: u64,
    /// `drift.estimator`.
    pub estimator: String,
    /// `motion.detector`.
    pub detector: String,
}

impl Compat {
    /// The values of a pipeline configuration.
    pub fn of(config: &PipelineConfig) -> Self {
        Self {
            wavelet: config.causal.denoise.wavelet.name().to_owned(),
            level: config.causal.denoise.level,
            denoise_window: config.causal.window,
            lag: config.causal.lag,
            embedding: config.embedding,
            period_ns: config.input.period_ns,
            estimator: config.drift.kind.name().to_owned(),
            detector: config.detector.name().to_owned(),
        }
    }

    /// `Ok` when equal; otherwise the configuration keys that differ, with both values.
    pub fn check(&self, running: &Self) -> Result<(), SnapshotError> {
        let mut diffs = Vec::new();
        let mut cmp = |key: &str, stored: String, now: String| {
            if stored != now {
                diffs.push(format!("{key} {stored} (snapshot) vs {now} (running)"));
            }
        };
        cmp("denoise.wavelet", self.wavelet.clone(), running.wavelet.clone());
        cmp("denoise.level", self.level.to_string(), running.level.to_string());
        cmp("denoise.window", self.denoise_window.to_string(), running.denoise_window.to_string());
        cmp("denoise.lag", self.lag.to_string(), running.lag.to_string());
        cmp("embedding.tau", self.embedding.tau.to_string(), running.embedding.tau.to_string());
        cmp("embedding.dim", self.embedding.dim.to_string(), running.embedding.dim.to_string());
        cmp("input.rate_hz (period ns)", self.period_ns.to_string(), running.period_ns.to_string());
        cmp("drift.estimator", self.estimator.clone(), running.estimator.clone());
        cmp("motion.detector", self.detector.clone(), running.detector.clone());
        if diffs.is_empty() { Ok(()) } else { Err(SnapshotError::Incompatible(diffs.join("; "))) }
    }
}

/// An installed model as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredModel {
    /// The model (normalised units).
    pub model: ModelState,
    /// The scaler of the model's training window (Eq. 21).
    pub scaler: MinMaxScaler,
    /// The model's version.
    pub version: u64,
}

/// One axis: its installed model (none for an estimator without models, e.g. the Kalman
/// tracker, or before the first retrain) and warm state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisSnapshot {
    /// The installed model, if any.
    pub model: Option<StoredModel>,
    /// Buffers and running values.
    pub warm: AxisWarm,
}

/// The whole snapshot: the settings it depends on, the three axes and their shared state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// Settings the content depends on.
    pub compat: Compat,
    /// Axes x, y, z.
    pub axes: [AxisSnapshot; 3],
    /// Detector, pending queue, input checks, sample index.
    pub stream: StreamWarm,
}

/// Why a snapshot could not be made, read or used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SnapshotError {
    /// Shorter than its header or than the payload length it announces.
    #[error("truncated: {have} bytes, {need} expected")]
    Truncated {
        /// Bytes present.
        have: usize,
        /// Bytes needed.
        need: usize,
    },
    /// The first bytes are not [`MAGIC`].
    #[error("not a gyrocomp snapshot (bad magic bytes)")]
    BadMagic,
    /// Written by another format version.
    #[error("format version {found}; this build reads version {FORMAT_VERSION}")]
    Version {
        /// The file's version.
        found: u32,
    },
    /// The payload length is above [`MAX_PAYLOAD`].
    #[error("payload of {0} bytes exceeds the {MAX_PAYLOAD}-byte limit")]
    TooLarge(u64),
    /// The payload does not match its checksum.
    #[error("checksum mismatch: the file is corrupt")]
    Checksum,
    /// The payload does not decode.
    #[error("cannot decode the payload: {0}")]
    Decode(String),
    /// The payload decodes but breaks an invariant.
    #[error("invalid content: {0}")]
    Invalid(String),
    /// Made under settings that differ from the running configuration.
    #[error("incompatible with the running configuration: {0}")]
    Incompatible(String),
    /// An installed model cannot be stored (its kind has no [`ModelState`]).
    #[error("axis {0}: the installed model cannot be stored")]
    NotStorable(usize),
}

impl Snapshot {
    /// The newest model version among the axes (0: no model).
    pub fn model_version(&self) -> u64 {
        self.axes.iter().filter_map(|a| a.model.as_ref()).map(|m| m.version).max().unwrap_or(0)
    }

    /// Checks what decoding cannot: valid models reading the stored embedding, finite scalers,
    /// warm states and shared state.
    pub fn validate(&self) -> Result<(), SnapshotError> {
        if !self.stream.is_valid() {
            return Err(SnapshotError::Invalid(
                "the pending samples, detector or input state hold a non-finite value".into(),
            ));
        }
        if self.stream.detector.kind().name() != self.compat.detector {
            return Err(SnapshotError::Invalid(format!(
                "the detector state is a {} one's, the snapshot says {}",
                self.stream.detector.kind().name(),
                self.compat.detector
            )));
        }
        for (axis, a) in self.axes.iter().enumerate() {
            let invalid = |m: String| SnapshotError::Invalid(format!("axis {axis}: {m}"));
            if !a.warm.is_finite() {
                return Err(invalid("the warm state holds a non-finite value".into()));
            }
            let Some(a) = &a.model else { continue };
            a.model.validate().map_err(|e| invalid(e.to_string()))?;
            if let Some(model) = a.model.embedding() {
                let pipeline = self.compat.embedding;
                if (model.tau, model.dim) != (pipeline.tau, pipeline.dim) {
                    return Err(invalid("the model's embedding differs from the snapshot's".into()));
                }
                if model.horizon != 1 && model.horizon != self.compat.lag + 1 {
                    return Err(invalid(format!(
                        "the model forecasts {} samples ahead; the pipeline needs 1 or denoise.lag + 1 = {}",
                        model.horizon,
                        self.compat.lag + 1
                    )));
                }
            }
            let s = a.scaler;
            if !(s.min.is_finite() && s.max.is_finite() && s.min <= s.max) {
                return Err(invalid(format!("scaler [{}, {}] is not a finite range", s.min, s.max)));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::format::fnv1a64;
    use super::*;
    use crate::config::Config;
    use crate::model::cpso::CpsoConfig;
    use crate::model::lssvm::CpsoLssvm;
    use crate::stream::pipeline::Pipeline;
    use crate::stream::retrain::fit_axis;
    use crate::stream::{InputSample, OutputSample, STATUS_NO_MODEL};

    fn config() -> Config {
        let mut c = Config::paper();
        c.denoise.window = 64;
        c.retrain.schedule.window = 300;
        c.retrain.schedule.min_samples = 100;
        c
    }

    /// A static three-axis stream: slow drift plus deterministic pseudo-random noise.
    fn sample(k: u64) -> InputSample {
        let noise = |a: u64| {
            let h = (k * 3 + a).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
            (h as f64 / (1u64 << 53) as f64 - 0.5) * 0.02
        };
        let drift = |a: u64| 0.05 * ((k as f64) * 0.01 + a as f64).sin();
        InputSample::new(k, k * 10_000_000, [drift(0) + noise(0), drift(1) + noise(1), drift(2) + noise(2)])
    }

    /// A pipeline that has run `n` samples and has the retrainer's kind of model (version 4):
    /// a CPSO-LSSVM forecasting denoise.lag + 1 samples ahead on axes x and y, and the constant
    /// model a constant training window gets on axis z.
    fn trained(config: &Config, n: u64) -> Pipeline {
        let mut p = Pipeline::new(config.pipeline().unwrap()).unwrap();
        for k in 0..n {
            p.process(&sample(k));
        }
        let fit = CpsoLssvm {
            embedding: config.cpso_lssvm().unwrap().embedding,
            cpso: CpsoConfig { candidates: 4, particles: 2, iterations: 2, ..CpsoConfig::default() },
            exact_max_rows: 150,
            prototypes: 30,
            ..CpsoLssvm::default()
        };
        assert!(fit.embedding.horizon > 1);
        for axis in 0..3 {
            let window = if axis == 2 { vec![0.25; 300] } else { p.training_window(axis) };
            let f = fit_axis(&fit, &window).unwrap();
            p.install_model(axis, f.model, f.scaler, 4).unwrap();
        }
        p
    }

    fn capture(p: &Pipeline) -> Snapshot {
        Snapshot::of_pipeline(p).unwrap()
    }

    fn run(p: &mut Pipeline, from: u64, n: u64) -> Vec<OutputSample> {
        (from..from + n).map(|k| p.process(&sample(k))).collect()
    }

    #[test]
    fn a_restored_pipeline_compensates_bit_identically_from_the_first_sample() {
        let c = config();
        let mut original = trained(&c, 600);
        let bytes = capture(&original).encode().unwrap();
        let snapshot = Snapshot::decode(&bytes).unwrap();
        assert_eq!(snapshot, capture(&original));
        assert_eq!(snapshot.model_version(), 4);

        let mut restored = Pipeline::new(c.pipeline().unwrap()).unwrap();
        snapshot.restore_into(&mut restored).unwrap();
        assert_eq!(restored.model_version(), 4);
        let want = run(&mut original, 600, 200);
        let got = run(&mut restored, 600, 200);
        assert!(got.iter().all(|o| o.status & STATUS_NO_MODEL == 0 && o.model_version == 4));
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g.drift_dps.map(f64::to_bits), w.drift_dps.map(f64::to_bits), "seq {}", g.seq);
            assert_eq!(g, w);
        }
        // A cold pipeline has no model for these samples: the snapshot is what made the difference.
        let mut cold = Pipeline::new(c.pipeline().unwrap()).unwrap();
        assert!(run(&mut cold, 600, 5).iter().all(|o| o.status & STATUS_NO_MODEL != 0));
        // The next retrain of the restored pipeline trains on the same window.
        assert_eq!(restored.training_windows(), original.training_windows());
    }

    #[test]
    fn corrupt_truncated_foreign_and_incompatible_snapshots_are_refused() {
        let c = config();
        let snapshot = capture(&trained(&c, 400));
        let good = snapshot.encode().unwrap();
        let decode = |b: &[u8]| Snapshot::decode(b).unwrap_err();

        assert!(matches!(decode(&good[..good.len() - 1]), SnapshotError::Truncated { .. }));
        assert!(matches!(decode(&good[..10]), SnapshotError::Truncated { .. }));
        assert!(matches!(decode(&[]), SnapshotError::Truncated { .. }));
        let mut longer = good.clone();
        longer.push(0);
        assert!(matches!(decode(&longer), SnapshotError::Truncated { .. }));
        let mut magic = good.clone();
        magic[0] = b'X';
        assert_eq!(decode(&magic), SnapshotError::BadMagic);
        assert_eq!(decode(b"{\"json\": 1}"), SnapshotError::BadMagic);
        let mut version = good.clone();
        version[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        assert_eq!(decode(&version), SnapshotError::Version { found: FORMAT_VERSION + 1 });
        let mut huge = good.clone();
        huge[12..20].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(matches!(decode(&huge), SnapshotError::TooLarge(_)));
        for at in [HEADER_LEN, HEADER_LEN + 100, good.len() / 2, good.len() - 1] {
            let mut flipped = good.clone();
            flipped[at] ^= 0x10;
            assert_eq!(decode(&flipped), SnapshotError::Checksum, "byte {at}");
        }
        // A payload with a valid checksum that is not a snapshot.
        let garbage = vec![0xFFu8; 64];
        let mut forged = good[..HEADER_LEN].to_vec();
        forged[12..20].copy_from_slice(&(garbage.len() as u64).to_le_bytes());
        forged[20..28].copy_from_slice(&fnv1a64(&garbage).to_le_bytes());
        forged.extend_from_slice(&garbage);
        assert!(matches!(decode(&forged), SnapshotError::Decode(_)));
        // Well-formed but invalid content.
        let mut nan = snapshot.clone();
        nan.axes[1].warm.history[3] = f64::NAN;
        assert!(matches!(decode(&nan.encode().unwrap()), SnapshotError::Invalid(m) if m.contains("axis 1")));
        let mut scaler = snapshot.clone();
        scaler.axes[0].model.as_mut().unwrap().scaler.min = 5.0;
        assert!(matches!(decode(&scaler.encode().unwrap()), SnapshotError::Invalid(_)));

        // Incompatible settings name the key and leave the pipeline untouched.
        let mut other = c.clone();
        other.denoise.lag = 7;
        other.input.rate_hz = crate::config::RateSetting::Hz(200.0);
        let mut p = Pipeline::new(other.pipeline().unwrap()).unwrap();
        let err = Snapshot::decode(&good).unwrap().restore_into(&mut p).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("denoise.lag 5 (snapshot) vs 7 (running)") && msg.contains("input.rate_hz"), "{msg}");
        assert_eq!(p.model_version(), 0);
        assert!(p.training_window(0).is_empty());
    }

    /// The default configuration (Kalman tracker with its temperature term, statistical
    /// detector) at 10 Hz.
    fn default_config() -> Config {
        let mut c = Config::default();
        c.input.rate_hz = crate::config::RateSetting::Hz(10.0);
        c
    }

    /// A static 10 Hz stream with a slow bias and a temperature ramp (NaN on every 97th sample),
    /// turns of 20 deg/s on axis z during `turns` (sample ranges).
    fn moving_sample(k: u64, turns: &[std::ops::Range<u64>]) -> InputSample {
        let noise = |a: u64| {
            let h = (k * 3 + a).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
            (h as f64 / (1u64 << 53) as f64 - 0.5) * 0.4
        };
        let bias = |a: u64| 0.1 * a as f64 + 0.02 * (k as f64 * 1e-3).sin();
        let turn = if turns.iter().any(|r| r.contains(&k)) { 20.0 } else { 0.0 };
        let mut s =
            InputSample::new(k, k * 100_000_000, [bias(0) + noise(0), bias(1) + noise(1), bias(2) + noise(2) + turn]);
        s.temp_c = if k.is_multiple_of(97) { f64::NAN } else { 25.0 + k as f64 * 1e-3 };
        s
    }

    #[test]
    fn a_restart_mid_motion_on_the_default_path_continues_bit_identically() {
        restart_mid_motion_continues_bit_identically(&default_config(), |snapshot| {
            assert!(snapshot.axes.iter().all(|a| a.warm.variance.is_finite() && a.warm.temperature.is_some()));
        });
    }

    #[test]
    fn a_restart_mid_motion_of_the_multiscale_tracker_continues_bit_identically() {
        let mut c = default_config();
        c.drift.kind = crate::stream::EstimatorKind::Multiscale;
        restart_mid_motion_continues_bit_identically(&c, |snapshot| {
            assert!(snapshot.axes.iter().all(|a| a.warm.bank.is_some_and(|b| b.started && b.model.fitted)));
        });
    }

    #[test]
    fn a_restart_mid_motion_of_the_adaptive_tracker_continues_bit_identically() {
        let mut c = default_config();
        c.drift.kind = crate::stream::EstimatorKind::Adaptive;
        restart_mid_motion_continues_bit_identically(&c, |snapshot| {
            assert!(snapshot.axes.iter().all(|a| {
                a.warm.variance.is_finite() && a.warm.bank.is_some_and(|b| b.started) && a.warm.model_evidence != 0.0
            }));
        });
    }

    /// Runs `c` into a turn, snapshots (checked by `check`), restores into a new pipeline and
    /// asserts that the two continue bit for bit and differ from a cold start.
    fn restart_mid_motion_continues_bit_identically(c: &Config, check: impl Fn(&Snapshot)) {
        let turns = [3000..3040, 4500..4530];
        let mut original = Pipeline::new(c.pipeline().unwrap()).unwrap();
        // Run into the first turn until the detector has flagged it for a while.
        let mut out = original.process(&moving_sample(0, &turns));
        let mut at = 1;
        while at < 3020 || out.status & crate::stream::STATUS_MOVING == 0 {
            out = original.process(&moving_sample(at, &turns));
            at += 1;
        }
        assert!(at < 3040, "the turn is flagged at once ({at})");
        let onsets = original.stats().detector.onsets;
        assert!(original.stats().committed > 1000 && original.stats().detector.onsets >= 1);
        // The default path has no model: the snapshot holds none and is written all the same.
        let snapshot = capture(&original);
        assert!(snapshot.axes.iter().all(|a| a.model.is_none()));
        assert_eq!(snapshot.model_version(), 0);
        // (The onset flushed the pending queue: it is empty during a motion.)
        check(&snapshot);
        let bytes = snapshot.encode().unwrap();
        let decoded = Snapshot::decode(&bytes).unwrap();
        // Bytes, not `==`: pending temperatures may be NaN (none).
        assert_eq!(decoded.encode().unwrap(), bytes);

        let mut restored = Pipeline::new(c.pipeline().unwrap()).unwrap();
        decoded.restore_into(&mut restored).unwrap();
        let mut cold = Pipeline::new(c.pipeline().unwrap()).unwrap();
        let mut differs = 0;
        for k in at..6000 {
            let s = moving_sample(k, &turns);
            let (w, g) = (original.process(&s), restored.process(&s));
            assert_eq!(g.drift_dps.map(f64::to_bits), w.drift_dps.map(f64::to_bits), "sample {k}");
            assert_eq!(g.drift_std_dps.map(f64::to_bits), w.drift_std_dps.map(f64::to_bits), "sample {k}");
            assert_eq!(g, w, "sample {k}");
            differs += (cold.process(&s) != w) as u32;
        }
        // Same flags and counts from the restart on, and the state left at the end is the same.
        let after = restored.stats().detector.onsets;
        assert!(
            after >= 1 && after == original.stats().detector.onsets - onsets,
            "the second turn is found after the restart"
        );
        assert_eq!(capture(&restored).encode().unwrap(), capture(&original).encode().unwrap());
        // A cold start is not the same: what made the difference is the snapshot.
        assert!(differs > 1000, "{differs}");
    }

    #[test]
    fn a_restart_with_a_full_pending_queue_finds_the_next_motion_as_the_uninterrupted_run_does() {
        let c = default_config();
        let turns = [2500..2540, 9000..9001]; // (the second lies past the end)
        let mut original = Pipeline::new(c.pipeline().unwrap()).unwrap();
        for k in 0..2000 {
            original.process(&moving_sample(k, &turns));
        }
        let snapshot = capture(&original);
        let discarded = original.stats().discarded;
        assert_eq!(snapshot.stream.pending.samples.len(), 620, "the 62 s commit delay at 10 Hz");
        assert!(snapshot.stream.pending.samples.iter().any(|s| s.2.is_nan()), "with samples lacking a temperature");
        let mut restored = Pipeline::new(c.pipeline().unwrap()).unwrap();
        Snapshot::decode(&snapshot.encode().unwrap()).unwrap().restore_into(&mut restored).unwrap();
        for k in 2000..3500 {
            let s = moving_sample(k, &turns);
            assert_eq!(restored.process(&s), original.process(&s), "sample {k}");
        }
        // The onset's look-back discarded the same restored pending samples.
        assert!(restored.stats().discarded > 0);
        assert_eq!(restored.stats().discarded, original.stats().discarded - discarded);
    }

    #[test]
    fn a_snapshot_for_another_detector_or_with_foreign_windows_is_refused_and_leaves_the_pipeline_alone() {
        let c = default_config();
        let mut p = Pipeline::new(c.pipeline().unwrap()).unwrap();
        for k in 0..200 {
            p.process(&moving_sample(k, &[]));
        }
        let snapshot = capture(&p);
        // Other windows: the stored residual windows do not fit.
        let mut other = c.clone();
        other.motion.statistical.windows_s = vec![0.5, 2.0, 10.0];
        other.motion.statistical.relearn_s = 600.0;
        let mut q = Pipeline::new(other.pipeline().unwrap()).unwrap();
        let err = snapshot.restore_into(&mut q).unwrap_err();
        assert!(err.to_string().contains("motion windows"), "{err}");
        assert_eq!(q.stream_state(), Pipeline::new(other.pipeline().unwrap()).unwrap().stream_state());
        // Another detector: named as an incompatible key.
        let mut threshold = c.clone();
        threshold.motion.detector = crate::stream::DetectorKind::Threshold;
        let mut q = Pipeline::new(threshold.pipeline().unwrap()).unwrap();
        let err = snapshot.restore_into(&mut q).unwrap_err();
        assert!(err.to_string().contains("motion.detector statistical (snapshot) vs threshold (running)"), "{err}");
        // A forged detector state of the other kind is refused at decoding.
        let mut forged = snapshot.clone();
        forged.compat.detector = "threshold".into();
        assert!(matches!(Snapshot::decode(&forged.encode().unwrap()), Err(SnapshotError::Invalid(_))));
        // An infinite temperature in the pending queue is invalid content.
        let mut inf = snapshot.clone();
        inf.stream.pending.samples[0].2 = f64::INFINITY;
        assert!(matches!(Snapshot::decode(&inf.encode().unwrap()), Err(SnapshotError::Invalid(_))));
    }
}
