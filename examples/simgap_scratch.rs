use gyrocomp::diag::simgap::baseline::NoiseTerms;
use gyrocomp::diag::simgap::model::simulate;
use gyrocomp::diag::simgap::selftest::{Injected, case_seed, synthesize};
use gyrocomp::diag::simgap::EffectKind;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case: usize = args[2].parse().unwrap();
    let dur: f64 = args.get(4).map_or(3600.0, |s| s.parse().unwrap());
    let (rate, temp) = if args[1] == "ieee" {
        let t = NoiseTerms { q: 0.0, n: 0.04, b: 0.0075, k: 1.7e-4, r: 0.0, floor_from_s: 0.1, gauss_markov: None, rms_relative_residual: 0.0 };
        let n = (dur * 10.0) as usize;
        (simulate(&t.to_model(10.0, dur, 0.4), 10.0, n, None, 1000 + case as u64).unwrap(), vec![25.0; n])
    } else {
        let kind = match args[1].as_str() {
            "none" => Injected::Nothing,
            "chirp" => Injected::OutOfCatalogue,
            k => Injected::Effect(*EffectKind::ALL.iter().find(|e| e.name() == k).unwrap()),
        };
        let (rate, temp, mag) = synthesize(kind, dur, 1.0, case_seed(1, kind, case)).unwrap();
        eprintln!("{mag}");
        (rate, temp)
    };
    let mut s = String::from("t_s,gx_dps,temp_c\n");
    for (i, (r, t)) in rate.iter().zip(&temp).enumerate() {
        s.push_str(&format!("{},{:?},{:?}\n", i as f64 / 10.0, r, t));
    }
    std::fs::write(&args[3], s).unwrap();
}
