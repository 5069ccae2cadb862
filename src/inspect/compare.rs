//! `kecsim compare`: the paper's Fig. 18–19 views for any scene — for the front bogie's wheelsets
//! (the first two; one on a single-wheelset scene), every contact model's lateral displacement and
//! yaw overlaid, their differences from the reference model, and the normal forces left and right;
//! the report below. Timeline `time` (simulated), over the time every run covers.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `compare/NAME/{y_mm, yaw_mrad}` | Scalars (one per model) | kinematics |
//! | `compare/NAME/{dy_mm, dyaw_mrad}` | Scalars (one per model after the first) | difference from the first model |
//! | `compare/NAME/{normal_left_kn, normal_right_kn}` | Scalars (one per model) | normal forces |
//! | `compare/summary` | TextDocument | the report |

use rerun::blueprint::{Blueprint, Horizontal, TextDocumentView, TimePanel, TimeSeriesView, Vertical};
use rerun::{Color, RecordingStream, TextDocument, TimeColumn};

use super::{log_static, send_scalar_rows, InspectError};
use crate::compare::Comparison;
use crate::dynamics::Sample;

/// The simulated-time timeline.
pub const TIME: &str = "time";

const PALETTE: [(u8, u8, u8); 8] = [
    (60, 180, 120),
    (230, 80, 60),
    (60, 140, 230),
    (200, 150, 40),
    (150, 90, 200),
    (120, 120, 120),
    (40, 190, 200),
    (220, 100, 170),
];

/// `n` series colours from the palette, starting at entry `skip`.
pub(crate) fn colors(n: usize, skip: usize) -> Vec<Color> {
    (0..n)
        .map(|k| {
            let (r, g, b) = PALETTE[(k + skip) % PALETTE.len()];
            Color::from_rgb(r, g, b)
        })
        .collect()
}

/// The wheelsets shown: the front bogie's (the first two).
fn shown(c: &Comparison) -> Vec<String> {
    c.runs
        .first()
        .map(|r| r.output.wheelsets.iter().take(2).map(|w| w.0.clone()).collect())
        .unwrap_or_default()
}

/// The layout: a row per wheelset shown, the report below.
pub fn blueprint_for(wheelsets: &[String]) -> Blueprint {
    let plot = |title: String, origin: String| TimeSeriesView::new(title).with_origin(origin).into();
    let mut rows: Vec<rerun::blueprint::ContainerLike> = wheelsets
        .iter()
        .map(|w| {
            Horizontal::new([
                plot(format!("{w}: y [mm]"), format!("/compare/{w}/y_mm")),
                plot(format!("{w}: yaw [mrad]"), format!("/compare/{w}/yaw_mrad")),
                plot(format!("{w}: Δy [mm]"), format!("/compare/{w}/dy_mm")),
                plot(format!("{w}: Δyaw [mrad]"), format!("/compare/{w}/dyaw_mrad")),
                plot(
                    format!("{w}: normal force left [kN]"),
                    format!("/compare/{w}/normal_left_kn"),
                ),
                plot(
                    format!("{w}: normal force right [kN]"),
                    format!("/compare/{w}/normal_right_kn"),
                ),
            ])
            .into()
        })
        .collect();
    rows.push(
        TextDocumentView::new("Report")
            .with_origin("/compare/summary")
            .into(),
    );
    Blueprint::new(Vertical::new(rows)).with_time_panel(TimePanel::new().with_timeline(TIME))
}

/// The layout for a comparison.
pub fn blueprint(c: &Comparison) -> Blueprint {
    blueprint_for(&shown(c))
}

/// Records the comparison (see the module doc).
pub fn record(rec: &RecordingStream, c: &Comparison) -> Result<(), InspectError> {
    let models: Vec<&str> = c.runs.iter().map(|r| r.model.as_str()).collect();
    for (k, name) in shown(c).iter().enumerate() {
        let series: Vec<&[Sample]> = c
            .runs
            .iter()
            .map(|r| r.output.wheelsets[k].1.as_slice())
            .collect();
        let n = series
            .iter()
            .map(|s| s.iter().take_while(|p| p.t <= c.common_s + 1e-9).count())
            .min()
            .unwrap_or(0);
        if n == 0 {
            continue;
        }
        let times = || {
            vec![TimeColumn::new_duration_secs(
                TIME,
                series[0][..n].iter().map(|s| s.t),
            )]
        };
        let all = |entity: &str, f: &dyn Fn(&Sample) -> f64| {
            send_scalar_rows(
                rec,
                times(),
                n,
                &format!("compare/{name}/{entity}"),
                (0..n)
                    .flat_map(|i| series.iter().map(move |s| f(&s[i])))
                    .collect(),
                &models,
                colors(models.len(), 0),
            )
        };
        all("y_mm", &|s| s.y * 1e3)?;
        all("yaw_mrad", &|s| s.yaw * 1e3)?;
        all("normal_left_kn", &|s| s.normal[0] * 1e-3)?;
        all("normal_right_kn", &|s| s.normal[1] * 1e-3)?;
        if models.len() > 1 {
            let diff = |entity: &str, f: &dyn Fn(&Sample) -> f64| {
                send_scalar_rows(
                    rec,
                    times(),
                    n,
                    &format!("compare/{name}/{entity}"),
                    {
                        let mut v = Vec::with_capacity(n * (series.len() - 1));
                        for i in 0..n {
                            let r = f(&series[0][i]);
                            v.extend(series[1..].iter().map(|s| f(&s[i]) - r));
                        }
                        v
                    },
                    &models[1..],
                    colors(models.len() - 1, 1),
                )
            };
            diff("dy_mm", &|s| s.y * 1e3)?;
            diff("dyaw_mrad", &|s| s.yaw * 1e3)?;
        }
    }
    log_static(rec, "compare/summary", &TextDocument::from_markdown(c.markdown()))
}
