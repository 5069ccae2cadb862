//! What an engineer reads off a run beside the safety figures, in the recording: the contact
//! stress on **Johnson's shakedown map** and the **ride comfort** at the carbodies' floor points
//! (the wear number and p0 per wheel are series of the run's table, `run/NAME/tgamma_n`, …).
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/shakedown/limit` | LineStrips2D static | the elastic shakedown limit p0/k = min(4, 1/μ) (drawn `[40 μ, −p0/k]`: μ 0.6 is 24 wide, p0/k up) |
//! | `run/shakedown/axes`, `run/shakedown/ticks` | LineStrips2D, Points2D static | axes with ticks (μ 0.25, 0.5; p0/k 4, 8, 12) |
//! | `run/shakedown/regions` | Points2D static | the regions named: elastic shakedown below the limit, plastic shakedown and ratchetting above |
//! | `run/shakedown/NAME` | Points2D static | every sample's contact of wheelset NAME's wheels, (μ, p0/k), at the run's end |
//! | `run/wear/{wheel,rail}/NAME_SIDE` | BarChart static | where wheel NAME's SIDE wheel wears: the mass lost (mg) in 2 mm bins of s^w, of s^r, at the run's end |
//! | `run/wear/{wheel,rail}/most_worn` | BarChart static | the same of the wheel with the largest wear per km |
//! | `run/comfort/{acc_y_m_s2, acc_z_m_s2}/CARBODY_POINT` | Scalars | the floor accelerations (carbody axes, less 1 g on z) |
//! | `run/comfort/{cc_y_m_s2, cc_z_m_s2}/CARBODY_POINT` | Scalars | EN 12299's continuous comfort Cc_y (Wd), Cc_z (Wb), 5 s r.m.s. |
//!
//! The comfort series are sent at the run's end (the weightings filter the whole signal), on the
//! run's `time` timeline.

use rerun::{BarChart, Color, LineStrips2D, Points2D, Radius, RecordingStream, TimeColumn};

use super::{log_static, send_scalar_rows, InspectError};
use crate::dynamics::contact_stress::{map_point, shakedown_limit, R260};
use crate::dynamics::ride::continuous_comfort;
use crate::dynamics::sample::Sample;
use crate::dynamics::system::FloorPoint;
use crate::dynamics::wear::{Wear, WearBin, BIN_MM};

/// The shakedown map's drawing scale of μ (μ 0.6 spans twice as much as p0/k 12: the map fills
/// a wide panel).
pub const MU_SCALE: f32 = 40.0;

/// The comfort series (entity stems under `run/comfort/`) and their plots' titles.
pub const COMFORT_SERIES: [(&str, &str); 4] = [
    ("acc_y_m_s2", "floor lateral acceleration [m/s²]"),
    ("acc_z_m_s2", "floor vertical acceleration − g [m/s²]"),
    ("cc_y_m_s2", "continuous comfort Cc_y (Wd, 5 s) [m/s²]"),
    ("cc_z_m_s2", "continuous comfort Cc_z (Wb, 5 s) [m/s²]"),
];

/// A floor point's series `stem` (one of [`COMFORT_SERIES`]).
pub fn floor_entity(stem: &str, p: &FloorPoint) -> String {
    format!("run/comfort/{stem}/{}_{}", p.carbody, p.point)
}

/// The map's point of (μ, p0/k).
fn map_xy(mu: f64, p0_over_k: f64) -> [f32; 2] {
    [MU_SCALE * mu as f32, -(p0_over_k as f32)]
}

/// The statics of the shakedown map: the limit and the axes with their ticks.
pub fn log_statics(rec: &RecordingStream) -> Result<(), InspectError> {
    let limit: Vec<[f32; 2]> = (0..=120)
        .map(|k| k as f64 * 0.005)
        .map(|mu| map_xy(mu, shakedown_limit(mu)))
        .collect();
    log_static(
        rec,
        "run/shakedown/limit",
        &LineStrips2D::new([limit]).with_colors([Color::from_rgb(220, 40, 40)]),
    )?;
    let axes = [vec![map_xy(0.0, 13.0), map_xy(0.0, 0.0), map_xy(0.6, 0.0)]];
    log_static(
        rec,
        "run/shakedown/axes",
        &LineStrips2D::new(axes).with_colors([Color::from_rgb(150, 150, 150)]),
    )?;
    let mut ticks = Vec::new();
    let mut labels = Vec::new();
    for mu in [0.25, 0.5] {
        ticks.push(map_xy(mu, 0.0));
        labels.push(format!("μ {mu}"));
    }
    for p in [4.0, 8.0, 12.0] {
        ticks.push(map_xy(0.0, p));
        labels.push(format!("p0/k {p}"));
    }
    log_static(
        rec,
        "run/shakedown/ticks",
        &Points2D::new(ticks)
            .with_labels(labels)
            .with_colors([Color::from_rgb(150, 150, 150)])
            .with_radii([Radius::new_ui_points(2.0)]),
    )?;
    // The regions named where they lie: below the limit the rail shakes down elastically,
    // above it plastic shakedown or ratchetting (μ > 0.3: surface ratchetting).
    log_static(
        rec,
        "run/shakedown/regions",
        &Points2D::new([map_xy(0.42, 1.6), map_xy(0.3, 9.5)])
            .with_labels([
                "below the red limit: elastic shakedown",
                "above it: plastic shakedown, ratchetting",
            ])
            .with_colors([Color::from_rgb(200, 200, 200)])
            .with_radii([Radius::new_ui_points(0.5)])
            .with_show_labels(true),
    )
}

/// The map's drawing bounds (x: 40 μ over μ −0.08 … 0.65; y: −p0/k over 13.5 … −1.5), for the
/// view's [`super::View::bounds`]: the map fills its panel.
pub const SHAKEDOWN_BOUNDS: ([f64; 2], [f64; 2]) = ([-3.2, 26.0], [-13.5, 1.5]);

/// A sample's wheels on the map (drawn; off the rail: none).
pub fn shakedown_points(s: &Sample) -> Vec<[f32; 2]> {
    [0, 1]
        .into_iter()
        .filter_map(|w| map_point(s, w, R260))
        .map(|(mu, pk)| map_xy(mu, pk))
        .collect()
}

/// One wheelset's [`shakedown_points`] over the run, coloured `color`.
pub fn log_shakedown_points(
    rec: &RecordingStream,
    name: &str,
    points: &[[f32; 2]],
    color: Color,
) -> Result<(), InspectError> {
    log_static(
        rec,
        &format!("run/shakedown/{name}"),
        &Points2D::new(points.iter().copied())
            .with_colors([color])
            .with_radii([Radius::new_ui_points(1.5)]),
    )
}

/// One floor point's accelerations and continuous comfort as series, at the sample times `t`
/// (rate `fs_hz`) on the duration timeline `timeline`, its lines named by the point and drawn in
/// `color` (one of its own: seven points in one plot). Returns each plot's origin
/// (`/run/comfort/STEM`) with the extent of this point's values in it (for its y range).
pub fn log_floor_series(
    rec: &RecordingStream,
    timeline: &'static str,
    point: &FloorPoint,
    t: &[f64],
    acc: &[[f64; 3]],
    fs_hz: f64,
    color: Color,
) -> Result<Vec<(String, Vec<f64>)>, InspectError> {
    let n = t.len().min(acc.len());
    let mut extents = Vec::new();
    if n == 0 {
        return Ok(extents);
    }
    let [cy, cz] = continuous_comfort(&acc[..n], fs_hz);
    let values = [
        acc[..n].iter().map(|a| a[1]).collect::<Vec<f64>>(),
        acc[..n].iter().map(|a| a[2]).collect(),
        cy,
        cz,
    ];
    for ((stem, _), values) in COMFORT_SERIES.iter().zip(values) {
        let finite = values.iter().copied().filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        if lo <= hi {
            extents.push((format!("/run/comfort/{stem}"), vec![lo, hi]));
        }
        let time = TimeColumn::new_duration_secs(timeline, t[..n].iter().copied());
        let name = format!("{}_{}", point.carbody, point.point);
        send_scalar_rows(
            rec,
            vec![time],
            n,
            &floor_entity(stem, point),
            values,
            &[name.as_str()],
            vec![color],
        )?;
    }
    Ok(extents)
}

/// One wear histogram as a bar chart over the profile's coordinate (mm), bars [`BIN_MM`] wide.
fn wear_chart(bins: &[WearBin], color: Color) -> BarChart {
    let values: Vec<f64> = bins.iter().map(|b| b.mass_mg).collect();
    let abscissa: Vec<f64> = bins.iter().map(|b| b.s_mm).collect();
    BarChart::new(values.as_slice())
        .with_abscissa(abscissa.as_slice())
        .with_widths(std::iter::repeat_n(BIN_MM as f32, bins.len()))
        .with_color(color)
}

/// Where every wheel wears, on the wheel (s^w) and on the rail (s^r), and the most worn wheel's
/// (the layout's charts).
pub fn log_wear_histograms(rec: &RecordingStream, wear: &Wear) -> Result<(), InspectError> {
    let (wheel, rail) = (Color::from_rgb(70, 130, 200), Color::from_rgb(200, 110, 40));
    for w in &wear.wheels {
        let name = format!("{}_{}", w.wheelset, w.wheel);
        log_static(
            rec,
            &format!("run/wear/wheel/{name}"),
            &wear_chart(&w.wheel_histogram, wheel),
        )?;
        log_static(
            rec,
            &format!("run/wear/rail/{name}"),
            &wear_chart(&w.rail_histogram, rail),
        )?;
    }
    if let Some(w) = wear
        .wheels
        .iter()
        .max_by(|a, b| a.mass_mg_per_km.total_cmp(&b.mass_mg_per_km))
    {
        log_static(
            rec,
            "run/wear/wheel/most_worn",
            &wear_chart(&w.wheel_histogram, wheel),
        )?;
        log_static(
            rec,
            "run/wear/rail/most_worn",
            &wear_chart(&w.rail_histogram, rail),
        )?;
    }
    Ok(())
}
