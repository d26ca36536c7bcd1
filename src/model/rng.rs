//! The crate's seeded random number generators and its one SplitMix64.
//!
//! - [`splitmix64`]: the SplitMix64 output function (Steele, Lea & Flood 2014), used wherever a
//!   seed or a stream key is mixed: [`Rng::new`], [`SplitMix64`], the simulator's stream keys
//!   ([`crate::sim::rng::Stream::indexed`]) and the sim-to-real ensemble seeds
//!   ([`crate::diag::simgap::model::member_seed`]).
//! - [`SplitMix64`]: the SplitMix64 generator itself, for the BP-ANN's weight initialisation and
//!   validation split.
//! - [`Rng`]: xoshiro256** 1.0 (Blackman & Vigna, "Scrambled linear pseudorandom number
//!   generators", ACM TOMS 47 (2021)) for the stochastic model code (CPSO, k-means++ prototype
//!   seeding), its state filled by SplitMix64 from a `u64` seed as the authors recommend.
//!
//! Same seed ⇒ same stream on every platform; no global state.

/// The SplitMix64 increment γ = ⌊2⁶⁴/φ⌋ (odd), added to the state before each output.
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// The SplitMix64 output function (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number
/// generators", OOPSLA; the constants of Vigna's `splitmix64.c`): `z + γ` mixed by two
/// xor-shift-multiply rounds and a final xor-shift. It is the output of a [`SplitMix64`] whose
/// state is `z`, and a good mixer of seeds and keys (`splitmix64(0) = 0xe220a8397b1dcdaf`).
pub fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(GOLDEN_GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The SplitMix64 generator (Steele, Lea & Flood 2014): the state advances by γ per draw and each
/// output is [`splitmix64`] of the state before the step, so `SplitMix64::new(0)` starts
/// `0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4` as Vigna's reference `splitmix64.c` seeded with 0.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator whose state is `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let out = splitmix64(self.0);
        self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
        out
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [−1, 1).
    pub fn symmetric(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }

    /// Uniform integer in `0..n` (`n ≥ 1`; the bias of the multiply-shift is below 2⁻⁵³·n).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }
}

/// xoshiro256** generator seeded through [`SplitMix64`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rng {
    s: [u64; 4],
}

impl Rng {
    /// A generator whose whole stream is fixed by `seed`.
    pub fn new(seed: u64) -> Self {
        let mut sm = SplitMix64::new(seed);
        let s = [sm.next_u64(), sm.next_u64(), sm.next_u64(), sm.next_u64()];
        // splitmix64 never yields four zero words in a row, so the state is never all-zero.
        Self { s }
    }

    /// Next 64 random bits (xoshiro256**).
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_reference_splitmix64_and_is_reproducible() {
        // splitmix64 from seed 0: first output of the reference C implementation.
        assert_eq!(splitmix64(0), 0xe220_a839_7b1d_cdaf);
        let a: Vec<u64> = (0..5)
            .map({
                let mut r = Rng::new(42);
                move |_| r.next_u64()
            })
            .collect();
        let mut r = Rng::new(42);
        let b: Vec<u64> = (0..5).map(|_| r.next_u64()).collect();
        assert_eq!(a, b);
        assert_ne!(Rng::new(43).next_u64(), a[0]);
    }

    #[test]
    fn splitmix64_generator_matches_the_reference_sequence() {
        // First outputs of Vigna's splitmix64.c seeded with 0.
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut r = SplitMix64::new(7);
        for _ in 0..1000 {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
            assert!(r.below(3) < 3);
        }
    }

    #[test]
    fn floats_lie_in_the_unit_interval_and_average_a_half() {
        let mut r = Rng::new(7);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let u = r.next_f64();
            assert!((0.0..1.0).contains(&u));
            sum += u;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.01);
    }
}
