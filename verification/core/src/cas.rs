//! The types of a credibility assessment ([`crate::credibility`]): a level of 0 to 4 per
//! factor, after NASA-STD-7009A's Credibility Assessment Scale, and the weakest named. Apart
//! from the assessment so that a matrix row can carry one.

use serde::Serialize;

/// One factor's level and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
pub struct Factor {
    /// 0 (no evidence, or contradicted) to 4 (the strongest the rubric knows).
    pub level: u8,
    /// Why, in words, from the row's own evidence.
    pub why: String,
}

/// The credibility of one row's verdict.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
pub struct Credibility {
    /// The row's level: its weakest factor's.
    pub level: u8,
    /// The weakest factor's name (the first of the weakest, in the order below).
    pub weakest: String,
    /// The level the requirement needs (`credibility:` in its YAML), if it states one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub required: Option<u8>,
    /// The code verified: traced tests.
    pub verification: Factor,
    /// The model validated against a measurement or reference.
    pub validation: Factor,
    /// The pedigree of the model inputs' parameters.
    pub input_pedigree: Factor,
    /// The uncertainty of the deciding value.
    pub results_uncertainty: Factor,
    /// The sensitivity of the deciding value to its inputs.
    pub results_robustness: Factor,
}

impl Credibility {
    /// The factors in order, with their names.
    pub fn factors(&self) -> [(&'static str, &Factor); 5] {
        [
            ("verification", &self.verification),
            ("validation", &self.validation),
            ("input pedigree", &self.input_pedigree),
            ("results uncertainty", &self.results_uncertainty),
            ("results robustness", &self.results_robustness),
        ]
    }

    /// In a cell: `1 (validation)`; with the requirement's need when below it.
    pub fn short(&self) -> String {
        match self.required {
            Some(n) if self.level < n => {
                format!("{} ({}; needs {n})", self.level, self.weakest)
            }
            _ => format!("{} ({})", self.level, self.weakest),
        }
    }

    /// The factors in one line: `verification 3, validation 0, ...`.
    pub fn levels(&self) -> String {
        self.factors()
            .iter()
            .map(|(n, f)| format!("{n} {}", f.level))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Whether the row falls short of the level its requirement needs.
    pub fn below_required(&self) -> bool {
        self.required.is_some_and(|n| self.level < n)
    }
}
