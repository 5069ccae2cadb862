//! `kecsim design-wheel`: a wheel profile designed on a rail from a target contact-angle function
//! (the direct conjugate design of [`kecsim::contact::design`]), written as a profile CSV (mm) and
//! recorded beside a reference wheel: profiles, contact points on wheel and rail against y (the
//! paper's Fig. 14), rolling-radius difference, contact angles, conicity, the flange measures.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::design::{design_wheel, jump_check, parse_target, DesignReport};
use kecsim::inspect;
use kecsim::profile::placement::{Inclination, WheelRailPair, WheelsetGeometry};
use kecsim::profile::{Profile, ProfileKind};
use kecsim::track::TrackGauge;

use super::{positive_mm, SinkArgs};

/// The MS vehicle's stand-in wheel's target (the default): `ms-tram` since issue 48 (the first
/// stand-in, `ms-standin`, is `--target assets/designs/ms-standin.toml`).
pub(super) const MS_TRAM_TARGET: &str = include_str!("../../assets/designs/ms-tram.toml");

#[derive(Args)]
pub(super) struct DesignArgs {
    /// Design target (TOML: name, contact_angle points, flange) [default: the MS vehicle's
    /// stand-in wheel, assets/designs/ms-tram.toml].
    #[arg(long, value_name = "FILE")]
    target: Option<PathBuf>,
    /// Rail profile: standard name (54e1, 60e1) or file [default: the target's, else 60e1].
    #[arg(long)]
    rail: Option<String>,
    /// Rail inclination: 1:N or "upright" [default: the target's, else 1:40].
    #[arg(long)]
    inclination: Option<Inclination>,
    /// Track gauge, mm [default: the target's, else 1435].
    #[arg(long)]
    gauge: Option<f64>,
    /// Wheelset back-to-back distance, mm [default: the target's, else 1360].
    #[arg(long)]
    back_to_back: Option<f64>,
    /// Nominal wheel radius at the taping line, mm [default: the target's, else 460].
    #[arg(long)]
    wheel_radius: Option<f64>,
    /// The wheel to compare the design with (standard name or file).
    #[arg(long, default_value = "s1002")]
    reference: String,
    /// Where to write the designed profile (CSV, mm) [default: NAME.csv].
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Largest |y| of the jump check, mm (each gauge column up to its flange-climb limit).
    #[arg(long, value_name = "MM", default_value_t = 10.0)]
    y_check: f64,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: DesignArgs) -> Result<()> {
    let sink = a.sink.sink();
    let (text, origin) = match &a.target {
        Some(p) => (
            kecsim::limits::read_text(p)
                .with_context(|| format!("{}: cannot read the design target", p.display()))?,
            p.display().to_string(),
        ),
        None => (
            MS_TRAM_TARGET.to_string(),
            "<embedded ms-tram target>".to_string(),
        ),
    };
    let (target, placed) = parse_target(&text, &origin).map_err(anyhow::Error::msg)?;
    let rail_spec = a.rail.clone().or(placed.rail).unwrap_or_else(|| "60e1".into());
    let inclination: Inclination = match (a.inclination, &placed.inclination) {
        (Some(i), _) => i,
        (None, Some(t)) => t
            .parse()
            .map_err(|e: String| anyhow::anyhow!("{origin}: inclination: {e}"))?,
        (None, None) => Inclination::one_in(40.0),
    };
    let gauge_mm = a.gauge.or(placed.gauge_mm).unwrap_or(1435.0);
    let b2b_mm = a.back_to_back.or(placed.back_to_back_mm).unwrap_or(1360.0);
    let r0_mm = a.wheel_radius.or(placed.nominal_radius_mm).unwrap_or(460.0);
    let csv = a
        .csv
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.csv", target.name)));
    let mut inputs = vec![Path::new(&rail_spec), Path::new(&a.reference)];
    inputs.extend(a.target.as_deref());
    let _outputs = super::guard(&inputs, &[("--csv", Some(&csv))], Some(&sink))?;
    let y_check = positive_mm("--y-check", a.y_check)?;
    let rail = Profile::resolve(&rail_spec, ProfileKind::Rail)?;
    let reference = Profile::resolve(&a.reference, ProfileKind::Wheel)?;
    let gauge = TrackGauge {
        gauge_m: positive_mm("--gauge", gauge_mm)?,
        ..TrackGauge::default()
    };
    let wheelset = WheelsetGeometry {
        back_to_back_m: positive_mm("--back-to-back", b2b_mm)?,
        nominal_radius_m: positive_mm("--wheel-radius", r0_mm)?,
        ..WheelsetGeometry::default()
    };
    let t = std::time::Instant::now();
    let stage = super::progress::Stage::new("designing the wheel on the rail");
    let design = design_wheel(&rail, inclination, gauge, wheelset, &target)?;
    let design_s = t.elapsed().as_secs_f64();
    stage.set("checking the designed and the reference wheel for contact jumps");
    let pair = WheelRailPair::new(design.profile.clone(), rail.clone(), inclination, gauge, wheelset)?;
    let ref_pair = WheelRailPair::new(reference, rail, inclination, gauge, wheelset)?;
    let checks = jump_check(&pair, y_check)?;
    let ref_checks = jump_check(&ref_pair, y_check)?;
    let report = DesignReport::new(&design, &pair, &ref_pair, &checks, &ref_checks, design_s)?;
    stage.finish();
    let summary = report.markdown(&inclination.to_string());
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::design::blueprint)?;
        inspect::design::record(&rec, &report, &pair, &ref_pair, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    kecsim::profile::io::write_csv_with_header(
        &design.profile,
        &csv,
        &report.header_lines(&inclination.to_string(), &pair),
    )
    .with_context(|| format!("cannot write {}", csv.display()))?;
    println!("wrote {}", csv.display());
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
