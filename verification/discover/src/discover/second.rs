//! Two terms outside the catalogue reported as two (issue 50, item 4): when the residual of the
//! final model is not noise and a term outside the catalogue leads, every pair of the best
//! kinds is fitted jointly with the model and the best pair by BIC whose two terms are both
//! resolved is listed (`Description::separate_terms`), with the pairs the record cannot tell
//! from it (`Description::separate_indistinguishable`); see [`crate::kinds::pairs`].

use crate::estimate::FitOutcome;
use crate::kinds::{Basis, KindFit};
use crate::numeric::observe::Observer;
use crate::prepare::Prepared;

/// The two terms of the best resolved pair of `all` (the kinds of `o`'s residual on `basis`,
/// most supported first) and the pairs within 10 in BIC of it; both empty when no pair is
/// resolved.
pub(crate) fn separate_terms(
    prep: &Prepared,
    o: &FitOutcome,
    all: &[KindFit],
    basis: &Basis,
    max_iter: usize,
    obs: &dyn Observer,
) -> (Vec<KindFit>, Vec<String>) {
    crate::kinds::pairs::best_pair(prep, o, all, basis, max_iter, obs)
        .map(|p| (p.terms, p.alike))
        .unwrap_or_default()
}
