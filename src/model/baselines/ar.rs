//! AR(p) baseline on consecutive lags with intercept (docs/design.md "Stage definitions",
//! *Compensation*): `x̂[t] = c + Σ_{i=1..p} a_i·x[t−i]`, fitted by least squares (Householder
//! QR, see `lstsq`).
//!
//! Order selection by Akaike's information criterion over p = 1..=p_max:
//! `AIC(p) = n·ln(RSS_p/n) + 2k`, `k = p + 1` (coefficients plus intercept; the noise variance
//! is common to every order and left out). Every order is fitted on the *same* targets
//! `t = p_max..N−1` (n = N − p_max), so the RSS values — and the AICs — are comparable; one QR
//! of the p_max-lag design gives all of them (nested prefixes). The smallest AIC wins (ties to
//! the lower order), then the chosen order is refitted on all its targets `t = p..N−1`, as
//! statsmodels' `ar_select_order` does. AIC is not consistent: on a true AR(p) it picks a larger
//! order with a probability that does not vanish as N grows (Shibata 1976).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::check_series;
use super::lstsq::QrFit;
use crate::model::{Fit, FitError, Predict};

/// How the AR order is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "rule", rename_all = "kebab-case")]
pub enum ArOrder {
    /// Minimum AIC over p = 1..=max on a common sample (module docs).
    Aic {
        /// p_max (≥ 1). Default 20.
        max: usize,
    },
    /// A fixed order p (≥ 1).
    Fixed {
        /// p.
        order: usize,
    },
}

/// AR(p) configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ar {
    /// Order rule; default AIC with p_max = 20.
    pub order: ArOrder,
}

impl Default for Ar {
    fn default() -> Self {
        Self { order: ArOrder::Aic { max: 20 } }
    }
}

impl Ar {
    /// A fixed-order AR(p).
    pub fn fixed(order: usize) -> Self {
        Self { order: ArOrder::Fixed { order } }
    }

    /// AR with the order chosen by AIC over 1..=max.
    pub fn aic(max: usize) -> Self {
        Self { order: ArOrder::Aic { max } }
    }
}

/// Fitted AR(p) model.
#[derive(Debug, Clone, PartialEq)]
pub struct ArModel {
    intercept: f64,
    /// `a_1..a_p`: `a_i` multiplies `x[t−i]`.
    coefficients: Vec<f64>,
    /// AIC of orders 1..=p_max on the common sample (empty for a fixed order).
    aic: Vec<f64>,
}

impl ArModel {
    /// The order p.
    pub fn order(&self) -> usize {
        self.coefficients.len()
    }

    /// The intercept c.
    pub fn intercept(&self) -> f64 {
        self.intercept
    }

    /// `a_1..a_p`, where `a_i` multiplies `x[t−i]`.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// AIC of orders 1..=p_max (index p − 1) on the common sample; `+∞` for an order whose
    /// design was rank-deficient; empty when the order was fixed.
    pub fn aic(&self) -> &[f64] {
        &self.aic
    }
}

/// Design `[1, x[t−1], …, x[t−p]]` and targets `x[t]` for `t = t0..N−1` (`t0 ≥ p`).
fn design(x: &[f64], p: usize, t0: usize) -> (DMatrix<f64>, DVector<f64>) {
    let n = x.len() - t0;
    let d = DMatrix::from_fn(n, p + 1, |r, c| if c == 0 { 1.0 } else { x[t0 + r - c] });
    (d, DVector::from_column_slice(&x[t0..]))
}

/// Samples an AR(p) fit needs: targets `N − p ≥ p + 2` (more targets than parameters).
fn need(p: usize) -> usize {
    2 * p + 2
}

/// Least-squares AR(p) on targets `t = p..N−1`.
fn fit_order(x: &[f64], p: usize) -> Result<(f64, Vec<f64>), FitError> {
    let (d, y) = design(x, p, p);
    let beta = QrFit::new(d, y).coefficients(p + 1)?;
    Ok((beta[0], beta[1..].to_vec()))
}

impl Fit for Ar {
    type Model = ArModel;

    fn fit(&self, train: &[f64]) -> Result<ArModel, FitError> {
        match self.order {
            ArOrder::Fixed { order: 0 } | ArOrder::Aic { max: 0 } => {
                Err(FitError::InvalidConfig("AR order must be at least 1".into()))
            }
            ArOrder::Fixed { order } => {
                check_series(train, need(order))?;
                let (intercept, coefficients) = fit_order(train, order)?;
                Ok(ArModel { intercept, coefficients, aic: Vec::new() })
            }
            ArOrder::Aic { max } => {
                check_series(train, need(max))?;
                let (d, y) = design(train, max, max);
                let n = y.len() as f64;
                let qr = QrFit::new(d, y);
                let aic: Vec<f64> = (1..=max)
                    .map(|p| {
                        if p + 1 > qr.rank() {
                            return f64::INFINITY;
                        }
                        // A perfect fit (RSS = 0) gives −∞: the lowest such order wins.
                        n * (qr.rss(p + 1) / n).ln() + 2.0 * (p + 1) as f64
                    })
                    .collect();
                let mut best = 0;
                for (i, &a) in aic.iter().enumerate() {
                    if a < aic[best] {
                        best = i;
                    }
                }
                if aic[best] == f64::INFINITY {
                    // Not even AR(1) is identifiable: report why.
                    qr.coefficients(2)?;
                }
                let (intercept, coefficients) = fit_order(train, best + 1)?;
                Ok(ArModel { intercept, coefficients, aic })
            }
        }
    }
}

impl Predict for ArModel {
    fn history_len(&self) -> usize {
        self.coefficients.len()
    }

    fn predict(&self, history: &[f64]) -> f64 {
        let n = history.len();
        self.coefficients.iter().enumerate().fold(self.intercept, |acc, (i, a)| acc + a * history[n - 1 - i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn design_rows_are_consecutive_lags() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let (d, y) = design(&x, 2, 2);
        assert_eq!(d.row(0).iter().copied().collect::<Vec<_>>(), vec![1.0, 1.0, 0.0]);
        assert_eq!(d.row(2).iter().copied().collect::<Vec<_>>(), vec![1.0, 3.0, 2.0]);
        assert_eq!(y.as_slice(), &[2.0, 3.0, 4.0]);
    }

    #[test]
    fn bad_input() {
        assert!(matches!(Ar::fixed(0).fit(&[0.0; 10]), Err(FitError::InvalidConfig(_))));
        assert_eq!(Ar::fixed(3).fit(&[0.0; 7]), Err(FitError::TooFewSamples { need: 8, have: 7 }));
        // A constant series: the lag columns equal the intercept column.
        assert!(matches!(Ar::aic(3).fit(&[1.0; 50]), Err(FitError::Numerical(_))));
        assert!(matches!(Ar::fixed(1).fit(&[1.0; 50]), Err(FitError::Numerical(_))));
    }
}
