//! The Welch PSD against scipy.signal.welch (tests/goldens/psd.json, made by
//! tools/goldens/psd_goldens.py).

mod common;

use common::{floats, golden};
use gyrocomp::diag::psd::welch;

#[test]
fn welch_equals_scipy() {
    let doc = golden("psd.json");
    for case in doc["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let x = floats(&case["x"]);
        let rate = case["rate_hz"].as_f64().unwrap();
        let segment = case["segment"].as_u64().unwrap() as usize;
        let psd = welch(&x, rate, segment).unwrap();
        let (freq, density) = (floats(&case["freq_hz"]), floats(&case["density"]));
        assert_eq!(psd.freq_hz.len(), freq.len(), "{name}: bins");
        for k in 0..freq.len() {
            assert!((psd.freq_hz[k] - freq[k]).abs() <= 1e-12 * freq[k].abs().max(1.0), "{name}: freq {k}");
            let rel = (psd.density[k] - density[k]).abs() / density[k].abs().max(1e-300);
            assert!(rel < 1e-9, "{name}: bin {k}: {} vs {}", psd.density[k], density[k]);
        }
    }
}
