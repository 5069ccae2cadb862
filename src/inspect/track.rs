//! `kecsim track`: the track plan, its curvature, cant and twist, and its irregularities.
//!
//! Timeline `s_mm`: arc length in mm (a sequence timeline, one step per sample). Entities:
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `track/plan/centreline` | LineStrips2D, static | plan view X–Y in m, stored `[X, −Y]` (Rerun's 2D views are Y-down: global Y points up on screen) |
//! | `track/plan/vertices` | Points2D, static | section starts, labelled with their type and s |
//! | `track/geometry/curvature_1pm` | Scalars on `s_mm` | ρ_h, 1/m |
//! | `track/geometry/cant_mrad` | Scalars | φ^t, mrad |
//! | `track/geometry/twist_mrad_per_m` | Scalars | ρ_tw, mrad/m |
//! | `track/geometry/z_m` | Scalars | height of the centreline, m |
//! | `track/irregularities/{al,vp,gv,cl}_mm` | Scalars | alignment, vertical profile, gauge variation, cross level, mm |
//! | `track/figures/{geometry,irregularities}/*` | [`super::xyplot`], static | the series above against s in m, as the layout shows them |
//! | `track/summary` | TextDocument | sections, end-of-track check, irregularity statistics |

use super::{Container, Layout, View};
use rerun::{
    Color, LineStrips2D, Points2D, Radius, RecordingStream, Scalars, SeriesLines, TextDocument, TimeColumn,
};

use super::contact::log_err;
use super::{log_static, InspectError};
use crate::track::report::Sample;
use crate::track::Track;

/// The timeline: arc length in mm.
pub const TIMELINE: &str = "s_mm";

/// The four irregularities in the order of [`crate::track::report::Sample::irregularity`] (§2.3):
/// entity name, title and colour.
pub(crate) const IRREGULARITIES: [(&str, &str, [u8; 3]); 4] = [
    ("al", "alignment al", [230, 120, 40]),
    ("vp", "vertical profile vp", [60, 170, 90]),
    ("gv", "gauge variation gv", [170, 80, 200]),
    ("cl", "cross level cl", [220, 60, 60]),
];

/// Layout: plan view and summary on the left, the s-diagrams on the right.
pub fn blueprint() -> Layout {
    // One line each, named by the title: no legend; static x–y figures, s in m at round ticks.
    let plot = |title: &str, origin: &str| {
        let (x, y) = super::xyplot::BOUNDS;
        View::spatial2d(format!("{title} along s [m]"))
            .origin(format!("/{}", figure_entity(origin)))
            .bounds(x, y)
            .into()
    };
    Layout::new(
        Container::horizontal([
            Container::vertical([
                View::spatial2d("Plan view X–Y [m] (stored [X, −Y])")
                    .origin("/track/plan")
                    .into(),
                View::text_document("Summary").origin("/track/summary").into(),
            ])
            .shares([3.0, 2.0])
            .into(),
            Container::grid(
                2,
                [
                    plot("curvature ρ_h [1/m]", "/track/geometry/curvature_1pm"),
                    plot("cant φ [mrad]", "/track/geometry/cant_mrad"),
                    plot("twist ρ_tw [mrad/m]", "/track/geometry/twist_mrad_per_m"),
                    plot("height Z [m]", "/track/geometry/z_m"),
                ]
                .into_iter()
                .chain(IRREGULARITIES.iter().map(|(name, title, _)| {
                    plot(
                        &format!("{title} [mm]"),
                        &format!("/track/irregularities/{name}_mm"),
                    )
                })),
            )
            .into(),
        ])
        .shares([1.0, 1.5]),
    )
    .timeline(TIMELINE)
    .play_state(super::layout::PlayState::Paused)
}

/// The figure drawn from the series at `entity` (`track/X/NAME` → `track/figures/X/NAME`).
fn figure_entity(entity: &str) -> String {
    entity
        .trim_start_matches('/')
        .replacen("track/", "track/figures/", 1)
}

/// One series along s: the Scalars on [`TIMELINE`] at `entity` and its figure (s in m).
fn series(
    rec: &RecordingStream,
    entity: &str,
    s_mm: &[i64],
    values: Vec<f64>,
    name: &str,
    color: [u8; 3],
) -> Result<(), InspectError> {
    let points: Vec<(f64, f64)> = s_mm
        .iter()
        .zip(&values)
        .map(|(&s, &v)| (s as f64 * 1e-3, v))
        .collect();
    super::xyplot::log(
        rec,
        &figure_entity(entity),
        &[super::xyplot::Series {
            name,
            color: Color::from_rgb(color[0], color[1], color[2]),
            width: 1.0,
            points: &points,
        }],
    )?;
    log_static(
        rec,
        entity,
        &SeriesLines::new()
            .with_names([name])
            .with_colors([Color::from_rgb(color[0], color[1], color[2])]),
    )?;
    let columns = Scalars::new(values)
        .columns(std::iter::repeat_n(1, s_mm.len()))
        .map_err(|e| InspectError::Log {
            entity: entity.to_string(),
            source: e.into(),
        })?;
    rec.send_columns(
        entity,
        [TimeColumn::new_sequence(TIMELINE, s_mm.iter().copied())],
        columns,
    )
    .map_err(log_err(entity))
}

/// Records the track sampled in `samples` and the `summary` text.
pub fn record(
    rec: &RecordingStream,
    track: &Track,
    samples: &[Sample],
    summary: &str,
) -> Result<(), InspectError> {
    let plan: Vec<[f32; 2]> = samples
        .iter()
        .map(|s| [s.frame.position.x as f32, -s.frame.position.y as f32])
        .collect();
    log_static(
        rec,
        "track/plan/centreline",
        &LineStrips2D::new([plan])
            .with_colors([Color::from_rgb(60, 140, 230)])
            .with_radii([Radius::new_ui_points(2.0)]),
    )?;
    let (h, _) = track.centreline.sections();
    let mut pts = Vec::new();
    let mut labels = Vec::new();
    for sec in h {
        let f = track
            .centreline
            .frame(sec.from_m)
            .map_err(|e| InspectError::Model(e.to_string()))?;
        pts.push([f.position.x as f32, -f.position.y as f32]);
        labels.push(format!("{} @ {} m", sec.kind.name(), sec.from_m));
    }
    log_static(
        rec,
        "track/plan/vertices",
        &Points2D::new(pts)
            .with_labels(labels)
            .with_colors([Color::from_rgb(230, 120, 40)])
            .with_radii([Radius::new_ui_points(5.0)]),
    )?;
    let s_mm: Vec<i64> = samples.iter().map(|s| (s.frame.s * 1e3).round() as i64).collect();
    let col = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(f).collect::<Vec<f64>>();
    let blue = [60, 140, 230];
    series(
        rec,
        "track/geometry/curvature_1pm",
        &s_mm,
        col(&|s| s.frame.rho_h),
        "ρ_h",
        blue,
    )?;
    series(
        rec,
        "track/geometry/cant_mrad",
        &s_mm,
        col(&|s| s.frame.cant_rad * 1e3),
        "cant",
        blue,
    )?;
    series(
        rec,
        "track/geometry/twist_mrad_per_m",
        &s_mm,
        col(&|s| s.frame.rho_tw * 1e3),
        "twist",
        blue,
    )?;
    series(
        rec,
        "track/geometry/z_m",
        &s_mm,
        col(&|s| s.frame.position.z),
        "Z",
        blue,
    )?;
    for (c, (name, _, color)) in IRREGULARITIES.iter().enumerate() {
        series(
            rec,
            &format!("track/irregularities/{name}_mm"),
            &s_mm,
            col(&|s| s.irregularity[c] * 1e3),
            name,
            *color,
        )?;
    }
    log_static(
        rec,
        "track/summary",
        &TextDocument::from_markdown(summary.to_string()),
    )
}
