//! `kecsim creep`: creep-force curves of the creep-force models for one contact ellipse, or
//! (`--at POINTS.csv`) the forces of the models at given points, for scripts.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::forces::points;
use kecsim::contact::forces::sweep::{self, SweepSettings};
use kecsim::contact::forces::{ContactPatch, CreepModel, KalkerTable};
use kecsim::inspect;

use super::{positive_mm, SinkArgs};

#[derive(Args)]
pub(super) struct CreepArgs {
    /// Creep-force model: kalker (linear, saturated), polach, fastsim, fastrip, exact (Kalker's
    /// exact theory on a grid, the reference), exact-table (it tabulated: the default), or all.
    #[arg(long, default_value = "all", value_parser = ["kalker", "polach", "fastsim", "fastrip", "exact", "exact-table", "all"])]
    model: String,
    /// Rebuild the exact-theory table of `model = "exact-table"` (every node solved by the exact
    /// solver: ~20 min on 2 cores) into FILE (the shipped one is assets/creep/exact_table.bin).
    #[arg(long, value_name = "FILE")]
    build_table: Option<PathBuf>,
    /// Forces at the points of this CSV (columns n_n,a_mm,b_mm,xi,eta,phi_per_m,mu), written
    /// back with model,fx_n,fy_n,mz_n_m per model to --csv (or stdout); no curves, no recording.
    #[arg(long, value_name = "POINTS.csv")]
    at: Option<PathBuf>,
    /// Normal force N, newtons (required without --at).
    #[arg(long, value_name = "N")]
    normal_force_n: Option<f64>,
    /// Semi-axis of the contact ellipse in the rolling direction, mm (required without --at).
    #[arg(long, value_name = "A")]
    a_mm: Option<f64>,
    /// Semi-axis of the contact ellipse in the lateral direction, mm (required without --at).
    #[arg(long, value_name = "B")]
    b_mm: Option<f64>,
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
    /// Write the curves at the given N and spin as CSV (with --at: the forces at the points).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: CreepArgs) -> Result<()> {
    let models: Vec<CreepModel> = if a.model == "all" {
        CreepModel::NAMES
            .iter()
            .filter_map(|n| CreepModel::by_name(n))
            .collect()
    } else {
        vec![CreepModel::by_name(&a.model).with_context(|| format!("unknown creep model {}", a.model))?]
    };
    if let Some(out) = a.build_table.clone() {
        return build_table(&out);
    }
    if let Some(points) = a.at.clone() {
        return at_points(a, &points, &models);
    }
    let CreepArgs {
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
        ..
    } = a;
    let required = |v: Option<f64>, flag: &str| {
        v.with_context(|| format!("{flag} is required (the contact ellipse and its load), or --at POINTS.csv for forces at given points"))
    };
    let (normal_force_n, a_mm, b_mm) = (
        required(normal_force_n, "--normal-force-n")?,
        required(a_mm, "--a-mm")?,
        required(b_mm, "--b-mm")?,
    );
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
    let settings = SweepSettings {
        max_creepage,
        points,
        ..SweepSettings::default()
    };
    if models.iter().any(|m| matches!(m, CreepModel::Exact(_))) {
        let spins = inspect::creep::spins(spin).len();
        eprintln!(
            "kecsim: the exact theory at {} points (~{:.0} s; --model polach, fastsim, … alone are instant)",
            settings.count() * (5 + spins),
            settings.count() as f64 * (5 + spins) as f64 * 0.035 / rayon::current_num_threads() as f64
        );
    }
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

/// `kecsim creep --at POINTS.csv [--csv OUT.csv]`: every model asked at every point.
fn at_points(a: CreepArgs, path: &std::path::Path, models: &[CreepModel]) -> Result<()> {
    for (given, flag) in [
        (a.normal_force_n.is_some(), "--normal-force-n"),
        (a.a_mm.is_some(), "--a-mm"),
        (a.b_mm.is_some(), "--b-mm"),
        (a.sink.given(), "--save/--spawn/--connect"),
    ] {
        anyhow::ensure!(
            !given,
            "{flag} with --at: the points file gives each point's load, ellipse and friction, and --at writes a CSV, no recording"
        );
    }
    anyhow::ensure!(
        a.shear_modulus_gpa.is_finite() && a.shear_modulus_gpa > 0.0,
        "--shear-modulus-gpa {}: expected a positive modulus",
        a.shear_modulus_gpa
    );
    anyhow::ensure!(
        (0.0..=0.5).contains(&a.poisson),
        "--poisson {}: expected 0 ..= 0.5",
        a.poisson
    );
    let _outputs = super::guard(&[path], &[("--csv", a.csv.as_deref())], None)?;
    let pts = points::read_points(path)?;
    let table = KalkerTable::new(a.poisson);
    let counter = super::progress::Counter::new(pts.len() as u64, "points");
    let rows = points::evaluate(
        &path.display().to_string(),
        &pts,
        models,
        a.shear_modulus_gpa * 1e9,
        &table,
        &|| counter.tick(),
    );
    counter.finish();
    let rows = rows?;
    match &a.csv {
        Some(out) => {
            let mut w =
                kecsim::files::csv_writer(out).with_context(|| format!("cannot write {}", out.display()))?;
            points::write_forces(&mut w, &rows).with_context(|| format!("cannot write {}", out.display()))?;
            kecsim::files::commit_csv(w).with_context(|| format!("cannot write {}", out.display()))?;
            eprintln!(
                "wrote {} ({} points × {} models)",
                out.display(),
                pts.len(),
                models.len()
            );
        }
        None => {
            let mut w = csv::Writer::from_writer(std::io::stdout().lock());
            points::write_forces(&mut w, &rows)?;
        }
    }
    Ok(())
}

/// `kecsim creep --build-table FILE`.
fn build_table(out: &std::path::Path) -> Result<()> {
    use kecsim::contact::forces::table::{ExactTable, TableSpec};
    let _outputs = super::guard::<&std::path::Path>(&[], &[("--build-table", Some(out))], None)?;
    let spec = TableSpec::default();
    let lines = spec.log_ab.len() * spec.u.len() * spec.theta.len();
    eprintln!(
        "kecsim: solving the exact theory at {} nodes ({} × {} elements, Richardson) on {} threads",
        lines * spec.t.len(),
        spec.elements,
        spec.elements,
        rayon::current_num_threads()
    );
    let counter = super::progress::Counter::new(lines as u64, "node lines");
    let t0 = std::time::Instant::now();
    let table = ExactTable::build(&spec, &|| counter.tick());
    counter.finish();
    let table = table?;
    kecsim::files::write_atomic(out, &table.to_bytes())
        .with_context(|| format!("cannot write {}", out.display()))?;
    println!(
        "wrote {} ({} nodes, {:.0} s)",
        out.display(),
        table.len(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
