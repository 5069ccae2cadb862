//! `kecsim contact`: the contact geometry sweep over y — lookup table, contact jumps, equivalent
//! conicity (EN 15302) — and, on request, the 2-entry table.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::lookup::LookupTable2;
use kecsim::contact::report::ContactReport;
use kecsim::inspect;

use super::{guard_pair, positive_mm, title, PairArgs, SinkArgs, TableArgs};

#[derive(Args)]
pub(super) struct ContactArgs {
    #[command(flatten)]
    pair: PairArgs,
    /// Write the 1-entry lookup table as CSV (one row per tabulated y).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    table: TableArgs,
    /// Also build the 2-entry table (y, gauge variation) and write it as CSV.
    #[arg(long, value_name = "FILE")]
    table2_csv: Option<PathBuf>,
    /// Gauge variations of the 2-entry table: −MAX..MAX, mm.
    #[arg(long, value_name = "MM", default_value_t = 10.0)]
    gv_max: f64,
    /// Gauge-variation step of the 2-entry table, mm.
    #[arg(long, value_name = "MM", default_value_t = 1.0)]
    gv_step: f64,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: ContactArgs) -> Result<()> {
    let ContactArgs {
        pair,
        csv,
        table,
        table2_csv,
        gv_max,
        gv_step,
        sink,
    } = a;
    let sink = sink.sink();
    let _outputs = guard_pair(
        &pair,
        &[("--csv", csv.as_deref()), ("--table2-csv", table2_csv.as_deref())],
        &sink,
    )?;
    if table2_csv.is_none() && (gv_max != 10.0 || gv_step != 1.0) {
        eprintln!(
            "kecsim: warning: --gv-max and --gv-step apply to the 2-entry table: add --table2-csv FILE"
        );
    }
    let gv_grid = match &table2_csv {
        Some(_) => {
            let (gv_max, gv_step) = (
                positive_mm("--gv-max", gv_max)?,
                positive_mm("--gv-step", gv_step)?,
            );
            let n = (gv_max / gv_step).round();
            kecsim::limits::check(
                "gauge variations of the 2-entry table (--gv-max / --gv-step)",
                2.0 * n + 1.0,
                1e3,
                "use a coarser --gv-step",
            )
            .map_err(anyhow::Error::msg)?;
            anyhow::ensure!(
                n >= 1.0,
                "--gv-max {} mm / --gv-step {} mm: fewer than two gauge variations; the 2-entry table needs --gv-step ≤ --gv-max",
                gv_max * 1e3,
                gv_step * 1e3
            );
            let n = n as i64;
            Some((-n..=n).map(|k| k as f64 * gv_step).collect::<Vec<f64>>())
        }
        None => None,
    };
    let pair = pair.pair()?;
    let title = title("contact", &pair);
    let geom = ContactGeometry::with_defaults(pair);
    let settings = table.settings()?;
    super::check_table_range(&geom, &settings)?;
    let report = ContactReport::new(&geom, &settings)?;
    let summary = report.summary(&title);
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::contact::blueprint)?;
        inspect::contact::record(&rec, &geom, &report.table, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    if let Some(path) = csv {
        report
            .table
            .write_csv(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if let (Some(path), Some(gvs)) = (table2_csv, gv_grid) {
        // Each gauge column up to its own flange climb (or ±--y-max).
        let t = std::time::Instant::now();
        let table2 = LookupTable2::build(&geom, &gvs, &settings)?;
        table2
            .write_csv(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!(
            "wrote {} ({} gauge variations, built in {:.1} s)",
            path.display(),
            gvs.len(),
            t.elapsed().as_secs_f64()
        );
    }
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
