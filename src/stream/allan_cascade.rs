//! A running, winsorised, non-overlapping Allan variance at octave block sizes ([`AllanCascade`]):
//! the accumulator behind the axis' self-calibration ([`NoiseCalibration`](super::NoiseCalibration))
//! and the multi-scale tracker's noise fit (`super::drift::multiscale`).
//!
//! Allan variance (IEEE Std 952-1997, Annex C): for block means ȳ_k over m samples,
//! σ²(m) = ½·E[(ȳ_{k+1} − ȳ_k)²]. Level j holds blocks of m = 2^j samples; each level's block
//! sum is the sum of two blocks of the level below (a cascade: amortised two additions per
//! sample). Once a level has [`TRUSTED_DIFFERENCES`] differences, a new difference d enters
//! clipped at [`ALLAN_CLIP`] of its standard deviations (½d² ≤ ALLAN_CLIP²·σ², σ² the level's
//! current estimate) and divided by [`ALLAN_CLIP_MEAN`], so that the estimate stays unbiased for
//! Gaussian differences (a Huber-type M-estimate of scale). A slow rotation the detector missed,
//! or the lead-in of one found late, gives block differences of many σ; unclipped they raise the
//! long-τ variance, which shortens the trackers' memory and widens the detector's thresholds, so
//! that the next slow rotation is missed too (a loop seen on the simulated tuning set).

/// Octave levels kept: blocks of 1 … 2^(LEVELS−1) samples (2^21 samples: 35 min at 1 kHz).
pub const LEVELS: usize = 22;
/// Differences a level needs before its variance is trusted (relative σ of the estimate ≈ √(2/16)).
pub const TRUSTED_DIFFERENCES: u64 = 16;
/// Winsorising threshold of a block difference, in its standard deviations (module documentation).
pub const ALLAN_CLIP: f64 = 2.5;
/// E[min(χ²₁, ALLAN_CLIP²)]: the mean of a winsorised ½d²/σ² (scipy.stats.chi2, 1 dof).
pub const ALLAN_CLIP_MEAN: f64 = 0.977_559_983_452_724;

#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct Level {
    /// Sum of the block in progress.
    partial: f64,
    /// Samples (level 0) or lower-level blocks (level ≥ 1) in the block in progress.
    filled: u8,
    /// Mean of the last complete block.
    previous: Option<f64>,
    /// Σ ½(ȳ_{k+1} − ȳ_k)² and the number of differences.
    sum_half_sq: f64,
    count: u64,
}

/// The octave levels (module documentation); allocation-free, serialisable.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AllanCascade {
    levels: [Level; LEVELS],
}

impl AllanCascade {
    /// No samples yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts new blocks at every level: no difference will span what came before (a gap).
    pub fn break_blocks(&mut self) {
        for level in &mut self.levels {
            level.partial = 0.0;
            level.filled = 0;
            level.previous = None;
        }
    }

    /// Adds the next sample; returns whether a trusted level got a new difference.
    pub fn push(&mut self, x: f64) -> bool {
        let mut sum = x;
        let mut changed = false;
        for (j, level) in self.levels.iter_mut().enumerate() {
            level.partial += sum;
            level.filled += 1;
            let needed = if j == 0 { 1 } else { 2 };
            if level.filled < needed {
                break;
            }
            let block = level.partial;
            let mean = block / (1u64 << j) as f64;
            if let Some(prev) = level.previous {
                let half_sq = 0.5 * (mean - prev) * (mean - prev);
                level.sum_half_sq += if level.count >= TRUSTED_DIFFERENCES {
                    let sigma2 = level.sum_half_sq / level.count as f64;
                    half_sq.min(ALLAN_CLIP * ALLAN_CLIP * sigma2) / ALLAN_CLIP_MEAN
                } else {
                    half_sq
                };
                level.count += 1;
                changed |= level.count >= TRUSTED_DIFFERENCES;
            }
            level.previous = Some(mean);
            level.partial = 0.0;
            level.filled = 0;
            sum = block;
        }
        changed
    }

    /// Allan variance of level j (blocks of 2^j samples) and its number of differences, once it
    /// has any.
    pub fn level(&self, j: usize) -> Option<(f64, u64)> {
        let l = self.levels.get(j)?;
        (l.count > 0).then(|| (l.sum_half_sq / l.count as f64, l.count))
    }

    /// [`AllanCascade::level`] once it has [`TRUSTED_DIFFERENCES`] differences.
    pub fn trusted(&self, j: usize) -> Option<(f64, u64)> {
        self.level(j).filter(|&(_, n)| n >= TRUSTED_DIFFERENCES)
    }

    /// Whether the stored sums are usable (finite, non-negative, block counters in range).
    pub fn is_valid(&self) -> bool {
        self.levels.iter().all(|l| {
            l.partial.is_finite()
                && l.sum_half_sq.is_finite()
                && l.sum_half_sq >= 0.0
                && l.filled <= 2
                && l.previous.is_none_or(f64::is_finite)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cascade_matches_block_means_computed_directly() {
        // Deterministic, not Gaussian, and short enough that no level clips (< 17 differences
        // at levels ≥ 6; the lower ones are checked against the unclipped sum only while < 16).
        let x: Vec<f64> = (0..64).map(|i| ((i * 37 % 101) as f64).sin()).collect();
        let mut c = AllanCascade::new();
        x.iter().for_each(|&v| {
            c.push(v);
        });
        for j in 2..6 {
            let m = 1 << j;
            let means: Vec<f64> = x.chunks_exact(m).map(|b| b.iter().sum::<f64>() / m as f64).collect();
            let direct: f64 = means.windows(2).map(|w| 0.5 * (w[1] - w[0]).powi(2)).sum::<f64>();
            let (v, n) = c.level(j).unwrap();
            assert_eq!(n as usize, means.len() - 1);
            assert!((v * n as f64 - direct).abs() < 1e-12, "level {j}");
        }
        c.break_blocks();
        let before = c.level(0).unwrap();
        c.push(100.0);
        assert_eq!(c.level(0).unwrap(), before, "no difference spans a break");
    }
}
