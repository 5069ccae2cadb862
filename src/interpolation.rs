//! Piecewise Hermite interpolation from values and slopes at nodes: the cubic and quintic
//! Hermite pieces, Catmull–Rom weights and Fritsch–Carlson (PCHIP) slopes shared by the contact
//! lookup tables ([`crate::contact::lookup`]), the KEC profiles, the Kalker coefficient table and
//! the profile design. The C² interpolating spline of the profiles is its neighbour
//! [`crate::spline`].

/// Quintic Hermite interpolation on [y0, y1] of (value, slope, curvature) at both ends: the value
/// and slope at y.
pub fn quintic(y0: f64, y1: f64, e0: (f64, f64, f64), e1: (f64, f64, f64), y: f64) -> (f64, f64) {
    let h = y1 - y0;
    let t = (y - y0) / h;
    let (t2, t3, t4, t5) = (t * t, t * t * t, t.powi(4), t.powi(5));
    let w = [
        1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5,
        t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5,
        0.5 * t2 - 1.5 * t3 + 1.5 * t4 - 0.5 * t5,
        0.5 * t3 - t4 + 0.5 * t5,
        -4.0 * t3 + 7.0 * t4 - 3.0 * t5,
        10.0 * t3 - 15.0 * t4 + 6.0 * t5,
    ];
    let dw = [
        -30.0 * t2 + 60.0 * t3 - 30.0 * t4,
        1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4,
        t - 4.5 * t2 + 6.0 * t3 - 2.5 * t4,
        1.5 * t2 - 4.0 * t3 + 2.5 * t4,
        -12.0 * t2 + 28.0 * t3 - 15.0 * t4,
        30.0 * t2 - 60.0 * t3 + 30.0 * t4,
    ];
    let c = [e0.0, h * e0.1, h * h * e0.2, h * h * e1.2, h * e1.1, e1.0];
    let v = (0..6).map(|i| w[i] * c[i]).sum();
    let d = (0..6).map(|i| dw[i] * c[i]).sum::<f64>() / h;
    (v, d)
}

/// [`hermite`] with the second derivative.
pub fn cubic_hermite(y0: f64, y1: f64, v0: f64, v1: f64, d0: f64, d1: f64, y: f64) -> (f64, f64, f64) {
    let h = y1 - y0;
    let t = (y - y0) / h;
    let (v, d) = hermite(y0, y1, v0, v1, d0, d1, y);
    let dd = ((12.0 * t - 6.0) * (v0 - v1) / h + (6.0 * t - 4.0) * d0 + (6.0 * t - 2.0) * d1) / h;
    (v, d, dd)
}

/// Cubic Hermite interpolation on [y0, y1] of the values v0, v1 and slopes d0, d1 at its ends:
/// the value and slope at y.
pub fn hermite(y0: f64, y1: f64, v0: f64, v1: f64, d0: f64, d1: f64, y: f64) -> (f64, f64) {
    let h = y1 - y0;
    let t = (y - y0) / h;
    let (t2, t3) = (t * t, t * t * t);
    let (h00, h10, h01, h11) = (
        2.0 * t3 - 3.0 * t2 + 1.0,
        t3 - 2.0 * t2 + t,
        -2.0 * t3 + 3.0 * t2,
        t3 - t2,
    );
    let v = h00 * v0 + h10 * h * d0 + h01 * v1 + h11 * h * d1;
    let (g00, g10, g01, g11) = (
        6.0 * t2 - 6.0 * t,
        3.0 * t2 - 4.0 * t + 1.0,
        -6.0 * t2 + 6.0 * t,
        3.0 * t2 - 2.0 * t,
    );
    let d = (g00 * v0 + g01 * v1) / h + g10 * d0 + g11 * d1;
    (v, d)
}

/// Weights of the Catmull–Rom interpolant at `x` in [x0, x1] on the values at (x_m, x0, x1, x2)
/// (x_m, x2 optional: one-sided slopes without them), and of its derivative: cubic Hermite with
/// the slopes d0 = (v1 − v_m)/(x1 − x_m), d1 = (v2 − v0)/(x2 − x0) (else (v1 − v0)/(x1 − x0)).
pub fn catmull_rom_weights(
    xm: Option<f64>,
    x0: f64,
    x1: f64,
    x2: Option<f64>,
    x: f64,
) -> ([f64; 4], [f64; 4]) {
    let h = x1 - x0;
    // Slopes as weights on (v_m, v0, v1, v2).
    let d0 = match xm {
        Some(xm) => [-1.0 / (x1 - xm), 0.0, 1.0 / (x1 - xm), 0.0],
        None => [0.0, -1.0 / h, 1.0 / h, 0.0],
    };
    let d1 = match x2 {
        Some(x2) => [0.0, -1.0 / (x2 - x0), 0.0, 1.0 / (x2 - x0)],
        None => [0.0, -1.0 / h, 1.0 / h, 0.0],
    };
    let mut w = [0.0; 4];
    let mut dw = [0.0; 4];
    for k in 0..4 {
        let e = |i: usize| if i == k { 1.0 } else { 0.0 };
        let (v, d) = hermite(x0, x1, e(1), e(2), d0[k], d1[k], x);
        w[k] = v;
        dw[k] = d;
    }
    (w, dw)
}

/// Fritsch–Carlson PCHIP slopes of `v` over `y` (one piece, no jumps inside).
pub fn pchip_slopes(y: &[f64], v: &[f64]) -> Vec<f64> {
    let n = y.len();
    if n < 2 {
        return vec![0.0; n];
    }
    let del: Vec<f64> = (0..n - 1)
        .map(|k| (v[k + 1] - v[k]) / (y[k + 1] - y[k]))
        .collect();
    if n == 2 {
        return vec![del[0], del[0]];
    }
    let mut d = vec![0.0; n];
    for k in 1..n - 1 {
        if del[k - 1] * del[k] > 0.0 {
            let (h0, h1) = (y[k] - y[k - 1], y[k + 1] - y[k]);
            let (w1, w2) = (2.0 * h1 + h0, h1 + 2.0 * h0);
            d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
        let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if s * d0 <= 0.0 {
            0.0
        } else if d0 * d1 <= 0.0 && s.abs() > 3.0 * d0.abs() {
            3.0 * d0
        } else {
            s
        }
    };
    d[0] = end(y[1] - y[0], y[2] - y[1], del[0], del[1]);
    d[n - 1] = end(y[n - 1] - y[n - 2], y[n - 2] - y[n - 3], del[n - 2], del[n - 3]);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_reproduces_a_cubic() {
        let f = |x: f64| x * x * x - 2.0 * x + 1.0;
        let df = |x: f64| 3.0 * x * x - 2.0;
        let (v, d) = hermite(0.5, 1.5, f(0.5), f(1.5), df(0.5), df(1.5), 0.8);
        assert!((v - f(0.8)).abs() < 1e-14 && (d - df(0.8)).abs() < 1e-13);
    }

    #[test]
    fn pchip_is_monotone_on_monotone_data() {
        let y = [0.0, 1.0, 2.0, 3.0, 4.0];
        let v = [0.0, 0.0, 1.0, 1.0, 5.0];
        let d = pchip_slopes(&y, &v);
        for k in 0..4 {
            for i in 0..=20 {
                let x = y[k] + i as f64 / 20.0;
                let a = hermite(y[k], y[k + 1], v[k], v[k + 1], d[k], d[k + 1], x).0;
                assert!(
                    a >= v[k] - 1e-12 && a <= v[k + 1] + 1e-12,
                    "overshoot at {x}: {a}"
                );
            }
        }
    }
}
