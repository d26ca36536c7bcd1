//! The planned generator: built once from a [`SimConfig`] and a seed, then asked for samples in
//! blocks of any length. No global state: two generators with the same config and seed produce the
//! same numbers, and cutting a run into blocks differently does not change them.

use super::config::{AxisConfig, BiasInstability, ConfigError, QuantizationMode, SimConfig};
use super::rng::{Stream, StreamId};
use super::temperature::TemperatureTrajectory;
use super::terms::{
    GaussMarkov, Jumps, Quantiser, RandomWalk, Spikes, TemperatureBias, TimeTerms, White, flicker_poles,
    gauss_markov_sigma,
};

/// Names of the axes, in order (x, y, z) as they appear in column names (`gx_dps`, …).
pub const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

/// Samples processed per inner block (keeps the working set in cache).
const CHUNK: usize = 4096;

/// One axis of a simulated block.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AxisSeries {
    /// Raw output, deg/s: `quantise(drift + white)`.
    pub raw: Vec<f64>,
    /// Truth drift, deg/s: every term except white noise and quantisation.
    pub drift: Vec<f64>,
    /// The white noise that was added, deg/s (quantisation error = raw − drift − white).
    pub white: Vec<f64>,
}

/// A block of simulated samples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimOutput {
    /// Time of each sample, s (`k / rate_hz`, k counted from the start of the run).
    pub t_s: Vec<f64>,
    /// Temperature reading, °C.
    pub temp_c: Vec<f64>,
    /// Axes x, y, z.
    pub axes: [AxisSeries; 3],
}

impl SimOutput {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether the block is empty.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    fn resize(&mut self, len: usize) {
        self.t_s.resize(len, 0.0);
        self.temp_c.resize(len, 0.0);
        for a in &mut self.axes {
            a.raw.resize(len, 0.0);
            a.drift.resize(len, 0.0);
            a.white.resize(len, 0.0);
        }
    }
}

/// The planned terms of one axis.
#[derive(Debug, Clone)]
struct AxisTerms {
    bias: f64,
    processes: Vec<GaussMarkov>,
    rrw: Option<RandomWalk>,
    time_terms: TimeTerms,
    temperature: Option<TemperatureBias>,
    jumps: Option<Jumps>,
    spikes: Option<Spikes>,
    white: Option<White>,
    quantiser: Option<Quantiser>,
}

impl AxisTerms {
    fn new(model: &AxisConfig, axis: u64, rate_hz: f64, seed: u64) -> Self {
        let dt = 1.0 / rate_hz;
        let processes = match &model.bias_instability {
            Some(BiasInstability::GaussMarkov { b_deg_h, correlation_time_s }) if *b_deg_h > 0.0 => {
                let sigma = gauss_markov_sigma(b_deg_h / 3600.0);
                let stream = Stream::indexed(seed, axis, StreamId::BiasInstability, 0);
                vec![GaussMarkov::new(sigma, *correlation_time_s, dt, stream)]
            }
            Some(BiasInstability::Flicker { b_deg_h, floor_from_s, floor_to_s }) if *b_deg_h > 0.0 => {
                flicker_poles(b_deg_h / 3600.0, *floor_from_s, *floor_to_s, dt)
                    .into_iter()
                    .enumerate()
                    .map(|(i, (var, corr))| {
                        let stream = Stream::indexed(seed, axis, StreamId::BiasInstability, i as u64);
                        GaussMarkov::new(var.sqrt(), corr, dt, stream)
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        let k = model.rrw_dps_rt_s();
        let rrw = (k > 0.0).then(|| RandomWalk::new(k * dt.sqrt(), Stream::new(seed, axis, StreamId::RateRandomWalk)));
        let time_terms = TimeTerms {
            ramp: model.ramp_dps2(),
            warmup: model.warmup.as_ref().map(|w| (w.amplitude_dps, w.time_constant_s)),
            sinusoids: model
                .sinusoids
                .iter()
                .flatten()
                .map(|s| TimeTerms::sinusoid(s.amplitude_dps, s.frequency_hz, s.phase_deg))
                .collect(),
        };
        let temperature = model
            .temperature_coefficient
            .as_ref()
            .map(|c| TemperatureBias::new(c.dps_per_c, c.reference_c, c.hysteresis_c));
        let jumps = model
            .jumps
            .as_ref()
            .map(|j| Jumps::new(j.rate_per_h / 3600.0, j.size_dps, Stream::new(seed, axis, StreamId::Jumps)));
        let spikes = model
            .spikes
            .as_ref()
            .map(|s| Spikes::new(s.rate_per_h / 3600.0, s.size_dps, Stream::new(seed, axis, StreamId::Spikes)));
        let n = model.arw_deg_rt_s();
        let white = (n > 0.0).then(|| White::new(n * rate_hz.sqrt(), Stream::new(seed, axis, StreamId::White)));
        let quantiser =
            model.quantization.as_ref().map(|q| Quantiser::new(q.step_dps, q.mode == QuantizationMode::Angle));
        Self {
            bias: model.bias_dps.unwrap_or(0.0),
            processes,
            rrw,
            time_terms,
            temperature,
            jumps,
            spikes,
            white,
            quantiser,
        }
    }

    /// Fills one chunk; `sum` is scratch of the same length.
    fn fill(&mut self, t_s: &[f64], temp: &[f64], out: ChunkOut<'_>, sum: &mut [f64]) {
        let ChunkOut { raw, drift, white } = out;
        drift.fill(self.bias);
        for p in &mut self.processes {
            p.add_to(drift);
        }
        if let Some(rrw) = &mut self.rrw {
            rrw.add_to(drift);
        }
        self.time_terms.add_to(drift, t_s);
        if let Some(tb) = &mut self.temperature {
            tb.add_to(drift, temp);
        }
        if let Some(j) = &mut self.jumps {
            j.add_to(drift, t_s);
        }
        if let Some(s) = &mut self.spikes {
            s.add_to(drift, t_s);
        }
        match &mut self.white {
            Some(w) => w.fill(white),
            None => white.fill(0.0),
        }
        for ((s, &d), &w) in sum.iter_mut().zip(drift.iter()).zip(white.iter()) {
            *s = d + w;
        }
        match &mut self.quantiser {
            Some(q) => q.apply(sum, raw),
            None => raw.copy_from_slice(sum),
        }
    }
}

/// The bounds `(start, end)` of the inner blocks of at most [`CHUNK`] samples that `len` samples
/// are simulated in, in order (both [`Generator::fill`] and [`AxisGenerator::fill`] walk them, so
/// a run splits at the same samples whichever simulates it).
fn chunk_bounds(len: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..len).step_by(CHUNK).map(move |start| (start, (start + CHUNK).min(len)))
}

struct ChunkOut<'a> {
    raw: &'a mut [f64],
    drift: &'a mut [f64],
    white: &'a mut [f64],
}

/// Seeded generator of a whole simulated IMU (three gyro axes and a temperature).
#[derive(Debug, Clone)]
pub struct Generator {
    rate_hz: f64,
    next: u64,
    temperature: TemperatureTrajectory,
    axes: Vec<AxisTerms>,
    temp_true: Vec<f64>,
    sum: Vec<f64>,
}

impl Generator {
    /// Plans the generator of `config` (validated) for `seed`.
    pub fn new(config: &SimConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let axes = (0..3).map(|i| AxisTerms::new(&config.axis_model(i), i as u64, config.rate_hz, seed)).collect();
        Ok(Self {
            rate_hz: config.rate_hz,
            next: 0,
            temperature: TemperatureTrajectory::new(&config.temperature, seed),
            axes,
            temp_true: vec![0.0; CHUNK],
            sum: vec![0.0; CHUNK],
        })
    }

    /// Simulates the whole run of `config` (`config.samples()` samples) for `seed`.
    pub fn generate(config: &SimConfig, seed: u64) -> Result<SimOutput, ConfigError> {
        let mut generator = Self::new(config, seed)?;
        let mut out = SimOutput::default();
        generator.fill(config.samples(), &mut out);
        Ok(out)
    }

    /// This generator reduced to one axis (0 = x, 1 = y, 2 = z), from its current position: the
    /// same samples of that axis as [`Self::fill`] would give, without simulating or storing the
    /// other two (each axis draws from its own streams, so leaving them out changes nothing).
    ///
    /// # Panics
    /// If `axis` is not 0, 1 or 2 (a programming error).
    pub fn into_axis(mut self, axis: usize) -> AxisGenerator {
        let generator = self.axes.swap_remove(axis);
        AxisGenerator {
            rate_hz: self.rate_hz,
            next: self.next,
            temperature: self.temperature,
            generator,
            temp_true: self.temp_true,
            temp_reading: vec![0.0; CHUNK],
            sum: self.sum,
            drift: vec![0.0; CHUNK],
            white: vec![0.0; CHUNK],
        }
    }

    /// Sample rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        self.rate_hz
    }

    /// Number of samples produced so far.
    pub fn position(&self) -> u64 {
        self.next
    }

    /// Replaces the contents of `out` with the next `len` samples.
    pub fn fill(&mut self, len: usize, out: &mut SimOutput) {
        out.resize(len);
        for (i, t) in out.t_s.iter_mut().enumerate() {
            *t = (self.next + i as u64) as f64 / self.rate_hz;
        }
        for (start, end) in chunk_bounds(len) {
            let n = end - start;
            let t_s = &out.t_s[start..end];
            let temp_true = &mut self.temp_true[..n];
            self.temperature.fill(t_s, temp_true, &mut out.temp_c[start..end]);
            for (axis, series) in self.axes.iter_mut().zip(out.axes.iter_mut()) {
                let chunk = ChunkOut {
                    raw: &mut series.raw[start..end],
                    drift: &mut series.drift[start..end],
                    white: &mut series.white[start..end],
                };
                axis.fill(t_s, temp_true, chunk, &mut self.sum[..n]);
            }
        }
        self.next += len as u64;
    }
}

/// One axis of a [`Generator`] ([`Generator::into_axis`]): its raw output alone, in blocks of any
/// length, with working buffers of one inner block rather than of the whole run (the ensembles of
/// the sim-to-real diagnosis simulate one axis many times over).
#[derive(Debug, Clone)]
pub struct AxisGenerator {
    rate_hz: f64,
    next: u64,
    temperature: TemperatureTrajectory,
    generator: AxisTerms,
    temp_true: Vec<f64>,
    temp_reading: Vec<f64>,
    sum: Vec<f64>,
    drift: Vec<f64>,
    white: Vec<f64>,
}

impl AxisGenerator {
    /// Replaces the contents of `raw` with the axis's next `len` raw samples, deg/s.
    pub fn fill(&mut self, len: usize, raw: &mut Vec<f64>) {
        raw.resize(len, 0.0);
        let mut t_s = [0.0; CHUNK];
        for (start, end) in chunk_bounds(len) {
            let n = end - start;
            for (i, t) in t_s[..n].iter_mut().enumerate() {
                *t = (self.next + (start + i) as u64) as f64 / self.rate_hz;
            }
            self.temperature.fill(&t_s[..n], &mut self.temp_true[..n], &mut self.temp_reading[..n]);
            let chunk =
                ChunkOut { raw: &mut raw[start..end], drift: &mut self.drift[..n], white: &mut self.white[..n] };
            self.generator.fill(&t_s[..n], &self.temp_true[..n], chunk, &mut self.sum[..n]);
        }
        self.next += len as u64;
    }
}
