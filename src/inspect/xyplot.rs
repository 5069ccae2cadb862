//! A static x–y plot drawn into a 2D view: for a curve over something other than a timeline (a
//! sweep over the lateral shift), which a time-series view shows only while the time panel is on
//! that sweep's timeline (Rerun 0.36's views cannot choose their own). Static, it shows whatever
//! the time panel holds: a recording with sweeps and histories then opens with every tab full.
//!
//! The plot is drawn in a box of [`WIDTH`] × [`HEIGHT`] drawing units (y down, as the 2D view's),
//! the axes at its left and bottom edges with round ticks ([`ticks`]: three labels at least), each
//! series a line strip named for hovering. Two extras ([`Extras`]): a legend right of the box
//! (each series' name in its colour, outside the data; without it the view's title says which is
//! which), and a cursor — a marker on each curve at the time panel's cursor, for a sweep whose
//! other views (the cross-sections) follow that cursor.

use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream};

use super::{log_static, InspectError};

/// The plot box, drawing units.
pub const WIDTH: f64 = 1000.0;
pub const HEIGHT: f64 = 560.0;

/// One series: its name, colour, line width (UI points) and points (x, y).
pub struct Series<'a> {
    pub name: &'a str,
    pub color: Color,
    pub width: f32,
    pub points: &'a [(f64, f64)],
}

/// A series that owns its name and points: what a recording builds from its data before drawing
/// it with [`log_owned`].
#[derive(Debug, Clone)]
pub struct OwnedSeries {
    pub name: String,
    pub color: Color,
    pub width: f32,
    pub points: Vec<(f64, f64)>,
}

/// [`log_with`] for series that own their data.
pub fn log_owned(
    rec: &RecordingStream,
    entity: &str,
    series: &[OwnedSeries],
    extras: Extras<'_>,
) -> Result<(), InspectError> {
    let borrowed: Vec<Series<'_>> = series
        .iter()
        .map(|s| Series {
            name: &s.name,
            color: s.color,
            width: s.width,
            points: &s.points,
        })
        .collect();
    log_with(rec, entity, &borrowed, extras)
}

/// Round tick values over `lo..=hi`: steps of 1, 2 or 5 × 10^k, the largest giving three ticks
/// at least (fewer than 3 only for a degenerate range).
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return vec![lo];
    }
    let span = hi - lo;
    let mut step = 10f64.powf(span.log10().ceil());
    let mut k = 0;
    let count = |step: f64| ((hi / step).floor() - (lo / step).ceil() + 1.0).max(0.0) as usize;
    while count(step) < 3 && k < 60 {
        // 10 → 5 → 2 → 1 → 0.5 …
        step = match k % 3 {
            0 => step / 2.0,
            1 => step / 2.5,
            _ => step / 2.0,
        };
        k += 1;
    }
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// A positive value in few characters: `0.02`, `5`, `1e-5` (below 0.001 or from 10⁵ on).
pub fn short(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.0e}");
        return s;
    }
    let decimals = if a >= 1.0 { 0 } else { (-a.log10()).ceil() as usize };
    format!("{v:.decimals$}")
}

/// A tick's label: as few decimals as its step needs.
fn label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10()).ceil() as usize
    };
    format!("{v:.decimals$}")
}

/// The view's bounds for a plot (drawing units, with room for the tick labels), for
/// [`super::View::bounds`].
pub const BOUNDS: ([f64; 2], [f64; 2]) = ([-90.0, WIDTH + 20.0], [-20.0, HEIGHT + 70.0]);

/// The width of the legend's column right of the box, drawing units (a label of ~20 characters
/// in a ~450 px wide panel).
pub const LEGEND_WIDTH: f64 = 380.0;

/// The view's bounds for a plot with its legend right of the box ([`Extras::legend`]).
pub const BOUNDS_WITH_LEGEND: ([f64; 2], [f64; 2]) =
    ([-90.0, WIDTH + 20.0 + LEGEND_WIDTH], [-20.0, HEIGHT + 70.0]);

/// What a plot shows besides its axes and curves.
#[derive(Debug, Default, Clone, Copy)]
pub struct Extras<'a> {
    /// A legend right of the box, outside the data: each series' name in its colour, one a row
    /// (`entity/legend`; the view then needs [`BOUNDS_WITH_LEGEND`]).
    pub legend: bool,
    /// The legend's entries where they are not the series' names (one a model whose lines are
    /// its shades); empty: the series'.
    pub legend_entries: &'a [(&'a str, Color)],
    /// A marker on each curve at the time panel's cursor (`entity/cursor`): the timeline and the
    /// time of each point index (the same for every series: `points[i]` at `times[i]`).
    pub cursor: Option<(&'static str, &'a [i64])>,
}

/// Logs the plot under `entity` (static): `entity/axes`, `entity/ticks`, `entity/tick_labels`,
/// `entity/series/K`. The axes' names go into the view's title (the caller's).
pub fn log(rec: &RecordingStream, entity: &str, series: &[Series<'_>]) -> Result<(), InspectError> {
    log_with(rec, entity, series, Extras::default())
}

/// [`log`] with a legend and/or a cursor ([`Extras`]).
pub fn log_with(
    rec: &RecordingStream,
    entity: &str,
    series: &[Series<'_>],
    extras: Extras<'_>,
) -> Result<(), InspectError> {
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in all.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if !x0.is_finite() {
        return Ok(());
    }
    // The y range padded to its round ticks (a flat series: ± 1 % or ± 1).
    if y1 <= y0 {
        let pad = if y0 == 0.0 { 1.0 } else { 0.01 * y0.abs() };
        (y0, y1) = (y0 - pad, y1 + pad);
    }
    let pad = 0.05 * (y1 - y0);
    let yt = ticks(y0 - pad, y1 + pad);
    let ystep = yt.get(1).map_or(1.0, |b| b - yt[0]);
    let (y0, y1) = (
        y0.min((y0 / ystep).floor() * ystep),
        y1.max((y1 / ystep).ceil() * ystep),
    );
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let xt = ticks(x0, x1);
    let xstep = xt.get(1).map_or(1.0, |b| b - xt[0]);
    let px = |x: f64| ((x - x0) / (x1 - x0) * WIDTH) as f32;
    let py = |y: f64| ((y1 - y) / (y1 - y0) * HEIGHT) as f32;
    let grey = Color::from_rgb(170, 170, 170);
    log_static(
        rec,
        &format!("{entity}/axes"),
        &LineStrips2D::new([vec![
            [0.0, 0.0],
            [0.0, HEIGHT as f32],
            [WIDTH as f32, HEIGHT as f32],
        ]])
        .with_colors([grey])
        .with_radii([Radius::new_ui_points(1.0)]),
    )?;
    // Tick marks and their labels: x below the axis, y left of it.
    let mut marks = Vec::new();
    let mut at = Vec::new();
    let mut labels = Vec::new();
    for &x in xt.iter().filter(|x| (x0..=x1).contains(*x)) {
        marks.push(vec![[px(x), HEIGHT as f32], [px(x), HEIGHT as f32 + 8.0]]);
        at.push([px(x), HEIGHT as f32 + 22.0]);
        labels.push(label(x, xstep));
    }
    for &y in yt.iter().filter(|y| (y0..=y1).contains(*y)) {
        marks.push(vec![[-8.0, py(y)], [0.0, py(y)]]);
        at.push([-40.0, py(y)]);
        labels.push(label(y, ystep));
    }
    log_static(
        rec,
        &format!("{entity}/ticks"),
        &LineStrips2D::new(marks)
            .with_colors([grey])
            .with_radii([Radius::new_ui_points(1.0)]),
    )?;
    log_static(
        rec,
        &format!("{entity}/tick_labels"),
        &Points2D::new(at)
            .with_labels(labels)
            .with_colors([grey])
            .with_radii([Radius::new_ui_points(0.5)])
            .with_show_labels(true),
    )?;
    for (k, s) in series.iter().enumerate() {
        let pts: Vec<[f32; 2]> = s
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&(x, y)| [px(x), py(y)])
            .collect();
        log_static(
            rec,
            &format!("{entity}/series/{k}"),
            &LineStrips2D::new([pts])
                .with_colors([s.color])
                .with_radii([Radius::new_ui_points(s.width)])
                // Named for hovering; the view's title says which is which (a label drawn on
                // the curves sat on the data).
                .with_labels([s.name])
                .with_show_labels(false),
        )?;
    }
    if extras.legend {
        // The names centred in the column right of the box, top down, each in its series' colour
        // (a label takes its point's colour).
        let entries: Vec<(&str, Color)> = if extras.legend_entries.is_empty() {
            series.iter().map(|s| (s.name, s.color)).collect()
        } else {
            extras.legend_entries.to_vec()
        };
        let row = (HEIGHT / 10.0).min(HEIGHT / entries.len().max(1) as f64);
        let x = (WIDTH + 20.0 + LEGEND_WIDTH / 2.0) as f32;
        log_static(
            rec,
            &format!("{entity}/legend"),
            &Points2D::new((0..entries.len()).map(|k| [x, (row * (k as f64 + 0.5)) as f32]))
                .with_labels(entries.iter().map(|e| e.0))
                .with_colors(entries.iter().map(|e| e.1))
                .with_radii([Radius::new_ui_points(0.5)])
                .with_show_labels(true),
        )?;
    }
    if let Some((timeline, times)) = extras.cursor {
        let cursor = format!("{entity}/cursor");
        for (i, &t) in times.iter().enumerate() {
            let (pts, colors): (Vec<[f32; 2]>, Vec<Color>) = series
                .iter()
                .filter_map(|s| s.points.get(i).map(|&p| (p, s.color)))
                .filter(|((x, y), _)| x.is_finite() && y.is_finite())
                .map(|((x, y), c)| ([px(x), py(y)], c))
                .unzip();
            rec.set_time_sequence(timeline, t);
            rec.log(
                cursor.as_str(),
                &Points2D::new(pts)
                    .with_colors(colors)
                    .with_radii([Radius::new_ui_points(4.0)]),
            )
            .map_err(|source| InspectError::Log {
                entity: cursor.clone(),
                source,
            })?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{log_with, ticks, Extras, Series, HEIGHT, LEGEND_WIDTH, WIDTH};
    use rerun::Color;

    /// The legend sits right of the plot box (outside the data), one label per entry in its
    /// colour; the cursor puts one marker per series at each time, on the curve's point there.
    #[test]
    fn the_legend_is_outside_the_box_and_the_cursor_on_the_curves() {
        let (rec, storage) = rerun::RecordingStreamBuilder::new("kecsim-test")
            .memory()
            .unwrap();
        let a: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, (i * i) as f64)).collect();
        let b: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, -(i as f64))).collect();
        let series = [
            Series {
                name: "a",
                color: Color::from_rgb(255, 0, 0),
                width: 1.0,
                points: &a,
            },
            Series {
                name: "b",
                color: Color::from_rgb(0, 0, 255),
                width: 1.0,
                points: &b,
            },
        ];
        let times = [10, 20, 30, 40, 50];
        log_with(
            &rec,
            "plot",
            &series,
            Extras {
                legend: true,
                cursor: Some(("y_um", &times)),
                ..Default::default()
            },
        )
        .unwrap();
        rec.flush_blocking().unwrap();
        let chunks = super::super::readback::message_chunks(&storage.take(), "memory").unwrap();
        let positions = |entity: &str, statics: bool| -> Vec<[f32; 2]> {
            chunks
                .iter()
                .filter(|c| c.entity_path().to_string() == entity && c.is_static() == statics)
                .flat_map(|c| {
                    c.iter_slices::<[f32; 2]>(rerun::Points2D::descriptor_positions().component)
                        .flat_map(|v| v.to_vec())
                        .collect::<Vec<_>>()
                })
                .collect()
        };
        let legend = positions("/plot/legend", true);
        assert_eq!(legend.len(), 2);
        assert!(legend
            .iter()
            .all(|p| (p[0] as f64) > WIDTH && (p[0] as f64) < WIDTH + 20.0 + LEGEND_WIDTH));
        let cursor = positions("/plot/cursor", false);
        assert_eq!(cursor.len(), 2 * times.len(), "{cursor:?}");
        // The first marker of each time at series a's point: x = i / 4 of the box, y from the top.
        for (i, pair) in cursor.chunks(2).enumerate() {
            assert!(
                (pair[0][0] as f64 - i as f64 / 4.0 * WIDTH).abs() < 1e-3,
                "{pair:?}"
            );
            assert!(
                pair[0][1] as f64 >= 0.0 && pair[0][1] as f64 <= HEIGHT,
                "{pair:?}"
            );
        }
        // a rises, b falls: the last markers at a's top and below b's start.
        let last = cursor[cursor.len() - 2..].to_vec();
        assert!(
            last[0][1] < cursor[0][1] && last[1][1] > cursor[1][1],
            "{cursor:?}"
        );
    }

    /// Three round ticks at least, inside the range, evenly spaced by 1, 2 or 5 × 10^k.
    #[test]
    fn ticks_are_round_and_three_at_least() {
        for (lo, hi) in [
            (0.0, 1.0),
            (-7.5, 7.5),
            (0.0, 0.0071),
            (12.3, 13.1),
            (-4000.0, 4000.0),
            (95.0, 105.0),
        ] {
            let t = ticks(lo, hi);
            assert!(t.len() >= 3 && t.len() <= 12, "{lo}..{hi}: {t:?}");
            assert!(
                t.iter().all(|v| (lo - 1e-12..=hi + 1e-12).contains(v)),
                "{lo}..{hi}: {t:?}"
            );
            let step = t[1] - t[0];
            let mantissa = step / 10f64.powf(step.log10().floor());
            assert!(
                [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9),
                "{lo}..{hi}: step {step}"
            );
        }
    }
}
