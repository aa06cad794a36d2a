//! Two terms outside the catalogue reported as two (issue 50, item 4): when the residual of the
//! final model is not noise and a term outside the catalogue leads, the term (its joint fit's
//! coefficients on its columns) is taken out of the data, the model refitted to what is left,
//! and the kinds of term searched again on that residual; a second term the evidence supports
//! strongly is listed after the first (`Description::separate_terms`).

use crate::diagnose::DELTA_BIC_STRONG;
use crate::error::FitError;
use crate::estimate::{FitOptions, FitOutcome, fit_model};
use crate::kinds::KindFit;
use crate::prepare::Prepared;
use crate::report::{FitReport, is_explained};

/// The leading term's contribution to the fitted channel [SI]: its columns times its
/// coefficients; `None` when it has none of either.
fn contribution(lead: &KindFit, n: usize) -> Option<Vec<f64>> {
    if lead.shape.is_empty()
        || lead.shape.len() != lead.coefs.len()
        || lead.shape.iter().any(|c| c.len() != n)
    {
        return None;
    }
    Some(
        (0..n)
            .map(|j| {
                lead.shape
                    .iter()
                    .zip(&lead.coefs)
                    .map(|(s, c)| c * s[j])
                    .sum()
            })
            .collect(),
    )
}

/// The term the residual of `o` (the model fitted to `prep`) still holds once `lead` is
/// removed: the data less `lead`'s contribution, the model refitted from `o`'s parameters,
/// and when that residual is still not noise, the best of its terms fitted jointly with the
/// model, if its delta BIC is below `DELTA_BIC_STRONG` and it is not `lead`'s own kind at the
/// same parameter. `None` otherwise.
pub(crate) fn second_term(
    prep: &Prepared,
    o: &FitOutcome,
    lead: &KindFit,
    opts: &FitOptions,
    max_iter: usize,
) -> Result<Option<KindFit>, FitError> {
    let Some(c) = contribution(lead, prep.data().len()) else {
        return Ok(None);
    };
    let mut less = prep.clone();
    let data = less
        .dataset
        .channels
        .get_mut(prep.channel)
        .expect("the fitted channel");
    for (d, c) in data.iter_mut().zip(&c) {
        *d -= c;
    }
    let mut again = fit_model(&less, &o.model, opts, std::slice::from_ref(&o.p))?;
    again.rescale(o.sigma, &o.sigma_source);
    if is_explained(&FitReport::new(&less, &again)).0 {
        return Ok(None);
    }
    let resid: Vec<f64> = less
        .data()
        .iter()
        .zip(&again.pred)
        .map(|(d, m)| d - m)
        .collect();
    let pk = super::peaks(less.channel, &resid, super::median_step(&less.dataset.t));
    let (all, basis) = crate::kinds::kinds(&less, &again, &pk);
    if all.first().is_none_or(|k| k.delta_bic >= DELTA_BIC_STRONG) {
        return Ok(None);
    }
    let refined = crate::kinds::refined_terms_of(&less, &again, &all, &basis, opts, max_iter)?;
    let same = |k: &KindFit| {
        k.kind == lead.kind
            && match (&k.parameter, &lead.parameter) {
                (Some(a), Some(b)) => (a.value - b.value).abs() <= 0.05 * b.value.abs(),
                _ => true,
            }
    };
    Ok(refined
        .into_iter()
        .next()
        .filter(|k| k.delta_bic < DELTA_BIC_STRONG && !same(k)))
}
