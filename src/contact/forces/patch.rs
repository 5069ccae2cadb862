//! One contact patch as the creep-force models see it ([`ContactPatch`]: the Hertz ellipse's
//! semi-axes, the normal force, G, μ and Kalker's coefficients at a/b) and what they give
//! ([`CreepForce`], on the wheel in the contact frame). The models ([`super::linear`],
//! [`super::polach`], [`super::fastsim`]) use these; [`super::CreepModel`] chooses between them.

use thiserror::Error;

use super::creepage::Creepage;
use super::hertz::{HertzContact, Material};
use super::kalker::{KalkerCoefficients, KalkerTable};

/// Errors of the creep-force evaluation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CreepForceError {
    #[error("creep forces: non-finite input ({0})")]
    NonFinite(&'static str),
    #[error("creep forces: invalid contact patch: {0}")]
    Patch(String),
    #[error("creep forces: {0}")]
    Exact(#[from] super::exact::error::ExactError),
    #[error("creep forces: {0}")]
    Table(#[from] super::table_error::TableError),
}

/// Everything about one contact patch that the creep-force models need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPatch {
    /// Semi-axis in the rolling direction, m.
    pub a: f64,
    /// Semi-axis in the lateral direction, m.
    pub b: f64,
    /// Normal force N (≤ 0: the wheel has lifted), N.
    pub normal_force: f64,
    /// Combined shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Coefficient of friction μ.
    pub friction: f64,
    /// Kalker's coefficients at a/b.
    pub kalker: KalkerCoefficients,
    /// Poisson's ratio ν of the (quasi-identical) bodies.
    pub poisson: f64,
}

impl ContactPatch {
    /// From semi-axes given directly (e.g. `kecsim creep --a-mm --b-mm`).
    pub fn new(
        a: f64,
        b: f64,
        normal_force: f64,
        shear_modulus: f64,
        friction: f64,
        table: &KalkerTable,
    ) -> Result<ContactPatch, CreepForceError> {
        for (v, what) in [
            (a, "a"),
            (b, "b"),
            (normal_force, "N"),
            (shear_modulus, "G"),
            (friction, "μ"),
        ] {
            if !v.is_finite() {
                return Err(CreepForceError::NonFinite(what));
            }
        }
        if a <= 0.0 || b <= 0.0 || shear_modulus <= 0.0 || friction < 0.0 {
            return Err(CreepForceError::Patch(format!(
                "need a > 0, b > 0, G > 0, μ ≥ 0 (a = {a} m, b = {b} m, G = {shear_modulus} Pa, μ = {friction})"
            )));
        }
        Ok(ContactPatch {
            a,
            b,
            normal_force,
            shear_modulus,
            friction,
            kalker: table.at(a / b),
            poisson: table.poisson(),
        })
    }

    /// From a Hertz solution (a, b and N from it) for wheel and rail of one material.
    pub fn from_hertz(
        hertz: &HertzContact,
        material: &Material,
        friction: f64,
        table: &KalkerTable,
    ) -> Result<ContactPatch, CreepForceError> {
        ContactPatch::new(
            hertz.a,
            hertz.b,
            hertz.normal_force,
            material.shear_modulus(),
            friction,
            table,
        )
    }

    /// The same contact at another normal force: a, b ∝ N^(1/3) (Hertz), a/b and so the Kalker
    /// coefficients unchanged.
    pub fn scaled(&self, normal_force: f64) -> ContactPatch {
        let s = if self.normal_force > 0.0 && normal_force > 0.0 {
            (normal_force / self.normal_force).cbrt()
        } else {
            1.0
        };
        ContactPatch {
            a: self.a * s,
            b: self.b * s,
            normal_force,
            ..*self
        }
    }

    /// √(ab), m.
    pub fn c(&self) -> f64 {
        (self.a * self.b).sqrt()
    }

    /// Kalker's linear forces (Fx, Fy) and moment Mz (without the C₃₃ term, see `super::kalker`).
    pub fn linear(&self, creep: &Creepage) -> (f64, f64, f64) {
        let g = self.shear_modulus;
        let ab = self.a * self.b;
        let ab15 = ab * ab.sqrt();
        let k = &self.kalker;
        (
            -g * ab * k.c11 * creep.longitudinal,
            -g * ab * k.c22 * creep.lateral - g * ab15 * k.c23 * creep.spin,
            g * ab15 * k.c23 * creep.lateral,
        )
    }
}

/// Creep forces on the wheel in the contact frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CreepForce {
    /// Longitudinal force Fx, N.
    pub fx: f64,
    /// Lateral force Fy, N.
    pub fy: f64,
    /// Spin moment Mz about the normal, N·m (0 where the model does not define it).
    pub mz: f64,
    /// |(Fx, Fy)| / (μ N): 0 free rolling, 1 full sliding.
    pub saturation: f64,
    /// The normal force was ≤ 0: the wheel has lifted, all forces are zero.
    pub lifted: bool,
}

impl CreepForce {
    /// Zero forces with the lift flag.
    pub fn lifted() -> CreepForce {
        CreepForce {
            lifted: true,
            ..CreepForce::default()
        }
    }

    pub(super) fn with_saturation(fx: f64, fy: f64, mz: f64, patch: &ContactPatch) -> CreepForce {
        let limit = patch.friction * patch.normal_force;
        let saturation = if limit > 0.0 { fx.hypot(fy) / limit } else { 0.0 };
        CreepForce {
            fx,
            fy,
            mz,
            saturation,
            lifted: false,
        }
    }
}
