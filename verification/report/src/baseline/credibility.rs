//! The gate reports a credibility drop as a regression (issue 49): a row whose credibility
//! level fell below the baseline's (say which factor and why), and a row that was compliant and
//! is now not verified because its credibility is below the level its requirement needs.

use super::OldRow;
use geodesic_core::matrix::{Row, Status};

/// The regressions of row `r`'s credibility against the baseline's row `o`.
pub(super) fn regressions(r: &Row, o: &OldRow) -> Vec<String> {
    let mut out = Vec::new();
    let Some(c) = &r.credibility else {
        return out;
    };
    let old = o
        .credibility
        .as_ref()
        .and_then(|v| v.get("level"))
        .and_then(serde_json::Value::as_u64);
    if let Some(old) = old
        && u64::from(c.level) < old
    {
        let why = c
            .factors()
            .iter()
            .find(|(n, _)| *n == c.weakest)
            .map_or(String::new(), |(_, f)| f.why.clone());
        out.push(format!(
            "credibility fell from {old} to {} (weakest: {}: {why})",
            c.level, c.weakest
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
