//! Dormand–Prince 5(4) ([`Method::Dopri5`]): the explicit step with its embedded error estimate
//! (FSAL) and Hairer's 4th-order continuous extension.

use super::*;

// Dormand–Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Nørsett & Wanner I, Table II.5.2).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Error coefficients b − b̂.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer's DOPRI5, contd5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

impl Stepper {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn dopri5<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        f0: &[f64],
        h: f64,
        s: &Settings,
        x1: &mut [f64],
        f1: &mut [f64],
        stats: &mut Stats,
    ) -> Result<f64, StepFailure<S::Error>> {
        let n = x.len();
        let rows: [(f64, &[f64]); 5] = [
            (C2, &[A21]),
            (C3, &[A31, A32]),
            (C4, &[A41, A42, A43]),
            (C5, &[A51, A52, A53, A54]),
            (1.0, &[A61, A62, A63, A64, A65]),
        ];
        self.k[0].copy_from_slice(f0);
        for (stage, (c, a)) in rows.iter().enumerate() {
            for (i, (ti, xi)) in self.tmp.iter_mut().zip(x).enumerate() {
                let acc: f64 = a.iter().enumerate().map(|(j, aj)| aj * self.k[j][i]).sum();
                *ti = xi + h * acc;
            }
            let rest = &mut self.k[stage + 1..];
            sys.rhs(t + c * h, &self.tmp, &mut rest[0])
                .map_err(StepFailure::Model)?;
            stats.rhs_evaluations += 1;
        }
        for i in 0..n {
            x1[i] = x[i]
                + h * (B1 * self.k[0][i]
                    + B3 * self.k[2][i]
                    + B4 * self.k[3][i]
                    + B5 * self.k[4][i]
                    + B6 * self.k[5][i]);
        }
        sys.rhs(t + h, x1, f1).map_err(StepFailure::Model)?;
        stats.rhs_evaluations += 1;
        let mut norm = ErrorNorm::default();
        for i in 0..n {
            let e = h
                * (E1 * self.k[0][i]
                    + E3 * self.k[2][i]
                    + E4 * self.k[3][i]
                    + E5 * self.k[4][i]
                    + E6 * self.k[5][i]
                    + E7 * f1[i]);
            norm.add(x[i], x1[i], e, s);
        }
        self.limiting = norm.worst_index;
        Ok(norm.value())
    }

    /// DOPRI5's continuous extension (Hairer's dense output, 4th order) at t + s h.
    pub(super) fn dopri5_dense(
        &self,
        x: &[f64],
        x1: &[f64],
        f0: &[f64],
        f1: &[f64],
        h: f64,
        s: f64,
    ) -> Vec<f64> {
        let s1 = 1.0 - s;
        (0..x.len())
            .map(|i| {
                let r2 = x1[i] - x[i];
                let r3 = h * f0[i] - r2;
                let r4 = r2 - h * f1[i] - r3;
                let k = &self.k;
                let r5 = h
                    * (D1 * k[0][i] + D3 * k[2][i] + D4 * k[3][i] + D5 * k[4][i] + D6 * k[5][i] + D7 * f1[i]);
                x[i] + s * (r2 + s1 * (r3 + s * (r4 + s1 * r5)))
            })
            .collect()
    }
}
