//! `kecsim bench creep-accuracy`: every creep-force model against Kalker's exact theory over a
//! grid of patches and creepages, with its cost per contact.
//!
//! **The grid** ([`grid`]): Hertz patches of 80 kN with √(ab) = 6 mm at a/b = 0.2, 0.5, 1, 2, 5
//! (G 82 GPa, ν 0.28, μ 0.3); spin φ = 0, 1, 2, 3, 4 1/m; creepage vectors (ξ, η) = s (cos θ,
//! sin θ) at θ = −90°, −45°, 0°, 45°, 90° with magnitudes s such that Kalker's linear force
//! G ab √(C₁₁C₂₂) s is 0.25, 0.5, 1, 2, 4, 8 × μN (from the linear range through the knee to full
//! sliding), and pure spin: 770 points. (θ beyond ±90° mirrors these: F(−ξ, η, φ) = (−Fx, Fy, Mz).)
//!
//! **The measure**: |ΔF|/μN with ΔF the difference of the force vectors (Fx, Fy) from the exact
//! theory's ([`crate::contact::forces::exact`], Richardson 32/16 elements: within ~0.3 % of μN of
//! the converged theory); max and RMS over the grid, over its points with spin and without; the
//! spin moment's max |ΔMz|/(μN √(ab)); ns per contact over the grid.

use std::time::Instant;

use rayon::prelude::*;

use crate::contact::forces::kalker::KalkerTable;
use crate::contact::forces::points::{force_fields, CreepPoint, FORCE_COLUMNS, POINT_COLUMNS};
use crate::contact::forces::{CreepForce, CreepForceError, CreepModel};

/// Shear modulus of the grid, Pa.
pub const GRID_SHEAR_MODULUS: f64 = 82e9;
/// Poisson's ratio of the grid.
pub const GRID_POISSON: f64 = 0.28;

/// The grid's points (see the module's documentation).
pub fn grid() -> Vec<CreepPoint> {
    let table = KalkerTable::new(GRID_POISSON);
    let (n, c, mu) = (80e3, 6.0, 0.3);
    let mut out = Vec::new();
    for ab in [0.2, 0.5, 1.0, 2.0, 5.0] {
        let (a, b) = (c * f64::sqrt(ab), c / f64::sqrt(ab));
        let k = table.at(ab);
        let linear = GRID_SHEAR_MODULUS * a * b * 1e-6 * (k.c11 * k.c22).sqrt();
        let point = |xi: f64, eta: f64, phi: f64| CreepPoint {
            line: 0,
            normal_force_n: n,
            a_mm: a,
            b_mm: b,
            xi,
            eta,
            phi_per_m: phi,
            mu,
        };
        for phi in [0.0, 1.0, 2.0, 3.0, 4.0] {
            if phi > 0.0 {
                out.push(point(0.0, 0.0, phi));
            }
            for theta_deg in [-90.0_f64, -45.0, 0.0, 45.0, 90.0] {
                for level in [0.25, 0.5, 1.0, 2.0, 4.0, 8.0] {
                    let s = level * mu * n / linear;
                    let t = theta_deg.to_radians();
                    // Exact zeros on the axes.
                    let (cx, cy) = match theta_deg as i32 {
                        0 => (1.0, 0.0),
                        90 => (0.0, 1.0),
                        -90 => (0.0, -1.0),
                        _ => (t.cos(), t.sin()),
                    };
                    out.push(point(s * cx, s * cy, phi));
                }
            }
        }
    }
    out
}

/// One model's accuracy over the grid.
#[derive(Debug, Clone)]
pub struct ModelAccuracy {
    pub label: String,
    pub max: f64,
    pub rms: f64,
    pub max_spin: f64,
    pub rms_spin: f64,
    pub max_no_spin: f64,
    pub rms_no_spin: f64,
    /// max |ΔMz| / (μN √(ab)).
    pub max_moment: f64,
    /// The grid point of the largest |ΔF|.
    pub worst: CreepPoint,
    /// Mean cost per contact over the grid, ns.
    pub ns_per_contact: f64,
}

/// Every model's forces and accuracy over the points.
#[derive(Debug, Clone)]
pub struct Accuracy {
    pub reference: String,
    pub points: Vec<CreepPoint>,
    /// The reference's forces, per point.
    pub exact: Vec<CreepForce>,
    pub models: Vec<ModelAccuracy>,
    /// Per model, per point.
    pub forces: Vec<Vec<CreepForce>>,
}

/// Measures `models` (label, model) against `reference` (the exact theory) at `points`.
pub fn measure(
    points: &[CreepPoint],
    reference: (&str, &CreepModel),
    models: &[(String, CreepModel)],
    done: &(dyn Fn() + Sync),
) -> Result<Accuracy, CreepForceError> {
    let table = KalkerTable::new(GRID_POISSON);
    let patches = points
        .iter()
        .map(|p| p.patch(GRID_SHEAR_MODULUS, &table))
        .collect::<Result<Vec<_>, _>>()?;
    let exact = points
        .par_iter()
        .zip(&patches)
        .map(|(p, patch)| {
            let f = reference.1.forces(patch, &p.creepage(), 0.0);
            done();
            f
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut out = Vec::new();
    let mut forces = Vec::new();
    for (label, model) in models {
        // The forces (a first pass: the table reads and refines its slices once per process);
        // the cost, a second pass repeated to at least 50 ms where the model is fast.
        let f = points
            .iter()
            .zip(&patches)
            .map(|(p, patch)| model.forces(patch, &p.creepage(), 0.0))
            .collect::<Result<Vec<_>, _>>()?;
        let t0 = Instant::now();
        let mut passes = 0usize;
        while passes == 0 || t0.elapsed().as_secs_f64() < 0.05 {
            for (p, patch) in points.iter().zip(&patches) {
                std::hint::black_box(model.forces(patch, &p.creepage(), 0.0)?);
            }
            passes += 1;
        }
        let ns = t0.elapsed().as_secs_f64() * 1e9 / (passes * points.len().max(1)) as f64;
        let mut acc = ModelAccuracy {
            label: label.clone(),
            max: 0.0,
            rms: 0.0,
            max_spin: 0.0,
            rms_spin: 0.0,
            max_no_spin: 0.0,
            rms_no_spin: 0.0,
            max_moment: 0.0,
            worst: points[0],
            ns_per_contact: ns,
        };
        let (mut n_spin, mut n_flat) = (0usize, 0usize);
        for ((p, e), m) in points.iter().zip(&exact).zip(&f) {
            let mun = p.mu * p.normal_force_n;
            let d = (m.fx - e.fx).hypot(m.fy - e.fy) / mun;
            let dm = (m.mz - e.mz).abs() / (mun * (p.a_mm * p.b_mm).sqrt() * 1e-3);
            if d > acc.max {
                acc.max = d;
                acc.worst = *p;
            }
            acc.rms += d * d;
            acc.max_moment = acc.max_moment.max(dm);
            if p.phi_per_m != 0.0 {
                acc.max_spin = acc.max_spin.max(d);
                acc.rms_spin += d * d;
                n_spin += 1;
            } else {
                acc.max_no_spin = acc.max_no_spin.max(d);
                acc.rms_no_spin += d * d;
                n_flat += 1;
            }
        }
        acc.rms = (acc.rms / points.len().max(1) as f64).sqrt();
        acc.rms_spin = (acc.rms_spin / n_spin.max(1) as f64).sqrt();
        acc.rms_no_spin = (acc.rms_no_spin / n_flat.max(1) as f64).sqrt();
        out.push(acc);
        forces.push(f);
    }
    Ok(Accuracy {
        reference: reference.0.to_string(),
        points: points.to_vec(),
        exact,
        models: out,
        forces,
    })
}

impl Accuracy {
    /// The table printed by the command.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "Creep-force models against {} at {} points (a/b 0.2–5, φ 0–4 1/m, creepage to full sliding): |ΔF|/μN, %\n\n",
            self.reference,
            self.points.len()
        );
        s += "| model | max | RMS | max, φ > 0 | RMS, φ > 0 | max, φ = 0 | RMS, φ = 0 | max ΔMz/(μN√ab) | ns/contact | worst at (a/b, ξ, η, φ) |\n";
        s += "|---|---|---|---|---|---|---|---|---|---|\n";
        for m in &self.models {
            let w = &m.worst;
            s += &format!(
                "| {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0} | ({:.1}, {:.2e}, {:.2e}, {}) |\n",
                m.label,
                100.0 * m.max,
                100.0 * m.rms,
                100.0 * m.max_spin,
                100.0 * m.rms_spin,
                100.0 * m.max_no_spin,
                100.0 * m.rms_no_spin,
                100.0 * m.max_moment,
                m.ns_per_contact,
                w.a_mm / w.b_mm,
                w.xi,
                w.eta,
                w.phi_per_m
            );
        }
        s
    }

    /// Summary as JSON (per model: max, rms, with and without spin, moment, cost).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "reference": self.reference,
            "points": self.points.len(),
            "grid": "80 kN, sqrt(ab) = 6 mm, a/b 0.2/0.5/1/2/5, phi 0-4 1/m, mu 0.3, G 82 GPa, nu 0.28",
            "models": self.models.iter().map(|m| serde_json::json!({
                "model": m.label,
                "max_df_over_mu_n": m.max,
                "rms_df_over_mu_n": m.rms,
                "max_df_over_mu_n_spin": m.max_spin,
                "rms_df_over_mu_n_spin": m.rms_spin,
                "max_df_over_mu_n_no_spin": m.max_no_spin,
                "rms_df_over_mu_n_no_spin": m.rms_no_spin,
                "max_dmz_over_mu_n_c": m.max_moment,
                "ns_per_contact": m.ns_per_contact,
                "worst": {
                    "a_over_b": m.worst.a_mm / m.worst.b_mm,
                    "xi": m.worst.xi,
                    "eta": m.worst.eta,
                    "phi_per_m": m.worst.phi_per_m,
                },
            })).collect::<Vec<_>>(),
        })
    }

    /// Every point with the exact forces and each model's: one row per (point, model), the
    /// exact theory's row first.
    pub fn write_csv<W: std::io::Write>(&self, w: &mut csv::Writer<W>) -> Result<(), csv::Error> {
        w.write_record(
            POINT_COLUMNS
                .iter()
                .chain(&FORCE_COLUMNS)
                .chain(&["df_over_mu_n"]),
        )?;
        for (k, p) in self.points.iter().enumerate() {
            let e = &self.exact[k];
            let mun = p.mu * p.normal_force_n;
            let rows = std::iter::once((self.reference.as_str(), e)).chain(
                self.models
                    .iter()
                    .zip(&self.forces)
                    .map(|(m, f)| (m.label.as_str(), &f[k])),
            );
            for (label, f) in rows {
                let df = format!("{:.6}", (f.fx - e.fx).hypot(f.fy - e.fy) / mun);
                w.write_record(p.csv_fields().iter().chain(&force_fields(label, f)).chain([&df]))?;
            }
        }
        w.flush()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_covers_the_stated_ranges() {
        let g = grid();
        assert_eq!(g.len(), 770);
        let ab: Vec<f64> = g.iter().map(|p| p.a_mm / p.b_mm).collect();
        assert!((ab.iter().cloned().fold(f64::INFINITY, f64::min) - 0.2).abs() < 1e-12);
        assert!((ab.iter().cloned().fold(0.0, f64::max) - 5.0).abs() < 1e-12);
        assert!(g.iter().all(|p| ((p.a_mm * p.b_mm).sqrt() - 6.0).abs() < 1e-12));
        assert_eq!(g.iter().filter(|p| p.phi_per_m == 4.0).count(), 5 * 31);
    }
}
