//! `kecsim run` of a simulation: wheelset kinematics, forces, contact positions over time, the
//! cross-sections with the wheels moving, and the track plan with the vehicle's position.
//!
//! Timelines: `time` (simulated time, a duration) and `distance_mm` (the wheelset's arc length, mm,
//! a sequence).
//!
//! Every wheelset `NAME` of the vehicle (the single-wheelset scenes: `wheelset_1`) has:
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/NAME/{y_mm, yaw_mrad, z_mm, roll_mrad}` | Scalars | kinematics (z − r0) |
//! | `run/NAME/normal_kn` | Scalars (left, right) | normal forces (constraint reactions, Eq. 53) |
//! | `run/NAME/creep_fx_kn`, `creep_fy_kn` | Scalars (left, right) | creep forces, contact frame |
//! | `run/NAME/y_over_q` | Scalars (left, right) | lateral over vertical wheel–rail force |
//! | `run/NAME/s_wheel_mm`, `s_rail_mm` | Scalars (left, right) | contact position on the real wheel and rail |
//! | `run/NAME/s_knife_mm` | Scalars (left, right) | KEC only: contact on the equivalent profiles |
//!
//! With more than one wheelset, every wheelset side by side (one series per wheelset, on `time`):
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/vehicle/{y_mm, yaw_mrad}` | Scalars (one per wheelset) | kinematics of the whole vehicle |
//! | `run/vehicle/min_normal_kn`, `max_abs_y_over_q` | Scalars (one per wheelset) | the smaller wheel load, the larger \|Y/Q\| |
//!
//! and the first wheelset's cross-section and position:
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/section/{left,right}/{rail,wheel,contact}` | LineStrips2D / Points2D | cross-section (mm, `[Y, −Z]`), at ≤ 50 Hz |
//! | `run/track/plan`, `run/track/position` | LineStrips2D static / Points2D | track plan (m, `[X, −Y]`) and the wheelset on it |
//! | `run/summary` | TextDocument | the run summary |

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, TextDocumentView, TimePanel, TimeSeriesView,
    Vertical,
};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument, TimeColumn};

use super::{log_static, section_mm, send_scalar_rows, InspectError};
use crate::dynamics::run::{RunSummary, Sample};
use crate::profile::Side;
use crate::scenario::Scene;

/// The simulated-time timeline.
pub const TIME: &str = "time";
/// The distance timeline (mm).
pub const DISTANCE: &str = "distance_mm";

/// The layout of a single-wheelset run.
pub fn blueprint() -> Blueprint {
    blueprint_for(1)
}

/// The layout for `wheelsets` wheelsets: the first wheelset in detail, and with more than one a
/// row with every wheelset side by side.
pub fn blueprint_for(wheelsets: usize) -> Blueprint {
    let plot = |title: &str, origin: &str| TimeSeriesView::new(title).with_origin(origin.to_string()).into();
    let w = "/run/wheelset_1";
    let mut rows: Vec<ContainerLike> = vec![Horizontal::new([
        Spatial2DView::new("Right wheel and rail (−Y)")
            .with_origin("/run/section/right")
            .into(),
        Spatial2DView::new("Left wheel and rail (+Y)")
            .with_origin("/run/section/left")
            .into(),
        Spatial2DView::new("Track plan [m]")
            .with_origin("/run/track")
            .into(),
    ])
    .into()];
    let mut shares = vec![3.0];
    if wheelsets > 1 {
        rows.push(
            Horizontal::new([
                plot("every wheelset: y [mm]", "/run/vehicle/y_mm"),
                plot("every wheelset: yaw [mrad]", "/run/vehicle/yaw_mrad"),
                plot(
                    "every wheelset: smaller wheel load [kN]",
                    "/run/vehicle/min_normal_kn",
                ),
                plot("every wheelset: larger |Y/Q|", "/run/vehicle/max_abs_y_over_q"),
            ])
            .into(),
        );
        shares.push(2.0);
    }
    rows.push(
        Horizontal::new([
            plot("y [mm]", &format!("{w}/y_mm")),
            plot("yaw [mrad]", &format!("{w}/yaw_mrad")),
            plot("z − r0 [mm]", &format!("{w}/z_mm")),
            plot("roll [mrad]", &format!("{w}/roll_mrad")),
        ])
        .into(),
    );
    rows.push(
        Horizontal::new([
            plot("normal force [kN]", &format!("{w}/normal_kn")),
            plot("creep Fx [kN]", &format!("{w}/creep_fx_kn")),
            plot("creep Fy [kN]", &format!("{w}/creep_fy_kn")),
            plot("Y/Q", &format!("{w}/y_over_q")),
        ])
        .into(),
    );
    rows.push(
        Horizontal::new([
            plot("contact on wheel s^w [mm]", &format!("{w}/s_wheel_mm")),
            plot("contact on rail s^r [mm]", &format!("{w}/s_rail_mm")),
            plot("KEC contact s^k [mm]", &format!("{w}/s_knife_mm")),
            TextDocumentView::new("Summary")
                .with_origin("/run/summary")
                .into(),
        ])
        .into(),
    );
    shares.extend([2.0, 2.0, 2.0]);
    Blueprint::new(Vertical::new(rows).with_row_shares(shares)).with_time_panel(
        TimePanel::new()
            .with_timeline(TIME)
            .with_play_state(rerun::blueprint::components::PlayState::Following),
    )
}

/// Every wheelset side by side under `run/vehicle/…` (one series per wheelset, on `time`).
fn record_vehicle(rec: &RecordingStream, wheelsets: &[(String, Vec<Sample>)]) -> Result<(), InspectError> {
    let n = wheelsets.iter().map(|w| w.1.len()).min().unwrap_or(0);
    let names: Vec<&str> = wheelsets.iter().map(|w| w.0.as_str()).collect();
    let palette = [
        Color::from_rgb(230, 80, 60),
        Color::from_rgb(60, 140, 230),
        Color::from_rgb(60, 180, 120),
        Color::from_rgb(200, 150, 40),
        Color::from_rgb(150, 90, 200),
        Color::from_rgb(40, 180, 190),
        Color::from_rgb(220, 100, 170),
        Color::from_rgb(120, 120, 120),
    ];
    let colors: Vec<Color> = (0..names.len()).map(|k| palette[k % palette.len()]).collect();
    let first = &wheelsets[0].1;
    let series = |entity: &str, f: &dyn Fn(&Sample) -> f64| {
        send_scalar_rows(
            rec,
            vec![TimeColumn::new_duration_secs(
                TIME,
                first[..n].iter().map(|s| s.t),
            )],
            n,
            &format!("run/vehicle/{entity}"),
            (0..n)
                .flat_map(|i| wheelsets.iter().map(move |w| f(&w.1[i])))
                .collect(),
            &names,
            colors.clone(),
        )
    };
    series("y_mm", &|s| s.y * 1e3)?;
    series("yaw_mrad", &|s| s.yaw * 1e3)?;
    series("min_normal_kn", &|s| s.normal[0].min(s.normal[1]) * 1e-3)?;
    series("max_abs_y_over_q", &|s| {
        (s.y_force[0] / s.q_force[0])
            .abs()
            .max((s.y_force[1] / s.q_force[1]).abs())
    })
}

fn lr_colors() -> Vec<Color> {
    vec![Color::from_rgb(230, 120, 40), Color::from_rgb(60, 140, 230)]
}

/// The time series of one wheelset under `run/{name}/…`.
fn record_wheelset(rec: &RecordingStream, name: &str, samples: &[Sample]) -> Result<(), InspectError> {
    let n = samples.len();
    let times = || TimeColumn::new_duration_secs(TIME, samples.iter().map(|s| s.t));
    let dist = || TimeColumn::new_sequence(DISTANCE, samples.iter().map(|s| (s.s * 1e3).round() as i64));
    let w = format!("run/{name}");
    let one = |entity: &str, f: &dyn Fn(&Sample) -> f64, name: &str| {
        send_scalar_rows(
            rec,
            vec![times(), dist()],
            n,
            &format!("{w}/{entity}"),
            samples.iter().map(f).collect(),
            &[name],
            vec![Color::from_rgb(60, 180, 120)],
        )
    };
    one("y_mm", &|s| s.y * 1e3, "y")?;
    one("yaw_mrad", &|s| s.yaw * 1e3, "yaw")?;
    one("z_mm", &|s| s.z * 1e3, "z − r0")?;
    one("roll_mrad", &|s| s.roll * 1e3, "roll")?;
    let two = |entity: &str, f: &dyn Fn(&Sample) -> [f64; 2]| {
        send_scalar_rows(
            rec,
            vec![times(), dist()],
            n,
            &format!("{w}/{entity}"),
            samples.iter().flat_map(f).collect(),
            &["left", "right"],
            lr_colors(),
        )
    };
    two("normal_kn", &|s| [s.normal[0] * 1e-3, s.normal[1] * 1e-3])?;
    two("creep_fx_kn", &|s| [s.creep_x[0] * 1e-3, s.creep_x[1] * 1e-3])?;
    two("creep_fy_kn", &|s| [s.creep_y[0] * 1e-3, s.creep_y[1] * 1e-3])?;
    two("y_over_q", &|s| {
        [s.y_force[0] / s.q_force[0], s.y_force[1] / s.q_force[1]]
    })?;
    two("s_wheel_mm", &|s| [s.s_wheel[0] * 1e3, s.s_wheel[1] * 1e3])?;
    two("s_rail_mm", &|s| [s.s_rail[0] * 1e3, s.s_rail[1] * 1e3])?;
    if samples.iter().all(|s| s.s_knife.is_some()) {
        two("s_knife_mm", &|s| {
            s.s_knife.map_or([f64::NAN; 2], |k| [k[0] * 1e3, k[1] * 1e3])
        })?;
    }

    Ok(())
}

/// Records the samples of a run (every wheelset's time series; the cross-section and the track
/// position of the first wheelset) and its summary.
pub fn record(
    rec: &RecordingStream,
    scene: &Scene,
    wheelsets: &[(String, Vec<Sample>)],
    summary: &RunSummary,
) -> Result<(), InspectError> {
    for (name, samples) in wheelsets {
        record_wheelset(rec, name, samples)?;
    }
    if wheelsets.len() > 1 {
        record_vehicle(rec, wheelsets)?;
    }
    let Some((_, samples)) = wheelsets.first() else {
        return Ok(());
    };
    // Cross-sections: static rails (ideal placement), the wheel and the contact points at ≤ 50 Hz.
    let pair = &scene.pair;
    for side in Side::BOTH {
        let pts: Vec<[f32; 2]> = pair
            .rail_positions(side)
            .into_iter()
            .map(|(y, z)| section_mm(y, z))
            .collect();
        log_static(
            rec,
            &format!("run/section/{}/rail", side.name()),
            &LineStrips2D::new([pts])
                .with_colors([Color::from_rgb(150, 150, 160)])
                .with_radii([Radius::new_ui_points(1.5)]),
        )?;
    }
    let (knots, _) = pair.wheel.knots();
    let every_knot = (knots.len() / 300).max(1);
    let mut next_t = f64::NEG_INFINITY;
    for s in samples {
        if s.t < next_t {
            continue;
        }
        next_t = s.t + 0.02;
        rec.set_duration_secs(TIME, s.t);
        rec.set_time_sequence(DISTANCE, (s.s * 1e3).round() as i64);
        let z = s.z + pair.wheelset.nominal_radius_m;
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let wheel: Vec<[f32; 2]> = knots
                .iter()
                .step_by(every_knot)
                .map(|&k| {
                    let (wy, wz) =
                        pair.wheelset
                            .wheel_point(&pair.wheel, side, side.sign() * k, s.y, z, s.roll);
                    section_mm(wy, wz)
                })
                .collect();
            let e = format!("run/section/{}/wheel", side.name());
            rec.log(
                e.as_str(),
                &LineStrips2D::new([wheel])
                    .with_colors([Color::from_rgb(70, 140, 230)])
                    .with_radii([Radius::new_ui_points(1.5)]),
            )
            .map_err(|source| InspectError::Log {
                entity: e.clone(),
                source,
            })?;
            let e = format!("run/section/{}/contact", side.name());
            let (py, pz) = s.position[i];
            rec.log(
                e.as_str(),
                &Points2D::new([section_mm(py, pz)])
                    .with_colors([Color::from_rgb(230, 50, 50)])
                    .with_radii([Radius::new_ui_points(5.0)])
                    .with_labels([format!("{:.1} kN", s.normal[i] * 1e-3)]),
            )
            .map_err(|source| InspectError::Log {
                entity: e.clone(),
                source,
            })?;
        }
        if let Some(track) = &scene.track {
            if let Ok(f) = track.centreline.frame(s.s) {
                let p = f.position;
                rec.log(
                    "run/track/position",
                    &Points2D::new([[p.x as f32, -p.y as f32]])
                        .with_colors([Color::from_rgb(230, 50, 50)])
                        .with_radii([Radius::new_ui_points(6.0)]),
                )
                .map_err(|source| InspectError::Log {
                    entity: "run/track/position".into(),
                    source,
                })?;
            }
        }
    }
    if let Some(track) = &scene.track {
        let (a, b) = track.centreline.range();
        let k = ((b - a) / 2.0).ceil().max(1.0) as usize;
        let plan: Vec<[f32; 2]> = (0..=k)
            .filter_map(|i| track.centreline.frame(a + (b - a) * i as f64 / k as f64).ok())
            .map(|f| [f.position.x as f32, -f.position.y as f32])
            .collect();
        log_static(
            rec,
            "run/track/plan",
            &LineStrips2D::new([plan])
                .with_colors([Color::from_rgb(150, 150, 160)])
                .with_radii([Radius::new_ui_points(1.5)]),
        )?;
    }
    let mut text = format!("# kecsim run: {}\n\n", summary.scene);
    text += &format!(
        "contact model **{}**, creep model **{}**, integrator **{}**\n\nsimulated {:.3} s in {:.3} s wall — real-time factor **{:.1}** (preprocessing {:.2} s); {} steps, {} rejected, {} right-hand sides\n\nmax |y| {:.3} mm, max |yaw| {:.3} mrad, normal forces {:.1} .. {:.1} kN, max |Y/Q| {:.3}\n",
        summary.contact_model,
        summary.creep_model,
        summary.integrator,
        summary.simulated_s,
        summary.wall_s,
        summary.realtime_factor,
        summary.preprocessing_s,
        summary.steps,
        summary.rejected_steps,
        summary.rhs_evaluations,
        summary.max_abs_y_mm,
        summary.max_abs_yaw_mrad,
        summary.min_normal_n * 1e-3,
        summary.max_normal_n * 1e-3,
        summary.max_abs_y_over_q
    );
    if let Some(e) = &summary.error {
        text += &format!("\n**Stopped early:** {e}\n");
    }
    log_static(rec, "run/summary", &TextDocument::from_markdown(text))?;
    Ok(())
}
