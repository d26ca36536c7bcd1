//! The pending queue of delayed commit ([`super::detector`]): static samples seen but not yet
//! confirmed, oldest first, with the running sum of each axis (for the estimators' provisional
//! use, [`PendingMean`]). A ring allocated once for the detector's commit delay.

use serde::{Deserialize, Serialize};

use super::drift::PendingMean;

/// The pending queue in a snapshot: the samples oldest first (index, rates, temperature) and the
/// running sums exactly as the queue holds them (a sum rebuilt from the samples could differ in
/// the last bit).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PendingState {
    /// Sample index, raw rates (deg/s) and temperature (°C, NaN: none), oldest first.
    pub samples: Vec<(u64, [f64; 3], f64)>,
    /// Running sum of each axis.
    pub sum: [f64; 3],
}

impl PendingState {
    /// Whether the rates and sums are finite and the temperatures finite or NaN (none).
    pub fn is_valid(&self) -> bool {
        self.sum.iter().all(|v| v.is_finite())
            && self.samples.iter().all(|(_, r, t)| r.iter().all(|v| v.is_finite()) && !t.is_infinite())
            && self.samples.windows(2).all(|w| w[0].0 < w[1].0)
    }
}

/// Pending static samples (module documentation).
#[derive(Debug, Clone)]
pub struct PendingQueue {
    index: Vec<u64>,
    rate: Vec<[f64; 3]>,
    /// Temperature of each sample, °C (NaN: none).
    temp: Vec<f64>,
    /// Position of the oldest entry.
    head: usize,
    len: usize,
    sum: [f64; 3],
}

impl PendingQueue {
    /// Room for `delay` pending samples plus the one being pushed.
    pub fn new(delay: usize) -> Self {
        let cap = delay + 1;
        Self {
            index: vec![0; cap],
            rate: vec![[0.0; 3]; cap],
            temp: vec![f64::NAN; cap],
            head: 0,
            len: 0,
            sum: [0.0; 3],
        }
    }

    /// Resizes for a new delay (the period became known); pending samples are kept, oldest
    /// first, as far as they fit.
    pub fn set_capacity(&mut self, delay: usize) {
        let mut next = Self::new(delay);
        while let Some((i, r, t)) = self.pop_oldest() {
            if next.len < next.index.len() {
                next.push(i, r, t);
            }
        }
        *self = next;
    }

    /// Samples pending.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether nothing is pending.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Count and sum of the pending samples of axis `k`.
    pub fn mean(&self, k: usize) -> PendingMean {
        PendingMean { count: self.len as u64, sum: self.sum[k] }
    }

    /// Appends a sample with its temperature (°C, NaN: none); the caller pops before the ring
    /// overflows (at most `delay + 1`).
    pub fn push(&mut self, index: u64, rate: [f64; 3], temp_c: f64) {
        let cap = self.index.len();
        debug_assert!(self.len < cap, "pending queue overflow");
        let slot = (self.head + self.len) % cap;
        self.index[slot] = index;
        self.rate[slot] = rate;
        self.temp[slot] = temp_c;
        self.len += 1;
        for (s, r) in self.sum.iter_mut().zip(rate) {
            *s += r;
        }
    }

    /// Removes and returns the oldest sample: index, rates, temperature.
    pub fn pop_oldest(&mut self) -> Option<(u64, [f64; 3], f64)> {
        if self.len == 0 {
            return None;
        }
        let out = (self.index[self.head], self.rate[self.head], self.temp[self.head]);
        self.head = (self.head + 1) % self.index.len();
        self.len -= 1;
        self.subtract(&out.1);
        Some(out)
    }

    /// A copy of the pending samples and sums, for a snapshot.
    pub fn state(&self) -> PendingState {
        let cap = self.index.len();
        let samples = (0..self.len)
            .map(|j| {
                let i = (self.head + j) % cap;
                (self.index[i], self.rate[i], self.temp[i])
            })
            .collect();
        PendingState { samples, sum: self.sum }
    }

    /// Replaces the content with what [`PendingQueue::state`] copied; refused (nothing changed)
    /// when it holds more samples than the queue's delay.
    pub fn restore(&mut self, state: &PendingState) -> Result<(), String> {
        let cap = self.index.len();
        if state.samples.len() >= cap {
            return Err(format!("{} pending samples stored, the commit delay holds {}", state.samples.len(), cap - 1));
        }
        (self.head, self.len) = (0, 0);
        for &(i, r, t) in &state.samples {
            self.push(i, r, t);
        }
        self.sum = state.sum;
        Ok(())
    }

    /// Drops the pending samples of index `from` or later (the newest ones); returns how many.
    pub fn drop_from(&mut self, from: u64) -> usize {
        let cap = self.index.len();
        let mut n = 0;
        while self.len > n && self.index[(self.head + self.len - 1 - n) % cap] >= from {
            n += 1;
        }
        self.drop_newest(n)
    }

    /// Drops the newest `n` samples (fewer when fewer are pending); returns how many.
    pub fn drop_newest(&mut self, n: usize) -> usize {
        let n = n.min(self.len);
        let cap = self.index.len();
        for _ in 0..n {
            let slot = (self.head + self.len - 1) % cap;
            let r = self.rate[slot];
            self.len -= 1;
            self.subtract(&r);
        }
        n
    }

    fn subtract(&mut self, rate: &[f64; 3]) {
        if self.len == 0 {
            // Exactly zero when empty: no rounding residue carried into the next static stretch.
            self.sum = [0.0; 3];
        } else {
            for (s, r) in self.sum.iter_mut().zip(rate) {
                *s -= r;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fifo_order_sums_and_look_back() {
        let mut q = PendingQueue::new(3);
        for i in 0..4 {
            q.push(i, [i as f64, 1.0, 0.0], 20.0 + i as f64);
        }
        assert_eq!(q.mean(0), PendingMean { count: 4, sum: 6.0 });
        assert_eq!(q.pop_oldest(), Some((0, [0.0, 1.0, 0.0], 20.0)));
        assert_eq!(q.drop_newest(1), 1);
        assert_eq!(q.mean(0), PendingMean { count: 2, sum: 3.0 });
        q.push(9, [5.0, 0.0, 0.0], f64::NAN);
        assert_eq!(q.pop_oldest().map(|p| p.0), Some(1));
        assert_eq!(q.pop_oldest().map(|p| p.0), Some(2));
        assert_eq!(q.pop_oldest().map(|p| p.0), Some(9));
        assert!(q.is_empty());
        assert_eq!(q.mean(0).sum, 0.0);
        assert_eq!(q.drop_newest(5), 0);
    }
}
