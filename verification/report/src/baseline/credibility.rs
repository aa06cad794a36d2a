//! The gate reports a credibility drop as a regression (issue 49): a row whose credibility
//! level fell below the baseline's (say which factor and why), and a row that was compliant and
//! is now not verified because its credibility is below the level its requirement needs.

use super::OldRow;
use geodesic_core::matrix::{Row, Status};

/// The regressions of row `r`'s credibility against the baseline's row `o`. When the test
/// results are not compared (this run's recorded test run is stale or absent: `--require-tests`
/// says so), the verification factor is left out of both levels, as the tests themselves are.
pub(super) fn regressions(r: &Row, o: &OldRow, tests_compared: bool) -> Vec<String> {
    let mut out = Vec::new();
    let Some(c) = &r.credibility else {
        return out;
    };
    const KEYS: [(&str, &str); 5] = [
        ("verification", "verification"),
        ("validation", "validation"),
        ("input_pedigree", "input pedigree"),
        ("results_uncertainty", "results uncertainty"),
        ("results_robustness", "results robustness"),
    ];
    let counted = |name: &str| tests_compared || name != "verification";
    let old = o.credibility.as_ref().and_then(|v| {
        KEYS.iter()
            .filter(|(_, n)| counted(n))
            .filter_map(|(k, _)| v.get(*k)?.get("level")?.as_u64())
            .min()
    });
    let now = c
        .factors()
        .into_iter()
        .filter(|(n, _)| counted(n))
        .min_by_key(|(_, f)| f.level);
    if let (Some(old), Some((name, f))) = (old, now)
        && u64::from(f.level) < old
    {
        out.push(format!(
            "credibility fell from {old} to {} (weakest: {name}: {})",
            f.level, f.why
        ));
    }
    if c.below_required() && r.status == Status::NotVerified && o.status == "compliant" {
        out.push(format!(
            "no longer compliant: credibility {} is below the {} its requirement needs",
            c.level,
            c.required.unwrap_or(0)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::baseline::diff_text;
    use crate::testutil::report;
    use geodesic_core::credibility::{Credibility, Factor};

    fn cred(level: u8) -> Credibility {
        let f = |l: u8| Factor {
            level: l,
            why: format!("level {l}"),
        };
        Credibility {
            level,
            weakest: "validation".into(),
            required: None,
            verification: f(4),
            validation: f(level),
            input_pedigree: f(4),
            results_uncertainty: f(4),
            results_robustness: f(4),
        }
    }

    #[test]
    fn a_credibility_drop_is_a_regression_naming_the_row_and_the_factor() {
        let mut old = report(1.3, 2.0);
        old.matrix.requirements[0].credibility = Some(cred(3));
        let mut new = report(1.3, 2.0);
        new.matrix.requirements[0].credibility = Some(cred(1));
        let text = serde_json::to_string(&old).unwrap();
        let d = diff_text(&new, &text, "old.json", 0.01).unwrap();
        assert_eq!(d.regressions, 1);
        let c = &d.changes[0];
        assert_eq!(c.id, "F-A");
        assert!(
            c.regressions[0]
                .contains("credibility fell from 3 to 1 (weakest: validation: level 1)"),
            "{:?}",
            c.regressions
        );
        // a rise is no regression
        let d = diff_text(&old, &serde_json::to_string(&new).unwrap(), "n.json", 0.01).unwrap();
        assert_eq!(d.regressions, 0);
    }
}
