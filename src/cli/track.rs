//! `kecsim track`: the track centreline from its sections, curvature, cant, twist, irregularities.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use kecsim::inspect;

use super::SinkArgs;

#[derive(Args)]
pub(super) struct TrackArgs {
    /// Track file or scenario file (TOML) with a [track] table; omit for the paper's Tab. 6 track.
    file: Option<PathBuf>,
    /// Sampling step along s for the CSV and the recording, m.
    #[arg(long, value_name = "M", default_value_t = 1.0)]
    step: f64,
    /// Write the sampled track as CSV (s_m, x_m, y_m, z_m, heading_rad, cant_rad, curvature_1pm,
    /// al_mm, vp_mm, gv_mm, cl_mm, …).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: TrackArgs) -> Result<()> {
    let TrackArgs {
        file,
        step,
        csv,
        sink,
    } = a;
    let sink = sink.sink();
    let t = std::time::Instant::now();
    let track = match &file {
        Some(path) => kecsim::track::file::read_track(path)?,
        None => kecsim::track::file::tab6()?,
    };
    let build_s = t.elapsed().as_secs_f64();
    // The track file and the irregularity file it names: read, never written.
    let mut inputs: Vec<&std::path::Path> = track.source_files.iter().map(|p| p.as_path()).collect();
    inputs.extend(file.as_deref());
    let _outputs = super::guard(&inputs, &[("--csv", csv.as_deref())], Some(&sink))?;
    let samples = kecsim::track::report::sample(&track, step)?;
    let summary = kecsim::track::report::summary_markdown(&track, &samples);
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::track::blueprint)?;
        inspect::track::record(&rec, &track, &samples, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    println!(
        "track built in {:.3} s; {} samples every {step} m",
        build_s,
        samples.len()
    );
    if let Some(path) = csv {
        kecsim::track::report::write_csv(&samples, &path)?;
        println!("wrote {}", path.display());
    }
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
