//! The classical fourth-order Runge-Kutta step shared by the TMMF integration and the
//! retraction model's cross-check, with its scratch space (no allocation per step).

/// Scratch space of [`rk4_step`].
pub(crate) struct Rk4Work {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    tmp: Vec<f64>,
}

impl Rk4Work {
    pub(crate) fn new(n: usize) -> Self {
        Rk4Work {
            k1: vec![0.0; n],
            k2: vec![0.0; n],
            k3: vec![0.0; n],
            k4: vec![0.0; n],
            tmp: vec![0.0; n],
        }
    }
}

/// One classical Runge-Kutta step of size `h` from `t`.
pub(crate) fn rk4_step<F: Fn(f64, &[f64], &mut [f64])>(
    f: &F,
    t: f64,
    h: f64,
    s: &mut [f64],
    w: &mut Rk4Work,
) {
    f(t, s, &mut w.k1);
    for ((o, &a), &k) in w.tmp.iter_mut().zip(s.iter()).zip(&w.k1) {
        *o = a + 0.5 * h * k;
    }
    f(t + 0.5 * h, &w.tmp, &mut w.k2);
    for ((o, &a), &k) in w.tmp.iter_mut().zip(s.iter()).zip(&w.k2) {
        *o = a + 0.5 * h * k;
    }
    f(t + 0.5 * h, &w.tmp, &mut w.k3);
    for ((o, &a), &k) in w.tmp.iter_mut().zip(s.iter()).zip(&w.k3) {
        *o = a + h * k;
    }
    f(t + h, &w.tmp, &mut w.k4);
    for (i, si) in s.iter_mut().enumerate() {
        *si += h / 6.0 * (w.k1[i] + 2.0 * w.k2[i] + 2.0 * w.k3[i] + w.k4[i]);
    }
}
