//! `kecsim run` of a simulation, **streamed as it runs**: wheelset kinematics, forces, contact
//! positions over time, the cross-sections with the wheels moving, and the track plan with the
//! vehicle's position. [`LiveRecorder`] is a run observer: it sends the samples to the sink in
//! batches (every [`BATCH_WALL`] of wall time to a viewer, every [`BATCH_WALL_FILE`] to an
//! `.rrd` file; as columns, the cross-sections too), so that a viewer connected with
//! `--spawn`/`--connect` shows the run while it is computed; the statics (rails, track plan, series
//! styles) go first, the summary last.
//!
//! Timelines: `time` (simulated time, a duration) and `distance_mm` (the wheelset's arc length, mm,
//! a sequence; the front wheelset's for the every-wheelset and the vehicle's own series, and for
//! the track strip): every history can be read against the distance along the track.
//!
//! The series, their line names and the plots of the layout are made from the table of recorded
//! quantities ([`crate::dynamics::sample::QUANTITIES`]; the tables below are what it gives). Every
//! wheelset `NAME` of the vehicle (the single-wheelset scenes: `wheelset_1`) has:
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
//!
//! and the 3D view of the vehicle on its track, `run/world/**` ([`super::world3d`]), the
//! running bands on both rails, `run/bands/**` ([`super::bands`]), the shakedown map and the
//! ride comfort at the carbodies' floor points, `run/shakedown/**`, `run/comfort/**`
//! ([`super::assessment`]). The wear number, its 2 m mean and p0 per wheel are the table's
//! series `run/NAME/{tgamma_n, tgamma_2m_n, p0_mpa}`.

use std::time::{Duration, Instant};

use super::layout::{PlayState, SentLayout};
use super::{Container, Item, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, SeriesLines, TextDocument, TimeColumn};

use super::assessment;
use super::bands::RunningBands;
use super::world3d::{World3d, World3dSettings};
use super::{
    log_static, open_recording_with, section_mm, send_scalar_rows, send_scalar_values, InspectError, Sink,
};
use crate::dynamics::output::{ObserverError, OutputSample, RunObserver, RunStart};
use crate::dynamics::sample::{Panel, Quantity, Sample, Series, QUANTITIES, WHEELS};
use crate::dynamics::RunSummary;
use crate::profile::Side;
use crate::scenario::Scene;
use crate::vehicle::spec::VehicleSpec;

/// The simulated-time timeline.
pub const TIME: &str = "time";
/// The distance timeline (mm).
pub const DISTANCE: &str = "distance_mm";

/// The wheelset the run's detailed views show: the first of `wheelsets`.
fn detail_wheelset(wheelsets: &[String]) -> &str {
    wheelsets.first().map_or("wheelset_1", String::as_str)
}

/// Where the run's detailed views look: the first of `wheelsets` (its series are logged under
/// `run/NAME/`).
pub fn detail_origin(wheelsets: &[String]) -> String {
    format!("/run/{}", detail_wheelset(wheelsets))
}

/// One plot of the run's layout: its title and the entity it shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plot {
    pub title: String,
    pub origin: String,
}

/// The per-wheelset series of `table` (recorded under `run/NAME/`), in its order.
fn wheelset_series(table: &'static [Quantity]) -> impl Iterator<Item = (&'static Quantity, &'static Series)> {
    table
        .iter()
        .filter_map(|q| q.series.as_ref().filter(|s| s.panel.is_some()).map(|s| (q, s)))
}

/// The every-wheelset series of `table` (recorded under `run/vehicle/` with more than one
/// wheelset), in its order.
fn vehicle_series(table: &'static [Quantity]) -> impl Iterator<Item = (&'static Quantity, &'static Series)> {
    table
        .iter()
        .filter_map(|q| q.series.as_ref().filter(|s| s.vehicle).map(|s| (q, s)))
}

/// The vehicle's own series of `table` (recorded once under `run/vehicle/`), in its order.
fn once_series(table: &'static [Quantity]) -> impl Iterator<Item = (&'static Quantity, &'static Series)> {
    table
        .iter()
        .filter_map(|q| q.series.as_ref().filter(|s| s.once).map(|s| (q, s)))
}

/// The line names of a per-wheelset series: its title for one value, else the wheels.
fn line_names(q: &Quantity, series: &Series) -> Vec<&'static str> {
    match q.value.width() {
        1 => vec![series.title],
        _ => WHEELS.to_vec(),
    }
}

/// One wheelset's plots, a row per [`Panel`] that has series, made from `table`: their titles
/// name the wheelset.
pub fn detail_rows(table: &'static [Quantity], wheelset: &str) -> Vec<(Panel, Vec<Plot>)> {
    Panel::ALL
        .into_iter()
        .filter_map(|panel| {
            let row: Vec<Plot> = wheelset_series(table)
                .filter(|(_, s)| s.panel == Some(panel))
                .map(|(_, s)| Plot {
                    title: format!("{wheelset}: {}", s.title()),
                    origin: format!("/run/{wheelset}/{}", s.entity()),
                })
                .collect();
            (!row.is_empty()).then_some((panel, row))
        })
        .collect()
}

/// The plots of the whole vehicle made from `table`: every wheelset side by side (its
/// [`Series::vehicle`] series, with more than one wheelset), then the vehicle's own series
/// ([`Series::once`]).
pub fn vehicle_plots(table: &'static [Quantity], wheelsets: &[String]) -> Vec<Plot> {
    let mut vehicle: Vec<Plot> = Vec::new();
    if wheelsets.len() > 1 {
        vehicle.extend(vehicle_series(table).map(|(_, s)| Plot {
            title: format!("every wheelset: {}", s.title()),
            origin: format!("/run/vehicle/{}", s.entity()),
        }));
    }
    vehicle.extend(once_series(table).map(|(_, s)| Plot {
        title: format!("vehicle: {}", s.title()),
        origin: format!("/run/vehicle/{}", s.entity()),
    }));
    vehicle
}

/// The time-series plots of the run, row by row, made from `table`: the [`vehicle_plots`], then
/// the first wheelset's [`detail_rows`]. (The layout places them in its tabs; every other
/// wheelset has the same detail rows.)
pub fn plot_rows(table: &'static [Quantity], wheelsets: &[String]) -> Vec<Vec<Plot>> {
    let mut rows = Vec::new();
    let vehicle = vehicle_plots(table, wheelsets);
    if !vehicle.is_empty() {
        rows.push(vehicle);
    }
    rows.extend(
        detail_rows(table, detail_wheelset(wheelsets))
            .into_iter()
            .map(|(_, r)| r),
    );
    rows
}

/// The running bands' track unit for `scene`'s run ([`RunningBands::unit_for`] the distance it
/// covers; 0 m without a simulation).
fn band_unit(scene: &Scene) -> f64 {
    RunningBands::unit_for(band_distance(scene))
}

/// The distance the scene's run is to cover, m (its speed and ramp over its duration).
fn band_distance(scene: &Scene) -> f64 {
    scene.simulation.as_ref().map_or(0.0, |(sim, _)| {
        let t = sim.duration_s;
        (sim.speed_m_s * t + 0.5 * sim.speed_ramp_m_s2 * t * t)
            .max(sim.speed_m_s * t)
            .max(0.0)
    })
}

/// The layout for the run of `wheelsets` (by name) with the default 3D view
/// ([`blueprint_with`]).
pub fn blueprint_for(wheelsets: &[String]) -> Layout {
    blueprint_with(
        wheelsets,
        &World3dSettings::default(),
        1.0,
        false,
        &Cameras::default(),
        RunTab::Overview,
    )
}

/// A time-series view of `plot` with a legend of `lines` lines (its y range, set at the end of the
/// run, makes room for it above the data), hidden where one line is named by the title.
fn series_view(plot: Plot, lines: usize) -> Item {
    let v = View::time_series(plot.title).origin(plot.origin);
    if lines > 1 {
        v.legend_rows(lines).into()
    } else {
        v.no_legend().into()
    }
}

/// The number of lines of the series plotted at `origin` (`/run/NAME/ENTITY`).
fn lines(table: &'static [Quantity], origin: &str) -> usize {
    wheelset_series(table)
        .filter(|(_, s)| origin.ends_with(&format!("/{}", s.entity())))
        .map(|(q, _)| q.value.width())
        .max()
        .unwrap_or(1)
}

/// The name of the tab container holding every wheelset's plots of `panel` (the recorder puts the
/// worst wheelset's tab first at the end of the run).
pub fn wheelset_tabs_name(panel: Panel) -> String {
    format!("wheelsets: {panel:?}").to_lowercase()
}

/// Every wheelset's plots of `panels` as tabs, one per wheelset (its name the tab's title).
fn wheelset_tabs(wheelsets: &[String], panels: &[Panel], name: String) -> Item {
    Container::tabs(wheelsets.iter().map(|w| {
        let rows: Vec<Item> = detail_rows(QUANTITIES, w)
            .into_iter()
            .filter(|(p, _)| panels.contains(p))
            .map(|(_, row)| {
                Container::horizontal(
                    row.into_iter()
                        .map(|p| {
                            let n = lines(QUANTITIES, &p.origin);
                            series_view(p, n)
                        })
                        .collect::<Vec<_>>(),
                )
                .into()
            })
            .collect();
        Container::vertical(rows).named(w.clone()).into()
    }))
    .named(name)
    .into()
}

/// The track strip's share of a tab's height: ~200 px of a 1000 px window, so that its y axes
/// carry three labels (the viewer labels at decade steps with room between labels; at ~130 px the
/// cant strip showed "0" alone).
const TRACK_STRIP_SHARE: f32 = 1.0;

/// The track under the front wheelset along the same x axis as the histories: its horizontal
/// curvature and its cant (where on the track a history's feature happens).
fn track_strip() -> Item {
    Container::horizontal([
        View::time_series("track: curvature [1/km]")
            .origin("/run/track/curvature_1pkm")
            .no_legend()
            .into(),
        View::time_series("track: cant [mrad]")
            .origin("/run/track/cant_mrad")
            .no_legend()
            .into(),
    ])
    .into()
}

/// The 3D views' cameras, from the vehicle's wheelsets along it: the front bogie (the first two
/// wheelsets) close up, and the whole vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cameras {
    /// The front bogie's centre along the track from the front wheelset, m (negative: behind).
    pub bogie_x_m: f64,
    /// The vehicle's middle from the front wheelset, m.
    pub middle_x_m: f64,
    /// Its length between the outer wheelsets, m.
    pub length_m: f64,
    /// The wheel radius, m.
    pub r0_m: f64,
}

impl Default for Cameras {
    fn default() -> Cameras {
        Cameras {
            bogie_x_m: 0.0,
            middle_x_m: 0.0,
            length_m: 0.0,
            r0_m: 0.45,
        }
    }
}

impl Cameras {
    /// The cameras for `scene`'s vehicle (the front wheelset the first; its followers behind).
    pub fn for_scene(scene: &Scene) -> Cameras {
        let r0_m = scene.pair.wheelset.nominal_radius_m;
        let xs: Vec<f64> = match scene.simulation.as_ref().map(|(_, v)| v) {
            Some(VehicleSpec::Multibody(m)) => m.wheelsets.iter().map(|w| w.x_m).collect(),
            _ => Vec::new(),
        };
        let Some(&front) = xs.first() else {
            return Cameras {
                r0_m,
                ..Cameras::default()
            };
        };
        // Along the track from the front wheelset: the others are behind it (negative).
        let rel: Vec<f64> = xs.iter().map(|&x| -(x - front).abs()).collect();
        let (lo, hi) = rel
            .iter()
            .fold((0.0f64, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        Cameras {
            bogie_x_m: 0.5 * (rel[0] + rel.get(1).copied().unwrap_or(rel[0])),
            middle_x_m: 0.5 * (lo + hi),
            length_m: hi - lo,
            r0_m,
        }
    }

    /// The close view: the front bogie from ahead and to the right, wheels, contact points and
    /// force arrows readable.
    fn bogie(&self, view: View) -> View {
        let (x, z) = (self.bogie_x_m as f32, self.r0_m as f32);
        view.eye([x + 3.2, -3.4, z + 1.7], [x, 0.0, z])
    }

    /// The whole vehicle from its side, a little above.
    fn train(&self, view: View) -> View {
        let l = (self.length_m as f32).max(4.0);
        let x = self.middle_x_m as f32;
        view.eye([x + 0.3 * l, -0.85 * l, 0.35 * l], [x, 0.0, 1.2])
    }
}

/// The tabs of the run's layout, in their order (`kecsim run --tab`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum RunTab {
    /// The vehicle in 3D, the track plan, the summary with the running safety.
    #[default]
    Overview,
    /// Every wheelset's kinematics and contact positions.
    Wheelsets,
    /// Running safety, wheel loads, traction, every wheelset's forces.
    Forces,
    /// Shakedown, wear, running bands, p0 and the wear number.
    Wear,
    /// The carbodies' floor accelerations and comfort (a vehicle with carbodies).
    Comfort,
}

/// The layout for the run of `wheelsets` (by name), in tabs that each fit a 1600×1000 screen:
/// * **overview**: the front bogie in 3D (close) and the whole vehicle (`world`'s exaggeration,
///   see [`super::world3d`]), the track plan with the vehicle on it, the summary with the running
///   safety, the front wheelset's cross-sections and the track's curvature and cant;
/// * **wheelsets**: every wheelset's y and yaw side by side, then each wheelset's kinematics and
///   contact positions in a tab of its own (the worst wheelset's first once the run has found
///   it);
/// * **forces and safety**: the running-safety series with their limits (`run/safety/`), the
///   smaller wheel load and larger |Y/Q| of every wheelset, the vehicle's speed and traction, and
///   each wheelset's forces;
/// * **wear and stress**: the shakedown map, the most worn wheel's wear, the running bands (the
///   track in units of `band_unit_m`) and each wheelset's p0 and wear number;
/// * **comfort** (`comfort`: where the vehicle has carbodies): the floor points' accelerations.
///
/// Every history tab ends with the track's curvature and cant on the same x axis.
pub fn blueprint_with(
    wheelsets: &[String],
    world: &World3dSettings,
    band_unit_m: f64,
    comfort: bool,
    cameras: &Cameras,
    first: RunTab,
) -> Layout {
    let world_view = |title: String| {
        View::spatial3d(title)
            .origin("/run/world/follow")
            .contents(["/run/world/**"])
    };
    let overview = Container::horizontal([
        Container::vertical([
            cameras
                .bogie(world_view(format!("Front bogie: {}", World3d::title(world))))
                .into(),
            Container::horizontal([
                cameras
                    .train(world_view("The whole vehicle on its track".to_string()))
                    .into(),
                View::spatial2d("Track plan [m] and the front wheelset (red)")
                    .origin("/run/track")
                    .contents(["/run/track/plan", "/run/track/position", "/run/track/scale"])
                    .into(),
            ])
            .shares([1.6, 1.0])
            .into(),
        ])
        .shares([1.6, 1.0])
        .into(),
        Container::vertical([
            View::text_document("Summary and running safety")
                .origin("/run/summary")
                .into(),
            Container::horizontal([
                View::spatial2d("front wheelset, right [mm]")
                    .origin("/run/section/right")
                    .into(),
                View::spatial2d("… left [mm]").origin("/run/section/left").into(),
            ])
            .into(),
            track_strip(),
        ])
        .shares([2.0, 1.2, 1.2])
        .into(),
    ])
    .shares([1.5, 1.0])
    .named("Overview");

    let vehicle = vehicle_plots(QUANTITIES, wheelsets);
    // The plots of `entities`. A line per wheelset: one legend in the tab (`legend` names the
    // view holding it, the first here or one above), the others' titles say their colours are
    // as there — a legend of six lines covered most of a plot a row high; the vehicle's own, one
    // line: none.
    let take = |entities: &[&str], legend: &str| -> Vec<Item> {
        let mut shown = false;
        vehicle
            .iter()
            .filter(|p| entities.iter().any(|e| p.origin.ends_with(&format!("/{e}"))))
            .map(|p| {
                if !p.title.starts_with("every wheelset:") {
                    return series_view(p.clone(), 1);
                }
                if legend.is_empty() && !shown {
                    shown = true;
                    return series_view(p.clone(), wheelsets.len());
                }
                let mut p = p.clone();
                p.title = format!(
                    "{}, coloured as {}",
                    p.title,
                    if legend.is_empty() { "left" } else { legend }
                );
                series_view(p, 1)
            })
            .collect()
    };
    // Each tab a column of (row, share); a row without plots (a one-wheelset vehicle's
    // every-wheelset row) left out.
    let stack = |rows: Vec<(Vec<Item>, f32)>, name: &str| {
        let (items, shares): (Vec<Item>, Vec<f32>) = rows
            .into_iter()
            .filter(|(r, _)| !r.is_empty())
            .map(|(mut r, share)| {
                let item = if r.len() == 1 {
                    r.remove(0)
                } else {
                    Container::horizontal(r).into()
                };
                (item, share)
            })
            .unzip();
        Container::vertical(items).shares(shares).named(name)
    };
    let kinematics = stack(
        vec![
            (take(&["y_mm", "yaw_mrad"], ""), 1.0),
            (
                vec![wheelset_tabs(
                    wheelsets,
                    &[Panel::Kinematics, Panel::Contact],
                    wheelset_tabs_name(Panel::Kinematics),
                )],
                2.0,
            ),
            (vec![track_strip()], TRACK_STRIP_SHARE),
        ],
        "Wheelsets",
    );
    let safety = stack(
        vec![
            (
                vec![
                    View::time_series("running safety: Y/Q, 2 m mean, larger wheel (grey: Nadal's limit)")
                        .origin("/run/safety/y_over_q_2m")
                        .legend_rows(wheelsets.len() + 1)
                        .into(),
                    // One legend for the row (it hid ΣY's data): the wheelsets keep their colours.
                    View::time_series("ΣY, 2 m mean [kN], colours as left (grey: ± Prud'homme's smallest)")
                        .origin("/run/safety/sum_y_2m_kn")
                        .no_legend()
                        .into(),
                    View::time_series("ΔQ/Q₀, larger wheel, coloured as left (grey: 0.6, EN 14363's limit)")
                        .origin("/run/safety/delta_q_over_q0")
                        .no_legend()
                        .into(),
                ],
                1.2,
            ),
            (
                take(
                    &[
                        "min_normal_kn",
                        "max_abs_y_over_q",
                        "vehicle_speed_m_s",
                        "traction_kn",
                        "traction_power_kw",
                    ],
                    "Y/Q's",
                ),
                1.0,
            ),
            (
                vec![wheelset_tabs(
                    wheelsets,
                    &[Panel::Forces],
                    wheelset_tabs_name(Panel::Forces),
                )],
                1.0,
            ),
            (vec![track_strip()], TRACK_STRIP_SHARE),
        ],
        "Forces and safety",
    );

    let wear = Container::vertical([
        // The map as wide as the two wear charts together.
        Container::horizontal([
            View::spatial2d(
                "Shakedown map (R260): p0/k against μ, every contact, wheelsets coloured as in Forces and safety",
            )
            .origin("/run/shakedown")
            .bounds(assessment::SHAKEDOWN_BOUNDS.0, assessment::SHAKEDOWN_BOUNDS.1)
            .into(),
            View::bar_chart("Most worn wheel: wear [mg] in 2 mm of the wheel profile s^w [mm]")
                .origin("/run/wear/wheel/most_worn")
                .no_legend()
                .into(),
            View::bar_chart("… and of the rail profile s^r [mm]")
                .origin("/run/wear/rail/most_worn")
                .no_legend()
                .into(),
        ])
        .shares([2.0, 1.0, 1.0])
        .into(),
        Container::horizontal([
            View::spatial2d(RunningBands::title("left", band_unit_m))
                .origin("/run/bands/left")
                .into(),
            View::spatial2d(RunningBands::title("right", band_unit_m))
                .origin("/run/bands/right")
                .into(),
        ])
        .into(),
        wheelset_tabs(wheelsets, &[Panel::Wear], wheelset_tabs_name(Panel::Wear)),
        track_strip(),
    ])
    .shares([1.3, 1.0, 1.1, 0.6])
    .named("Wear and stress");

    let mut tabs: Vec<Item> = vec![overview.into(), kinematics.into(), safety.into(), wear.into()];
    if comfort {
        let views: Vec<Item> = assessment::COMFORT_SERIES
            .iter()
            .map(|(stem, title)| {
                // A line per floor point (the MS: seven; more than six take half the plot).
                View::time_series(format!("every floor point: {title}"))
                    .origin(format!("/run/comfort/{stem}"))
                    .legend_rows(7)
                    .into()
            })
            .collect();
        tabs.push(
            Container::vertical([Container::grid(2, views).into(), track_strip()])
                .shares([4.0, 1.2])
                .named("Comfort")
                .into(),
        );
    }
    let first = (first as usize).min(tabs.len() - 1);
    Layout::new(Container::tabs(tabs).active(first))
        .timeline(TIME)
        .play_state(PlayState::Following)
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

/// The running-safety verdict at the head of the recorded summary: each figure's worst wheelset
/// against its limit, within or over it (nothing without safety figures).
pub fn safety_verdict(summary: &RunSummary) -> String {
    let Some(safety) = &summary.safety else {
        return String::new();
    };
    let worst = |f: &dyn Fn(&crate::dynamics::safety::WheelsetSafety) -> f64| {
        safety
            .wheelsets
            .iter()
            .map(|w| (w.name.as_str(), f(w)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    };
    let mut lines = Vec::new();
    let mut over = false;
    let mut line = |what: &str, (name, value): (&str, f64), limit: f64, unit: &str, scale: f64| {
        let ok = value <= limit;
        over |= !ok;
        lines.push(format!(
            "- {what}: **{:.3}{unit}** ({name}) {} {:.3}{unit} — {}",
            value * scale,
            if ok { "≤" } else { ">" },
            limit * scale,
            if ok { "within" } else { "**OVER THE LIMIT**" }
        ));
    };
    if let Some(w) = worst(&|w| w.y_over_q_2m) {
        line("Y/Q, 2 m mean (Nadal)", w, safety.nadal_limit, "", 1.0);
    }
    if let Some(w) = worst(&|w| w.sum_y_2m_n / w.prudhomme_limit_n) {
        let limit = safety
            .wheelsets
            .iter()
            .find(|x| x.name == w.0)
            .map_or(1.0, |x| x.prudhomme_limit_n);
        line(
            "ΣY, 2 m mean (Prud'homme)",
            (w.0, w.1 * limit),
            limit,
            " kN",
            1e-3,
        );
    }
    if let Some(w) = worst(&|w| w.delta_q_over_q0) {
        line("ΔQ/Q₀ (EN 14363)", w, DELTA_Q_LIMIT, "", 1.0);
    }
    format!(
        "## Running safety: {}\n\n{}\n\n",
        if over {
            "**a limit is exceeded**"
        } else {
            "within every limit"
        },
        lines.join("\n")
    )
}

/// The limit of a wheel's unloading ΔQ/Q₀ drawn with its series (the summary holds the figures
/// against it).
pub use crate::dynamics::safety::DELTA_Q_LIMIT;

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
    /// The entities of series that not every sample has ([`Value::WheelsWhereGiven`]), styled
    /// when first sent.
    ///
    /// [`Value::WheelsWhereGiven`]: crate::dynamics::sample::Value::WheelsWhereGiven
    styled: std::collections::HashSet<String>,
    /// Samples sent per wheelset.
    sent: usize,
    /// The 3D view's frames.
    world: World3d,
    /// The running bands' batches.
    bands: RunningBands,
    /// Per wheelset: its wheels' contacts on the shakedown map, drawn ([`assessment`]).
    shakedown: Vec<Vec<[f32; 2]>>,
    /// The carbodies' floor points, the sample times and each point's accelerations.
    floor_points: Vec<crate::dynamics::system::FloorPoint>,
    floor_t: Vec<f64>,
    floor_acc: Vec<Vec<[f64; 3]>>,
    /// The layout as sent (None: a stream opened elsewhere), to put the worst wheelset first.
    layout: Option<SentLayout>,
    /// Per wheelset: each sample's time, arc length and both wheels' Y and Q (the running-safety
    /// series, drawn at the end).
    forces: Vec<Vec<SafetyRow>>,
    /// Each plot's data extent (by its view's origin), for the y ranges set at the end.
    extents: std::sync::Mutex<std::collections::HashMap<String, [f64; 2]>>,
}

/// What the running-safety series need of a sample.
#[derive(Debug, Clone, Copy)]
struct SafetyRow {
    t: f64,
    s: f64,
    y: [f64; 2],
    q: [f64; 2],
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
        Self::open_with(sink, scene, wheelsets, &World3dSettings::default())
    }

    /// [`Self::open`] with the 3D view's settings (the command line's `--exaggerate`).
    pub fn open_with(
        sink: &Sink,
        scene: &Scene,
        wheelsets: &[String],
        world: &World3dSettings,
    ) -> Result<LiveRecorder, InspectError> {
        Self::open_on(sink, scene, wheelsets, world, RunTab::Overview)
    }

    /// [`Self::open_with`], the layout opening on the tab `first` (the command line's `--tab`).
    pub fn open_on(
        sink: &Sink,
        scene: &Scene,
        wheelsets: &[String],
        world: &World3dSettings,
        first: RunTab,
    ) -> Result<LiveRecorder, InspectError> {
        let unit = band_unit(scene);
        let comfort =
            matches!(&scene.simulation, Some((_, VehicleSpec::Multibody(m))) if !m.carbodies().is_empty());
        let cameras = Cameras::for_scene(scene);
        let (rec, layout) = open_recording_with("kecsim", sink, || {
            blueprint_with(wheelsets, world, unit, comfort, &cameras, first)
        })?;
        let mut r = Self::on_with(rec, scene, wheelsets, world)?;
        r.layout = Some(layout);
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
        Self::on_with(rec, scene, wheelsets, &World3dSettings::default())
    }

    /// [`Self::on`] with the 3D view's settings.
    pub fn on_with(
        rec: RecordingStream,
        scene: &Scene,
        wheelsets: &[String],
        world: &World3dSettings,
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
            styled: std::collections::HashSet::new(),
            sent: 0,
            world: World3d::new(scene, *world),
            bands: RunningBands::with_axes(band_unit(scene), band_distance(scene)),
            shakedown: vec![Vec::new(); wheelsets.len()],
            floor_points: Vec::new(),
            floor_t: Vec::new(),
            floor_acc: Vec::new(),
            layout: None,
            forces: vec![Vec::new(); wheelsets.len()],
            extents: Default::default(),
        };
        r.log_statics()?;
        assessment::log_statics(&r.rec)?;
        r.world.log_statics(&r.rec)?;
        Ok(r)
    }

    fn log_statics(&self) -> Result<(), InspectError> {
        for name in &self.names {
            for (q, series) in wheelset_series(QUANTITIES).filter(|(q, _)| !q.value.is_conditional()) {
                self.log_style(name, q, series)?;
            }
        }
        for (_, series) in once_series(QUANTITIES) {
            log_static(
                &self.rec,
                &format!("run/vehicle/{}", series.entity()),
                &SeriesLines::new()
                    .with_names([series.title])
                    .with_colors([Color::from_rgb(60, 180, 120)]),
            )?;
        }
        if self.names.len() > 1 {
            let colors: Vec<Color> = (0..self.names.len()).map(palette).collect();
            for (_, series) in vehicle_series(QUANTITIES) {
                log_static(
                    &self.rec,
                    &format!("run/vehicle/{}", series.entity()),
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
            super::log_scale_bar(
                &self.rec,
                &format!("run/section/{}/scale", side.name()),
                &pts,
                10.0,
                "10 mm",
            )?;
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
            // A bar of a round length about a fifth of the plan's extent.
            let extent = plan.iter().fold(0.0f32, |m, p| {
                m.max((p[0] - plan[0][0]).abs()).max((p[1] - plan[0][1]).abs())
            });
            let bar = 10f32.powf((extent / 5.0).max(1.0).log10().floor());
            super::log_scale_bar(&self.rec, "run/track/scale", &plan, bar, &format!("{bar} m"))?;
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

    /// The style of one wheelset's series: its line names, green for one value, a colour per
    /// wheel for two.
    fn log_style(&self, name: &str, q: &Quantity, series: &Series) -> Result<(), InspectError> {
        let lines = line_names(q, series);
        let colors = if lines.len() == 1 {
            vec![Color::from_rgb(60, 180, 120)]
        } else {
            lr_colors()
        };
        log_static(
            &self.rec,
            &format!("run/{name}/{}", series.entity()),
            &SeriesLines::new().with_names(lines).with_colors(colors),
        )
    }

    /// Sends one series of one wheelset's pending samples as columns on `time` and `distance_mm`
    /// (nothing where a sample lacks it: a series that not every sample has).
    fn send_series(
        &self,
        name: &str,
        samples: &[Sample],
        q: &Quantity,
        series: &Series,
    ) -> Result<(), InspectError> {
        let Some(values) = samples
            .iter()
            .map(|s| q.value.of(s, series.unit))
            .collect::<Option<Vec<_>>>()
        else {
            return Ok(());
        };
        let flat: Vec<f64> = values.iter().flat_map(|v| v.iter().copied()).collect();
        self.widen(&format!("/run/{name}/{}", series.entity()), &flat);
        send_scalar_values(
            &self.rec,
            vec![
                TimeColumn::new_duration_secs(TIME, samples.iter().map(|s| s.t)),
                TimeColumn::new_sequence(DISTANCE, samples.iter().map(|s| (s.s * 1e3).round() as i64)),
            ],
            samples.len(),
            &format!("run/{name}/{}", series.entity()),
            flat,
            q.value.width(),
        )
    }

    /// Widens the data extent of the plot at `origin` by `values` (NaN skipped).
    fn widen(&self, origin: &str, values: &[f64]) {
        let (lo, hi) = values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        if lo > hi {
            return;
        }
        let mut map = self.extents.lock().unwrap_or_else(|e| e.into_inner());
        let e = map.entry(origin.to_string()).or_insert([lo, hi]);
        *e = [e[0].min(lo), e[1].max(hi)];
    }

    /// Sends what is pending.
    fn send_batch(&mut self) -> Result<(), InspectError> {
        let n = self.pending.first().map_or(0, Vec::len);
        if n == 0 {
            return Ok(());
        }
        for (name, samples) in self.names.iter().zip(&self.pending) {
            for (q, series) in wheelset_series(QUANTITIES) {
                // A series that not every sample has is styled when first sent.
                let given = || samples.iter().all(|s| q.value.of(s, series.unit).is_some());
                if q.value.is_conditional()
                    && given()
                    && self.styled.insert(format!("run/{name}/{}", series.entity()))
                {
                    self.log_style(name, q, series)?;
                }
                self.send_series(name, samples, q, series)?;
            }
        }
        for (q, series) in once_series(QUANTITIES) {
            let first = &self.pending[0];
            let value = |s: &Sample| q.value.of(s, series.unit).map_or(f64::NAN, |v| v[0]);
            send_scalar_values(
                &self.rec,
                vec![
                    TimeColumn::new_duration_secs(TIME, first.iter().map(|s| s.t)),
                    TimeColumn::new_sequence(DISTANCE, first.iter().map(|s| (s.s * 1e3).round() as i64)),
                ],
                n,
                &format!("run/vehicle/{}", series.entity()),
                {
                    let values: Vec<f64> = first.iter().map(value).collect();
                    self.widen(&format!("/run/vehicle/{}", series.entity()), &values);
                    values
                },
                1,
            )?;
        }
        if self.names.len() > 1 {
            let pending = &self.pending;
            let first = &pending[0];
            for (q, series) in vehicle_series(QUANTITIES) {
                let value = |s: &Sample| q.value.of(s, series.unit).map_or(f64::NAN, |v| v[0]);
                // On `distance_mm` too: the front wheelset's (as the vehicle's own series).
                send_scalar_values(
                    &self.rec,
                    vec![
                        TimeColumn::new_duration_secs(TIME, first.iter().map(|s| s.t)),
                        TimeColumn::new_sequence(DISTANCE, first.iter().map(|s| (s.s * 1e3).round() as i64)),
                    ],
                    n,
                    &format!("run/vehicle/{}", series.entity()),
                    {
                        let values: Vec<f64> = (0..n)
                            .flat_map(|i| pending.iter().map(move |w| value(&w[i])))
                            .collect();
                        self.widen(&format!("/run/vehicle/{}", series.entity()), &values);
                        values
                    },
                    self.names.len(),
                )?;
            }
        }
        self.send_track_strip()?;
        self.send_sections()?;
        self.world.send(&self.rec, TIME, DISTANCE)?;
        self.bands.send(&self.rec, &self.pending)?;
        self.sent += n;
        for p in &mut self.pending {
            p.clear();
        }
        self.last_batch = Instant::now();
        Ok(())
    }

    /// The track's curvature and cant under the front wheelset at its pending samples
    /// (`run/track/{curvature_1pkm, cant_mrad}`, on `time` and `distance_mm`).
    fn send_track_strip(&self) -> Result<(), InspectError> {
        let (Some(track), Some(first)) = (&self.track, self.pending.first()) else {
            return Ok(());
        };
        let frames: Vec<(f64, i64, f64, f64)> = first
            .iter()
            .filter_map(|p| {
                let f = track.centreline.frame(p.s).ok()?;
                Some((p.t, (p.s * 1e3).round() as i64, f.rho_h * 1e3, f.cant_rad * 1e3))
            })
            .collect();
        if frames.is_empty() {
            return Ok(());
        }
        let timelines = || {
            vec![
                TimeColumn::new_duration_secs(TIME, frames.iter().map(|f| f.0)),
                TimeColumn::new_sequence(DISTANCE, frames.iter().map(|f| f.1)),
            ]
        };
        let grey = || vec![Color::from_rgb(170, 170, 180)];
        let n = frames.len();
        self.widen(
            "/run/track/curvature_1pkm",
            &frames.iter().map(|f| f.2).collect::<Vec<_>>(),
        );
        self.widen(
            "/run/track/cant_mrad",
            &frames.iter().map(|f| f.3).collect::<Vec<_>>(),
        );
        send_scalar_rows(
            &self.rec,
            timelines(),
            n,
            "run/track/curvature_1pkm",
            frames.iter().map(|f| f.2).collect(),
            &["curvature"],
            grey(),
        )?;
        send_scalar_rows(
            &self.rec,
            timelines(),
            n,
            "run/track/cant_mrad",
            frames.iter().map(|f| f.3).collect(),
            &["cant"],
            grey(),
        )
    }

    /// The running-safety series along the run (`run/safety/`): each wheelset's 2 m sliding means
    /// of Y/Q (the larger wheel's) and ΣY, and its larger ΔQ/Q₀, as the summary's figures take
    /// them ([`crate::dynamics::safety`]: the same sliding mean, only full windows), with the
    /// limits as grey lines; returns the wheelsets' indices, the most loaded against its limits
    /// first (none without safety figures).
    fn log_safety(&self, summary: &RunSummary) -> Result<Vec<usize>, InspectError> {
        let Some(safety) = &summary.safety else {
            return Ok(Vec::new());
        };
        let mut worst: Vec<(usize, f64)> = Vec::new();
        let (mut t_span, mut s_span) = (
            (f64::INFINITY, f64::NEG_INFINITY),
            (f64::INFINITY, f64::NEG_INFINITY),
        );
        // The wheelsets' Prud'homme limits differ with their axle loads: the strictest is drawn.
        let mut sum_y_limit = f64::INFINITY;
        for (k, (name, rows)) in self.names.iter().zip(&self.forces).enumerate() {
            let Some(w) = safety.wheelsets.iter().find(|w| &w.name == name) else {
                continue;
            };
            let Some(first) = rows.first() else {
                continue;
            };
            // The summary's own series (its figures are their largest values), drawn where the
            // 2 m window is full; the larger wheel's Y/Q and ΔQ/Q₀.
            let series = crate::dynamics::safety::series(
                &rows.iter().map(|r| r.s).collect::<Vec<_>>(),
                &rows.iter().map(|r| r.y).collect::<Vec<_>>(),
                &rows.iter().map(|r| r.q).collect::<Vec<_>>(),
                w.static_wheel_load_n,
            );
            let where_full = |i: usize, v: f64| if series.full[i] { v } else { f64::NAN };
            let [left, right] = &series.y_over_q_2m;
            let y_over_q: Vec<f64> = (0..rows.len())
                .map(|i| where_full(i, left[i].max(right[i])))
                .collect();
            let sum_y: Vec<f64> = (0..rows.len())
                .map(|i| where_full(i, series.sum_y_2m_n[i] * 1e-3))
                .collect();
            let dq: Vec<f64> = (0..rows.len())
                .map(|i| {
                    series
                        .delta_q_over_q0
                        .iter()
                        .flatten()
                        .map(|d| d[i])
                        .fold(f64::NAN, f64::max)
                })
                .collect();
            let timelines = || {
                vec![
                    TimeColumn::new_duration_secs(TIME, rows.iter().map(|r| r.t)),
                    TimeColumn::new_sequence(DISTANCE, rows.iter().map(|r| (r.s * 1e3).round() as i64)),
                ]
            };
            for (what, values) in [
                ("y_over_q_2m", y_over_q),
                ("sum_y_2m_kn", sum_y),
                ("delta_q_over_q0", dq),
            ] {
                self.widen(&format!("/run/safety/{what}"), &values);
                send_scalar_rows(
                    &self.rec,
                    timelines(),
                    rows.len(),
                    &format!("run/safety/{what}/{name}"),
                    values,
                    &[name.as_str()],
                    vec![palette(k)],
                )?;
            }
            let last = rows.last().unwrap_or(first);
            t_span = (t_span.0.min(first.t), t_span.1.max(last.t));
            s_span = (s_span.0.min(first.s), s_span.1.max(last.s));
            sum_y_limit = sum_y_limit.min(w.prudhomme_limit_n * 1e-3);
            let load = (w.y_over_q_2m / safety.nadal_limit)
                .max(w.sum_y_2m_n / w.prudhomme_limit_n)
                .max(w.delta_q_over_q0 / DELTA_Q_LIMIT);
            worst.push((k, load));
        }
        if t_span.0 <= t_span.1 {
            let limit = |entity: &str, label: &str, value: f64| {
                super::log_bound(
                    &self.rec,
                    vec![
                        TimeColumn::new_duration_secs(TIME, [t_span.0, t_span.1]),
                        TimeColumn::new_sequence(
                            DISTANCE,
                            [s_span.0, s_span.1].map(|s| (s * 1e3).round() as i64),
                        ),
                    ],
                    entity,
                    value,
                    label,
                )
            };
            self.widen("/run/safety/y_over_q_2m", &[0.0, safety.nadal_limit]);
            self.widen("/run/safety/sum_y_2m_kn", &[-sum_y_limit, sum_y_limit]);
            self.widen("/run/safety/delta_q_over_q0", &[DELTA_Q_LIMIT]);
            limit(
                "run/safety/y_over_q_2m/limit",
                "Nadal's limit",
                safety.nadal_limit,
            )?;
            limit(
                "run/safety/sum_y_2m_kn/limit",
                "Prud'homme's limit (smallest)",
                sum_y_limit,
            )?;
            limit(
                "run/safety/sum_y_2m_kn/limit_negative",
                "− Prud'homme's limit",
                -sum_y_limit,
            )?;
            limit(
                "run/safety/delta_q_over_q0/limit",
                "EN 14363's limit",
                DELTA_Q_LIMIT,
            )?;
        }
        worst.sort_by(|a, b| b.1.total_cmp(&a.1));
        Ok(worst.into_iter().map(|(k, _)| k).collect())
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
        text += &safety_verdict(summary);
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
        self.floor_points = run.floor_points.to_vec();
        self.floor_acc = vec![Vec::new(); run.floor_points.len()];
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        for ((p, m), s) in self
            .pending
            .iter_mut()
            .zip(&mut self.shakedown)
            .zip(sample.wheelsets)
        {
            p.push(*s);
            m.extend(assessment::shakedown_points(s));
        }
        for (f, s) in self.forces.iter_mut().zip(sample.wheelsets) {
            f.push(SafetyRow {
                t: s.t,
                s: s.s,
                y: s.y_force,
                q: s.q_force,
            });
        }
        if !self.floor_points.is_empty() {
            self.floor_t.push(sample.t);
            for (f, a) in self.floor_acc.iter_mut().zip(sample.floor) {
                f.push(*a);
            }
        }
        if let Some(first) = sample.wheelsets.first() {
            self.log_section(first);
        }
        self.world
            .sample(sample.t, sample.wheelsets, sample.bodies, sample.elements);
        if self.last_batch.elapsed() >= self.batch_wall {
            self.send_batch()?;
        }
        Ok(())
    }

    fn finish(&mut self, summary: &RunSummary) -> Result<(), ObserverError> {
        for (k, (name, points)) in self.names.iter().zip(&self.shakedown).enumerate() {
            assessment::log_shakedown_points(&self.rec, name, points, palette(k))?;
        }
        if let Some(wear) = &summary.wear {
            assessment::log_wear_histograms(&self.rec, wear)?;
        }
        let n = self.floor_t.len();
        if n > 1 {
            let fs = (n - 1) as f64 / (self.floor_t[n - 1] - self.floor_t[0]);
            for (k, (p, a)) in self.floor_points.iter().zip(&self.floor_acc).enumerate() {
                let extents =
                    assessment::log_floor_series(&self.rec, TIME, p, &self.floor_t, a, fs, palette(k))?;
                for (origin, values) in extents {
                    self.widen(&origin, &values);
                }
            }
        }
        let order = self.log_safety(summary)?;
        self.log_summary(summary)?;
        if let (Some(layout), false) = (self.layout.take(), order.is_empty()) {
            let mut layout = Some(layout);
            for panel in [Panel::Kinematics, Panel::Forces, Panel::Wear] {
                if let Some(l) = layout.take() {
                    layout = Some(
                        l.reorder(&self.rec, &wheelset_tabs_name(panel), &order)
                            .map_err(log_err("the layout (blueprint)"))?,
                    );
                }
            }
            self.layout = layout;
        }
        // Each plot's y range from its data, labelled at both ends.
        if let Some(layout) = self.layout.take() {
            let extents = self.extents.lock().unwrap_or_else(|e| e.into_inner()).clone();
            self.layout = Some(
                layout
                    .set_y_ranges(&self.rec, |origin| extents.get(origin).copied())
                    .map_err(log_err("the layout (blueprint)"))?,
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::output::{csv_header, CSV_COLUMNS};
    use crate::dynamics::sample::{Csv, Unit, Value};

    /// The per-wheelset series `table` records: entity under `run/NAME/`, line names, values of
    /// [`Sample::distinct`].
    fn recorded_wheelset_series(table: &'static [Quantity]) -> Vec<(String, Vec<String>, Vec<f64>)> {
        let s = Sample::distinct();
        wheelset_series(table)
            .map(|(q, series)| {
                (
                    series.entity(),
                    line_names(q, series).iter().map(|l| l.to_string()).collect(),
                    q.value.of(&s, series.unit).unwrap().to_vec(),
                )
            })
            .collect()
    }

    /// The vehicle's own series under `run/vehicle/`: entity, value of [`Sample::distinct`].
    fn recorded_once_series(table: &'static [Quantity]) -> Vec<(String, f64)> {
        let s = Sample::distinct();
        once_series(table)
            .map(|(q, series)| (series.entity(), q.value.of(&s, series.unit).unwrap()[0]))
            .collect()
    }

    /// The every-wheelset series under `run/vehicle/`: entity, value of [`Sample::distinct`].
    fn recorded_vehicle_series(table: &'static [Quantity]) -> Vec<(String, f64)> {
        let s = Sample::distinct();
        vehicle_series(table)
            .map(|(q, series)| (series.entity(), q.value.of(&s, series.unit).unwrap()[0]))
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
            ("p0_mpa".into(), lr(), vec![916.3659258389814, 1128.040487157459]),
            ("tgamma_n".into(), lr(), vec![9.0, 13.6]),
            ("tgamma_2m_n".into(), lr(), vec![7.5, 12.5]),
            ("pmax_mpa".into(), lr(), vec![1200.0, 900.0]),
        ];
        let mut got = recorded_wheelset_series(QUANTITIES);
        pinned.sort_by(|a, b| a.0.cmp(&b.0));
        got.sort_by(|a, b| a.0.cmp(&b.0));
        assert_eq!(got.len(), pinned.len(), "{got:?}");
        for (g, p) in got.iter().zip(&pinned) {
            assert!(g.0 == p.0 && g.1 == p.1 && near(&g.2, &p.2), "{g:?} vs {p:?}");
        }
        let mut vehicle = recorded_vehicle_series(QUANTITIES);
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
        // Issue 46: the vehicle's traction and its power, once.
        let once = recorded_once_series(QUANTITIES);
        let pinned = [
            ("vehicle_speed_m_s", 19.125),
            ("traction_kn", 0.45),
            ("traction_power_kw", 8.55),
        ];
        assert_eq!(once.len(), pinned.len(), "{once:?}");
        for (g, p) in once.iter().zip(pinned) {
            assert!(g.0 == p.0 && near(&[g.1], &[p.1]), "{g:?} vs {p:?}");
        }
        // A sample without the KEC parameters records no `s_knife_mm` (NaN in no CSV column).
        let knife = QUANTITIES
            .iter()
            .find(|q| q.series.is_some_and(|s| s.stem == "s_knife"))
            .unwrap();
        assert!(knife.value.of(&Sample::at(0.0, 0.0, 0.0), Unit::MM).is_none());
    }

    /// The run's layout (the plots below the cross-sections), pinned as it was before it was made
    /// from the table: titles and entities, row by row.
    #[test]
    fn layout_is_pinned() {
        let rows = |names: &[&str]| -> Vec<Vec<(String, String)>> {
            let names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
            plot_rows(QUANTITIES, &names)
                .into_iter()
                .map(|r| r.into_iter().map(|p| (p.title, p.origin)).collect())
                .collect()
        };
        let detail = |w: &str| -> Vec<Vec<(String, String)>> {
            [
                vec![
                    ("y [mm]", "y_mm"),
                    ("yaw [mrad]", "yaw_mrad"),
                    ("z − r0 [mm]", "z_mm"),
                    ("roll [mrad]", "roll_mrad"),
                ],
                vec![
                    ("normal force [kN]", "normal_kn"),
                    ("creep Fx [kN]", "creep_fx_kn"),
                    ("creep Fy [kN]", "creep_fy_kn"),
                    ("Y/Q", "y_over_q"),
                ],
                vec![
                    ("contact on wheel s^w [mm]", "s_wheel_mm"),
                    ("contact on rail s^r [mm]", "s_rail_mm"),
                    ("KEC contact s^k [mm]", "s_knife_mm"),
                    ("wheel lift [mm]", "lift_mm"),
                ],
                vec![
                    ("max. Hertz pressure p0 [MPa]", "p0_mpa"),
                    ("wear number Tγ [N]", "tgamma_n"),
                    ("wear number Tγ, 2 m mean [N]", "tgamma_2m_n"),
                    ("max. contact pressure (valid model) [MPa]", "pmax_mpa"),
                ],
            ]
            .into_iter()
            .map(|r| {
                r.into_iter()
                    .map(|(t, e)| (format!("{w}: {t}"), format!("/run/{w}/{e}")))
                    .collect()
            })
            .collect()
        };
        let own = || -> Vec<(String, String)> {
            vec![
                (
                    "vehicle: speed (centre of mass) [m/s]".to_string(),
                    "/run/vehicle/vehicle_speed_m_s".to_string(),
                ),
                (
                    "vehicle: traction [kN]".to_string(),
                    "/run/vehicle/traction_kn".to_string(),
                ),
                (
                    "vehicle: traction power [kW]".to_string(),
                    "/run/vehicle/traction_power_kw".to_string(),
                ),
            ]
        };
        let mut single = vec![own()];
        single.extend(detail("wheelset_1"));
        assert_eq!(rows(&["wheelset_1"]), single);
        let mut vehicle: Vec<(String, String)> = [
            ("every wheelset: y [mm]", "/run/vehicle/y_mm"),
            ("every wheelset: yaw [mrad]", "/run/vehicle/yaw_mrad"),
            (
                "every wheelset: smaller wheel load [kN]",
                "/run/vehicle/min_normal_kn",
            ),
            ("every wheelset: larger |Y/Q|", "/run/vehicle/max_abs_y_over_q"),
        ]
        .into_iter()
        .map(|(t, e)| (t.to_string(), e.to_string()))
        .collect();
        vehicle.extend(own());
        let mut expected = vec![vehicle];
        expected.extend(detail("w1"));
        assert_eq!(rows(&["w1", "w2"]), expected);
    }

    /// Issue 47: the run's layout in tabs that each fit a screen: their names in order, every
    /// wheelset's detail plots (each in its wheelset's tab, not only the first wheelset's), the
    /// running-safety plots, the track strip on every history tab, both 3D views with a camera,
    /// every time-series view opening on its whole timeline, no tab with more than 16 views.
    #[test]
    fn the_run_layout_is_in_tabs() {
        let names: Vec<String> = (1..=6).map(|k| format!("w{k}")).collect();
        let cameras = Cameras {
            bogie_x_m: -0.9,
            middle_x_m: -14.0,
            length_m: 28.0,
            r0_m: 0.37,
        };
        let layout = blueprint_with(
            &names,
            &World3dSettings::default(),
            5.0,
            true,
            &cameras,
            RunTab::Forces,
        );
        let tabs: Vec<&str> = layout
            .root()
            .children()
            .iter()
            .map(|t| match t {
                Item::Container(c) => c.name().unwrap_or("?"),
                Item::View(v) => v.name(),
            })
            .collect();
        assert_eq!(
            tabs,
            [
                "Overview",
                "Wheelsets",
                "Forces and safety",
                "Wear and stress",
                "Comfort"
            ]
        );
        let views = layout.views();
        let origins: Vec<&str> = views.iter().map(|v| v.origin_path()).collect();
        for w in &names {
            for (_, row) in detail_rows(QUANTITIES, w) {
                for p in row {
                    assert_eq!(
                        origins.iter().filter(|o| **o == p.origin).count(),
                        1,
                        "{}",
                        p.origin
                    );
                }
            }
        }
        for p in vehicle_plots(QUANTITIES, &names) {
            assert!(origins.contains(&p.origin.as_str()), "{}", p.origin);
        }
        for o in [
            "/run/safety/y_over_q_2m",
            "/run/safety/sum_y_2m_kn",
            "/run/safety/delta_q_over_q0",
            "/run/summary",
        ] {
            assert!(origins.contains(&o), "{o}");
        }
        for v in &views {
            if v.blueprint_path().starts_with("view/") && v.property_names().contains(&"EyeControls3D") {
                assert_eq!(v.origin_path(), "/run/world/follow");
            }
        }
        assert_eq!(
            views
                .iter()
                .filter(|v| v.property_names().contains(&"EyeControls3D"))
                .count(),
            2
        );
        // The strip: once on the overview, once on each history tab.
        assert_eq!(
            origins
                .iter()
                .filter(|o| **o == "/run/track/curvature_1pkm")
                .count(),
            5
        );
        for (tab, item) in tabs.iter().zip(layout.root().children()) {
            let Item::Container(c) = item else { continue };
            // Each wheelset's tab shows one at a time: count the views of the first.
            fn shown(item: &Item) -> usize {
                match item {
                    Item::View(_) => 1,
                    Item::Container(c)
                        if c.children()
                            .iter()
                            .all(|k| matches!(k, Item::Container(x) if x.name().is_some()))
                            && !c.children().is_empty() =>
                    {
                        shown(&c.children()[0])
                    }
                    Item::Container(c) => c.children().iter().map(shown).sum(),
                }
            }
            let n: usize = c.children().iter().map(shown).sum();
            assert!(n <= 16, "{tab}: {n} views at once");
        }
        for v in views.iter().filter(|v| v.property_names().contains(&"TimeAxis")) {
            assert!(v.property_names().contains(&"PlotLegend"), "{}", v.name());
        }
    }

    /// Checks that every quantity of `table` appears once, and only as declared, in the CSV
    /// header, the recording's series and the layout made from it.
    fn check_made_from(table: &'static [Quantity]) {
        // The CSV: a column per value of every quantity written, each name once.
        let header = csv_header(table);
        let widths: usize = table
            .iter()
            .filter(|q| q.csv != Csv::No)
            .map(|q| q.value.width())
            .sum();
        assert_eq!(header.len(), widths, "{header:?}");
        let mut unique = header.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), header.len(), "a CSV column twice: {header:?}");
        for q in table {
            let (stem, unit) = match q.csv {
                Csv::No => continue,
                Csv::Columns(stem, unit) | Csv::WheelByWheelWithPrevious(stem, unit) => (stem, unit),
            };
            let columns: Vec<String> = match q.value.width() {
                1 => vec![unit.name(stem)],
                _ => WHEELS.iter().map(|w| unit.name(&format!("{stem}_{w}"))).collect(),
            };
            for c in &columns {
                assert_eq!(header.iter().filter(|h| *h == c).count(), 1, "{}: {c}", q.name);
            }
        }
        // The series and the layout: every series recorded once and plotted once (per wheelset
        // in its panel; every wheelset side by side under `run/vehicle/`).
        let names = ["w1".to_string(), "w2".to_string()];
        let plots: Vec<Plot> = plot_rows(table, &names).into_iter().flatten().collect();
        let per_wheelset = recorded_wheelset_series(table);
        let vehicle = recorded_vehicle_series(table);
        let once = recorded_once_series(table);
        let mut entities: Vec<&String> = per_wheelset.iter().map(|s| &s.0).collect();
        entities.sort();
        entities.dedup();
        assert_eq!(
            entities.len(),
            per_wheelset.len(),
            "a series twice: {per_wheelset:?}"
        );
        for q in table {
            let Some(series) = q.series else {
                continue;
            };
            let entity = series.entity();
            let shown = |origin: &str| plots.iter().filter(|p| p.origin == origin).count();
            let (recorded, plotted) = (
                per_wheelset.iter().filter(|s| s.0 == entity).count(),
                shown(&format!("/run/w1/{entity}")),
            );
            let expected = usize::from(series.panel.is_some());
            assert_eq!((recorded, plotted), (expected, expected), "{}: {entity}", q.name);
            let (recorded, plotted) = (
                vehicle.iter().chain(&once).filter(|s| s.0 == entity).count(),
                shown(&format!("/run/vehicle/{entity}")),
            );
            let expected = usize::from(series.vehicle || series.once);
            assert_eq!((recorded, plotted), (expected, expected), "{}: {entity}", q.name);
        }
        let series = table.iter().filter_map(|q| q.series);
        assert_eq!(
            plots.len(),
            series.clone().filter(|s| s.panel.is_some()).count()
                + series.filter(|s| s.vehicle || s.once).count()
        );
    }

    /// The CSV header, the recording's series and the layout are made from the table: every
    /// quantity of [`QUANTITIES`] is in each once, as declared; and a quantity added to the table
    /// is in all three with nothing else changed.
    #[test]
    fn outputs_are_made_from_the_table() {
        assert_eq!(csv_header(QUANTITIES), *CSV_COLUMNS);
        check_made_from(QUANTITIES);
        let mut table = QUANTITIES.to_vec();
        table.push(Quantity {
            name: "wheel spin (a quantity added to the table)",
            value: Value::Wheels(|s| [s.t, s.speed]),
            csv: Csv::Columns("spin", Unit::MM),
            series: Some(Series {
                stem: "spin",
                unit: Unit::MM,
                title: "spin",
                panel: Some(Panel::Kinematics),
                vehicle: false,
                once: false,
            }),
        });
        let table: &'static [Quantity] = table.leak();
        check_made_from(table);
        let mut header = CSV_COLUMNS.iter().map(|c| c.to_string()).collect::<Vec<_>>();
        header.extend(["spin_left_mm".to_string(), "spin_right_mm".to_string()]);
        assert_eq!(csv_header(table), header);
        let series = recorded_wheelset_series(table);
        assert_eq!(
            series.last().unwrap(),
            &(
                "spin_mm".to_string(),
                WHEELS.map(String::from).to_vec(),
                vec![1500.0, 19000.0]
            )
        );
        // (The first row is the vehicle's own: speed and traction.)
        let rows = plot_rows(table, &["w1".to_string()]);
        assert_eq!(
            rows[1].last().unwrap(),
            &Plot {
                title: "w1: spin [mm]".into(),
                origin: "/run/w1/spin_mm".into()
            }
        );
    }
}
