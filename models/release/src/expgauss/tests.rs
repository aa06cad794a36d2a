use super::*;

#[test]
fn phi_functions_agree_across_the_branches() {
    for z in [
        Complex64::new(0.999, 0.0),
        Complex64::new(-0.3, 0.95),
        Complex64::new(0.0, 0.9999),
    ] {
        let a = phis(z);
        let b = phis(z * 1.0000001);
        let c = {
            let e = z.exp();
            let p1 = (e - 1.0) / z;
            let p2 = (p1 - 1.0) / z;
            [e, p1, p2, (p2 - 0.5) / z]
        };
        for k in 0..4 {
            assert!((a[k] - c[k]).norm() < 1e-12, "{k}: {} vs {}", a[k], c[k]);
            assert!((a[k] - b[k]).norm() < 1e-6);
        }
    }
    let small = phis(Complex64::new(1e-9, 0.0));
    assert!((small[3].re - (1.0 / 6.0 + 1e-9 / 24.0)).abs() < 1e-15);
}

/// The truncated series of `phis` (9 to 17 terms by the size of `z`) against the full
/// 20-term series, on both sides of every band edge and in every direction of the complex
/// plane: within 4 units of rounding (the bands were chosen for a first neglected term below
/// 1e-17 of phi_3; the rest is the rounding of a Horner sum that starts elsewhere). Two terms
/// fewer in any band exceed it (checked: 15 instead of 17 fails).
#[test]
fn truncated_phi_series_matches_the_full_one() {
    let full = |z: Complex64| {
        let mut p3 = Complex64::new(0.0, 0.0);
        for &c in INV_FACT3.iter().rev() {
            p3 = p3 * z + c;
        }
        let p2 = z * p3 + 0.5;
        let p1 = z * p2 + 1.0;
        [z * p1 + 1.0, p1, p2, p3]
    };
    for r in [
        0.01, 0.0624, 0.0626, 0.124, 0.126, 0.249, 0.251, 0.499, 0.501, 0.999,
    ] {
        for k in 0..16 {
            let z = Complex64::from_polar(r, std::f64::consts::TAU * k as f64 / 16.0);
            let (a, b) = (phis(z), full(z));
            for m in 0..4 {
                assert!(
                    (a[m] - b[m]).norm() <= 4.0 * f64::EPSILON * b[m].norm(),
                    "|z| {r}, phi_{m}: {} vs {}",
                    a[m],
                    b[m]
                );
            }
        }
    }
}

#[test]
fn lagrange_basis_is_cardinal() {
    let lag = lagrange();
    for (j, &c) in NODES.iter().enumerate() {
        let b = basis_at(&lag, c);
        for (l, v) in b.iter().enumerate() {
            assert!((v - if l == j { 1.0 } else { 0.0 }).abs() < 1e-14);
        }
    }
}
