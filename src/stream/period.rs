//! The sample period: configured (`input.rate_hz`), or "auto" — the median of the first
//! [`AUTO_STEPS`] positive timestamp steps of accepted samples (a median, so one late or early
//! sample does not set it).

/// Timestamp steps the automatic period is the median of.
pub const AUTO_STEPS: usize = 9;

/// Known or being measured (module documentation); a snapshot carries it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PeriodEstimate {
    period_ns: Option<u64>,
    steps: [u64; AUTO_STEPS],
    seen: usize,
    last_t_ns: Option<u64>,
}

impl PeriodEstimate {
    /// A configured period (`period_ns` > 0) or an automatic one (0).
    pub fn new(period_ns: u64) -> Self {
        Self { period_ns: (period_ns > 0).then_some(period_ns), steps: [0; AUTO_STEPS], seen: 0, last_t_ns: None }
    }

    /// The period in seconds, once known.
    pub fn period_s(&self) -> Option<f64> {
        self.period_ns.map(|p| p as f64 * 1e-9)
    }

    /// Feeds the timestamp of an accepted sample; returns the period on the sample that makes
    /// it known (never for a configured one).
    pub fn observe(&mut self, t_ns: u64) -> Option<u64> {
        if self.period_ns.is_some() {
            return None;
        }
        if let Some(prev) = self.last_t_ns.replace(t_ns)
            && t_ns > prev
        {
            self.steps[self.seen] = t_ns - prev;
            self.seen += 1;
            if self.seen == AUTO_STEPS {
                let mut s = self.steps;
                s.sort_unstable();
                let p = s[AUTO_STEPS / 2];
                self.period_ns = Some(p);
                return Some(p);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_the_median_step_and_a_configured_period_stays() {
        let mut p = PeriodEstimate::new(0);
        let t = [0u64, 10, 20, 31, 40, 50, 500, 60, 70, 80, 90];
        let found: Vec<_> = t.iter().filter_map(|&x| p.observe(x * 1_000_000)).collect();
        // Steps 10, 10, 11, 9, 10, 450, (backwards: skipped), 10, 10, 10: the ninth comes at 90.
        assert_eq!(found, vec![10_000_000]);
        let mut q = PeriodEstimate::new(5);
        assert_eq!(q.period_s(), Some(5e-9));
        assert_eq!(q.observe(7), None);
    }
}
