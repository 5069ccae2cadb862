//! `kecsim kec`: the knife-edge-equivalent profiles, their kinks, and their accuracy.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::kec::KecModel;
use kecsim::contact::lookup::{LookupTable1, LookupTable2};
use kecsim::contact::report::{kec_error_markdown, kec_irregularity_errors, kec_summary};
use kecsim::inspect;

use super::{guard_pair, title, PairArgs, SinkArgs, TableArgs};

#[derive(Args)]
pub(super) struct KecArgs {
    #[command(flatten)]
    pair: PairArgs,
    /// Write the equivalent profiles as CSV (one row per tabulated y).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    table: TableArgs,
    /// Also measure KEC against the online constraints and the tables under gauge variation and
    /// cross level (±10 mm; builds a 2-entry table, some seconds).
    #[arg(long)]
    accuracy: bool,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: KecArgs) -> Result<()> {
    let KecArgs {
        pair,
        csv,
        table,
        accuracy,
        sink,
    } = a;
    let sink = sink.sink();
    let _outputs = guard_pair(&pair, &[("--csv", csv.as_deref())], &sink)?;
    let pair = pair.pair()?;
    let title = title("kec", &pair);
    let l_w = pair.wheelset.l_w();
    let geom = ContactGeometry::with_defaults(pair);
    let settings = table.settings()?;
    super::check_table_range(&geom, &settings)?;
    let table = LookupTable1::build(&geom, &settings)?;
    let model = KecModel::from_table(&table, l_w)?;
    let mut summary = kec_summary(&title, &geom, &table, &model).map_err(anyhow::Error::msg)?;
    if accuracy {
        let gvs: Vec<f64> = (-10..=10).map(|k| k as f64 * 1e-3).collect();
        let table2 = LookupTable2::build(&geom, &gvs, &settings)?;
        // Gauge variations between the 2-entry table's 1 mm columns, so that its
        // interpolation is measured, not its nodes.
        let mut cases: Vec<(f64, f64)> = [-9.5, -4.5, -1.5, 1.5, 4.5, 9.5]
            .iter()
            .map(|g| (g * 1e-3, 0.0))
            .collect();
        cases.extend([-10.0, -5.0, 5.0, 10.0].iter().map(|c| (0.0, c * 1e-3)));
        let rows = kec_irregularity_errors(&geom, &model, &table, &table2, &cases, 41)
            .map_err(anyhow::Error::msg)?;
        summary += "\nWith irregularities (max error against the online approximate constraints, 41 y per case; 2-entry table gv step 1 mm, each gauge column to its own flange climb; the 1-entry table sees only al, vp, cl; the tables entered by the rail pair's rigid motion — Eq. 44–46 rederived, cross_level_entry = \"rotated\" — and, in the last two columns, by Eq. 44–46 as printed, cross_level_entry = \"paper\"):\n\n";
        summary += &kec_error_markdown(&rows);
    }
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::kec::blueprint)?;
        inspect::kec::record(&rec, &geom.pair, &table, &model, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    if let Some(path) = csv {
        model
            .write_csv(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
