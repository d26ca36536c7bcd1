//! Min–max normalisation to [−1, 1], paper Eq. 21:
//! `x' = (x'_max − x'_min)(x − x_min)/(x_max − x_min) + x'_min` with `x'_min = −1`, `x'_max = 1`.
//!
//! One range serves inputs and target alike, because every PSR column is a delayed copy of the
//! same series. It is fitted on training data only and stored with the model; test data may fall
//! outside [−1, 1] and is not clipped.

use serde::{Deserialize, Serialize};

/// Fitted min–max scaler mapping `[min, max]` onto `[−1, 1]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MinMaxScaler {
    /// Smallest training value.
    pub min: f64,
    /// Largest training value.
    pub max: f64,
}

impl MinMaxScaler {
    /// Fits the range of `data`; `None` when `data` is empty or holds a non-finite value.
    pub fn fit(data: &[f64]) -> Option<Self> {
        let mut min = f64::INFINITY;
        let mut max = f64::NEG_INFINITY;
        for &v in data {
            if !v.is_finite() {
                return None;
            }
            min = min.min(v);
            max = max.max(v);
        }
        (!data.is_empty()).then_some(Self { min, max })
    }

    /// Half the range; a constant training series maps everything to 0 and back to its value.
    fn half_range(&self) -> f64 {
        let half = 0.5 * (self.max - self.min);
        if half > 0.0 { half } else { 1.0 }
    }

    fn centre(&self) -> f64 {
        0.5 * (self.max + self.min)
    }

    /// Maps a value to normalised units (Eq. 21).
    #[inline]
    pub fn transform(&self, x: f64) -> f64 {
        (x - self.centre()) / self.half_range()
    }

    /// Maps a normalised value back to the original units (the inverse of Eq. 21).
    #[inline]
    pub fn inverse(&self, y: f64) -> f64 {
        y * self.half_range() + self.centre()
    }

    /// Converts a difference (an error) from normalised units back to original units.
    #[inline]
    pub fn inverse_scale(&self, dy: f64) -> f64 {
        dy * self.half_range()
    }

    /// Transforms a slice in place.
    pub fn transform_in_place(&self, data: &mut [f64]) {
        for v in data {
            *v = self.transform(*v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_the_training_range_onto_minus_one_one_and_back() {
        let data = [0.5, -1.5, 2.5, 1.0];
        let s = MinMaxScaler::fit(&data).unwrap();
        assert_eq!(s.transform(-1.5), -1.0);
        assert_eq!(s.transform(2.5), 1.0);
        assert_eq!(s.transform(0.5), 0.0);
        // Eq. 21 literally: 2(x − min)/(max − min) − 1.
        for &x in &[-3.0, 0.1, 1.7, 4.0] {
            let eq21 = 2.0 * (x - (-1.5)) / (2.5 - (-1.5)) - 1.0;
            assert!((s.transform(x) - eq21).abs() < 1e-15);
            assert!((s.inverse(s.transform(x)) - x).abs() < 1e-15);
        }
        assert_eq!(s.inverse_scale(0.5), 1.0);
    }

    #[test]
    fn degenerate_and_bad_input() {
        assert!(MinMaxScaler::fit(&[]).is_none());
        assert!(MinMaxScaler::fit(&[1.0, f64::NAN]).is_none());
        let c = MinMaxScaler::fit(&[2.0, 2.0]).unwrap();
        assert_eq!(c.transform(2.0), 0.0);
        assert_eq!(c.inverse(0.0), 2.0);
    }
}
