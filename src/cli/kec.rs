//! `kecsim kec`: the knife-edge-equivalent profiles, their kinks, and their accuracy.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::kec::KecModel;
use kecsim::contact::lookup::{LookupTable1, LookupTable2};
use kecsim::contact::report::{kec_error_markdown, kec_irregularity_errors, kec_summary, MeasuredTables};
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
    /// Also measure KEC and every table against the online constraints under gauge variation and
    /// cross level (±10 mm; builds 2-entry tables with 1 mm columns and 0.1 mm columns around each case, a minute).
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
        // Gauge variations between the columns (0.1 mm and 1 mm), so that their interpolation is
        // measured, not their nodes; cross level alone; both together. A case is kept where the
        // wheelset has 1 mm of room either side before flange contact.
        let mut cases: Vec<(f64, f64)> = [-9.55, -4.55, -1.55, -0.45, 0.45, 1.55, 4.55, 9.55]
            .iter()
            .map(|g| (g * 1e-3, 0.0))
            .collect();
        cases.extend([-10.0, -5.0, 5.0, 10.0].iter().map(|c| (0.0, c * 1e-3)));
        cases.extend(
            [(-4.55, 5.0), (4.55, -5.0), (1.55, 5.0), (-1.55, -5.0)]
                .iter()
                .map(|(g, c)| (g * 1e-3, c * 1e-3)),
        );
        let (lo, hi) = table.range();
        let room = |(gv, cl): &(f64, f64)| {
            lo.abs().min(hi) - gv.abs() / 2.0 - table.r0 * cl.abs() / (2.0 * table.l_r)
        };
        let least = cases
            .iter()
            .map(|c| 1e-3 + (lo.abs().min(hi) - room(c)))
            .fold(f64::INFINITY, f64::min);
        cases.retain(|c| room(c) >= 1e-3);
        // A range that leaves no case room measures nothing (an empty table with exit 0 was printed).
        anyhow::ensure!(
            !cases.is_empty(),
            "--accuracy: the table spans {:.3} .. {:.3} mm, which leaves none of the accuracy cases 1 mm of room before its ends; the least needs ±{:.3} mm: give --y-max ≥ {:.3} (or omit it)",
            lo * 1e3,
            hi * 1e3,
            least * 1e3,
            (least * 1e3 * 1000.0).ceil() / 1000.0
        );
        // The columns just cover the cases' gauge variations.
        let reach = cases.iter().map(|c| c.0.abs()).fold(0.0, f64::max);
        let columns = |step: f64| -> Vec<f64> {
            let n = ((reach / 1e-3).ceil() * 1e-3 / step).round().max(1.0) as i64;
            (-n..=n).map(|k| k as f64 * step).collect()
        };
        let stage = super::progress::Stage::new("accuracy: building the gauge columns' tables");
        let table2 = LookupTable2::build(&geom, &columns(1e-3), &settings)?;
        // The 0.1 mm columns only around each case's gv (the four the interpolation reads there).
        let fine_step = 1e-4;
        let mut around: Vec<i64> = cases.iter().map(|c| (c.0 / fine_step).floor() as i64).collect();
        around.sort_unstable();
        around.dedup();
        let fine = around
            .iter()
            .map(|&k| {
                let gvs: Vec<f64> = (k - 1..=k + 2).map(|j| j as f64 * fine_step).collect();
                LookupTable2::build(&geom, &gvs, &settings)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let tables = MeasuredTables {
            table1: &table,
            table2: &table2,
            table2_fine: Some((&fine, fine_step)),
        };
        stage.set(&format!(
            "accuracy: every model against the online constraints, {} cases × 41 positions",
            cases.len()
        ));
        let rows = kec_irregularity_errors(&geom, &model, &tables, &cases, 41).map_err(anyhow::Error::msg)?;
        stage.finish();
        summary += "\nWith irregularities: each model's largest distance from the online approximate constraints, |Δz| [mm] / |Δφ| [mrad] / |Δγ| [°] (the contact angle of either wheel), 41 y per case. `lookup2` reads each wheel from the centred table at its own offset from its own rail (its default, `gauge_entry = \"per_wheel\"`); the gauge columns are `lookup2` with `gauge_entry = \"columns\"` (every 0.1 mm) and the paper's literal 2-entry table `lookup2-paper` (every 1 mm), each column to its own flange climb; the 1-entry table sees only al, vp, cl. All are entered by the rail pair's rigid motion (Eq. 44–46 rederived, `cross_level_entry = \"rotated\"`) but for the last two columns, by Eq. 44–46 as printed:\n\n";
        summary += &kec_error_markdown(&rows, Some(fine_step));
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
