//! The scalar gap between a recording and a simulated ensemble, and when it is significant.
//!
//! **Gap**: the root mean square of the standard scores z ([`super::band`]) with every group of
//! statistics ([`Group`]) weighted equally: gap² = mean over groups of the mean z² in the group.
//! A series drawn from the simulated model itself scores about 1; the gap is in units of the
//! ensemble's own spread.
//!
//! **Null distribution** (calibrated from the ensemble, no fixed threshold): every member is scored
//! like the real series against the bands of the *other* members (leave-one-out), which gives the
//! gaps and group scores that a series of the simulated model shows by chance.
//!
//! **Significant gap**: one test on the largest standardised excess,
//!
//! T = max( s(gap), max over groups s(RMS z of the group) ),  s(v) = (v^(2/3) − m)/sd,
//!
//! where v^(2/3) is the Wilson–Hilferty cube root of a mean square (close to normal) and m, sd are
//! the mean and standard deviation of the same transformed quantity over the members. The gap
//! catches a difference spread over many statistics, a group one in one kind of statistic (one
//! far-out statistic in a group, such as the grid coherence or a spectral line, shows there too).
//! T is a maximum, so its null law is taken as a Gumbel law (Fisher–Tippett) with the mean and
//! standard deviation of the members' own T; the gap is significant when T exceeds that law's
//! [`NULL_LEVEL`] quantile (the baseline's comparison, which says whether there is a gap at all,
//! tests each part at [`super::greedy::BASELINE_LEVEL`], so that its two parts together keep one
//! false alarm in 100). A single test, so the groups do not add up to many chances. (A
//! Gaussian threshold at mean + 3 sd, on untransformed scores and with the largest |z| as a third
//! kind of component, was tried first: on simulated recordings without any effect it flagged a
//! few per cent of them, because those scores have long upper tails.)

use serde::Serialize;

use super::band::{Band, MIN_SD, bands, gumbel_parameters};
use super::stats::{Group, Scale, StatInfo};
use crate::model::metrics::{quantile_sorted, sample_std_dev};

/// Probability that the members' T stays below the threshold (one false alarm in 100).
pub const NULL_LEVEL: f64 = 0.99;

/// Mean z² of one group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupScore {
    /// The group.
    pub group: Group,
    /// Root mean square z of its statistics.
    pub rms_z: f64,
    /// Number of statistics.
    pub statistics: usize,
    /// How many lie outside the 95 % band.
    pub outside: usize,
}

/// A series scored against an ensemble's bands.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GapScore {
    /// The scalar gap (module docs).
    pub gap: f64,
    /// Per group.
    pub groups: Vec<GroupScore>,
    /// Statistics outside the 95 % band.
    pub outside: usize,
    /// Largest |z|.
    pub max_abs_z: f64,
    /// Mean |log10(real / median)| over the Allan deviation points, decades (a unit-free figure
    /// that does not depend on the ensemble's spread).
    pub allan_decades: f64,
    /// The Dawid–Sebastiani score, groups weighted equally: mean over groups of the mean of
    /// z² + 2·ln s over the group's statistics (s the band's standard deviation). A proper
    /// scoring rule for a predictive distribution given by its mean and spread (Dawid & Sebastiani
    /// 1999; Gneiting & Raftery 2007, eq. 27), lower is better: unlike the gap it charges a model
    /// for a band widened until the recording fits inside. Only differences between models of the
    /// same recording and part mean anything.
    pub log_score: f64,
}

/// Scores `values` against `bands`; returns each statistic's z and the summary.
pub fn score(info: &[StatInfo], bands: &[Band], values: &[f64]) -> (Vec<f64>, GapScore) {
    let z: Vec<f64> = bands.iter().zip(values).zip(info).map(|((b, &v), i)| b.z_on(i.scale, v)).collect();
    let mut groups = Vec::new();
    let mut log_score = 0.0;
    for group in Group::ALL {
        let idx: Vec<usize> = (0..info.len()).filter(|&i| info[i].group == group).collect();
        if idx.is_empty() {
            continue;
        }
        let mean_sq = idx.iter().map(|&i| z[i] * z[i]).sum::<f64>() / idx.len() as f64;
        log_score +=
            idx.iter().map(|&i| z[i] * z[i] + 2.0 * bands[i].sd.max(MIN_SD).ln()).sum::<f64>() / idx.len() as f64;
        let outside = idx.iter().filter(|&&i| bands[i].outside(values[i])).count();
        groups.push(GroupScore { group, rms_z: mean_sq.sqrt(), statistics: idx.len(), outside });
    }
    let gap = (groups.iter().map(|g| g.rms_z * g.rms_z).sum::<f64>() / groups.len().max(1) as f64).sqrt();
    let allan: Vec<f64> = (0..info.len())
        .filter(|&i| info[i].statistic == "allan_deviation" && info[i].scale == Scale::Log10)
        .map(|i| (values[i] - bands[i].median).abs())
        .collect();
    let summary = GapScore {
        gap,
        outside: groups.iter().map(|g| g.outside).sum(),
        max_abs_z: z.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
        allan_decades: allan.iter().sum::<f64>() / allan.len().max(1) as f64,
        log_score: log_score / groups.len().max(1) as f64,
        groups,
    };
    (z, summary)
}

/// Mean and standard deviation of one scalar over the members.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Moments {
    /// Mean.
    pub mean: f64,
    /// Standard deviation (n − 1).
    pub sd: f64,
}

impl Moments {
    fn of(x: &[f64]) -> Moments {
        // sd 0 for fewer than two values (the members do not vary).
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        Moments { mean, sd: sample_std_dev(x).unwrap_or(0.0) }
    }

    /// Moments of the Wilson–Hilferty transform v^(2/3) of root-mean-square scores v (see
    /// [`wilson_hilferty`]).
    fn of_rms(x: &[f64]) -> Moments {
        Moments::of(&x.iter().map(|&v| wilson_hilferty(v)).collect::<Vec<_>>())
    }

    /// (v − mean)/sd (0 when the members do not vary).
    pub fn standardise(&self, v: f64) -> f64 {
        if self.sd > 0.0 { (v - self.mean) / self.sd } else { 0.0 }
    }
}

/// v^(2/3) = (v²)^(1/3): the Wilson–Hilferty cube root of a mean square, which makes a χ²-like
/// mean of squared scores close to normal (Wilson & Hilferty 1931), so that the standardised
/// values below have tails that a moment fit describes.
pub fn wilson_hilferty(rms: f64) -> f64 {
    rms.max(0.0).powf(2.0 / 3.0)
}

/// Which part of the significance test stands out most.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Flag {
    /// The gap.
    Gap,
    /// One group's RMS z.
    Group(Group),
}

/// What series drawn from the simulated model score (leave-one-out over the members).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Null {
    /// Members scored.
    pub members: usize,
    /// Their gaps (Wilson–Hilferty transformed).
    pub gap: Moments,
    /// Median of their gaps: the gap a matching simulation leaves (the floor of "how far").
    pub median: f64,
    /// Their RMS z per group (Wilson–Hilferty transformed), in the order of
    /// [`GapScore::groups`].
    pub groups: Vec<Moments>,
    /// Their test statistic T (module docs).
    pub t: Moments,
    /// The threshold of T: the [`NULL_LEVEL`] quantile of a Gumbel law with the members' mean
    /// and standard deviation of T (module docs).
    pub threshold: f64,
    /// Mean number of statistics a member has outside the band.
    pub mean_outside: f64,
}

impl Null {
    /// The test statistic T of a score and what stands out most in it.
    pub fn t_of(&self, s: &GapScore) -> (f64, Flag) {
        let mut best = (self.gap.standardise(wilson_hilferty(s.gap)), Flag::Gap);
        for (group, t) in self.group_scores(s) {
            if t > best.0 {
                best = (t, Flag::Group(group));
            }
        }
        best
    }

    /// Each group's standard score in `s`: its RMS z, Wilson–Hilferty transformed and
    /// standardised by what the members score.
    pub fn group_scores<'a>(&'a self, s: &'a GapScore) -> impl Iterator<Item = (Group, f64)> + 'a {
        s.groups.iter().zip(&self.groups).map(|(g, m)| (g.group, m.standardise(wilson_hilferty(g.rms_z))))
    }

    /// The gap at which the gap alone makes T reach the threshold.
    pub fn gap_threshold(&self) -> f64 {
        (self.gap.mean + self.threshold * self.gap.sd).max(0.0).powf(1.5)
    }
}

/// The null distribution of the gap for `members` (at least 3).
pub fn null(info: &[StatInfo], members: &[Vec<f64>]) -> Null {
    let scores: Vec<GapScore> = (0..members.len())
        .map(|j| {
            let loo = bands(members, Some(j));
            score(info, &loo, &members[j]).1
        })
        .collect();
    let column = |f: &dyn Fn(&GapScore) -> f64| scores.iter().map(f).collect::<Vec<f64>>();
    let mut gaps = column(&|s| s.gap);
    let groups = (0..scores.first().map_or(0, |s| s.groups.len()))
        .map(|g| Moments::of_rms(&column(&|s| s.groups[g].rms_z)))
        .collect();
    let mut null = Null {
        members: members.len(),
        gap: Moments::of_rms(&gaps),
        median: 0.0,
        groups,
        t: Moments { mean: 0.0, sd: 0.0 },
        threshold: 0.0,
        mean_outside: column(&|s| s.outside as f64).iter().sum::<f64>() / members.len() as f64,
    };
    gaps.sort_unstable_by(f64::total_cmp);
    null.median = quantile_sorted(&gaps, 0.5);
    let t: Vec<f64> = scores.iter().map(|s| null.t_of(s).0).collect();
    null.t = Moments::of(&t);
    null.threshold = gumbel_quantile(null.t, NULL_LEVEL);
    null
}

/// The `p` quantile of the Gumbel (maximum) law with the mean and standard deviation of `m`
/// ([`gumbel_parameters`]: quantile μ − β·ln(−ln p)).
pub fn gumbel_quantile(m: Moments, p: f64) -> f64 {
    let (mu, beta) = gumbel_parameters(m.mean, m.sd);
    mu - beta * (-p.ln()).ln()
}

/// A part of the recording compared with its simulated ensemble.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartComparison {
    /// The real statistics (comparison scale).
    pub real: Vec<f64>,
    /// The ensemble band of each.
    pub bands: Vec<Band>,
    /// z of each real statistic.
    pub z: Vec<f64>,
    /// The real series' score.
    pub score: GapScore,
    /// What members score.
    pub null: Null,
    /// The real series' test statistic T.
    pub t: f64,
    /// What stands out most in T.
    pub flag: Flag,
    /// T above its threshold (module docs).
    pub significant: bool,
}

impl PartComparison {
    /// Compares `real` with `members` (statistics vectors of the layout `info`).
    pub fn new(info: &[StatInfo], real: Vec<f64>, members: &[Vec<f64>]) -> Self {
        let bands = bands(members, None);
        let (z, score) = score(info, &bands, &real);
        let null = null(info, members);
        let (t, flag) = null.t_of(&score);
        let significant = t > null.threshold;
        Self { real, bands, z, score, null, t, flag, significant }
    }

    /// The same comparison tested at the stricter level `p` (> [`NULL_LEVEL`]): T against the `p`
    /// quantile of the members' Gumbel law, for a test that is one of several.
    pub fn at_level(&self, p: f64) -> PartComparison {
        let mut strict = self.clone();
        strict.null.threshold = gumbel_quantile(self.null.t, p);
        strict.significant = strict.t > strict.null.threshold;
        strict
    }

    /// The gap² above what a matching simulation leaves (gap² − null median², ≥ 0): the quantity
    /// whose share an effect must remove.
    pub fn excess(&self) -> f64 {
        (self.score.gap * self.score.gap - self.null.median * self.null.median).max(0.0)
    }

    /// Indices of the statistics outside the band, largest |z| first.
    pub fn outside_by_size(&self) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..self.real.len()).filter(|&i| self.bands[i].outside(self.real[i])).collect();
        idx.sort_by(|&a, &b| self.z[b].abs().total_cmp(&self.z[a].abs()));
        idx
    }
}

/// Test members: `count` statistics vectors of `stats` values uniform on [−0.5, 0.5) from a
/// seeded LCG (Knuth's MMIX constants), shared by the tests of the gap, the greedy combination and
/// the naming order.
#[cfg(test)]
pub(crate) fn uniform_members(count: usize, stats: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut state = seed;
    let mut uniform = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..count).map(|_| (0..stats).map(|_| uniform()).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(group: Group) -> StatInfo {
        StatInfo { statistic: "psd", band: String::new(), group, scale: Scale::Log10, unit: "", x: f64::NAN }
    }

    /// Members on a deterministic spread; a real vector inside is not significant, one far out is.
    #[test]
    fn significance_follows_the_members() {
        let layout = vec![info(Group::Psd), info(Group::Psd), info(Group::Distribution)];
        let members = uniform_members(40, 3, 11);
        let inside = PartComparison::new(&layout, vec![0.05, -0.1, 0.0], &members);
        assert!(!inside.significant, "{:?}", inside.score);
        let outside = PartComparison::new(&layout, vec![0.05, -0.1, 5.0], &members);
        assert!(outside.significant, "{} {:?}", outside.t, outside.null);
        assert_eq!(outside.outside_by_size(), vec![2]);
        assert!(outside.excess() > 0.0 && inside.excess() < outside.excess());
        // The null median is what members show: below the threshold.
        assert!(inside.null.median < inside.null.threshold);
    }

    /// A band widened until the recording sits inside it lowers the gap but pays in the
    /// Dawid–Sebastiani score; a band centred on the recording at the same width scores best.
    #[test]
    fn the_log_score_charges_a_widened_band() {
        let layout = vec![info(Group::Psd), info(Group::Distribution)];
        let spread = |centre: f64, width: f64| -> Vec<Vec<f64>> {
            (0..40).map(|j| vec![centre + width * (j as f64 / 39.0 - 0.5); 2]).collect()
        };
        let real = vec![1.0, 1.0];
        let narrow_off = PartComparison::new(&layout, real.clone(), &spread(0.0, 1.0));
        let wide = PartComparison::new(&layout, real.clone(), &spread(0.0, 20.0));
        let narrow_on = PartComparison::new(&layout, real, &spread(1.0, 1.0));
        assert!(wide.score.gap < narrow_off.score.gap, "{} {}", wide.score.gap, narrow_off.score.gap);
        assert!(narrow_on.score.log_score < narrow_off.score.log_score);
        assert!(narrow_on.score.log_score < wide.score.log_score);
        // z² + 2 ln s by hand: the members are uniform on [−w/2, w/2], s = w·√(40·41/12)/39.
        let s = 20.0 * (40.0 * 41.0 / 12.0f64).sqrt() / 39.0;
        let want = (1.0 / s).powi(2) + 2.0 * s.ln();
        assert!((wide.score.log_score - want).abs() < 1e-9, "{} vs {want}", wide.score.log_score);
    }
}
