//! A fixed-capacity ring buffer whose latest samples are always one contiguous slice.
//!
//! Every sample is written twice, at `i` and `i + capacity` of a `2·capacity` array, so the last
//! `len` samples in time order are `storage[start..start + len]` without copying: O(1) per push,
//! no allocation after construction.

/// Ring buffer of the most recent `capacity` samples, readable as one slice.
#[derive(Debug, Clone)]
pub struct RingBuffer {
    storage: Vec<f64>,
    capacity: usize,
    write: usize,
    len: usize,
    pushed: u64,
}

impl RingBuffer {
    /// An empty buffer holding at most `capacity` (> 0) samples.
    pub fn new(capacity: usize) -> Self {
        assert!(capacity > 0, "ring buffer capacity must be positive");
        Self { storage: vec![0.0; 2 * capacity], capacity, write: 0, len: 0, pushed: 0 }
    }

    /// Appends a sample, dropping the oldest once full.
    #[inline]
    pub fn push(&mut self, value: f64) {
        self.storage[self.write] = value;
        self.storage[self.write + self.capacity] = value;
        self.write = if self.write + 1 == self.capacity { 0 } else { self.write + 1 };
        self.len = (self.len + 1).min(self.capacity);
        self.pushed += 1;
    }

    /// The held samples, oldest first.
    #[inline]
    pub fn as_slice(&self) -> &[f64] {
        let start = self.write + self.capacity - self.len;
        &self.storage[start..start + self.len]
    }

    /// Number of samples held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no sample is held.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether the buffer holds `capacity` samples.
    pub fn is_full(&self) -> bool {
        self.len == self.capacity
    }

    /// Maximum number of samples held.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Samples pushed since creation (or the last [`clear`](Self::clear)).
    pub fn total_pushed(&self) -> u64 {
        self.pushed
    }

    /// Forgets every sample.
    pub fn clear(&mut self) {
        self.write = 0;
        self.len = 0;
        self.pushed = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_the_latest_samples_in_order() {
        let mut ring = RingBuffer::new(4);
        assert!(ring.as_slice().is_empty());
        for v in 0..3 {
            ring.push(v as f64);
        }
        assert_eq!(ring.as_slice(), &[0.0, 1.0, 2.0]);
        for v in 3..11 {
            ring.push(v as f64);
            let want: Vec<f64> = ((v - 3).max(0)..=v).map(|k| k as f64).collect();
            assert_eq!(ring.as_slice(), want.as_slice());
        }
        assert!(ring.is_full());
        assert_eq!(ring.total_pushed(), 11);
        ring.clear();
        assert!(ring.is_empty());
    }
}
