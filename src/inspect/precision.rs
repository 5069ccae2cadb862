//! `kecsim bench precision`: the work–precision diagram, error against wall time on log–log axes,
//! one line per contact model and integrator through its tolerance sweep (each point labelled with
//! its rtol), grid lines labelled (wall time at 1, 2, 5 × 10^k, error at its decades); the report
//! below. Plotted in 2D views with x = 100 s_x log₁₀(wall time / s) and y = −100 log₁₀(error) (so
//! that smaller errors lie lower, as on paper: the 2D view's y axis points down), s_x widening a
//! decade of wall time so that the diagram is 1.6 times as wide as high.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `precision/{dy,dpsi}/grid` | LineStrips2D, static | decades of wall time and of error, labelled |
//! | `precision/{dy,dpsi}/CONTACT_METHOD` | LineStrips2D, Points2D, static | one sweep (error in mm or mrad) |
//! | `precision/summary` | TextDocument, static | the report |

use super::{Container, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument};

use super::{log_static, InspectError};
use crate::compare::precision::{Precision, PrecisionRow};

/// Plot coordinates of (wall s, error) on the log–log axes, a decade of wall time `sx` times as
/// wide as a decade of error (so that a sweep over one decade of time and three of error is not
/// drawn as a narrow column).
fn at(wall: f64, error: f64, sx: f64) -> [f32; 2] {
    [
        (100.0 * sx * wall.log10()) as f32,
        (-100.0 * error.log10()) as f32,
    ]
}

/// The width of a decade of wall time against one of error: the diagram 1.6 times as wide as it
/// is high, or square decades where that is wider already.
fn decade_aspect(wall_decades: i32, error_decades: i32) -> f64 {
    (1.6 * error_decades.max(1) as f64 / wall_decades.max(1) as f64).max(1.0)
}

/// The layout: Δy and Δψ diagrams side by side, the report below them.
pub fn blueprint() -> Layout {
    Layout::new(Container::vertical([
        Container::horizontal([
            View::spatial2d("max |Δy| [mm] against wall time [s] (log–log)")
                .origin("/precision/dy")
                .into(),
            View::spatial2d("max |Δψ| [mrad] against wall time [s] (log–log)")
                .origin("/precision/dpsi")
                .into(),
        ])
        .into(),
        View::text_document("Report").origin("/precision/summary").into(),
    ]))
}

/// The decades spanning `values` (positive ones): floor(log₁₀ min) ..= ceil(log₁₀ max).
fn decades(values: impl Iterator<Item = f64>) -> Option<(i32, i32)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    (lo <= hi).then(|| (lo.log10().floor() as i32, hi.log10().ceil() as i32))
}

/// Records the diagrams and the report.
pub fn record(rec: &RecordingStream, p: &Precision) -> Result<(), InspectError> {
    // A zero error (a run identical to the reference) is drawn at the plot's floor.
    let floor = 1e-9;
    for (view, unit, error) in [
        (
            "dy",
            "mm",
            (|r: &PrecisionRow| r.max_dy * 1e3) as fn(&PrecisionRow) -> f64,
        ),
        ("dpsi", "mrad", |r: &PrecisionRow| r.max_dpsi * 1e3),
    ] {
        let (Some((w0, w1)), Some((e0, e1))) = (
            decades(p.rows.iter().map(|r| r.wall_s)),
            decades(p.rows.iter().map(|r| error(r).max(floor))),
        ) else {
            continue;
        };
        let (wl, wh) = (10f64.powi(w0), 10f64.powi(w1));
        let (el, eh) = (10f64.powi(e0), 10f64.powi(e1));
        let sx = decade_aspect(w1 - w0, e1 - e0);
        let at = |w: f64, e: f64| at(w, e, sx);
        let mut strips = Vec::new();
        let mut labels = Vec::new();
        // Wall time at 1, 2 and 5 in each decade (three labels at least on a single decade).
        for k in w0..=w1 {
            for m in [1.0, 2.0, 5.0] {
                let w = m * 10f64.powi(k);
                if w > wh * (1.0 + 1e-9) {
                    break;
                }
                strips.push(vec![at(w, el), at(w, eh)]);
                labels.push(format!("{} s", super::xyplot::short(w)));
            }
        }
        for k in e0..=e1 {
            let e = 10f64.powi(k);
            strips.push(vec![at(wl, e), at(wh, e)]);
            labels.push(format!("{} {unit}", super::xyplot::short(e)));
        }
        log_static(
            rec,
            &format!("precision/{view}/grid"),
            &LineStrips2D::new(strips)
                .with_labels(labels)
                .with_colors([Color::from_rgb(90, 90, 100)])
                .with_radii([Radius::new_ui_points(0.5)]),
        )?;
        let mut series: Vec<(String, Vec<&PrecisionRow>)> = Vec::new();
        for r in &p.rows {
            let name = format!("{}_{:?}", r.contact, r.method).to_lowercase();
            match series.iter_mut().find(|s| s.0 == name) {
                Some(s) => s.1.push(r),
                None => series.push((name, vec![r])),
            }
        }
        for (k, (name, rows)) in series.iter().enumerate() {
            let color = super::compare::colors(1, k)[0];
            let mut rows = rows.clone();
            rows.sort_by(|a, b| b.rtol.total_cmp(&a.rtol));
            let pts: Vec<[f32; 2]> = rows.iter().map(|r| at(r.wall_s, error(r).max(floor))).collect();
            let entity = format!("precision/{view}/{name}");
            log_static(
                rec,
                &entity,
                &LineStrips2D::new([pts.clone()])
                    .with_labels([name.clone()])
                    .with_colors([color])
                    .with_radii([Radius::new_ui_points(1.5)]),
            )?;
            log_static(
                rec,
                &format!("{entity}/points"),
                &Points2D::new(pts)
                    .with_labels(rows.iter().map(|r| {
                        let failed = if r.outcome == "completed" {
                            ""
                        } else {
                            " (not completed)"
                        };
                        format!("{:.0e}{failed}", r.rtol)
                    }))
                    .with_colors([color])
                    .with_radii([Radius::new_ui_points(4.0)]),
            )?;
        }
    }
    log_static(
        rec,
        "precision/summary",
        &TextDocument::from_markdown(p.markdown()),
    )
}
