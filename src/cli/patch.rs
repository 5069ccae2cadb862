//! `kecsim patch`: the contact patches of one wheelset at prescribed lateral shifts, yaw and
//! vertical wheel load — Hertz and the non-Hertzian strip model side by side (the Manchester
//! contact benchmark's set-up).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::forces::{ContactForceSettings, CreepModel, Material};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::nonhertz::sweep::{self, PatchModel, PatchSweepSettings};
use kecsim::contact::nonhertz::StripSettings;
use kecsim::inspect;

use super::{guard_pair, title, PairArgs, SinkArgs};

#[derive(Args)]
pub(super) struct PatchArgs {
    #[command(flatten)]
    pair: PairArgs,
    /// Lateral shifts of the wheelset, mm, comma separated (positive to the left: the right
    /// wheel's flange approaches its rail at negative y).
    #[arg(
        long,
        value_name = "Y1,Y2,…",
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    y_mm: Vec<f64>,
    /// Yaw per mm of shift, mrad (yaw = y × this; the Manchester benchmark: 2.4).
    #[arg(long, value_name = "MRAD", default_value_t = 0.0, allow_hyphen_values = true)]
    yaw_per_mm: f64,
    /// Vertical load on each wheel, N.
    #[arg(long, value_name = "N")]
    load_n: f64,
    /// Patch model: hertz, kp (the strip model), or all.
    #[arg(long, default_value = "all", value_parser = ["hertz", "kp", "all"])]
    model: String,
    /// Creep-force model on each patch's equivalent ellipse (same area and width): fastsim
    /// (Kalker's simplified theory, spin included), polach, kalker, fastrip, exact-table (the exact
    /// theory tabulated), exact (solved: tens of ms a patch).
    #[arg(long, default_value = "fastsim", value_parser = ["kalker", "polach", "fastsim", "fastrip", "exact-table", "exact"])]
    creep: String,
    /// Coefficient of friction.
    #[arg(long, default_value_t = 0.3)]
    mu: f64,
    /// Forward speed, m/s (the creepages do not depend on it; Polach's falling friction does).
    #[arg(long, default_value_t = 2.0)]
    speed_m_s: f64,
    /// Write one row per patch as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    sink: SinkArgs,
}

/// The largest yaw a patch is computed at, mrad (0.05 rad).
const MAX_PATCH_YAW_MRAD: f64 = 50.0;

pub(super) fn run(a: PatchArgs) -> Result<()> {
    let PatchArgs {
        pair,
        y_mm,
        yaw_per_mm,
        load_n,
        model,
        creep,
        mu,
        speed_m_s,
        csv,
        sink,
    } = a;
    let sink = sink.sink();
    let _outputs = guard_pair(&pair, &[("--csv", csv.as_deref())], &sink)?;
    anyhow::ensure!(
        load_n.is_finite() && load_n > 0.0,
        "--load-n {load_n}: expected a positive vertical wheel load in N (a wheel load is 20–125 kN; the Manchester benchmark's 10 kN)"
    );
    if load_n > 1e6 {
        eprintln!("kecsim: warning: --load-n {load_n}: above 1 MN, far beyond a wheel load");
    }
    anyhow::ensure!(
        yaw_per_mm.is_finite() && yaw_per_mm.abs() <= 100.0,
        "--yaw-per-mm {yaw_per_mm}: expected a yaw of at most 100 mrad per mm"
    );
    anyhow::ensure!(
        mu.is_finite() && mu > 0.0 && mu <= 1.5,
        "--mu {mu}: expected a coefficient of friction in (0, 1.5]"
    );
    anyhow::ensure!(
        speed_m_s.is_finite() && speed_m_s > 0.0 && speed_m_s <= 200.0,
        "--speed-m-s {speed_m_s}: expected a forward speed in (0, 200] m/s"
    );
    anyhow::ensure!(
        y_mm.len() <= 10_000,
        "--y-mm: {} shifts; at most 10000",
        y_mm.len()
    );
    for &y in &y_mm {
        anyhow::ensure!(y.is_finite(), "--y-mm {y}: expected a finite shift in mm");
        // The yaw the shift is given (a wheelset in a curve: a few mrad; flange to flange at the
        // Manchester benchmark's 2.4 mrad/mm: 24 mrad).
        let yaw = y * yaw_per_mm;
        anyhow::ensure!(
            yaw.abs() <= MAX_PATCH_YAW_MRAD,
            "--y-mm {y} with --yaw-per-mm {yaw_per_mm}: a yaw of {yaw} mrad; expected |yaw| ≤ {MAX_PATCH_YAW_MRAD} mrad (0.05 rad: beyond it the wheel is across its rail, no contact patch a wheelset meets)"
        );
    }
    let pair = pair.pair()?;
    let geometry = ContactGeometry::with_defaults(pair.clone());
    let (lo, hi) = kecsim::contact::lookup::flange_limits(&geometry, 0.0)?;
    let beyond: Vec<String> = y_mm
        .iter()
        .filter(|&&y| y * 1e-3 < lo - 1e-9 || y * 1e-3 > hi + 1e-9)
        .map(|y| format!("{y}"))
        .collect();
    if !beyond.is_empty() {
        eprintln!(
            "kecsim: warning: --y-mm {}: past the flange's steepest point at {:.3} / {:.3} mm — the wheel is climbing its flange (a prescribed shift there is a quasi-static check, as the Manchester benchmark's 6.5–10 mm; a free wheelset would derail)",
            beyond.join(","),
            lo * 1e3,
            hi * 1e3
        );
    }
    let forces = ContactForceSettings::new(
        CreepModel::by_name(&creep).with_context(|| format!("unknown creep model {creep}"))?,
        mu,
        Material::STEEL,
    )
    .map_err(|p| anyhow::anyhow!(p.join("; ")))?;
    let settings = PatchSweepSettings {
        yaw_per_m: yaw_per_mm,
        load: load_n,
        speed: speed_m_s,
        forces,
        strips: StripSettings::default(),
        window_m: 0.04,
        pitch_rate: None,
    };
    let models: Vec<PatchModel> = if model == "all" {
        PatchModel::ALL.to_vec()
    } else {
        vec![PatchModel::by_name(&model).with_context(|| format!("unknown patch model {model}"))?]
    };
    // A point whose contact cannot be solved is reported and left out; the rest of the sweep is
    // kept (one point at the flange's edge lost the whole sweep).
    let mut shifts = Vec::new();
    let mut failed = Vec::new();
    for &y in &y_mm {
        for &m in &models {
            match sweep::patches_at(&pair, &geometry, y * 1e-3, m, &settings) {
                Ok(s) => shifts.push(s),
                Err(e) => {
                    eprintln!(
                        "kecsim: warning: --y-mm {y} ({} patches): failed, left out of the table{}: {e}",
                        m.name(),
                        if csv.is_some() { " and the CSV" } else { "" }
                    );
                    failed.push(format!("{y} ({})", m.name()));
                }
            }
        }
    }
    anyhow::ensure!(
        !shifts.is_empty(),
        "--y-mm: every point failed ({}); see the warnings above",
        failed.join(", ")
    );
    let summary = sweep::summary_markdown(&title("patch", &pair), &shifts, &settings);
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::patch::blueprint)?;
        inspect::patch::record(&rec, &pair, &shifts, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    if let Some(path) = csv {
        let rows =
            sweep::write_csv(&path, &shifts).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {} ({rows} rows)", path.display());
    }
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
