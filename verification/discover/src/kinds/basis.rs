//! The fit's freedom and residual as [`super::kinds`] and the detection thresholds judge a shape
//! against them: the fit's Jacobian at its optimum made orthonormal ([`Basis::new`]), a shape
//! projected out of it (modified Gram-Schmidt, twice) and scored against the residual, all
//! whitened and normalised as the fit sees them. The projections are most of the cost of the
//! kinds' scans and of the thresholds on a long record; their dot products are summed side by
//! side ([`dots`]), each in its own order.

use crate::coords::{from_u, to_u};
use crate::estimate::FitOutcome;
use crate::numeric::lm::{LmOptions, fd_steps, jacobian_columns};
use crate::prepare::Prepared;

/// The residual and the fit's freedom, whitened and normalised as the fit sees them.
pub struct Basis<'a> {
    pub(super) prep: &'a Prepared,
    sigma: f64,
    /// Orthonormal basis of the fit's Jacobian columns.
    pub(super) q: Vec<Vec<f64>>,
    /// Normalised residual (data - model).
    r: Vec<f64>,
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// [`dot`] of each pair of `pairs`, each the same bits: up to four sums side by side in one
/// pass, each in [`dot`]'s order. A sum of 400 000 products in turn waits on each addition;
/// four of them interleaved fill those waits (the projections of the kinds' scans and of the
/// thresholds, a fifth of a 400 000-sample `discover`, were bound by that latency).
fn dots(pairs: &[(&[f64], &[f64])]) -> Vec<f64> {
    let mut out = Vec::with_capacity(pairs.len());
    for group in pairs.chunks(4) {
        match group.len() {
            1 => out.push(dot(group[0].0, group[0].1)),
            2 => out.extend(dots_side_by_side::<2>(group)),
            3 => out.extend(dots_side_by_side::<3>(group)),
            _ => out.extend(dots_side_by_side::<4>(group)),
        }
    }
    out
}

/// [`dots`] of `K` pairs in one pass (each pair's own sum, from -0.0 as `Iterator::sum`, in
/// index order); pairs of unequal lengths are summed one by one.
fn dots_side_by_side<const K: usize>(g: &[(&[f64], &[f64])]) -> [f64; K] {
    let n = g[0].0.len().min(g[0].1.len());
    if g.iter().any(|(a, b)| a.len().min(b.len()) != n) {
        return std::array::from_fn(|j| dot(g[j].0, g[j].1));
    }
    let a: [&[f64]; K] = std::array::from_fn(|j| &g[j].0[..n]);
    let b: [&[f64]; K] = std::array::from_fn(|j| &g[j].1[..n]);
    let mut acc = [-0.0f64; K];
    for i in 0..n {
        for j in 0..K {
            acc[j] += a[j][i] * b[j][i];
        }
    }
    acc
}

impl<'a> Basis<'a> {
    /// The basis of the fit `o` of `prep`.
    pub fn new(prep: &'a Prepared, o: &FitOutcome) -> Basis<'a> {
        let t = &prep.dataset.t;
        let sigma = o.sigma;
        let mut r: Vec<f64> = prep
            .data()
            .iter()
            .zip(&o.pred)
            .map(|(d, m)| d - m)
            .collect();
        prep.normalise(&mut r, sigma);
        let specs = o.model.specs();
        let fidx: Vec<usize> = (0..specs.len()).filter(|&i| o.free[i]).collect();
        let u0: Vec<f64> = fidx.iter().map(|&i| to_u(&specs[i], o.p[i])).collect();
        let lo: Vec<f64> = fidx
            .iter()
            .map(|&i| to_u(&specs[i], specs[i].lower))
            .collect();
        let hi: Vec<f64> = fidx
            .iter()
            .map(|&i| to_u(&specs[i], specs[i].upper))
            .collect();
        let f = |u: &[f64]| {
            let mut p = o.p.clone();
            for (k, &i) in fidx.iter().enumerate() {
                p[i] = from_u(&specs[i], u[k]);
            }
            let mut v = o.model.predict(&p, t, &prep.inputs);
            prep.normalise(&mut v, sigma);
            v
        };
        let r0 = f(&u0);
        let steps = fd_steps(&f, &u0, &r0, &lo, &hi, LmOptions::default().fd_step);
        let cols = jacobian_columns(&f, &u0, &r0, &lo, &hi, &steps);
        // modified Gram-Schmidt, twice, dropping dependent columns
        let mut q: Vec<Vec<f64>> = Vec::new();
        for mut c in cols {
            let norm0 = dot(&c, &c).sqrt();
            if !(norm0 > 0.0 && norm0.is_finite()) {
                continue;
            }
            for _ in 0..2 {
                for e in &q {
                    let a = dot(e, &c);
                    for (ci, ei) in c.iter_mut().zip(e) {
                        *ci -= a * ei;
                    }
                }
            }
            let norm = dot(&c, &c).sqrt();
            if norm > 1e-9 * norm0 {
                c.iter_mut().for_each(|v| *v /= norm);
                q.push(c);
            }
        }
        Basis { prep, sigma, q, r }
    }

    /// The raw shape `s` [SI per unit coefficient] whitened, normalised and projected out of the
    /// fit's span.
    pub(super) fn project(&self, mut s: Vec<f64>) -> Vec<f64> {
        self.prep.normalise(&mut s, self.sigma);
        for _ in 0..2 {
            for e in &self.q {
                let a = dot(e, &s);
                for (si, ei) in s.iter_mut().zip(e) {
                    *si -= a * ei;
                }
            }
        }
        s
    }

    /// [`Self::project`] of each of `cols`, the same bits, their dot products with each basis
    /// vector taken side by side ([`dots`]).
    pub(super) fn project_many(&self, mut cols: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        if cols.len() == 1 {
            return vec![self.project(cols.remove(0))];
        }
        for c in &mut cols {
            self.prep.normalise(c, self.sigma);
        }
        for _ in 0..2 {
            for e in &self.q {
                let pairs: Vec<(&[f64], &[f64])> = cols.iter().map(|c| (&e[..], &c[..])).collect();
                let a = dots(&pairs);
                for (c, a) in cols.iter_mut().zip(a) {
                    for (ci, ei) in c.iter_mut().zip(e) {
                        *ci -= a * ei;
                    }
                }
            }
        }
        cols
    }

    /// Coefficients, their 1-sigma and the chi-square removed by the raw shapes `cols`.
    pub(super) fn score(&self, cols: Vec<Vec<f64>>) -> Option<(Vec<f64>, Vec<f64>, f64)> {
        let p: Vec<Vec<f64>> = self.project_many(cols);
        let k = p.len();
        // the Gram matrix's entries (row by row) and the right-hand side, summed side by side
        let mut pairs: Vec<(&[f64], &[f64])> = Vec::with_capacity(k * k + k);
        for i in 0..k {
            for j in 0..k {
                pairs.push((&p[i], &p[j]));
            }
        }
        pairs.extend(p.iter().map(|pi| (&pi[..], &self.r[..])));
        let sums = dots(&pairs);
        let g = nalgebra::DMatrix::from_fn(k, k, |i, j| sums[i * k + j]);
        let b = nalgebra::DVector::from_fn(k, |i, _| sums[k * k + i]);
        if (0..k).any(|i| !(g[(i, i)] > 0.0 && g[(i, i)].is_finite())) {
            return None;
        }
        let ginv = g.try_inverse()?;
        let c = &ginv * &b;
        let d = b.dot(&c);
        if !d.is_finite() {
            return None;
        }
        let sig = (0..k).map(|i| ginv[(i, i)].max(0.0).sqrt()).collect();
        Some((c.iter().copied().collect(), sig, d))
    }

    /// The 1-sigma of the coefficient of a column already whitened and normalised as the fit
    /// sees it (`d normalised prediction / d coefficient`), after the fit's own freedom:
    /// `1 / |P s|`, `P` the projection out of the fit's Jacobian; `None` when the column lies
    /// in the fit's span (the fit absorbs it whole) or is not finite.
    pub fn sigma_of_normalised(&self, s: Vec<f64>) -> Option<f64> {
        self.projected_norm(s)
            .filter(|&norm| norm > 0.0)
            .map(|norm| 1.0 / norm)
    }

    /// The norm of a column already whitened and normalised as the fit sees it, projected out
    /// of the fit's Jacobian (0 when the fit absorbs it whole); `None` when it is not finite.
    pub fn projected_norm(&self, mut s: Vec<f64>) -> Option<f64> {
        for _ in 0..2 {
            for e in &self.q {
                let a = dot(e, &s);
                for (si, ei) in s.iter_mut().zip(e) {
                    *si -= a * ei;
                }
            }
        }
        let norm = dot(&s, &s).sqrt();
        norm.is_finite().then_some(norm)
    }

    /// Correlation of the residual with the projected raw shape `s` (0 when it vanishes).
    pub(super) fn correlation(&self, s: Vec<f64>) -> f64 {
        let p = self.project(s);
        let (pp, rr) = (dot(&p, &p), dot(&self.r, &self.r));
        if pp > 0.0 && rr > 0.0 {
            dot(&p, &self.r) / (pp * rr).sqrt()
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sums taken side by side are the bits of each taken alone: groups of one to nine
    /// pairs (so partial groups of four), zero and negative-zero vectors, a pair shorter than
    /// the others.
    #[test]
    fn dots_side_by_side_are_the_bits_of_each_dot() {
        let v = |k: usize, n: usize| -> Vec<f64> {
            (0..n)
                .map(|i| ((i * (k + 2) + k) as f64 * 0.731).sin() * 10f64.powi(k as i32 % 5 - 2))
                .collect()
        };
        let n = 5003;
        let mut vs: Vec<Vec<f64>> = (0..9).map(|k| v(k, n)).collect();
        vs.push(vec![0.0; n]);
        vs.push(vec![-0.0; n]);
        vs.push(v(3, n - 7));
        for count in 1..=12 {
            let pairs: Vec<(&[f64], &[f64])> = (0..count)
                .map(|j| (&vs[j][..], &vs[(j * 5 + 1) % vs.len()][..]))
                .collect();
            let side = dots(&pairs);
            for ((a, b), got) in pairs.iter().zip(&side) {
                assert_eq!(got.to_bits(), dot(a, b).to_bits(), "{count} pairs");
            }
        }
    }

    /// The projection of several columns at once is the bits of projecting each alone, on the
    /// basis of a real fit (a retraction record with a missing voltage ramp).
    #[test]
    fn projecting_columns_together_is_the_bits_of_each_alone() {
        use crate::synth::{SynthSpec, generate};
        let mut spec = SynthSpec::defaults(
            geodesic_facility::Scenario::RtRetraction,
            &["piezo", "voltage_ramp"],
        );
        spec.post_s = 2e-4;
        let prep = Prepared::new(generate(&spec, "k.yaml").unwrap());
        let o = crate::estimate::fit(&prep, &["piezo"], &crate::estimate::FitOptions::default())
            .unwrap();
        let basis = Basis::new(&prep, &o);
        assert!(basis.q.len() >= 3, "a basis to project out of");
        let t = &prep.dataset.t;
        for k in [2, 3, 5] {
            let cols: Vec<Vec<f64>> = (0..k)
                .map(|j| {
                    t.iter()
                        .map(|&ti| (ti * 1e4 * (j + 1) as f64).cos() * 1e-9)
                        .collect()
                })
                .collect();
            let together = basis.project_many(cols.clone());
            for (c, p) in cols.into_iter().zip(&together) {
                let alone = basis.project(c);
                assert!(
                    alone.iter().zip(p).all(|(a, b)| a.to_bits() == b.to_bits()),
                    "{k}"
                );
            }
        }
    }
}
