//! A small version of `gyrocomp simgap --selftest` (the full one — ten seeded 10,000 s cases of
//! each kind with ensembles of 32, 97 of 100 right — is in docs/evaluation.md "Sim-to-real diagnosis"): one
//! seeded case of each effect and of each control on 3000 s recordings with ensembles of 24, so
//! that it runs in the dev profile in under a minute (47 s here). Short recordings hide some
//! effects (here the spikes case stays unexplained at 3000 s), so this asserts what must not
//! regress: both controls behave (no significant gap without an effect; the out-of-catalogue chirp
//! stays unexplained, no effect named), at least six of the eight effects are named, and no effect
//! is named in place of the injected one but for one known confusion: since the ranking by the
//! Dawid–Sebastiani score (sixth session), this seed's bias-step case (about three steps in the
//! 2,100 s training part, the first early) is named warmup, as one of the full self-test's ten is.
//! The same change cut wrong names on the independent generator's report set from 17 to 10 of 220
//! (docs/evaluation.md "Independent cases"), so the trade was taken, and this test pins it.

use gyrocomp::diag::simgap::selftest::{Injected, SelftestSettings, run_selftest};
use gyrocomp::diag::simgap::{EffectKind, Settings};

#[test]
fn small_selftest_keeps_the_controls_and_names_most_effects() {
    let settings = SelftestSettings {
        cases: 1,
        duration_s: 3000.0,
        scale: 1.0,
        seed: 1,
        diagnosis: Settings { ensemble: 24, threads: 2, ..Settings::default() },
    };
    let results = run_selftest(&settings, &Injected::all(), |_| {}).unwrap();
    for r in &results {
        eprintln!("{:<16} {:<5} {:?} {:?} {}", r.injected.name(), r.correct, r.verdict, r.named, r.magnitudes);
    }
    for r in results.iter().filter(|r| !matches!(r.injected, Injected::Effect(_))) {
        assert!(r.correct, "{}: {:?} {:?}", r.injected.name(), r.verdict, r.named);
    }
    let named = results.iter().filter(|r| matches!(r.injected, Injected::Effect(_)) && r.correct).count();
    assert!(named >= 6, "only {named} of 8 effects named");
    // A wrong name is worse than a miss: no effect is named in place of the injected one, but for
    // the known bias-step/warm-up confusion (module docs).
    for r in &results {
        if let (Injected::Effect(k), Some(named)) = (r.injected, r.named) {
            let known = k == EffectKind::BiasJumps && named == EffectKind::Warmup;
            assert!(named == k || known, "{} named {}", k.name(), named.name());
        }
    }
}
