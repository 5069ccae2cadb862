//! Contact forces at the real contact points (paper §7): the Hertz ellipse from the real profiles'
//! curvatures and the normal force, Kalker's linear-theory coefficients, the creepages, and three
//! creep-force models, selectable per scene.
//!
//! Data flow for one wheel: [`hertz::RelativeCurvature::wheel_rail`] (rolling radius, contact
//! angle, profile curvatures at the real contact point) → [`hertz::HertzContact::solve`] (a, b) →
//! [`ContactPatch::new`] (with G, μ and [`kalker::KalkerTable`]) → [`CreepModel::forces`] with the
//! [`creepage::Creepage`] → [`CreepForce`] in the contact frame ([`creepage::ContactFrame`] turns
//! it into global vectors).
//!
//! Sign convention (all models): forces act **on the wheel**, in the contact frame (x rolling
//! direction, y lateral, z the normal from rail to wheel), opposing the creepage. At small creepage
//! every model reduces to Kalker's linear theory:
//! Fx = −G a b C₁₁ ξx, Fy = −G a b C₂₂ ξy − G (ab)^{3/2} C₂₃ φ.
//!
//! Wheel lift: a normal force ≤ 0 gives zero forces and [`CreepForce::lifted`] set, never NaN.
//! Non-finite input is an error.

pub mod creepage;
pub mod elliptic;
pub mod fastsim;
pub mod hertz;
pub mod kalker;
pub mod linear;
pub mod polach;
pub mod sweep;

use serde::Deserialize;
use thiserror::Error;

pub use creepage::{ContactFrame, Creepage};
pub use fastsim::{FastsimSettings, TractionBound};
pub use hertz::{HertzContact, Material, RelativeCurvature};
pub use kalker::{KalkerCoefficients, KalkerTable};
pub use linear::Saturation;
pub use polach::PolachParams;

/// Errors of the creep-force evaluation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CreepForceError {
    #[error("creep forces: non-finite input ({0})")]
    NonFinite(&'static str),
    #[error("creep forces: invalid contact patch: {0}")]
    Patch(String),
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

    /// Kalker's linear forces (Fx, Fy) and moment Mz (without the C₃₃ term, see [`kalker`]).
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

    fn with_saturation(fx: f64, fy: f64, mz: f64, patch: &ContactPatch) -> CreepForce {
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

/// The creep-force model of a scene (TOML: `model = "kalker" | "polach" | "fastsim"`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase", deny_unknown_fields)]
pub enum CreepModel {
    /// Kalker's linear theory with a saturation law.
    Kalker {
        #[serde(default)]
        saturation: Saturation,
    },
    /// Polach's method (1999, with spin; 2005 extension optional).
    Polach(PolachParams),
    /// Kalker's FASTSIM (simplified theory) on a discretised ellipse.
    Fastsim(FastsimSettings),
}

impl CreepModel {
    /// Names accepted on the command line.
    pub const NAMES: [&'static str; 3] = ["kalker", "polach", "fastsim"];

    /// The model by name with its default settings.
    pub fn by_name(name: &str) -> Option<CreepModel> {
        match name.to_ascii_lowercase().as_str() {
            "kalker" | "linear" => Some(CreepModel::Kalker {
                saturation: Saturation::default(),
            }),
            "polach" => Some(CreepModel::Polach(PolachParams::default())),
            "fastsim" => Some(CreepModel::Fastsim(FastsimSettings::default())),
            _ => None,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            CreepModel::Kalker { .. } => "kalker",
            CreepModel::Polach(_) => "polach",
            CreepModel::Fastsim(_) => "fastsim",
        }
    }

    /// Creep forces on the wheel for the creepages at rolling speed `speed` (m/s; only Polach's
    /// falling-friction extension uses it).
    pub fn forces(
        &self,
        patch: &ContactPatch,
        creep: &Creepage,
        speed: f64,
    ) -> Result<CreepForce, CreepForceError> {
        for (v, what) in [
            (creep.longitudinal, "ξx"),
            (creep.lateral, "ξy"),
            (creep.spin, "φ"),
            (patch.normal_force, "N"),
            (patch.a, "a"),
            (patch.b, "b"),
        ] {
            if !v.is_finite() {
                return Err(CreepForceError::NonFinite(what));
            }
        }
        if patch.normal_force <= 0.0 {
            return Ok(CreepForce::lifted());
        }
        Ok(match self {
            CreepModel::Kalker { saturation } => linear::forces(patch, creep, *saturation),
            CreepModel::Polach(p) => polach::forces(patch, creep, p, speed),
            CreepModel::Fastsim(s) => fastsim::forces(patch, creep, s),
        })
    }
}

/// Polach is the default: 20× cheaper than FASTSIM 25 × 25, spin included, within ~5 % of μN of
/// converged FASTSIM without spin (`kecsim bench creep`).
impl Default for CreepModel {
    fn default() -> Self {
        CreepModel::Polach(PolachParams::default())
    }
}

impl CreepModel {
    /// Problems with the model's parameters (empty when valid).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        match self {
            CreepModel::Kalker { .. } => {}
            CreepModel::Polach(q) => {
                if !(q.k_s > 0.0 && q.k_s <= q.k_a && q.k_a <= 1.0) {
                    p.push(format!(
                        "polach: need 0 < k_s ≤ k_a ≤ 1 (k_a = {}, k_s = {})",
                        q.k_a, q.k_s
                    ));
                }
                if !(q.friction_ratio > 0.0 && q.friction_ratio <= 1.0) {
                    p.push(format!(
                        "polach: friction_ratio = {}: expected (0, 1]",
                        q.friction_ratio
                    ));
                }
                if !(q.friction_decay_s_per_m.is_finite() && q.friction_decay_s_per_m >= 0.0) {
                    p.push(format!(
                        "polach: friction_decay_s_per_m = {}: expected ≥ 0",
                        q.friction_decay_s_per_m
                    ));
                }
            }
            CreepModel::Fastsim(f) => {
                for (n, what) in [(f.strips, "strips"), (f.elements, "elements")] {
                    if !(1..=1000).contains(&n) {
                        p.push(format!("fastsim: {what} = {n}: expected 1 ..= 1000"));
                    }
                }
            }
        }
        p
    }
}

/// What a scene needs to compute contact forces: the creep-force model, friction and the
/// material of wheel and rail (both the same steel).
#[derive(Debug, Clone)]
pub struct ContactForceSettings {
    pub model: CreepModel,
    /// Coefficient of friction μ.
    pub friction: f64,
    pub material: Material,
    /// Kalker's table for the material's Poisson's ratio.
    pub kalker: KalkerTable,
}

impl ContactForceSettings {
    /// Validated settings; every problem is listed.
    pub fn new(model: CreepModel, friction: f64, material: Material) -> Result<Self, Vec<String>> {
        let mut p = model.problems();
        if !(friction.is_finite() && (0.0..=1.5).contains(&friction)) {
            p.push(format!(
                "friction = {friction}: expected 0 ..= 1.5 (0: no creep forces)"
            ));
        }
        if !(material.young_pa.is_finite() && material.young_pa > 1e9) {
            p.push(format!(
                "young_modulus_pa = {}: expected > 1e9",
                material.young_pa
            ));
        }
        if !(0.0..=0.5).contains(&material.poisson) {
            p.push(format!(
                "poisson_ratio = {}: expected 0 ..= 0.5",
                material.poisson
            ));
        }
        if p.is_empty() {
            Ok(ContactForceSettings {
                model,
                friction,
                material,
                kalker: KalkerTable::new(material.poisson),
            })
        } else {
            Err(p)
        }
    }
}

#[cfg(test)]
mod tests;
