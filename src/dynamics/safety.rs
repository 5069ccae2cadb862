//! Running safety of a run, as engineers read it from EN 14363 (and UIC 518): per wheelset, from
//! the output samples' wheel–rail forces in the track frame (Y lateral, Q vertical):
//!
//! - **Y/Q** of each wheel (flange climb), as the largest 2 m sliding mean along the track of
//!   |Y|/Q (a sample with Q ≤ 0, a lifted wheel, counts as 0: the lift is reported by ΔQ/Q₀ = 1
//!   and the run's lift figures), against **Nadal's limit** for the friction the run uses and the flange angle of its
//!   profiles, (Y/Q)_lim = (tan γ − μ)/(1 + μ tan γ);
//! - **ΣY** (Prud'homme, track shift): the sum of both wheels' lateral forces, its largest 2 m
//!   sliding mean in magnitude, against α (10 kN + 2Q₀/3) with 2Q₀ the static axle load (α = 1,
//!   passenger vehicles);
//! - **ΔQ/Q₀** (wheel unloading): the largest (Q₀ − Q)/Q₀ of a wheel, Q₀ its static load — from
//!   the instantaneous samples (the unloading that lets a wheel lift; EN 14363's twist test reads it
//!   quasi-statically, which a 2 m mean of the same samples approaches at low speed).
//!
//! EN 14363 takes the 99.85 % value of the sliding means over a test zone; a simulation's one run
//! gives the largest, which is on the safe side. Only full windows count: the means start 2 m after
//! the first sample (a run shorter than that has none: its figures are 0). The sliding mean is over the samples whose arc
//! length lies within the window ending at each sample (the output rate sets its resolution:
//! 100 Hz at 19 m/s is a sample every 0.19 m).

use std::fmt;

use serde::Serialize;

use super::sample::Sample;

pub use super::sample::WINDOW_M;

/// Nadal's single-wheel flange-climb limit for flange angle `gamma` (rad) and friction `mu`:
/// (tan γ − μ)/(1 + μ tan γ).
pub fn nadal_limit(gamma: f64, mu: f64) -> f64 {
    let t = gamma.tan();
    (t - mu) / (1.0 + mu * t)
}

/// Prud'homme's track-shift limit α (10 kN + 2Q₀/3), N, for the static axle load 2Q₀ (N).
pub fn prudhomme_limit_n(static_axle_load_n: f64, alpha: f64) -> f64 {
    alpha * (10e3 + static_axle_load_n / 3.0)
}

/// The sliding mean of `v` over the arc-length window `window` ending at each sample: the mean of
/// the v_j with s_i − window < s_j ≤ s_i (samples in order of s; the first window holds what there
/// is).
pub fn sliding_mean(s: &[f64], v: &[f64], window: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(v.len());
    let (mut start, mut sum) = (0usize, 0.0);
    for i in 0..v.len().min(s.len()) {
        sum += v[i];
        while s[i] - s[start] >= window && start < i {
            sum -= v[start];
            start += 1;
        }
        out.push(sum / (i + 1 - start) as f64);
    }
    out
}

/// What the limits need: the friction coefficient and the flange angle (the largest contact angle
/// of the wheel–rail pair, reached at flange contact), rad.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SafetyBasis {
    pub friction: f64,
    pub flange_angle_rad: f64,
}

/// One wheelset's running-safety figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelsetSafety {
    pub name: String,
    /// Largest 2 m sliding mean of |Y|/Q of either wheel, the wheel (`left`/`right`) and where
    /// (arc length of the wheelset, m).
    pub y_over_q_2m: f64,
    pub y_over_q_wheel: &'static str,
    pub y_over_q_at_s_m: f64,
    /// Largest |2 m sliding mean of ΣY|, N, where, and the Prud'homme limit, N.
    pub sum_y_2m_n: f64,
    pub sum_y_at_s_m: f64,
    pub prudhomme_limit_n: f64,
    /// Largest wheel unloading (Q₀ − Q)/Q₀ (0: never below the static load) and the wheel.
    pub delta_q_over_q0: f64,
    pub delta_q_wheel: &'static str,
    /// Static wheel loads Q₀ (left, right), N.
    pub static_wheel_load_n: [f64; 2],
}

/// The run's running-safety figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Safety {
    pub friction: f64,
    pub flange_angle_deg: f64,
    /// Nadal's Y/Q limit for them.
    pub nadal_limit: f64,
    /// The limit of a wheel's unloading ΔQ/Q₀ ([`DELTA_Q_LIMIT`]).
    pub delta_q_over_q0_limit: f64,
    pub wheelsets: Vec<WheelsetSafety>,
}

/// The limit of a wheel's unloading ΔQ/Q₀: EN 14363's 0.6 (the twist test's limit, held here
/// against the run's largest unloading).
pub const DELTA_Q_LIMIT: f64 = 0.6;

/// A running-safety criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// Y/Q, 2 m mean, against Nadal's limit.
    YOverQ,
    /// ΣY, 2 m mean, kN, against Prud'homme's limit.
    SumY,
    /// ΔQ/Q₀ against [`DELTA_Q_LIMIT`].
    DeltaQ,
}

impl Criterion {
    /// Its symbol (`Y/Q`, `ΣY`, `ΔQ/Q₀`).
    pub fn symbol(self) -> &'static str {
        match self {
            Criterion::YOverQ => "Y/Q",
            Criterion::SumY => "ΣY",
            Criterion::DeltaQ => "ΔQ/Q₀",
        }
    }

    /// A figure of it with its unit: `0.512`, `18.1 kN`.
    pub fn format(self, v: f64) -> String {
        match self {
            Criterion::SumY => format!("{v:.1} kN"),
            _ => format!("{v:.3}"),
        }
    }
}

/// One figure against its limit: which wheelset, what, the figure and the limit (ΣY in kN).
#[derive(Debug, Clone, PartialEq)]
pub struct Utilisation {
    pub wheelset: String,
    pub what: Criterion,
    pub value: f64,
    pub limit: f64,
}

impl Utilisation {
    /// The figure as a share of its limit.
    pub fn share(&self) -> f64 {
        if self.limit > 0.0 {
            self.value / self.limit
        } else {
            f64::INFINITY
        }
    }
}

impl Safety {
    /// Every wheelset's three figures against their limits (Y/Q against Nadal, ΣY against
    /// Prud'homme, in kN, ΔQ/Q₀ against [`DELTA_Q_LIMIT`]), the largest share first.
    pub fn utilisations(&self) -> Vec<Utilisation> {
        let mut u: Vec<Utilisation> = self
            .wheelsets
            .iter()
            .flat_map(|w| {
                [
                    (Criterion::YOverQ, w.y_over_q_2m, self.nadal_limit),
                    (Criterion::SumY, w.sum_y_2m_n * 1e-3, w.prudhomme_limit_n * 1e-3),
                    (Criterion::DeltaQ, w.delta_q_over_q0, self.delta_q_over_q0_limit),
                ]
                .map(|(what, value, limit)| Utilisation {
                    wheelset: w.name.clone(),
                    what,
                    value,
                    limit,
                })
            })
            .collect();
        u.sort_by(|a, b| b.share().total_cmp(&a.share()));
        u
    }

    /// The one-line verdict: `running safety: within every limit; nearest: w5 Y/Q 0.51 of 1.37`,
    /// or `running safety: LIMIT EXCEEDED: w1 Y/Q 1.52 over 1.37 (and 2 more)`.
    pub fn verdict(&self) -> String {
        let u = self.utilisations();
        let fmt = |x: &Utilisation| format!("{} {} {}", x.wheelset, x.what.symbol(), x.what.format(x.value));
        let limit = |x: &Utilisation| x.what.format(x.limit);
        let over: Vec<&Utilisation> = u.iter().filter(|x| x.share() > 1.0).collect();
        match (over.first(), u.first()) {
            (Some(x), _) => format!(
                "running safety: LIMIT EXCEEDED: {} over {}{}",
                fmt(x),
                limit(x),
                if over.len() > 1 {
                    format!(" (and {} more)", over.len() - 1)
                } else {
                    String::new()
                }
            ),
            (None, Some(x)) => format!(
                "running safety: within every limit; nearest: {} of {}",
                fmt(x),
                limit(x)
            ),
            (None, None) => "running safety: no wheelset samples to assess".into(),
        }
    }
}

const WHEELS: [&str; 2] = ["left", "right"];

/// One wheelset's running-safety quantities along its samples, of which its figures
/// ([`WheelsetSafety`]) are the largest: what `kecsim run` draws under `run/safety/`.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetySeries {
    /// Whether the 2 m window ending at each sample is full (from [`WINDOW_M`] after the first
    /// sample on): only those count (EN 14363).
    pub full: Vec<bool>,
    /// Each wheel's (left, right) 2 m sliding mean of |Y|/Q (a sample with Q ≤ 0 counts as 0).
    pub y_over_q_2m: [Vec<f64>; 2],
    /// The 2 m sliding mean of ΣY = Y_left + Y_right, N.
    pub sum_y_2m_n: Vec<f64>,
    /// Each wheel's unloading (Q₀ − Q)/Q₀ (None for a wheel without a static load).
    pub delta_q_over_q0: [Option<Vec<f64>>; 2],
}

/// The series of one wheelset from its samples' arc lengths `s` (in order), lateral and vertical
/// wheel–rail forces `y`, `q` (left, right; N) and its wheels' static loads `q0`.
pub fn series(s: &[f64], y: &[[f64; 2]], q: &[[f64; 2]], q0: [f64; 2]) -> SafetySeries {
    let s0 = s.first().copied().unwrap_or(0.0);
    let ratio = |i: usize| -> Vec<f64> {
        let v: Vec<f64> = y
            .iter()
            .zip(q)
            .map(|(y, q)| if q[i] > 0.0 { (y[i] / q[i]).abs() } else { 0.0 })
            .collect();
        sliding_mean(s, &v, WINDOW_M)
    };
    let unloading = |i: usize| (q0[i] > 0.0).then(|| q.iter().map(|q| (q0[i] - q[i]) / q0[i]).collect());
    let sum_y: Vec<f64> = y.iter().map(|y| y[0] + y[1]).collect();
    SafetySeries {
        full: s.iter().map(|&si| si - s0 >= WINDOW_M).collect(),
        y_over_q_2m: [ratio(0), ratio(1)],
        sum_y_2m_n: sliding_mean(s, &sum_y, WINDOW_M),
        delta_q_over_q0: [unloading(0), unloading(1)],
    }
}

/// The figures of every wheelset from its samples; `static_wheel_loads` are each wheelset's Q₀
/// (left, right), N: the largest values of its [`series`].
pub fn assess(
    wheelsets: &[(String, Vec<Sample>)],
    static_wheel_loads: &[[f64; 2]],
    basis: SafetyBasis,
) -> Safety {
    let list = wheelsets
        .iter()
        .zip(static_wheel_loads)
        .filter(|((_, samples), _)| !samples.is_empty())
        .map(|((name, samples), q0)| {
            let s: Vec<f64> = samples.iter().map(|p| p.s).collect();
            let y: Vec<[f64; 2]> = samples.iter().map(|p| p.y_force).collect();
            let q: Vec<[f64; 2]> = samples.iter().map(|p| p.q_force).collect();
            let series = series(&s, &y, &q, *q0);
            let full = |k: &usize| series.full[*k];
            let mut w = WheelsetSafety {
                name: name.clone(),
                y_over_q_2m: 0.0,
                y_over_q_wheel: WHEELS[0],
                y_over_q_at_s_m: s[0],
                sum_y_2m_n: 0.0,
                sum_y_at_s_m: s[0],
                prudhomme_limit_n: prudhomme_limit_n(q0[0] + q0[1], 1.0),
                delta_q_over_q0: 0.0,
                delta_q_wheel: WHEELS[0],
                static_wheel_load_n: *q0,
            };
            for (i, wheel) in WHEELS.iter().enumerate() {
                for k in (0..s.len()).filter(full) {
                    let m = series.y_over_q_2m[i][k];
                    if m > w.y_over_q_2m {
                        (w.y_over_q_2m, w.y_over_q_wheel, w.y_over_q_at_s_m) = (m, wheel, s[k]);
                    }
                }
                for &dq in series.delta_q_over_q0[i].iter().flatten() {
                    if dq > w.delta_q_over_q0 {
                        (w.delta_q_over_q0, w.delta_q_wheel) = (dq, wheel);
                    }
                }
            }
            for k in (0..s.len()).filter(full) {
                let m = series.sum_y_2m_n[k];
                if m.abs() > w.sum_y_2m_n {
                    (w.sum_y_2m_n, w.sum_y_at_s_m) = (m.abs(), s[k]);
                }
            }
            w
        })
        .collect();
    Safety {
        friction: basis.friction,
        flange_angle_deg: basis.flange_angle_rad.to_degrees(),
        nadal_limit: nadal_limit(basis.flange_angle_rad, basis.friction),
        delta_q_over_q0_limit: DELTA_Q_LIMIT,
        wheelsets: list,
    }
}

impl fmt::Display for Safety {
    /// The lines `kecsim run` prints.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "running safety (EN 14363 style: largest 2 m sliding means): Y/Q limit (Nadal, μ {}, flange {:.1}°) {:.3}; ΔQ/Q₀ limit {}; ΣY limit per wheelset (Prud'homme)",
            self.friction, self.flange_angle_deg, self.nadal_limit, self.delta_q_over_q0_limit
        )?;
        for w in &self.wheelsets {
            writeln!(
                f,
                "  {}: Y/Q {:.3} ({} wheel at s = {:.1} m); ΣY {:.1} kN of {:.1} kN (Prud'homme, at s = {:.1} m); ΔQ/Q₀ {:.3} ({} wheel)",
                w.name,
                w.y_over_q_2m,
                w.y_over_q_wheel,
                w.y_over_q_at_s_m,
                w.sum_y_2m_n * 1e-3,
                w.prudhomme_limit_n * 1e-3,
                w.sum_y_at_s_m,
                w.delta_q_over_q0,
                w.delta_q_wheel
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The facts sheet's values for S1002's 70° flange (`conicity-safety-comfort.txt`): μ 0.36 →
    /// 1.200 (the basis of EN 14363's 1.2), 0.5 → 0.947, 0.3 → 1.342.
    #[test]
    fn nadal_limits_of_the_s1002_flange() {
        let g = 70f64.to_radians();
        for (mu, lim) in [(0.36, 1.200), (0.5, 0.947), (0.3, 1.342)] {
            assert!(
                (nadal_limit(g, mu) - lim).abs() < 1e-3,
                "μ {mu}: {}",
                nadal_limit(g, mu)
            );
        }
        // Frictionless: tan γ.
        assert!((nadal_limit(g, 0.0) - g.tan()).abs() < 1e-12);
    }

    #[test]
    fn prudhomme_of_a_20_t_axle() {
        // 2Q₀ = 196.2 kN: 10 + 65.4 = 75.4 kN.
        assert!((prudhomme_limit_n(196.2e3, 1.0) - 75.4e3).abs() < 1e-6);
        assert!((prudhomme_limit_n(196.2e3, 0.85) - 0.85 * 75.4e3).abs() < 1e-6);
    }

    /// The sliding mean of a linear signal sampled every 0.25 m over a 2 m window is the signal at
    /// the window's middle (8 samples: s − 1.75 … s); before the window fills, the mean of what there is.
    #[test]
    fn sliding_mean_of_a_ramp() {
        let s: Vec<f64> = (0..40).map(|k| 0.25 * k as f64).collect();
        let v: Vec<f64> = s.iter().map(|x| 3.0 * x + 1.0).collect();
        let m = sliding_mean(&s, &v, 2.0);
        for (k, (&x, &mk)) in s.iter().zip(&m).enumerate() {
            let first = x - 0.25 * (k.min(7)) as f64;
            let expect = 3.0 * 0.5 * (first + x) + 1.0;
            assert!((mk - expect).abs() < 1e-12, "s {x}: {mk} vs {expect}");
        }
    }

    fn sample(s: f64, y: [f64; 2], q: [f64; 2]) -> Sample {
        Sample {
            normal: q,
            y_force: y,
            q_force: q,
            ..Sample::at(s / 19.0, s, 19.0)
        }
    }

    /// A flange force pulse on the right wheel over 1 m of 40 m: its 2 m mean is half its peak;
    /// the left wheel unloads to 30 kN of 50 kN; ΣY's mean where the pulse is; a larger spike in
    /// the first sample, whose windows are not full, is not counted.
    #[test]
    fn assess_a_pulse() {
        // Samples every 0.125 m (exact in binary): 16 in a 2 m window, the pulse 8 of them.
        let samples: Vec<Sample> = (0..320)
            .map(|k| {
                let s = 0.125 * k as f64;
                let pulse = (160..168).contains(&k);
                // A spike at the start, in a window not yet full: not counted.
                let (yr, qr) = match (pulse, k) {
                    (true, _) => (-40e3, 60e3),
                    (false, 0) => (-100e3, 50e3),
                    _ => (-2e3, 50e3),
                };
                let ql = if pulse { 30e3 } else { 50e3 };
                sample(s, [1e3, yr], [ql, qr])
            })
            .collect();
        let safety = assess(
            &[("w1".to_string(), samples)],
            &[[50e3, 50e3]],
            SafetyBasis {
                friction: 0.3,
                flange_angle_rad: 70f64.to_radians(),
            },
        );
        let w = &safety.wheelsets[0];
        // 8 pulse samples of 2/3 and 8 of 0.04 in the 16-sample window (first at s = 20.875 m).
        assert!(
            (w.y_over_q_2m - 0.5 * (40.0 / 60.0 + 2.0 / 50.0)).abs() < 1e-12,
            "{}",
            w.y_over_q_2m
        );
        assert_eq!(w.y_over_q_wheel, "right");
        assert_eq!(w.y_over_q_at_s_m, 20.875);
        assert!((w.delta_q_over_q0 - 0.4).abs() < 1e-12 && w.delta_q_wheel == "left");
        assert!(
            (w.sum_y_2m_n - 0.5 * (39e3 + 1e3)).abs() < 1e-6,
            "{}",
            w.sum_y_2m_n
        );
        assert!((w.prudhomme_limit_n - (10e3 + 100e3 / 3.0)).abs() < 1e-6);
        assert!((safety.nadal_limit - 1.342).abs() < 1e-3);
        assert!(
            safety.to_string().contains("w1: Y/Q 0.353 (right wheel"),
            "{safety}"
        );
    }
}
