//! `kecsim run` of a simulation, **streamed as it runs**: wheelset kinematics, forces, contact
//! positions over time, the cross-sections with the wheels moving, and the track plan with the
//! vehicle's position. [`LiveRecorder`] is a run observer: it sends the samples to the sink in
//! batches (every [`BATCH_WALL`] of wall time to a viewer, every [`BATCH_WALL_FILE`] to an
//! `.rrd` file; as columns, the cross-sections too), so that a viewer connected with
//! `--spawn`/`--connect` shows the run while it is computed; the statics (rails, track plan, series
//! styles) go first, the summary last.
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
//! | `run/NAME/lift_mm` | Scalars (left, right) | each wheel's gap to its rail (0 on it; a lifted wheel) |
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

use std::time::{Duration, Instant};

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, TextDocumentView, TimePanel, TimeSeriesView,
    Vertical,
};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, SeriesLines, TextDocument, TimeColumn};

use super::{log_static, open_recording, section_mm, send_scalar_values, InspectError, Sink};
use crate::dynamics::output::{ObserverError, OutputSample, RunObserver, RunStart};
use crate::dynamics::{RunSummary, Sample};
use crate::profile::Side;
use crate::scenario::Scene;

/// The simulated-time timeline.
pub const TIME: &str = "time";
/// The distance timeline (mm).
pub const DISTANCE: &str = "distance_mm";

/// The layout of a single-wheelset run.
pub fn blueprint() -> Blueprint {
    blueprint_for(&["wheelset_1".to_string()])
}

/// The wheelset the run's detailed views show: the first of `wheelsets`.
fn detail_wheelset(wheelsets: &[String]) -> &str {
    wheelsets.first().map_or("wheelset_1", String::as_str)
}

/// Where the run's detailed views look: the first of `wheelsets` (its series are logged under
/// `run/NAME/`).
pub fn detail_origin(wheelsets: &[String]) -> String {
    format!("/run/{}", detail_wheelset(wheelsets))
}

/// The layout for the run of `wheelsets` (by name): the first wheelset in detail, and with more
/// than one a row with every wheelset side by side.
pub fn blueprint_for(wheelsets: &[String]) -> Blueprint {
    let plot = |title: &str, origin: &str| TimeSeriesView::new(title).with_origin(origin.to_string()).into();
    let w = detail_origin(wheelsets);
    // The detailed views' titles name their wheelset.
    let first = detail_wheelset(wheelsets);
    let title = |t: &str| format!("{first}: {t}");
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
    if wheelsets.len() > 1 {
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
            plot(&title("y [mm]"), &format!("{w}/y_mm")),
            plot(&title("yaw [mrad]"), &format!("{w}/yaw_mrad")),
            plot(&title("z − r0 [mm]"), &format!("{w}/z_mm")),
            plot(&title("roll [mrad]"), &format!("{w}/roll_mrad")),
        ])
        .into(),
    );
    rows.push(
        Horizontal::new([
            plot(&title("normal force [kN]"), &format!("{w}/normal_kn")),
            plot(&title("creep Fx [kN]"), &format!("{w}/creep_fx_kn")),
            plot(&title("creep Fy [kN]"), &format!("{w}/creep_fy_kn")),
            plot(&title("Y/Q"), &format!("{w}/y_over_q")),
        ])
        .into(),
    );
    rows.push(
        Horizontal::new([
            plot(&title("contact on wheel s^w [mm]"), &format!("{w}/s_wheel_mm")),
            plot(&title("contact on rail s^r [mm]"), &format!("{w}/s_rail_mm")),
            plot(&title("KEC contact s^k [mm]"), &format!("{w}/s_knife_mm")),
            plot(&title("wheel lift [mm]"), &format!("{w}/lift_mm")),
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

/// One cross-section snapshot of the first wheelset, waiting for its batch.
struct SectionRow {
    t: f64,
    distance_mm: i64,
    /// The wheels' outlines (left, right), mm in the section's `[Y, −Z]`.
    wheel: [Vec<[f32; 2]>; 2],
    /// The contact points (left, right).
    contact: [[f32; 2]; 2],
    normal_n: [f64; 2],
    /// The wheelset on the track plan (m, `[X, −Y]`), where the track is known.
    plan: Option<[f32; 2]>,
}

/// Sends one entity's cross-section columns, one row per snapshot of `rows`, on `time` and
/// `distance_mm`.
fn send_section_columns<C: IntoIterator<Item = rerun::SerializedComponentColumn>>(
    rec: &RecordingStream,
    entity: &str,
    rows: &[&SectionRow],
    columns: Result<C, rerun::SerializationError>,
) -> Result<(), InspectError> {
    let columns = columns.map_err(|e| log_err(entity)(e.into()))?;
    let timelines = [
        TimeColumn::new_duration_secs(TIME, rows.iter().map(|r| r.t)),
        TimeColumn::new_sequence(DISTANCE, rows.iter().map(|r| r.distance_mm)),
    ];
    rec.send_columns(entity, timelines, columns)
        .map_err(log_err(entity))
}

/// Wall time between two batches of samples sent to a viewer (`--spawn`, `--connect`).
pub const BATCH_WALL: Duration = Duration::from_millis(50);

/// Wall time between two batches written to an `.rrd` file, where nobody watches the run: each
/// batch is a chunk per entity (~75 on the MS vehicle), and a chunk's encoding costs far more
/// than its rows (measured on one core over the MS kilometre: the recording took ~20 % of the
/// wall time with 50 ms batches and row-wise cross-sections).
pub const BATCH_WALL_FILE: Duration = Duration::from_millis(1000);

/// Simulated time between two cross-section snapshots (≤ 50 Hz), s.
const SECTION_INTERVAL_S: f64 = 0.02;

fn palette(k: usize) -> Color {
    const P: [(u8, u8, u8); 8] = [
        (230, 80, 60),
        (60, 140, 230),
        (60, 180, 120),
        (200, 150, 40),
        (150, 90, 200),
        (40, 180, 190),
        (220, 100, 170),
        (120, 120, 120),
    ];
    let (r, g, b) = P[k % P.len()];
    Color::from_rgb(r, g, b)
}

fn lr_colors() -> Vec<Color> {
    vec![Color::from_rgb(230, 120, 40), Color::from_rgb(60, 140, 230)]
}

/// One wheelset's series: entity under `run/NAME/`, line names, value(s) of a sample.
type Series = (&'static str, &'static [&'static str], fn(&Sample) -> Vec<f64>);

/// The per-wheelset series (kinematics, forces, contact positions; `s_knife_mm` apart: KEC only).
const WHEELSET_SERIES: [Series; 11] = [
    ("y_mm", &["y"], |s| vec![s.y * 1e3]),
    ("yaw_mrad", &["yaw"], |s| vec![s.yaw * 1e3]),
    ("z_mm", &["z − r0"], |s| vec![s.z * 1e3]),
    ("roll_mrad", &["roll"], |s| vec![s.roll * 1e3]),
    ("normal_kn", &["left", "right"], |s| {
        vec![s.normal[0] * 1e-3, s.normal[1] * 1e-3]
    }),
    ("creep_fx_kn", &["left", "right"], |s| {
        vec![s.creep_x[0] * 1e-3, s.creep_x[1] * 1e-3]
    }),
    ("creep_fy_kn", &["left", "right"], |s| {
        vec![s.creep_y[0] * 1e-3, s.creep_y[1] * 1e-3]
    }),
    ("y_over_q", &["left", "right"], |s| {
        vec![s.y_force[0] / s.q_force[0], s.y_force[1] / s.q_force[1]]
    }),
    ("s_wheel_mm", &["left", "right"], |s| {
        vec![s.s_wheel[0] * 1e3, s.s_wheel[1] * 1e3]
    }),
    ("s_rail_mm", &["left", "right"], |s| {
        vec![s.s_rail[0] * 1e3, s.s_rail[1] * 1e3]
    }),
    ("lift_mm", &["left", "right"], |s| {
        vec![s.lift[0] * 1e3, s.lift[1] * 1e3]
    }),
];

const KNIFE_SERIES: Series = ("s_knife_mm", &["left", "right"], |s| {
    s.s_knife
        .map_or(vec![f64::NAN; 2], |k| vec![k[0] * 1e3, k[1] * 1e3])
});

/// One every-wheelset series: entity under `run/vehicle/`, the value of a wheelset's sample.
type VehicleSeries = (&'static str, fn(&Sample) -> f64);

/// The every-wheelset series under `run/vehicle/` (one line per wheelset).
const VEHICLE_SERIES: [VehicleSeries; 4] = [
    ("y_mm", |s| s.y * 1e3),
    ("yaw_mrad", |s| s.yaw * 1e3),
    ("min_normal_kn", |s| s.normal[0].min(s.normal[1]) * 1e-3),
    ("max_abs_y_over_q", |s| s.max_abs_y_over_q()),
];

fn log_err(entity: &str) -> impl Fn(rerun::RecordingStreamError) -> InspectError + '_ {
    move |source| InspectError::Log {
        entity: entity.to_string(),
        source,
    }
}

/// The run recorder: a [`RunObserver`] that streams a run to a Rerun sink as it is computed.
pub struct LiveRecorder {
    rec: RecordingStream,
    pair: crate::profile::placement::WheelRailPair,
    track: Option<std::sync::Arc<crate::track::Track>>,
    names: Vec<String>,
    /// Samples not yet sent, per wheelset.
    pending: Vec<Vec<Sample>>,
    last_batch: Instant,
    /// [`BATCH_WALL`] or [`BATCH_WALL_FILE`] by the sink.
    batch_wall: Duration,
    next_section_t: f64,
    /// Cross-section snapshots not yet sent (sent as columns with the samples' batch).
    sections: Vec<SectionRow>,
    /// The wheel profile's points drawn in the cross-section (surface parameters).
    wheel_knots: Vec<f64>,
    knife_styled: Vec<bool>,
    /// Samples sent per wheelset.
    sent: usize,
}

impl LiveRecorder {
    /// Sends what is pending and ends the stream as [`super::finish_recording`] does: the line
    /// saying where the recording went.
    pub fn finish_stream(self, sink: &Sink) -> Result<String, String> {
        super::finish_recording(self.rec, sink)
    }
    /// Opens the recording on `sink` with the run layout for `wheelsets`, and logs the statics
    /// (rails, track plan, series styles): a sink that cannot be opened fails before the run.
    pub fn open(sink: &Sink, scene: &Scene, wheelsets: &[String]) -> Result<LiveRecorder, InspectError> {
        let rec = open_recording("kecsim", sink, || blueprint_for(wheelsets))?;
        let mut r = Self::on(rec, scene, wheelsets)?;
        if matches!(sink, Sink::Save(_)) {
            r.batch_wall = BATCH_WALL_FILE;
        }
        Ok(r)
    }

    /// A recorder on an open stream.
    pub fn on(
        rec: RecordingStream,
        scene: &Scene,
        wheelsets: &[String],
    ) -> Result<LiveRecorder, InspectError> {
        let pair = scene.pair.clone();
        let (knots, _) = pair.wheel.knots();
        let every_knot = (knots.len() / 300).max(1);
        let wheel_knots: Vec<f64> = knots.iter().step_by(every_knot).copied().collect();
        let r = LiveRecorder {
            rec,
            pair,
            track: scene.track.clone(),
            names: wheelsets.to_vec(),
            pending: vec![Vec::new(); wheelsets.len()],
            last_batch: Instant::now(),
            batch_wall: BATCH_WALL,
            next_section_t: f64::NEG_INFINITY,
            sections: Vec::new(),
            wheel_knots,
            knife_styled: vec![false; wheelsets.len()],
            sent: 0,
        };
        r.log_statics()?;
        Ok(r)
    }

    fn log_statics(&self) -> Result<(), InspectError> {
        let green = vec![Color::from_rgb(60, 180, 120)];
        for name in &self.names {
            for (entity, lines, _) in WHEELSET_SERIES {
                let colors = if lines.len() == 1 {
                    green.clone()
                } else {
                    lr_colors()
                };
                log_static(
                    &self.rec,
                    &format!("run/{name}/{entity}"),
                    &SeriesLines::new()
                        .with_names(lines.iter().copied())
                        .with_colors(colors),
                )?;
            }
        }
        if self.names.len() > 1 {
            let colors: Vec<Color> = (0..self.names.len()).map(palette).collect();
            for (entity, _) in VEHICLE_SERIES {
                log_static(
                    &self.rec,
                    &format!("run/vehicle/{entity}"),
                    &SeriesLines::new()
                        .with_names(self.names.iter().map(String::as_str))
                        .with_colors(colors.clone()),
                )?;
            }
        }
        // Cross-sections: static rails (ideal placement).
        for side in Side::BOTH {
            let pts: Vec<[f32; 2]> = self
                .pair
                .rail_positions(side)
                .into_iter()
                .map(|(y, z)| section_mm(y, z))
                .collect();
            log_static(
                &self.rec,
                &format!("run/section/{}/rail", side.name()),
                &LineStrips2D::new([pts])
                    .with_colors([Color::from_rgb(150, 150, 160)])
                    .with_radii([Radius::new_ui_points(1.5)]),
            )?;
        }
        if let Some(track) = &self.track {
            let (a, b) = track.centreline.range();
            let k = ((b - a) / 2.0).ceil().max(1.0) as usize;
            let plan: Vec<[f32; 2]> = (0..=k)
                .filter_map(|i| track.centreline.frame(a + (b - a) * i as f64 / k as f64).ok())
                .map(|f| [f.position.x as f32, -f.position.y as f32])
                .collect();
            log_static(
                &self.rec,
                "run/track/plan",
                &LineStrips2D::new([plan])
                    .with_colors([Color::from_rgb(150, 150, 160)])
                    .with_radii([Radius::new_ui_points(1.5)]),
            )?;
        }
        Ok(())
    }

    /// Sends one series of one wheelset's pending samples as columns on `time` and `distance_mm`.
    fn send_series(&self, name: &str, samples: &[Sample], series: &Series) -> Result<(), InspectError> {
        send_scalar_values(
            &self.rec,
            vec![
                TimeColumn::new_duration_secs(TIME, samples.iter().map(|s| s.t)),
                TimeColumn::new_sequence(DISTANCE, samples.iter().map(|s| (s.s * 1e3).round() as i64)),
            ],
            samples.len(),
            &format!("run/{name}/{}", series.0),
            samples.iter().flat_map(series.2).collect(),
            series.1.len(),
        )
    }

    /// Sends what is pending.
    fn send_batch(&mut self) -> Result<(), InspectError> {
        let n = self.pending.first().map_or(0, Vec::len);
        if n == 0 {
            return Ok(());
        }
        for (k, name) in self.names.iter().enumerate() {
            let samples = &self.pending[k];
            for series in &WHEELSET_SERIES {
                self.send_series(name, samples, series)?;
            }
            if samples.iter().all(|s| s.s_knife.is_some()) {
                if !self.knife_styled[k] {
                    log_static(
                        &self.rec,
                        &format!("run/{name}/{}", KNIFE_SERIES.0),
                        &SeriesLines::new()
                            .with_names(KNIFE_SERIES.1.iter().copied())
                            .with_colors(lr_colors()),
                    )?;
                    self.knife_styled[k] = true;
                }
                self.send_series(name, samples, &KNIFE_SERIES)?;
            }
        }
        if self.names.len() > 1 {
            let first = &self.pending[0];
            for (entity, f) in VEHICLE_SERIES {
                send_scalar_values(
                    &self.rec,
                    vec![TimeColumn::new_duration_secs(TIME, first.iter().map(|s| s.t))],
                    n,
                    &format!("run/vehicle/{entity}"),
                    (0..n)
                        .flat_map(|i| self.pending.iter().map(move |w| f(&w[i])))
                        .collect(),
                    self.names.len(),
                )?;
            }
        }
        self.send_sections()?;
        self.sent += n;
        for p in &mut self.pending {
            p.clear();
        }
        self.last_batch = Instant::now();
        Ok(())
    }

    /// The first wheelset's cross-section (wheels and contact points) and its position on the
    /// track plan, at ≤ 50 Hz of simulated time: kept for the next batch.
    fn log_section(&mut self, s: &Sample) {
        // (With a tolerance: the output times are multiples of the record interval, which
        // rounding would otherwise put just short of the next snapshot's time now and then.)
        if s.t < self.next_section_t - 1e-9 {
            return;
        }
        self.next_section_t = s.t + SECTION_INTERVAL_S;
        let pair = &self.pair;
        let z = s.z + pair.wheelset.nominal_radius_m;
        let wheel = Side::BOTH.map(|side| {
            self.wheel_knots
                .iter()
                .map(|&k| {
                    let (wy, wz) =
                        pair.wheelset
                            .wheel_point(&pair.wheel, side, side.sign() * k, s.y, z, s.roll);
                    section_mm(wy, wz)
                })
                .collect()
        });
        let contact = [0, 1].map(|i| section_mm(s.position[i].0, s.position[i].1));
        let plan = self
            .track
            .as_ref()
            .and_then(|track| track.centreline.frame(s.s).ok())
            .map(|f| [f.position.x as f32, -f.position.y as f32]);
        self.sections.push(SectionRow {
            t: s.t,
            distance_mm: (s.s * 1e3).round() as i64,
            wheel,
            contact,
            normal_n: s.normal,
            plan,
        });
    }

    /// Sends the pending cross-sections as columns on `time` and `distance_mm`: one row per
    /// snapshot of each entity (row by row, each snapshot was a log call of its own: on one core
    /// the recording then cost ~20 % of the MS kilometre's wall time).
    fn send_sections(&mut self) -> Result<(), InspectError> {
        let rows = std::mem::take(&mut self.sections);
        let all: Vec<&SectionRow> = rows.iter().collect();
        let n = all.len();
        if n == 0 {
            return Ok(());
        }
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let wheel = LineStrips2D::new(all.iter().map(|r| r.wheel[i].clone()))
                .with_colors(std::iter::repeat_n(Color::from_rgb(70, 140, 230), n))
                .with_radii(std::iter::repeat_n(Radius::new_ui_points(1.5), n))
                .columns(std::iter::repeat_n(1, n));
            send_section_columns(
                &self.rec,
                &format!("run/section/{}/wheel", side.name()),
                &all,
                wheel,
            )?;
            let contact = Points2D::new(all.iter().map(|r| r.contact[i]))
                .with_colors(std::iter::repeat_n(Color::from_rgb(230, 50, 50), n))
                .with_radii(std::iter::repeat_n(Radius::new_ui_points(5.0), n))
                .with_labels(all.iter().map(|r| format!("{:.1} kN", r.normal_n[i] * 1e-3)))
                .columns(std::iter::repeat_n(1, n));
            send_section_columns(
                &self.rec,
                &format!("run/section/{}/contact", side.name()),
                &all,
                contact,
            )?;
        }
        let placed: Vec<&SectionRow> = rows.iter().filter(|r| r.plan.is_some()).collect();
        if !placed.is_empty() {
            let m = placed.len();
            let position = Points2D::new(placed.iter().filter_map(|r| r.plan))
                .with_colors(std::iter::repeat_n(Color::from_rgb(230, 50, 50), m))
                .with_radii(std::iter::repeat_n(Radius::new_ui_points(6.0), m))
                .columns(std::iter::repeat_n(1, m));
            send_section_columns(&self.rec, "run/track/position", &placed, position)?;
        }
        Ok(())
    }

    /// Sends the rest and the summary document.
    fn log_summary(&mut self, summary: &RunSummary) -> Result<(), InspectError> {
        self.send_batch()?;
        let mut text = format!("# kecsim run: {}\n\n", summary.scene);
        text += &format!(
            "contact model **{}**, creep model **{}**, integrator **{}**\n\n",
            summary.contact_model, summary.creep_model, summary.integrator
        );
        for line in summary.to_string().lines() {
            text += &format!("{line}\n\n");
        }
        log_static(&self.rec, "run/summary", &TextDocument::from_markdown(text))
    }
}

impl RunObserver for LiveRecorder {
    fn start(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        if run.wheelsets != self.names.as_slice() {
            return Err(format!(
                "the recording was opened for wheelsets {:?}, the run has {:?}",
                self.names, run.wheelsets
            )
            .into());
        }
        self.last_batch = Instant::now();
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        for (p, s) in self.pending.iter_mut().zip(sample.wheelsets) {
            p.push(*s);
        }
        if let Some(first) = sample.wheelsets.first() {
            self.log_section(first);
        }
        if self.last_batch.elapsed() >= self.batch_wall {
            self.send_batch()?;
        }
        Ok(())
    }

    fn finish(&mut self, summary: &RunSummary) -> Result<(), ObserverError> {
        Ok(self.log_summary(summary)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The per-wheelset series a recording has: entity under `run/NAME/`, line names, values of
    /// [`Sample::distinct`].
    fn wheelset_series() -> Vec<(String, Vec<String>, Vec<f64>)> {
        let s = Sample::distinct();
        WHEELSET_SERIES
            .iter()
            .chain([&KNIFE_SERIES])
            .map(|(e, lines, f)| {
                (
                    e.to_string(),
                    lines.iter().map(|l| l.to_string()).collect(),
                    f(&s),
                )
            })
            .collect()
    }

    /// The every-wheelset series under `run/vehicle/`: entity, value of [`Sample::distinct`].
    fn vehicle_series() -> Vec<(String, f64)> {
        let s = Sample::distinct();
        VEHICLE_SERIES
            .iter()
            .map(|(e, f)| (e.to_string(), f(&s)))
            .collect()
    }

    fn near(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs().max(1.0))
    }

    /// The recording's series are an interface (entity paths users and scripts look up): pinned
    /// here with their line names and what they record of a sample.
    #[test]
    fn recorded_series_are_pinned() {
        let lr = || vec!["left".to_string(), "right".to_string()];
        let one = |l: &str| vec![l.to_string()];
        let mut pinned: Vec<(String, Vec<String>, Vec<f64>)> = vec![
            ("y_mm".into(), one("y"), vec![2.0]),
            ("yaw_mrad".into(), one("yaw"), vec![-1.5]),
            ("z_mm".into(), one("z − r0"), vec![0.7]),
            ("roll_mrad".into(), one("roll"), vec![0.3]),
            ("normal_kn".into(), lr(), vec![48.0, 52.0]),
            ("creep_fx_kn".into(), lr(), vec![-1.5, 2.5]),
            ("creep_fy_kn".into(), lr(), vec![3.5, -4.5]),
            ("y_over_q".into(), lr(), vec![0.15, -0.16]),
            ("s_wheel_mm".into(), lr(), vec![4.0, -5.0]),
            ("s_rail_mm".into(), lr(), vec![6.0, -7.0]),
            ("s_knife_mm".into(), lr(), vec![8.5, -9.5]),
            ("lift_mm".into(), lr(), vec![0.0, 12.5]),
        ];
        let mut got = wheelset_series();
        pinned.sort_by(|a, b| a.0.cmp(&b.0));
        got.sort_by(|a, b| a.0.cmp(&b.0));
        assert_eq!(got.len(), pinned.len(), "{got:?}");
        for (g, p) in got.iter().zip(&pinned) {
            assert!(g.0 == p.0 && g.1 == p.1 && near(&g.2, &p.2), "{g:?} vs {p:?}");
        }
        let mut vehicle = vehicle_series();
        vehicle.sort_by(|a, b| a.0.cmp(&b.0));
        let pinned = [
            ("max_abs_y_over_q", 0.16),
            ("min_normal_kn", 48.0),
            ("y_mm", 2.0),
            ("yaw_mrad", -1.5),
        ];
        assert_eq!(vehicle.len(), pinned.len(), "{vehicle:?}");
        for (g, p) in vehicle.iter().zip(pinned) {
            assert!(g.0 == p.0 && near(&[g.1], &[p.1]), "{g:?} vs {p:?}");
        }
    }
}
