//! `kecsim compare`: the paper's Fig. 18–19 views for any scene — for the front bogie's wheelsets
//! (the first two; one on a single-wheelset scene), every contact model's lateral displacement and
//! yaw overlaid, their differences from the reference model, and the normal forces left and right;
//! the report below. Timeline `time` (simulated), over the time every run covers.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `compare/NAME/{y_mm, yaw_mrad}` | Scalars (one per model) | kinematics |
//! | `compare/NAME/{dy_mm, dyaw_mrad}` | Scalars (one per model after the first) | difference from the first model |
//! | `compare/NAME/{dy_mm, dyaw_mrad}/{bound, bound_negative}` | Scalars | the paper's bounds, ± 1 mm and ± 0.5 mrad |
//! | `compare/NAME/{normal_left_kn, normal_right_kn}` | Scalars (one per model) | normal forces |
//! | `compare/summary` | TextDocument | the report |
//! | `compare/world/MODEL/**` | as `run/world/**` ([`super::world3d`]) | every model's vehicle in one 3D view: the first with the track, the others ghosted in their series colour |

use super::{Container, Item, Layout, View};
use rerun::{Color, RecordingStream, TextDocument, TimeColumn};

use super::world3d::{World3d, World3dSettings, WorldStyle};
use super::{log_static, send_scalar_rows, InspectError};
use crate::compare::Comparison;
use crate::dynamics::Sample;
use crate::scenario::Scene;

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

/// The layout without a 3D view: a tab per wheelset shown, the report.
pub fn blueprint_for(wheelsets: &[String]) -> Layout {
    let mut tabs = wheelset_tabs(wheelsets, 2, &|_, _| None);
    tabs.push(View::text_document("Report").origin("/compare/summary").into());
    Layout::new(Container::tabs(tabs)).timeline(TIME)
}

/// A tab per wheelset shown: its y, yaw and normal forces by model, and the differences from the
/// first model, three plots a row. `extent(k, quantity)`: the differences' smallest and largest
/// value on the `k`th wheelset shown (`dy_mm`, `dyaw_mrad`), so that their plots open on the data
/// (a 0.007 mm difference lay flat on zero in a plot scaled to the paper's ± 1 mm), the bound in
/// the title.
fn wheelset_tabs(
    wheelsets: &[String],
    models: usize,
    extent: &dyn Fn(usize, &str) -> Option<[f64; 2]>,
) -> Vec<Item> {
    // Each plot's legend (a line per model) above its data (the y range raised to make room).
    let values = |k: usize, title: String, quantity: &str, w: &String| -> Item {
        let view = View::time_series(title)
            .origin(format!("/compare/{w}/{quantity}"))
            .legend_rows(models);
        match extent(k, quantity).and_then(|[lo, hi]| super::layout::round_range(lo, hi)) {
            Some([lo, hi]) => view.y_range(lo, hi).into(),
            None => view.into(),
        }
    };
    let diff = |k: usize, w: &String, quantity: &str, label: &str, unit: &str, bound: f64| {
        let base = format!("{w}: {label} from the first model [{unit}]");
        // The models but the first, and the bound.
        let view = |title: String| {
            View::time_series(title)
                .origin(format!("/compare/{w}/{quantity}"))
                .legend_rows(models)
        };
        match extent(k, quantity).and_then(|[lo, hi]| super::layout::round_range(lo.min(0.0), hi.max(0.0))) {
            Some([lo, hi]) => {
                let largest = lo.abs().max(hi.abs());
                let title = if largest < bound {
                    format!("{base}; the paper's ± {bound} {unit} lie off this scale")
                } else {
                    format!("{base} (grey: the paper's ± {bound} {unit})")
                };
                view(title).y_range(lo, hi).into()
            }
            None => view(format!("{base} (grey: the paper's ± {bound} {unit})")).into(),
        }
    };
    wheelsets
        .iter()
        .enumerate()
        .map(|(k, w)| {
            Container::grid(
                3,
                [
                    values(k, format!("{w}: y [mm]"), "y_mm", w),
                    diff(k, w, "dy_mm", "Δy", "mm", 1.0),
                    values(k, format!("{w}: normal force left [kN]"), "normal_left_kn", w),
                    values(k, format!("{w}: yaw [mrad]"), "yaw_mrad", w),
                    diff(k, w, "dyaw_mrad", "Δyaw", "mrad", 0.5),
                    values(k, format!("{w}: normal force right [kN]"), "normal_right_kn", w),
                ],
            )
            .named(w.clone())
            .into()
        })
        .collect()
}

/// The smallest and largest value of `quantity` (`y_mm`, `yaw_mrad`, `normal_left_kn`,
/// `normal_right_kn`) on the `k`th wheelset over every model, over the samples every run covers
/// (what [`record`] logs); None for another quantity.
fn value_extent(c: &Comparison, k: usize, quantity: &str) -> Option<[f64; 2]> {
    let f: fn(&Sample) -> f64 = match quantity {
        "y_mm" => |s| s.y * 1e3,
        "yaw_mrad" => |s| s.yaw * 1e3,
        "normal_left_kn" => |s| s.normal[0] * 1e-3,
        "normal_right_kn" => |s| s.normal[1] * 1e-3,
        _ => return None,
    };
    let mut range: Option<[f64; 2]> = None;
    for run in &c.runs {
        for s in run
            .output
            .wheelsets
            .get(k)?
            .1
            .iter()
            .take_while(|s| s.t <= c.common_s + 1e-9)
        {
            let v = f(s);
            if v.is_finite() {
                range = Some(range.map_or([v, v], |[lo, hi]| [lo.min(v), hi.max(v)]));
            }
        }
    }
    range
}

/// The smallest and largest difference from the first model of `quantity` (`dy_mm`, `dyaw_mrad`)
/// on the `k`th wheelset, over the samples every run covers (what [`record`] logs).
fn difference_extent(c: &Comparison, k: usize, quantity: &str) -> Option<[f64; 2]> {
    let f = |s: &Sample| match quantity {
        "dy_mm" => s.y * 1e3,
        _ => s.yaw * 1e3,
    };
    let first = &c.runs.first()?.output.wheelsets.get(k)?.1;
    let mut range: Option<[f64; 2]> = None;
    for run in c.runs.iter().skip(1) {
        let other = &run.output.wheelsets.get(k)?.1;
        for (a, b) in first
            .iter()
            .zip(other)
            .take_while(|(a, _)| a.t <= c.common_s + 1e-9)
        {
            let d = f(b) - f(a);
            if d.is_finite() {
                range = Some(range.map_or([d, d], |[lo, hi]| [lo.min(d), hi.max(d)]));
            }
        }
    }
    range
}

/// Lateral spacing of the models' vehicles in the 3D view, m: each on a track of its own, drawn
/// side by side (the models ran on the same track).
pub const MODEL_SPACING_M: f64 = 4.0;

/// The layout for a comparison: the models' vehicles in 3D, side by side on parallel tracks
/// (following the first model's front wheelset), with the report; then a tab per wheelset shown.
pub fn blueprint(c: &Comparison) -> Layout {
    let Some(first) = c.runs.first() else {
        return blueprint_for(&shown(c));
    };
    let k = c.runs.len() as f32;
    let spread = (k - 1.0) * MODEL_SPACING_M as f32;
    let world = View::spatial3d(format!(
        "every model's vehicle on a track of its own, {} m apart (left to right: {}); {}",
        MODEL_SPACING_M,
        c.runs
            .iter()
            .map(|r| r.model.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        World3d::title(&World3dSettings::default()),
    ))
    .origin(format!("/compare/world/{}/follow", first.model))
    .contents(["/compare/world/**"])
    .eye([12.0, -14.0 - spread, 9.0], [-8.0, 0.5 * spread, 1.0]);
    // The result first: the report (its result lines, then the tables) above the vehicles.
    let mut tabs: Vec<Item> = vec![Container::vertical([
        View::text_document("Report").origin("/compare/summary").into(),
        world.into(),
    ])
    .shares([1.3, 1.0])
    .named("Report and vehicles")
    .into()];
    tabs.extend(wheelset_tabs(&shown(c), c.runs.len(), &|k, q| match q {
        "dy_mm" | "dyaw_mrad" => difference_extent(c, k, q),
        _ => value_extent(c, k, q),
    }));
    Layout::new(Container::tabs(tabs)).timeline(TIME)
}

/// Every model's vehicle in 3D (`compare/world/MODEL`, see the module doc), over the time every run
/// covers.
fn record_world(rec: &RecordingStream, c: &Comparison, scene: &Scene) -> Result<(), InspectError> {
    for (k, run) in c.runs.iter().enumerate() {
        let (r, g, b) = PALETTE[k % PALETTE.len()];
        let style = WorldStyle {
            root: format!("compare/world/{}", run.model),
            track: true,
            offset_m: k as f64 * MODEL_SPACING_M,
            // Every model in its plots' colour (the first one too: it was left grey).
            tint: Some(Color::from_unmultiplied_rgba(r, g, b, 110)),
        };
        let mut world = World3d::styled(scene, World3dSettings::default(), style);
        world.log_statics(rec)?;
        let out = &run.output;
        let n = out
            .wheelsets
            .iter()
            .map(|(_, s)| s.iter().take_while(|p| p.t <= c.common_s + 1e-9).count())
            .min()
            .unwrap_or(0);
        for i in 0..n {
            let wheelsets: Vec<Sample> = out.wheelsets.iter().map(|(_, s)| s[i]).collect();
            let bodies: Vec<_> = out
                .bodies
                .iter()
                .filter_map(|(_, b)| b.get(i).map(|(_, q)| *q))
                .collect();
            world.sample(wheelsets[0].t, &wheelsets, &bodies, &[]);
        }
        world.send(rec, TIME, super::run::DISTANCE)?;
    }
    Ok(())
}

/// Records the comparison (see the module doc) of `scene`'s runs.
pub fn record(rec: &RecordingStream, c: &Comparison, scene: &Scene) -> Result<(), InspectError> {
    record_world(rec, c, scene)?;
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
            // The paper's bounds, ± (KEC within 1 mm and 0.5 mrad of the tables).
            for (quantity, bound) in super::PAPER_BOUNDS {
                for (sign, which) in [(1.0, "bound"), (-1.0, "bound_negative")] {
                    super::log_bound(
                        rec,
                        vec![TimeColumn::new_duration_secs(
                            TIME,
                            [series[0][0].t, series[0][n - 1].t],
                        )],
                        &format!("compare/{name}/{quantity}/{which}"),
                        sign * bound,
                        "the paper's bound",
                    )?;
                }
            }
        }
    }
    log_static(rec, "compare/summary", &TextDocument::from_markdown(c.markdown()))
}
