//! Traced tests of the ground-test image analyses' accuracy (issue 17): the check's errors on
//! synthetic inputs against the requirements' own limits, for several seeds (other noise, other
//! surfaces).

use geodesic_checks::images::{registration_error_px, tiptrack_error_px};
use geodesic_core::trace::assert_limit;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4))]
    /// For any seed, the tip trajectory is within 0.25 px and the registration within 0.1 px.
    #[test]
    fn image_analyses_meet_their_accuracy(seed in 0u64..10_000) {
        geodesic_core::verifies!("FAC-TIPTRACK-ACC", "FAC-SURF-REG");
        let (e, tr) = tiptrack_error_px(seed).unwrap();
        assert_limit("FAC-TIPTRACK-ACC", e);
        prop_assert_eq!(tr.t_s.len(), geodesic_checks::images::FRAMES);
        let (e, reg) = registration_error_px(seed).unwrap();
        assert_limit("FAC-SURF-REG", e);
        // the transferred patch (radius 6 px, 0.2 um) is found: the changed area is of its size
        let patch = std::f64::consts::PI * 36.0 * 1.10365e-7f64.powi(2);
        prop_assert!(reg.changed_area_m2 > 0.5 * patch && reg.changed_area_m2 < 2.0 * patch);
    }
}
