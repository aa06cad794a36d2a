//! Eigen-decompositions that return instead of hanging.
//!
//! nalgebra's `symmetric_eigen()` and `pseudo_inverse()` iterate without a cap: on a matrix
//! holding a NaN or an infinity (a Jacobian of a model pushed far out of its range, a record
//! whose time axis is in the wrong unit) they never return. These check the input and cap the
//! iterations; `None` means the matrix has no decomposition the fit can use.

use nalgebra::{DMatrix, Dyn, SVD, SymmetricEigen};

/// At most this many QR sweeps; a finite 20 x 20 matrix converges in well under a hundred.
const MAX_ITERATIONS: usize = 10_000;

/// The eigen-decomposition of the symmetric matrix `m`; `None` when `m` is not finite or the
/// iteration does not converge. An empty matrix (a fit whose every parameter is held) has the
/// empty decomposition (nalgebra panics on it).
pub fn sym_eigen(m: DMatrix<f64>) -> Option<SymmetricEigen<f64, Dyn>> {
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    if m.is_empty() {
        return Some(SymmetricEigen {
            eigenvectors: DMatrix::zeros(0, 0),
            eigenvalues: nalgebra::DVector::zeros(0),
        });
    }
    SymmetricEigen::try_new(m, f64::EPSILON, MAX_ITERATIONS)
}

/// The pseudo-inverse of `m`, singular values up to `eps` taken as zero; `None` when `m` is
/// not finite or the SVD does not converge.
pub fn pseudo_inverse(m: &DMatrix<f64>, eps: f64) -> Option<DMatrix<f64>> {
    if m.iter().any(|v| !v.is_finite()) || !eps.is_finite() {
        return None;
    }
    if m.is_empty() {
        return Some(DMatrix::zeros(m.ncols(), m.nrows()));
    }
    SVD::try_new(m.clone(), true, true, f64::EPSILON, MAX_ITERATIONS)?
        .pseudo_inverse(eps)
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matrix_with_a_nan_or_an_infinity_has_no_decomposition() {
        for bad in [f64::NAN, f64::INFINITY] {
            let m = DMatrix::from_row_slice(2, 2, &[1.0, bad, bad, 2.0]);
            assert!(sym_eigen(m.clone()).is_none());
            assert!(pseudo_inverse(&m, 1e-12).is_none());
        }
    }

    /// A fit whose every parameter is held has empty normal matrices: empty answers, no panic
    /// (nalgebra's decompositions panic on them).
    #[test]
    fn an_empty_matrix_has_the_empty_decomposition() {
        let e = sym_eigen(DMatrix::zeros(0, 0)).expect("the empty decomposition");
        assert!(e.eigenvalues.is_empty() && e.eigenvectors.is_empty());
        assert_eq!(
            pseudo_inverse(&DMatrix::zeros(0, 0), 1e-12)
                .unwrap()
                .shape(),
            (0, 0)
        );
    }

    #[test]
    fn a_finite_matrix_decomposes_as_nalgebra_does() {
        let m = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let mut ev: Vec<f64> = sym_eigen(m.clone())
            .unwrap()
            .eigenvalues
            .iter()
            .copied()
            .collect();
        ev.sort_by(f64::total_cmp);
        approx::assert_relative_eq!(ev[0], 1.0, epsilon = 1e-12);
        approx::assert_relative_eq!(ev[1], 3.0, epsilon = 1e-12);
        let inv = pseudo_inverse(&m, 1e-12).unwrap();
        approx::assert_relative_eq!(inv, m.try_inverse().unwrap(), epsilon = 1e-12);
    }
}
