//! Creepages at a contact point (paper §7: "the normalized relative tangential velocities at the
//! contact points"), from the velocities of the wheel and rail material points there.
//!
//! Contact frame at the real contact point: n the contact normal (from the rail into the wheel),
//! t₁ = (a × n)/|a × n| the wheel's rolling direction (a the wheel's axle direction; oriented so
//! that t₁ points forward), t₂ = n × t₁ (lateral). With v the velocity of the material point and ω
//! the angular velocity of each body, and V_ref the reference (rolling) speed:
//!
//! ```text
//! ξx = (v_w − v_r) · t₁ / V_ref,   ξy = (v_w − v_r) · t₂ / V_ref,   φ = (ω_w − ω_r) · n / V_ref  [1/m]
//! ```
//!
//! For a solid-axle wheelset ω_w is the axle's angular velocity (rolling plus yaw rate); for a wheel of
//! an IRW-wheelset it is that wheel's own angular velocity: the same definition serves both.
//!
//! **Reference speed.** Kalker normalises by the rolling speed, the speed at which the contact point
//! travels along the rail — for a vehicle, its forward speed V. At V → 0 the creepages would be
//! undefined, so kecsim uses the regularised V_ref = √(V² + v_ε²) with v_ε =
//! [`REGULARISATION_SPEED`] (0.1 m/s by default): at 19 m/s the creepages change by 1.4·10⁻⁵
//! relative; at standstill a slip velocity w gives the creepage w/v_ε, which saturates the creep
//! force at μN for w ≫ 1 mm/s — Coulomb friction, regularised. Documented departure: the paper runs
//! at constant speed and does not need it.

use nalgebra::Vector3;
use thiserror::Error;

/// Default regularisation speed v_ε of the reference speed, m/s.
pub const REGULARISATION_SPEED: f64 = 0.1;

/// A contact frame could not be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CreepageError {
    #[error("contact frame: the normal is parallel to the wheel axle (or not finite)")]
    DegenerateFrame,
}

/// Orthonormal contact frame (t₁, t₂, n) at a contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// t₁: rolling (longitudinal) direction.
    pub longitudinal: Vector3<f64>,
    /// t₂ = n × t₁: lateral direction.
    pub lateral: Vector3<f64>,
    /// n: contact normal, from the rail into the wheel.
    pub normal: Vector3<f64>,
}

impl ContactFrame {
    /// From the contact normal n, the wheel's axle direction a and the forward direction of travel
    /// (which only orients t₁).
    pub fn new(
        normal: Vector3<f64>,
        axle: Vector3<f64>,
        forward: Vector3<f64>,
    ) -> Result<ContactFrame, CreepageError> {
        let n = normal
            .try_normalize(1e-12)
            .ok_or(CreepageError::DegenerateFrame)?;
        let mut t1 = axle
            .cross(&n)
            .try_normalize(1e-9)
            .ok_or(CreepageError::DegenerateFrame)?;
        if t1.dot(&forward) < 0.0 {
            t1 = -t1;
        }
        if !t1.iter().all(|x| x.is_finite()) {
            return Err(CreepageError::DegenerateFrame);
        }
        Ok(ContactFrame {
            longitudinal: t1,
            lateral: n.cross(&t1),
            normal: n,
        })
    }

    /// A force given in the contact frame (Fx along t₁, Fy along t₂, N along n) in the global frame.
    pub fn force_to_global(&self, fx: f64, fy: f64, normal_force: f64) -> Vector3<f64> {
        self.longitudinal * fx + self.lateral * fy + self.normal * normal_force
    }

    /// A moment about n (spin moment) in the global frame.
    pub fn moment_to_global(&self, mz: f64) -> Vector3<f64> {
        self.normal * mz
    }
}

/// Creepages at a contact point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Creepage {
    /// ξx, longitudinal (dimensionless).
    pub longitudinal: f64,
    /// ξy, lateral (dimensionless).
    pub lateral: f64,
    /// φ, spin, 1/m.
    pub spin: f64,
}

impl Creepage {
    pub fn new(longitudinal: f64, lateral: f64, spin: f64) -> Creepage {
        Creepage {
            longitudinal,
            lateral,
            spin,
        }
    }

    /// The creepages from the material-point velocities `v_wheel`, `v_rail` and the angular
    /// velocities `w_wheel`, `w_rail` (all in one frame), at rolling speed `rolling_speed` (m/s),
    /// regularised with `v_eps` (m/s; see the module doc).
    pub fn from_velocities(
        frame: &ContactFrame,
        v_wheel: Vector3<f64>,
        v_rail: Vector3<f64>,
        w_wheel: Vector3<f64>,
        w_rail: Vector3<f64>,
        rolling_speed: f64,
        v_eps: f64,
    ) -> Creepage {
        let v_ref = reference_speed(rolling_speed, v_eps);
        let slip = v_wheel - v_rail;
        Creepage {
            longitudinal: slip.dot(&frame.longitudinal) / v_ref,
            lateral: slip.dot(&frame.lateral) / v_ref,
            spin: (w_wheel - w_rail).dot(&frame.normal) / v_ref,
        }
    }
}

/// V_ref = √(V² + v_ε²) (never zero for v_ε > 0; falls back to 1e-9 m/s if both are zero).
pub fn reference_speed(rolling_speed: f64, v_eps: f64) -> f64 {
    (rolling_speed * rolling_speed + v_eps * v_eps).sqrt().max(1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Vector3};

    /// A wheelset with yaw ψ, lateral velocity ẏ, yaw rate ψ̇, rolling at Ω = V/r0: at first order
    /// (the textbook linear creepages, e.g. Garg & Dukkipati §6) the left wheel (Y = +l, radius r,
    /// contact angle γ, normal tilted toward the track centre) has
    /// ξx = 1 − r/r0 − l ψ̇ / V,  ξy = (ẏ/V − ψ) cos γ,  φ = ψ̇ cos γ / V − sin γ / r0.
    #[test]
    fn wheelset_creepages_match_the_linear_formulas() {
        let (v, r0, l) = (20.0, 0.46, 0.75);
        for &(psi, y_dot, psi_dot, r, gamma) in &[
            (1e-4, 2e-3, 1e-3, 0.4605, 0.03_f64),
            (-2e-4, -1e-3, 2e-3, 0.4590, 0.05),
            (5e-5, 0.0, 0.0, 0.4612, 1.0),
        ] {
            let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), psi);
            let axle = rot * Vector3::y();
            let omega = axle * (v / r0) + Vector3::z() * psi_dot;
            let u = axle * l - Vector3::z() * r;
            let v_c = Vector3::new(v, y_dot, 0.0);
            let v_w = v_c + omega.cross(&u);
            let n = rot * Vector3::new(0.0, -gamma.sin(), gamma.cos());
            let frame = ContactFrame::new(n, axle, Vector3::x()).unwrap();
            let c = Creepage::from_velocities(&frame, v_w, Vector3::zeros(), omega, Vector3::zeros(), v, 0.0);
            let ex = 1.0 - r / r0 - l * psi_dot / v;
            let ey = (y_dot / v - psi) * gamma.cos();
            let ephi = psi_dot * gamma.cos() / v - gamma.sin() / r0;
            // Second-order terms: ψ², ψ·(r − r0)/r0, ψ·ψ̇ l/V.
            assert!(
                (c.longitudinal - ex).abs() < 1e-7,
                "ξx {} vs {ex}",
                c.longitudinal
            );
            assert!((c.lateral - ey).abs() < 1e-6, "ξy {} vs {ey}", c.lateral);
            assert!((c.spin - ephi).abs() < 1e-6, "φ {} vs {ephi}", c.spin);
        }
    }

    #[test]
    fn frame_is_orthonormal_right_handed_and_forward() {
        let n = Vector3::new(0.0, -0.5, 0.8);
        let frame = ContactFrame::new(n, Vector3::new(0.01, 1.0, 0.0), Vector3::new(-1.0, 0.0, 0.0)).unwrap();
        assert!(frame.longitudinal.x < 0.0);
        for (a, b) in [
            (frame.longitudinal, frame.lateral),
            (frame.lateral, frame.normal),
            (frame.normal, frame.longitudinal),
        ] {
            assert!(a.dot(&b).abs() < 1e-14);
            assert!((a.norm() - 1.0).abs() < 1e-14);
        }
        assert!((frame.longitudinal.cross(&frame.lateral) - frame.normal).norm() < 1e-14);
        let f = frame.force_to_global(1.0, 2.0, 3.0);
        assert!((f.norm() - 14f64.sqrt()).abs() < 1e-14);
        assert!(ContactFrame::new(Vector3::y(), Vector3::y(), Vector3::x()).is_err());
        assert!(ContactFrame::new(Vector3::new(f64::NAN, 0.0, 1.0), Vector3::y(), Vector3::x()).is_err());
    }

    #[test]
    fn zero_speed_is_regularised_not_nan() {
        let frame = ContactFrame::new(Vector3::z(), Vector3::y(), Vector3::x()).unwrap();
        let c = Creepage::from_velocities(
            &frame,
            Vector3::new(1e-3, 0.0, 0.0),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
            0.0,
            REGULARISATION_SPEED,
        );
        assert!((c.longitudinal - 1e-2).abs() < 1e-15);
        let c0 = Creepage::from_velocities(
            &frame,
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
            0.0,
            0.0,
        );
        assert!(c0.longitudinal == 0.0 && c0.lateral == 0.0 && c0.spin == 0.0);
        // Relative change at 19 m/s.
        assert!((reference_speed(19.0, REGULARISATION_SPEED) / 19.0 - 1.0) < 1.5e-5);
    }
}
