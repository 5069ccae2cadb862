//! `kecsim creep`: creep-force curves of the creep-force models for one contact ellipse.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::forces::sweep::{self, SweepSettings};
use kecsim::contact::forces::{ContactPatch, CreepModel, KalkerTable};
use kecsim::inspect;

use super::{positive_mm, SinkArgs};

#[derive(Args)]
pub(super) struct CreepArgs {
    /// Creep-force model: kalker (linear, saturated), polach, fastsim, or all.
    #[arg(long, default_value = "all", value_parser = ["kalker", "polach", "fastsim", "all"])]
    model: String,
    /// Normal force N, newtons.
    #[arg(long, value_name = "N")]
    normal_force_n: f64,
    /// Semi-axis of the contact ellipse in the rolling direction, mm.
    #[arg(long, value_name = "A")]
    a_mm: f64,
    /// Semi-axis of the contact ellipse in the lateral direction, mm.
    #[arg(long, value_name = "B")]
    b_mm: f64,
    /// Coefficient of friction.
    #[arg(long, default_value_t = 0.3)]
    mu: f64,
    /// Spin creepage φ, 1/m.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    spin: f64,
    /// The creepage is swept over −MAX..MAX.
    #[arg(long, value_name = "MAX", default_value_t = 0.01)]
    max_creepage: f64,
    /// Points per curve.
    #[arg(long, default_value_t = 201)]
    points: usize,
    /// Shear modulus G, GPa.
    #[arg(long, default_value_t = 82.0)]
    shear_modulus_gpa: f64,
    /// Poisson's ratio ν (for Kalker's coefficients).
    #[arg(long, default_value_t = 0.28)]
    poisson: f64,
    /// Write the curves at the given N and spin as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: CreepArgs) -> Result<()> {
    let CreepArgs {
        model,
        normal_force_n,
        a_mm,
        b_mm,
        mu,
        spin,
        max_creepage,
        points,
        shear_modulus_gpa,
        poisson,
        csv,
        sink,
    } = a;
    let sink = sink.sink();
    let _outputs = super::guard::<&std::path::Path>(&[], &[("--csv", csv.as_deref())], Some(&sink))?;
    anyhow::ensure!(
        normal_force_n.is_finite() && normal_force_n > 0.0,
        "--normal-force-n {normal_force_n}: expected a positive force in N (a lifted wheel has no creep forces)"
    );
    anyhow::ensure!(
        mu.is_finite() && mu > 0.0 && mu <= 1.5,
        "--mu {mu}: expected a coefficient of friction in (0, 1.5] (dry rail ~0.4)"
    );
    let ratio = (a_mm / b_mm).max(b_mm / a_mm);
    if ratio.is_finite() && ratio > 10.0 {
        eprintln!(
            "kecsim: warning: --a-mm {a_mm} / --b-mm {b_mm}: semi-axis ratio {ratio:.1} beyond Kalker's table (up to 10); its coefficients are extrapolated"
        );
    }
    if normal_force_n > 1e6 {
        eprintln!(
            "kecsim: warning: --normal-force-n {normal_force_n}: above 1 MN, far beyond a wheel load (50–125 kN)"
        );
    }
    anyhow::ensure!(
        spin.is_finite(),
        "--spin {spin}: expected a finite spin creepage in 1/m"
    );
    anyhow::ensure!(
        max_creepage.is_finite() && max_creepage > 0.0 && max_creepage <= 1.0,
        "--max-creepage {max_creepage}: expected a creepage in (0, 1]"
    );
    anyhow::ensure!(
        (3..=100_001).contains(&points),
        "--points {points}: expected 3 ..= 100001"
    );
    anyhow::ensure!(
        shear_modulus_gpa.is_finite() && shear_modulus_gpa > 0.0,
        "--shear-modulus-gpa {shear_modulus_gpa}: expected a positive modulus"
    );
    anyhow::ensure!(
        (0.0..=0.5).contains(&poisson),
        "--poisson {poisson}: expected 0 ..= 0.5"
    );
    let table = KalkerTable::new(poisson);
    let patch = ContactPatch::new(
        positive_mm("--a-mm", a_mm)?,
        positive_mm("--b-mm", b_mm)?,
        normal_force_n,
        shear_modulus_gpa * 1e9,
        mu,
        &table,
    )?;
    let models: Vec<CreepModel> = if model == "all" {
        CreepModel::NAMES
            .iter()
            .filter_map(|n| CreepModel::by_name(n))
            .collect()
    } else {
        vec![CreepModel::by_name(&model).with_context(|| format!("unknown creep model {model}"))?]
    };
    let settings = SweepSettings {
        max_creepage,
        points,
        ..SweepSettings::default()
    };
    let summary = sweep::summary_markdown(&models, &patch, spin, &settings);
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::creep::blueprint)?;
        inspect::creep::record(&rec, &models, &patch, spin, &settings, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    if let Some(path) = csv {
        let mut rows = Vec::new();
        for m in &models {
            for c in sweep::Curve::BOTH {
                rows.extend(sweep::curve(m, &patch, c, spin, &settings)?);
            }
        }
        sweep::write_csv(&path, &rows).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {} ({} rows)", path.display(), rows.len());
    }
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
