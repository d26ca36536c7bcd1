//! Daubechies wavelet filters db1–db10 with PyWavelets' sign and ordering conventions.
//!
//! The decomposition low-pass taps below are PyWavelets 1.8 `Wavelet('dbN').dec_lo`, printed at
//! full `f64` precision. The other three filters follow from it as in PyWavelets:
//! `rec_lo = reverse(dec_lo)`, `dec_hi[k] = (-1)^(k+1) rec_lo[k]`, `rec_hi = reverse(dec_hi)`.
//! Tests check orthonormality (`Σh = √2`, `Σh² = 1`, `Σ h[k]h[k+2j] = 0`) independently of the table.

use std::fmt;

const DB1: [f64; 2] = [std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2];
const DB2: [f64; 4] = [-0.12940952255126037, 0.2241438680420134, 0.8365163037378079, 0.48296291314453416];
const DB3: [f64; 6] = [
    0.03522629188570953,
    -0.08544127388202666,
    -0.13501102001025458,
    0.45987750211849154,
    0.8068915093110925,
    0.33267055295008263,
];
const DB4: [f64; 8] = [
    -0.010597401785069032,
    0.0328830116668852,
    0.030841381835560764,
    -0.18703481171909309,
    -0.027983769416859854,
    0.6308807679298589,
    0.7148465705529157,
    0.2303778133088965,
];
const DB5: [f64; 10] = [
    0.0033357252854737712,
    -0.012580751999081999,
    -0.006241490212798274,
    0.07757149384004572,
    -0.032244869584638375,
    -0.24229488706638203,
    0.13842814590132074,
    0.7243085284377729,
    0.6038292697971896,
    0.16010239797419293,
];
const DB6: [f64; 12] = [
    -0.0010773010853084796,
    0.004777257510945511,
    0.0005538422011614961,
    -0.03158203931748603,
    0.027522865530305727,
    0.09750160558732304,
    -0.12976686756726194,
    -0.22626469396543983,
    0.31525035170919763,
    0.7511339080210954,
    0.49462389039845306,
    0.11154074335010947,
];
const DB7: [f64; 14] = [
    0.00035371379997452024,
    -0.0018016407040474908,
    0.0004295779729213665,
    0.01255099855609984,
    -0.01657454163066688,
    -0.03802993693501441,
    0.08061260915108308,
    0.07130921926683026,
    -0.22403618499387498,
    -0.14390600392856498,
    0.4697822874051931,
    0.7291320908462351,
    0.3965393194819173,
    0.07785205408500918,
];
const DB8: [f64; 16] = [
    -0.00011747678412476953,
    0.0006754494064505693,
    -0.00039174037337694705,
    -0.004870352993451574,
    0.008746094047405777,
    0.013981027917398282,
    -0.044088253930794755,
    -0.017369301001807547,
    0.12874742662047847,
    0.0004724845739132828,
    -0.2840155429615469,
    -0.015829105256349306,
    0.5853546836542067,
    0.6756307362972898,
    0.31287159091429995,
    0.05441584224310401,
];
const DB9: [f64; 18] = [
    3.93473203162716e-05,
    -0.0002519631889427101,
    0.00023038576352319597,
    0.0018476468830562265,
    -0.00428150368246343,
    -0.004723204757751397,
    0.022361662123679096,
    0.00025094711483145197,
    -0.06763282906132997,
    0.03072568147933338,
    0.14854074933810638,
    -0.09684078322297646,
    -0.2932737832791749,
    0.13319738582500756,
    0.6572880780513005,
    0.6048231236901112,
    0.24383467461259034,
    0.038077947363878345,
];
const DB10: [f64; 20] = [
    -1.3264202894521244e-05,
    9.358867032006959e-05,
    -0.00011646685512928545,
    -0.0006858566949597116,
    0.001992405295185056,
    0.001395351747052901,
    -0.010733175483330575,
    0.0036065535669561697,
    0.033212674059341,
    -0.029457536821875813,
    -0.07139414716639708,
    0.09305736460357235,
    0.12736934033579325,
    -0.19594627437737705,
    -0.24984642432731538,
    0.2811723436605775,
    0.6884590394536035,
    0.5272011889317256,
    0.1881768000776915,
    0.026670057900555554,
];

const DB_DEC_LO: [&[f64]; 10] = [&DB1, &DB2, &DB3, &DB4, &DB5, &DB6, &DB7, &DB8, &DB9, &DB10];

/// An orthogonal wavelet's four filters, in PyWavelets' conventions.
#[derive(Debug, Clone, PartialEq)]
pub struct Wavelet {
    name: String,
    dec_lo: Vec<f64>,
    dec_hi: Vec<f64>,
    rec_lo: Vec<f64>,
    rec_hi: Vec<f64>,
}

/// Error for an unknown wavelet name or order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownWavelet(pub String);

impl fmt::Display for UnknownWavelet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown wavelet `{}`: supported are db1 … db10", self.0)
    }
}

impl std::error::Error for UnknownWavelet {}

impl Wavelet {
    /// Daubechies wavelet `dbN` with N vanishing moments (2N taps), N in 1..=10.
    pub fn daubechies(order: usize) -> Result<Self, UnknownWavelet> {
        let dec_lo = DB_DEC_LO.get(order.wrapping_sub(1)).ok_or_else(|| UnknownWavelet(format!("db{order}")))?.to_vec();
        let rec_lo: Vec<f64> = dec_lo.iter().rev().copied().collect();
        let dec_hi: Vec<f64> = rec_lo.iter().enumerate().map(|(k, &c)| if k % 2 == 0 { -c } else { c }).collect();
        let rec_hi: Vec<f64> = dec_hi.iter().rev().copied().collect();
        Ok(Self { name: format!("db{order}"), dec_lo, dec_hi, rec_lo, rec_hi })
    }

    /// The paper's mother wavelet, db4 (8 taps).
    pub fn db4() -> Self {
        Self::daubechies(4).expect("db4 is in the table")
    }

    /// Parses a name such as `db4`.
    pub fn from_name(name: &str) -> Result<Self, UnknownWavelet> {
        name.strip_prefix("db")
            .and_then(|n| n.parse::<usize>().ok())
            .map_or_else(|| Err(UnknownWavelet(name.to_owned())), Self::daubechies)
    }

    /// Name, e.g. `db4`.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of taps F of each filter.
    pub fn filter_len(&self) -> usize {
        self.dec_lo.len()
    }

    /// Decomposition low-pass filter.
    pub fn dec_lo(&self) -> &[f64] {
        &self.dec_lo
    }

    /// Decomposition high-pass filter.
    pub fn dec_hi(&self) -> &[f64] {
        &self.dec_hi
    }

    /// Reconstruction low-pass filter.
    pub fn rec_lo(&self) -> &[f64] {
        &self.rec_lo
    }

    /// Reconstruction high-pass filter.
    pub fn rec_hi(&self) -> &[f64] {
        &self.rec_hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_daubechies_filter_is_orthonormal() {
        for order in 1..=10 {
            let w = Wavelet::daubechies(order).unwrap();
            let h = w.rec_lo();
            assert_eq!(h.len(), 2 * order);
            let sum: f64 = h.iter().sum();
            assert!((sum - std::f64::consts::SQRT_2).abs() < 1e-12, "db{order}: Σh = {sum}");
            for shift in (0..h.len()).step_by(2) {
                let dot: f64 = (0..h.len() - shift).map(|k| h[k] * h[k + shift]).sum();
                let want = if shift == 0 { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-12, "db{order}: shift {shift} gives {dot}");
            }
            // The high-pass filter has a zero at DC and is orthogonal to the low-pass filter.
            let hi_sum: f64 = w.rec_hi().iter().sum();
            assert!(hi_sum.abs() < 1e-12);
            let cross: f64 = w.dec_lo().iter().zip(w.dec_hi()).map(|(a, b)| a * b).sum();
            assert!(cross.abs() < 1e-12);
        }
    }

    #[test]
    fn names_parse_and_unknown_ones_are_rejected() {
        assert_eq!(Wavelet::from_name("db4").unwrap(), Wavelet::db4());
        assert!(Wavelet::from_name("db0").is_err());
        assert!(Wavelet::from_name("db11").is_err());
        assert!(Wavelet::from_name("sym4").is_err());
    }
}
