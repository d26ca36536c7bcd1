//! Random streams of the simulator.
//!
//! Every random term of every axis draws from its own stream: a `Xoshiro256PlusPlus` generator
//! (rand_xoshiro, a documented, stable algorithm) seeded through SplitMix64 (the crate's one
//! [`crate::model::rng::splitmix64`]) from the run's seed, the axis and the term. So the same seed
//! gives the same numbers on every platform and version of this crate (Cargo.lock pins the
//! generator crates), and switching one term on or off leaves the noise paths of all other terms
//! unchanged: runs that differ by one term are common-random-number comparisons.
//!
//! Normal deviates come from `rand_distr::StandardNormal` (ziggurat); uniform deviates are the top
//! 53 bits of one 64-bit output.

use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::model::rng::splitmix64;

/// Which term a stream feeds (part of the stream key; the numbers are fixed forever).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u64)]
pub enum StreamId {
    /// White rate noise (ARW).
    White = 1,
    /// Bias instability (Gauss–Markov or flicker bank).
    BiasInstability = 2,
    /// Rate random walk.
    RateRandomWalk = 3,
    /// Bias jumps.
    Jumps = 4,
    /// Spikes.
    Spikes = 5,
    /// Temperature reading noise (axis index 3).
    TemperatureNoise = 6,
    /// Motion profiles (axis index 4).
    Motion = 7,
}

/// One independent random stream.
#[derive(Debug, Clone)]
pub struct Stream {
    rng: Xoshiro256PlusPlus,
}

impl Stream {
    /// The stream of `term` on `axis` (0..3 the gyro axes, 3 temperature, 4 motion) for `seed`.
    pub fn new(seed: u64, axis: u64, term: StreamId) -> Self {
        Self::indexed(seed, axis, term, 0)
    }

    /// The `index`-th stream of `term` on `axis` (e.g. one per process of the flicker bank). The
    /// key is chained through [`splitmix64`]: seed, then axis, then term, then index.
    pub fn indexed(seed: u64, axis: u64, term: StreamId, index: u64) -> Self {
        let mut key = splitmix64(seed);
        for part in [axis, term as u64, index] {
            key = splitmix64(key ^ part);
        }
        Self { rng: Xoshiro256PlusPlus::seed_from_u64(key) }
    }

    /// A standard normal deviate.
    #[inline]
    pub fn normal(&mut self) -> f64 {
        StandardNormal.sample(&mut self.rng)
    }

    /// A uniform deviate in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// An exponential deviate with mean 1 (inverse transform of a uniform in (0, 1]).
    #[inline]
    pub fn exponential(&mut self) -> f64 {
        -(1.0 - self.uniform()).ln()
    }

    /// +1 or −1 with equal probability.
    #[inline]
    pub fn sign(&mut self) -> f64 {
        if self.rng.next_u64() >> 63 == 0 { 1.0 } else { -1.0 }
    }

    /// A uniform deviate in [lo, hi).
    #[inline]
    pub fn uniform_in(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// A log-uniform deviate in [lo, hi) (lo, hi > 0).
    #[inline]
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.uniform()).exp()
    }
}
