//! The vehicle's longitudinal drive: what holds its speed (issue 46; the paper runs its case "at a
//! constant forward velocity of 19 m/s" and says no more).
//!
//! Every body's longitudinal coordinate is free (s_i = s₀ + d_i + x_i, [`super::multibody`]):
//! without a drive the curving resistance — the longitudinal components of the yawed wheels'
//! creep forces — slows the vehicle while the reference frames move on at V. A held speed is a
//! **traction law on the motored wheels**: a torque T on each driven wheel about its axle (added
//! to the wheel's spin row of Eq. 53's system, [`super::wheelset::Load::drive_torque`]), its
//! reaction −ΣT on the bogie frame that carries the motors (bogie-mounted motors). The traction
//! reaches the vehicle only through the longitudinal creep forces it raises at the motored wheels'
//! real contacts, as a motor's does — so the creepages, their saturation and the load transfer of
//! the reaction torque are the physical ones. (A driving constraint on the vehicle's longitudinal
//! coordinates was the alternative: exact, but its reaction would act on every body in proportion
//! to its mass, or pull the wheelsets at their axles, and leave the motored wheels' creepages as a
//! coasting vehicle's; a torque does not enter the acceleration-level equations at the instant it
//! is applied — it acts through the wheels' spin and creep, milliseconds later —, so it cannot be
//! the multiplier of such a constraint.)
//!
//! The torque comes from a **speed controller** on the position along the track of the driven
//! wheelsets and the bogie frames that carry their motors, x_D = Σ m_j x_j / Σ m_j over them (x
//! relative to the reference, which moves at the scene's V(t)):
//!
//! ```text
//! F = −K_p ẋ_D − K_i x_D,     K_p = 2 ζ ω_c M_e,  K_i = ω_c² M_e,  ζ = 1,  ω_c = 2π f_c
//! T = F r₀ / n   on each of the n driven wheels
//! ```
//!
//! — a PI law on the speed error ẋ_D (x_D is its integral), with M_e the whole vehicle's
//! translating masses plus each wheel's I/r₀²: for the vehicle as one rigid mass the loop is
//! critically damped at the bandwidth f_c (`controller_hz`, default 0.2 Hz). In steady state every body moves at the reference's speed exactly, the vehicle F/K_i
//! behind it (a millimetre for the MS vehicle's curving resistance). The loop reads the speed where
//! it acts, as a traction controller reads its motors' (collocated: the wheelsets and their bogie
//! frame are one mass through the stiff primary suspension at the loop's frequencies, and the
//! frame's speed is free of the wheelsets' own longitudinal vibration on it, which read alone
//! swung the MS vehicle's traction by ±2 kN on the irregular track): it then acts as a spring and
//! a damper between the reference and the driven bogies, which cannot destabilise the
//! suspension's longitudinal modes. (Closed on the whole vehicle's centre of mass, with the drive
//! at the wheels, it did: the Manchester vehicle's carbody, 32 t on four 160 kN/m secondary
//! springs with no longitudinal damper, has its longitudinal mode at 0.71 Hz, and the 0.5 Hz loop
//! drove it to ±40 kN of traction in 30 s — measured.) f_c sits far below the creep's time
//! constants (~1 ms), so the loop needs no place in the integrator's Newton matrix.
//!
//! **A speed ramp** (V̇ ≠ 0: the critical-speed scenes) is a prescribed motion: each body and
//! wheelset is given m V̇ along its track frame's x and each wheel I V̇ / r₀ about its axle — the
//! ramp's inertia, whose sum M_e V̇ is counted in the traction —, so that the vehicle follows the
//! ramp with its wheels rolling freely: the loop supplies only the resistance. (Braking the ramp
//! through the wheels' creep instead, M_e V̇ as motor torque, used a third of the adhesion of the
//! Cooperrider car's wheels at 0.5 m/s² and μ 0.15 and took its hunting mode at 60 m/s from
//! Re λ = +0.37 to −0.04 1/s: a braking vehicle's stability, not the ramp method's constant-speed
//! one.)
//!
//! The other laws: **coasting** (no drive, the behaviour before issue 46), a **given force** F
//! (traction > 0, braking < 0) through the same wheels, and a vehicle **tied** to the track frame
//! by force elements (a bogie under an ideal carbody, the single wheelset on its frame): the tie
//! holds the speed, and its longitudinal force is the traction.

use std::f64::consts::PI;

/// How the vehicle's longitudinal motion is driven.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TractionLaw {
    /// Nothing drives: the vehicle rolls freely, the curving resistance slowing it.
    Coast,
    /// A given longitudinal force through the driven wheels, N (traction > 0, braking < 0).
    Force { force_n: f64 },
    /// The speed held by the controller of the module's documentation.
    HoldSpeed(SpeedLoop),
    /// The vehicle is tied to the track frame, which moves at the reference speed: the tie holds
    /// the speed (no drive).
    Tied,
}

/// The speed controller of [`TractionLaw::HoldSpeed`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedLoop {
    /// Bandwidth f_c, Hz.
    pub bandwidth_hz: f64,
    /// M_e, kg: the translating masses plus each wheel's I/r₀².
    pub effective_mass_kg: f64,
    /// The drive's largest force (traction or braking), N: a demand beyond it ends the run with a
    /// diagnosis (None: no limit).
    pub max_force_n: Option<f64>,
}

impl SpeedLoop {
    /// K_p = 2 ζ ω_c M_e, N s/m.
    pub fn k_p(&self) -> f64 {
        2.0 * DAMPING_RATIO * 2.0 * PI * self.bandwidth_hz * self.effective_mass_kg
    }

    /// K_i = ω_c² M_e, N/m.
    pub fn k_i(&self) -> f64 {
        let w = 2.0 * PI * self.bandwidth_hz;
        w * w * self.effective_mass_kg
    }

    /// The force the loop asks for at the driven wheelsets' offset `x_d` (m) and speed error
    /// `x_d_dot` (m/s), N (a ramp's inertia is the prescribed motion's, not the loop's).
    pub fn demand(&self, x_d: f64, x_d_dot: f64) -> f64 {
        -self.k_p() * x_d_dot - self.k_i() * x_d
    }
}

/// The speed loop's damping ratio ζ (critically damped: no overshoot of the speed).
pub const DAMPING_RATIO: f64 = 1.0;

/// The speed loop's bandwidth where the scene gives none, Hz: the MS vehicle on its irregular
/// kilometre holds 19 m/s within 0.02 % at 0.2, 0.5 and 1 Hz alike, while the traction's swing
/// with the bogies' longitudinal vibration grows with the loop's gain (its standard deviation in
/// the curve 310 N at 0.2 Hz, 1.2 kN at 1 Hz, about a 0.58 kN mean; measured 2026-12-04).
pub const DEFAULT_BANDWIDTH_HZ: f64 = 0.2;

/// The largest bandwidth accepted, Hz. A traction controller's speed loop is slow against the
/// vehicle's dynamics, and this one, collocated, stays stable far beyond it — but not for any
/// gain (measured 2026-12-04 on 14 s of the MS vehicle and 12 s of the Manchester vehicle into the
/// Tab. 6 curve): above ~2 Hz the traction follows the bogies' longitudinal vibration (its swing
/// grows with the gain), from ~20 Hz it costs right-hand sides (1.8× the 0.2 Hz run's at 20 Hz,
/// 36× at 1000 Hz), and at hundreds of Hz it reaches the wheels' spin–creep time constants (~1
/// ms) and turns unstable: the Manchester vehicle at 500 Hz threw a wheel 5 mm off its rail within
/// 1 s.
pub const MAX_BANDWIDTH_HZ: f64 = 2.0;

/// The speed error beyond which a held speed is declared lost (the run stops with the
/// diagnosis), as a fraction of the reference speed.
pub const LOST_SPEED_FRACTION: f64 = 0.01;

/// The vehicle's drive at one evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TractionState {
    /// The force the law asks for, N (0 when coasting or tied).
    pub demand_n: f64,
    /// The force applied through the driven wheels (T r₀⁻¹ summed), N.
    pub drive_n: f64,
    /// A held speed's ramp: the prescribed M_e V̇ given to the bodies and wheels, N.
    pub ramp_n: f64,
    /// The longitudinal force of the vehicle's ties to the track frame on it, N (0: none).
    pub tie_n: f64,
    /// The drive's power at the wheels, Σ T Ω (or the tie's force times its speed), W.
    pub power_w: f64,
    /// The centre of mass's offset x_G behind (−) or ahead of (+) the reference, m.
    pub offset_m: f64,
    /// The centre of mass's speed along the track, V + ẋ_G, m/s.
    pub speed_m_s: f64,
}

impl TractionState {
    /// The traction: every longitudinal force from outside the wheel–rail contacts, the drive's,
    /// the ramp's and the ties', N (> 0 pushing forward).
    pub fn traction_n(&self) -> f64 {
        self.drive_n + self.ramp_n + self.tie_n
    }
}

/// What the run's traction summary (`super::resistance::assess`) needs of the vehicle: its law's name, bandwidth and driven wheelsets, its
/// weight (N) and M_e (kg, [`SpeedLoop::effective_mass_kg`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DriveInfo {
    pub mode: &'static str,
    pub controller_hz: Option<f64>,
    pub driven_wheelsets: Vec<String>,
    pub weight_n: f64,
    pub effective_mass_kg: f64,
}

/// What drives the vehicle, in words, from a [`DriveInfo`]'s mode, bandwidth and driven wheelsets
/// (the run's printed lines).
pub fn describe(mode: &str, controller_hz: Option<f64>, driven: &[String]) -> String {
    match mode {
        "hold_speed" => format!(
            "speed held by a {} Hz loop on {}",
            controller_hz.unwrap_or(DEFAULT_BANDWIDTH_HZ),
            driven.join(", ")
        ),
        "tied" => "speed held by the vehicle's tie to the track frame".to_string(),
        "coast" => "coasting: nothing drives".to_string(),
        _ => format!("a given force on {}", driven.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loop is critically damped at its bandwidth: the closed loop of a mass M_e,
    /// M_e ẍ = −K_p ẋ − K_i x, has the double root −ω_c; after a step in the resistance F₀ the
    /// centre of mass settles F₀/K_i behind with no speed error (simulated here by the exact
    /// solution of the linear loop against a small-step Euler integration).
    #[test]
    fn the_speed_loop_is_critically_damped_at_its_bandwidth() {
        let l = SpeedLoop {
            bandwidth_hz: 0.5,
            effective_mass_kg: 60e3,
            max_force_n: None,
        };
        let w = 2.0 * PI * 0.5;
        // Characteristic polynomial s² + (K_p/M) s + K_i/M = (s + ω)².
        assert!((l.k_p() / 60e3 - 2.0 * w).abs() < 1e-12);
        assert!((l.k_i() / 60e3 - w * w).abs() < 1e-9);
        // A resistance of 500 N from t = 0: x(t) = −(F₀/K_i)(1 − (1 + ω t) e^{−ω t}).
        let (f0, dt) = (500.0, 1e-5);
        let (mut x, mut xd) = (0.0, 0.0);
        let mut t = 0.0;
        while t < 5.0 {
            let a = (l.demand(x, xd) - f0) / 60e3;
            x += dt * xd;
            xd += dt * a;
            t += dt;
        }
        let exact = -(f0 / l.k_i()) * (1.0 - (1.0 + w * t) * (-w * t).exp());
        assert!((x - exact).abs() < 1e-3 * exact.abs(), "{x} vs {exact}");
        // Settled: the offset F₀/K_i (0.86 mm), the speed error below 0.1 mm/s.
        assert!((exact + f0 / l.k_i()).abs() < 1e-3 * f0 / l.k_i());
        assert!(xd.abs() < 1e-4, "{xd}");
    }
}
