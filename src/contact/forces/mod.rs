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
//!
//! The patch and the force the models share are in `patch`; each model in its own file
//! (`linear`, `polach`, [`fastsim`]) uses them, and [`CreepModel`] here chooses the model.

pub mod creepage;
pub(crate) mod elliptic;
pub mod exact;
pub mod fastrip;
pub mod fastsim;
pub mod hertz;
pub(crate) mod kalker;
pub(crate) mod linear;
pub(crate) mod patch;
pub mod points;
pub(crate) mod polach;
pub mod sweep;
pub mod table;
pub mod table_error;

use serde::Deserialize;

pub use creepage::{ContactFrame, Creepage};
pub use fastrip::FastripSettings;
pub use fastsim::{FastsimSettings, SlipDirection, TractionBound};
pub use hertz::{HertzContact, Material, RelativeCurvature};
pub use kalker::{KalkerCoefficients, KalkerTable};
pub use linear::Saturation;
pub use patch::{ContactPatch, CreepForce, CreepForceError};
pub use polach::PolachParams;

/// The creep-force model of a scene (TOML: `model = "kalker" | "polach" | "fastsim" | "fastrip" |
/// "exact"`).
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
    /// FaStrip: strip theory with FASTSIM's directions in the slip zones (Sichani et al. 2016).
    Fastrip(FastripSettings),
    /// Kalker's exact theory on a grid (the reference; ~10–70 ms per contact).
    Exact(exact::ExactSettings),
    /// Kalker's exact theory tabulated (`table::ExactTable`): interpolated in the shipped table,
    /// the exact solver where a patch lies outside it.
    #[serde(rename = "exact-table")]
    ExactTable,
}

impl CreepModel {
    /// Names accepted on the command line.
    pub const NAMES: [&'static str; 6] = ["kalker", "polach", "fastsim", "fastrip", "exact", "exact-table"];

    /// The model by name with its default settings.
    pub fn by_name(name: &str) -> Option<CreepModel> {
        match name.to_ascii_lowercase().as_str() {
            "kalker" | "linear" => Some(CreepModel::Kalker {
                saturation: Saturation::default(),
            }),
            "polach" => Some(CreepModel::Polach(PolachParams::default())),
            "fastsim" => Some(CreepModel::Fastsim(FastsimSettings::default())),
            "fastrip" => Some(CreepModel::Fastrip(FastripSettings::default())),
            "exact" => Some(CreepModel::Exact(exact::ExactSettings::default())),
            "exact-table" => Some(CreepModel::ExactTable),
            _ => None,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            CreepModel::Kalker { .. } => "kalker",
            CreepModel::Polach(_) => "polach",
            CreepModel::Fastsim(_) => "fastsim",
            CreepModel::Fastrip(_) => "fastrip",
            CreepModel::Exact(_) => "exact",
            CreepModel::ExactTable => "exact-table",
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
            CreepModel::Fastrip(s) => fastrip::forces(patch, creep, s),
            CreepModel::Exact(s) => exact::forces(patch, creep, s)?,
            CreepModel::ExactTable => {
                let table = table::ExactTable::embedded()?;
                match table.forces(patch, creep) {
                    Ok(f) => f,
                    Err(table::TableError::OutOfRange(..)) => {
                        exact::forces(patch, creep, &exact::ExactSettings::default())?
                    }
                    Err(e) => return Err(e.into()),
                }
            }
        })
    }
}

/// The exact theory tabulated is the default: the most accurate model at Polach's cost (`kecsim
/// bench creep-accuracy`: RMS 0.5 %, at most 5.9 % of μN off the exact theory over a/b 0.2–5, spin
/// 0–4 1/m and creepages to full sliding, where Polach is off by up to 63 %, FASTSIM 20 %).
impl Default for CreepModel {
    fn default() -> Self {
        CreepModel::ExactTable
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
            CreepModel::Fastrip(f) => {
                for (n, what) in [(f.strips, "strips"), (f.elements, "elements")] {
                    if !(1..=1000).contains(&n) {
                        p.push(format!("fastrip: {what} = {n}: expected 1 ..= 1000"));
                    }
                }
            }
            CreepModel::Exact(e) => p.extend(e.problems()),
            CreepModel::ExactTable => {
                if let Err(e) = table::ExactTable::embedded() {
                    p.push(e.to_string());
                }
            }
        }
        p
    }
}

/// The smallest coefficient of friction but 0 (no creep forces): below it the creep forces
/// vanish against the wheelsets' other forces and their equations become singular (1e-300 was
/// accepted, then failed as "singular wheelset equations").
pub const MIN_FRICTION: f64 = 0.01;

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
    /// The strip model in the dynamics where Hertz does not hold (`[contact_forces] patches =
    /// "dynamics"`); None: Hertz's ellipse everywhere in the dynamics.
    pub patches: Option<std::sync::Arc<crate::contact::nonhertz::DynamicPatches>>,
}

impl ContactForceSettings {
    /// Physically doubtful but possible values (warnings, each naming its key): no friction at
    /// all, a friction beyond dry steel on steel, an elastic modulus far from steel's.
    pub fn doubtful(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.friction == 0.0 {
            w.push("friction = 0: no creep forces at all — the wheelsets are neither steered nor braked by their rails, only the flanges' normal forces guide them (wet or leaf-covered rails still give μ ≈ 0.05)".to_string());
        } else if self.friction > 0.6 {
            w.push(format!(
                "friction = {}: above dry steel on steel (≈ 0.4–0.6)",
                self.friction
            ));
        }
        if let CreepModel::Exact(e) = self.model {
            w.push(format!(
                "model = \"exact\": Kalker's exact theory solved at every contact of every right-hand side ({} elements across{}): ~10–70 ms a contact, hours for a kilometre — a reference for short runs",
                e.elements,
                if e.richardson { ", Richardson" } else { "" }
            ));
        }
        let e = self.material.young_pa;
        if !(5e10..=5e11).contains(&e) {
            w.push(format!(
                "young_modulus_pa = {e:e}: far from steel's 2.1e11 Pa (wheels and rails are steel; a unit mistake?)"
            ));
        }
        w
    }

    /// Validated settings; every problem is listed.
    pub fn new(model: CreepModel, friction: f64, material: Material) -> Result<Self, Vec<String>> {
        let mut p = model.problems();
        if !(friction.is_finite() && (friction == 0.0 || (MIN_FRICTION..=1.5).contains(&friction))) {
            p.push(format!(
                "friction = {friction:?}: expected 0 (no creep forces) or {MIN_FRICTION} ..= 1.5 (wet or leaf-covered rails: ≈ 0.05; a smaller μ leaves the creep forces too small against the wheelsets' equations, which become singular)"
            ));
        }
        if !(material.young_pa.is_finite() && material.young_pa > 1e9 && material.young_pa <= 1e12) {
            p.push(format!(
                "young_modulus_pa = {}: expected 1e9 < E ≤ 1e12 Pa (steel: 2.1e11; no engineering material is stiffer than 1e12 — a unit mistake?)",
                material.young_pa
            ));
        }
        if !(0.0..=0.5).contains(&material.poisson) {
            p.push(format!(
                "poisson_ratio = {}: expected 0 ..= 0.5",
                material.poisson
            ));
        }
        if let (CreepModel::ExactTable, Ok(t)) = (&model, table::ExactTable::embedded()) {
            if (material.poisson - t.spec.poisson).abs() > 1e-9 {
                p.push(format!(
                    "model = \"exact-table\" is the exact theory tabulated for Poisson's ratio {}; poisson_ratio = {}: use model = \"exact\" (slow) or \"fastrip\"",
                    t.spec.poisson, material.poisson
                ));
            }
        }
        if p.is_empty() {
            Ok(ContactForceSettings {
                model,
                friction,
                material,
                kalker: KalkerTable::new(material.poisson),
                patches: None,
            })
        } else {
            Err(p)
        }
    }
}

#[cfg(test)]
mod tests;
