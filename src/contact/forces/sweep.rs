//! Creep-force curves: force against creepage for one contact patch (what `kecsim creep` writes
//! and records).

use super::{ContactPatch, CreepForce, CreepForceError, CreepModel, Creepage};

/// Which creepage a curve sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Curve {
    /// ξx swept, ξy = 0.
    Longitudinal,
    /// ξy swept, ξx = 0.
    Lateral,
}

impl Curve {
    pub const BOTH: [Curve; 2] = [Curve::Longitudinal, Curve::Lateral];

    pub fn name(self) -> &'static str {
        match self {
            Curve::Longitudinal => "longitudinal",
            Curve::Lateral => "lateral",
        }
    }
}

/// Range and resolution of a sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepSettings {
    /// The creepage runs over −max..max.
    pub max_creepage: f64,
    /// Points per curve (made odd, so that 0 is one of them).
    pub points: usize,
    /// Rolling speed, m/s (only Polach's falling friction uses it).
    pub speed: f64,
}

impl Default for SweepSettings {
    fn default() -> Self {
        SweepSettings {
            max_creepage: 0.01,
            points: 201,
            speed: 20.0,
        }
    }
}

impl SweepSettings {
    /// The swept creepage values, −max..max.
    pub fn creepages(&self) -> Vec<f64> {
        let n = self.count();
        let half = (n / 2) as i64;
        (0..n as i64).map(|i| (i - half) as f64 * self.step()).collect()
    }

    /// Points per curve actually used (odd, ≥ 3).
    pub fn count(&self) -> usize {
        self.points.max(3) | 1
    }

    /// Creepage step Δξ = 2 ξmax / (count − 1).
    pub fn step(&self) -> f64 {
        2.0 * self.max_creepage / (self.count() - 1) as f64
    }
}

/// One point of a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    pub model: &'static str,
    pub curve: Curve,
    pub normal_force: f64,
    pub spin: f64,
    pub creepage: Creepage,
    pub force: CreepForce,
}

/// One curve of `model` on `patch` with spin φ (1/m).
pub fn curve(
    model: &CreepModel,
    patch: &ContactPatch,
    curve: Curve,
    spin: f64,
    settings: &SweepSettings,
) -> Result<Vec<CurvePoint>, CreepForceError> {
    use rayon::prelude::*;
    // In parallel: the exact solver costs tens of ms a point.
    settings
        .creepages()
        .into_par_iter()
        .map(|xi| {
            let creepage = match curve {
                Curve::Longitudinal => Creepage::new(xi, 0.0, spin),
                Curve::Lateral => Creepage::new(0.0, xi, spin),
            };
            Ok(CurvePoint {
                model: model.name(),
                curve,
                normal_force: patch.normal_force,
                spin,
                creepage,
                force: model.forces(patch, &creepage, settings.speed)?,
            })
        })
        .collect()
}

/// Writes curve points as CSV: `model, curve, normal_force_n, spin_1pm, creepage_x, creepage_y,
/// fx_n, fy_n, mz_nm, saturation`.
pub fn write_csv(path: &std::path::Path, points: &[CurvePoint]) -> Result<(), csv::Error> {
    let mut w = crate::files::csv_writer(path)?;
    w.write_record([
        "model",
        "curve",
        "normal_force_n",
        "spin_1pm",
        "creepage_x",
        "creepage_y",
        "fx_n",
        "fy_n",
        "mz_nm",
        "saturation",
    ])?;
    for p in points {
        w.write_record([
            p.model.to_string(),
            p.curve.name().to_string(),
            format!("{}", p.normal_force),
            format!("{}", p.spin),
            format!("{:.9e}", p.creepage.longitudinal),
            format!("{:.9e}", p.creepage.lateral),
            format!("{:.6}", p.force.fx + 0.0), // + 0.0: no "-0"
            format!("{:.6}", p.force.fy + 0.0), // + 0.0: no "-0"
            format!("{:.6}", p.force.mz + 0.0), // + 0.0: no "-0"
            format!("{:.6}", p.force.saturation),
        ])?;
    }
    crate::files::commit_csv(w)?;
    Ok(())
}

/// Markdown summary of a sweep's inputs: the patch, the Kalker coefficients, the linear slopes
/// and each model's settings.
pub fn summary_markdown(
    models: &[CreepModel],
    patch: &ContactPatch,
    spin: f64,
    settings: &SweepSettings,
) -> String {
    let k = &patch.kalker;
    let mut s = String::from("# kecsim creep\n\n");
    s += &format!(
        "Contact ellipse a = {:.3} mm (rolling), b = {:.3} mm (lateral), a/b = {:.3}; N = {:.1} kN; G = {:.1} GPa; μ = {}; spin φ = {} 1/m; creepage swept over ±{} ({} points; the recording's timeline `creepage_step` counts steps of Δξ = {:.3e}), rolling speed {} m/s.\n\n",
        patch.a * 1e3,
        patch.b * 1e3,
        patch.a / patch.b,
        patch.normal_force * 1e-3,
        patch.shear_modulus * 1e-9,
        patch.friction,
        spin,
        settings.max_creepage,
        settings.count(),
        settings.step(),
        settings.speed
    );
    let g = patch.shear_modulus;
    let ab = patch.a * patch.b;
    s += &format!(
        "Kalker coefficients C11 = {:.4}, C22 = {:.4}, C23 = {:.4} (C33 not available). Linear slopes: G a b C11 = {:.4e} N, G a b C22 = {:.4e} N, G (ab)^1.5 C23 = {:.4e} N·m.\n\n",
        k.c11,
        k.c22,
        k.c23,
        g * ab * k.c11,
        g * ab * k.c22,
        g * ab * ab.sqrt() * k.c23
    );
    s += "| model | settings |\n|---|---|\n";
    for m in models {
        let detail = match m {
            CreepModel::Kalker { saturation } => format!("linear theory, saturation {saturation:?}"),
            CreepModel::Polach(p) => format!(
                "k_A = {}, k_S = {}, A = {}, B = {} s/m",
                p.k_a, p.k_s, p.friction_ratio, p.friction_decay_s_per_m
            ),
            CreepModel::Fastsim(f) => format!(
                "{} strips × {} elements, {:?} traction bound, {:?} slip direction",
                f.strips, f.elements, f.bound, f.direction
            ),
            CreepModel::Fastrip(f) => format!(
                "{} strips × {} elements (strip theory; FASTSIM's direction in slip)",
                f.strips, f.elements
            ),
            CreepModel::ExactTable => "the exact theory tabulated (assets/creep/exact_table.bin)".to_string(),
            CreepModel::Exact(e) => format!(
                "Kalker's exact theory, {} × {} elements{}",
                e.elements,
                e.elements,
                if e.richardson {
                    format!(", Richardson with {} × {}", e.elements / 2, e.elements / 2)
                } else {
                    String::new()
                }
            ),
        };
        s += &format!("| {} | {detail} |\n", m.name());
    }
    s
}
