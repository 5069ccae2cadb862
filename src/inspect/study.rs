//! `kecsim study`: one recording that compares a study's cases — each extract against the first
//! axis (one line per combination of the other axes that vary: e.g. the statistic against speed,
//! one line per track realisation, so that the scatter over seeds shows; for a critical-speed
//! study the limit cycle's amplitude against speed, the bifurcation diagram), every case's front
//! wheelset y over time on one plot, and the results table.
//!
//! The diagrams are 2D views with linear axes: x from the first axis's smallest to largest value
//! (its values' order where they are not numbers) mapped to 0..1000, y from the extract's smallest
//! to largest value mapped to 600..0 (the 2D view's y axis points down); frame and round ticks
//! (1, 2 or 5 × 10^k) labelled, the axes named as a reader reads them with their units
//! ([`axis_label`]: `simulation.speed_m_s` → `speed [m/s]`). Failed and derailed cases are drawn red, stopped ones amber.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `study/EXTRACT/grid` | LineStrips2D, static | frame and ticks |
//! | `study/EXTRACT/grid/labels` | Points2D, static | the ticks' values and the first axis's name, placed off the frame so that none overlaps |
//! | `study/EXTRACT/critical_K`, `…/critical_K/label` | LineStrips2D and Points2D, static | a critical-speed study: each critical speed as a vertical line, its label at a height of its own |
//! | `study/EXTRACT/group_K` | LineStrips2D, Points2D, static | the cases of one combination of the other varying axes |
//! | `study/front_y/case_NNNNN` | Scalars on `time` | the case's first wheelset's lateral displacement, mm |
//! | `study/summary` | TextDocument, static | the results table |

use std::path::Path;

use super::{Container, Item, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument, TimeColumn};

use super::{log_static, send_scalar_rows, InspectError};
use crate::study::run::front_wheelset_y;
use crate::study::{first_appearances, CaseResult, Manifest, StudyError};

/// The simulated-time timeline.
pub const TIME: &str = "time";

/// Entity-path part of an extract's name (`rms(w1.y_mm)` → `rms_w1_y_mm`).
fn slug(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    s.trim_matches('_').replace("__", "_")
}

/// The layout, readable at 1600×1000: the extracts' diagrams in a grid across the top (up to three
/// a row), every case's front wheelset y and the table below.
pub fn blueprint_for(manifest: &Manifest) -> Layout {
    blueprint_with(manifest, None)
}

/// The smallest and largest front wheelset y (mm) of the cases `rows` of the study in `out` (for
/// [`blueprint_with`]); None without any. A case CSV that cannot be read (a FIFO, a device, a
/// link, a file past its bound, a row that does not read) is an error naming it.
pub fn front_y_extent(out: &Path, rows: &[CaseResult]) -> Result<Option<[f64; 2]>, StudyError> {
    let mut range: Option<[f64; 2]> = None;
    for r in rows {
        for (_, y) in front_wheelset_y(out, r)? {
            if y.is_finite() {
                range = Some(range.map_or([y, y], |[lo, hi]| [lo.min(y), hi.max(y)]));
            }
        }
    }
    Ok(range)
}

/// [`blueprint_for`] with the every-case plot's y extent `front_y` (mm) known: its y range padded
/// to round labels, with room above the data for its legend (a line per case up to four; more
/// cases go without one, each line named on hover).
pub fn blueprint_with(manifest: &Manifest, front_y: Option<[f64; 2]>) -> Layout {
    let against = manifest.axes.first().map_or("case".to_string(), |a| a.clone());
    let views: Vec<Item> = manifest
        .extracts
        .iter()
        .map(|x| {
            View::spatial2d(format!("{} against {}", axis_label(x), axis_label(&against)))
                .origin(format!("/study/{}", slug(x)))
                .into()
        })
        .collect();
    let below = Container::horizontal([
        {
            let view = View::time_series(if manifest.cases <= 4 {
                "every case: front wheelset y [mm]".to_string()
            } else {
                format!(
                    "every case: front wheelset y [mm], a line per case ({}; hover for its case)",
                    manifest.cases
                )
            })
            .origin("/study/front_y");
            let view = if manifest.cases <= 4 {
                view.legend_rows(manifest.cases)
            } else {
                view.no_legend()
            };
            match front_y.and_then(|[lo, hi]| super::layout::round_range(lo, hi)) {
                Some([lo, hi]) => view.y_range(lo, hi).into(),
                None => view.into(),
            }
        },
        View::text_document("Results").origin("/study/summary").into(),
    ])
    .into();
    let columns = match views.len() {
        0..=2 => views.len().max(1),
        4 => 2,
        _ => 3,
    };
    let rows_of_views = views.len().div_ceil(columns) as f32;
    let layout: Item = if views.is_empty() {
        below
    } else {
        Container::vertical([Container::grid(columns as u32, views).into(), below])
            .shares([2.0 * rows_of_views, 2.0])
            .into()
    };
    Layout::new(layout).timeline(TIME)
}

/// A linear axis: the values' span mapped onto `0..len` (`flip`: len..0).
struct Scale {
    lo: f64,
    hi: f64,
    len: f64,
    flip: bool,
}

impl Scale {
    fn of(values: impl Iterator<Item = f64>, len: f64, flip: bool) -> Option<Scale> {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if lo > hi {
            return None;
        }
        // A single value: a unit span around it.
        let (lo, hi) = if hi > lo { (lo, hi) } else { (lo - 0.5, hi + 0.5) };
        Some(Scale { lo, hi, len, flip })
    }
    fn at(&self, v: f64) -> f32 {
        let u = (v - self.lo) / (self.hi - self.lo) * self.len;
        (if self.flip { self.len - u } else { u }) as f32
    }
    /// Round ticks within the span: a step of 1, 2 or 5 × 10^k giving 3 to 6 of them.
    fn ticks(&self) -> Vec<f64> {
        nice_ticks(self.lo, self.hi).0
    }

    /// The decimals the ticks' step needs.
    fn decimals(&self) -> usize {
        let step = nice_ticks(self.lo, self.hi).1;
        (-step.log10().floor()).max(0.0) as usize
    }
}

/// Round ticks within `lo..=hi` and their step: 1, 2 or 5 × 10^k, the largest giving at least 3.
pub(crate) fn nice_ticks(lo: f64, hi: f64) -> (Vec<f64>, f64) {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let mut step = 10f64.powf((span / 3.0).log10().floor());
    for m in [5.0, 2.0, 1.0] {
        if span / (m * step) >= 3.0 - 1e-9 {
            step *= m;
            break;
        }
    }
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let ticks = (first..=last).map(|k| k as f64 * step).collect();
    (ticks, step)
}

/// A tick label with `decimals` decimals (a power-of-ten form for very large or small values).
fn tick(v: f64, decimals: usize) -> String {
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-4) {
        format!("{v:.2e}")
    } else {
        format!("{v:.decimals$}")
    }
}

/// A study key or extract as a reader reads it: the last part of the path, its unit suffix in
/// brackets (`simulation.speed_m_s` → `speed [m/s]`, `max_abs(w1.y_mm)` → `max_abs(w1.y) [mm]`).
pub fn axis_label(key: &str) -> String {
    const UNITS: [(&str, &str); 14] = [
        ("_m_s2", "m/s²"),
        ("_m_s", "m/s"),
        ("_km_h", "km/h"),
        ("_mrad", "mrad"),
        ("_rad", "rad"),
        ("_deg", "°"),
        ("_mm", "mm"),
        ("_kn", "kN"),
        ("_n", "N"),
        ("_hz", "Hz"),
        ("_kg", "kg"),
        ("_pa", "Pa"),
        ("_m", "m"),
        ("_s", "s"),
    ];
    // A function of a series (`max_abs(w1.y_mm)`): its unit after the closing bracket.
    let (head, inner, tail) = match (key.find('('), key.rfind(')')) {
        (Some(a), Some(b)) if a < b => (&key[..=a], &key[a + 1..b], &key[b..]),
        _ => ("", key, ""),
    };
    let last = if head.is_empty() {
        inner.rsplit('.').next().unwrap_or(inner)
    } else {
        inner
    };
    for (suffix, unit) in UNITS {
        if let Some(stem) = last.strip_suffix(suffix) {
            if !stem.is_empty() {
                return format!("{head}{}{tail} [{unit}]", stem.replace('_', " "))
                    .replace("( ", "(")
                    .trim()
                    .to_string();
            }
        }
    }
    format!("{head}{}{tail}", last.replace('_', " "))
}

fn status_color(status: &str, normal: Color) -> Color {
    match status {
        "completed" => normal,
        "stopped" => Color::from_rgb(230, 170, 40),
        _ => Color::from_rgb(220, 50, 50),
    }
}

/// A critical-speed study's critical speeds (m/s) with their labels: each group's linear critical
/// speed and the speed by which its nonlinear critical speed is reached (none for another study).
fn critical_markers(manifest: &Manifest, rows: &[CaseResult]) -> Vec<(f64, String)> {
    let Some(threshold) = manifest.critical_speed_threshold_mm else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for c in crate::study::critical::critical_speeds(manifest, rows, threshold) {
        let group = if c.group.is_empty() {
            String::new()
        } else {
            format!(" ({})", c.group)
        };
        if let Some(v) = c.linear_m_s {
            out.push((v, format!("linear critical speed {v:.1} m/s{group}")));
        }
        if let Some(v) = c.nonlinear_at_most_m_s {
            out.push((v, format!("nonlinear critical speed ≤ {v:.1} m/s{group}")));
        }
    }
    out
}

/// Records the study's results (`out`: its directory, for the cases' CSVs).
pub fn record(
    rec: &RecordingStream,
    manifest: &Manifest,
    rows: &[CaseResult],
    table: &str,
    out: &Path,
) -> Result<(), InspectError> {
    // x of each case: the first axis's value, or its rank among the distinct values where they
    // are not numbers (or the case index without axes).
    let first: Vec<String> = rows
        .iter()
        .map(|r| r.values.first().cloned().unwrap_or_default())
        .collect();
    let numeric: Option<Vec<f64>> = first.iter().map(|v| v.parse::<f64>().ok()).collect();
    let distinct = first_appearances(first.iter());
    let xs: Vec<f64> = match (&numeric, manifest.axes.is_empty()) {
        (_, true) => rows.iter().map(|r| r.case as f64).collect(),
        (Some(v), false) => v.clone(),
        (None, false) => first
            .iter()
            .map(|v| distinct.iter().position(|d| *d == v).unwrap_or(0) as f64)
            .collect(),
    };
    let x_name = manifest.axes.first().cloned().unwrap_or_else(|| "case".into());
    // Groups: the values of the other axes that vary (one line per combination).
    let varies: Vec<bool> = (0..manifest.axes.len())
        .map(|k| rows.iter().any(|r| r.values.get(k) != rows[0].values.get(k)))
        .collect();
    let group_of = |r: &CaseResult| r.axes_text(&manifest.axes, |k| k >= 1 && varies[k]);
    let groups = first_appearances(rows.iter().map(group_of));
    let Some(sx) = Scale::of(xs.iter().copied(), 1000.0, false) else {
        return log_static(rec, "study/summary", &TextDocument::from_markdown(table));
    };
    for (e, name) in manifest.extracts.iter().enumerate() {
        let ys: Vec<Option<f64>> = rows
            .iter()
            .map(|r| r.extracts.get(e).copied().flatten())
            .collect();
        let Some(sy) = Scale::of(ys.iter().flatten().copied(), 600.0, true) else {
            continue;
        };
        let base = format!("study/{}", slug(name));
        let (x0, x1, y0, y1) = (sx.at(sx.lo), sx.at(sx.hi), sy.at(sy.lo), sy.at(sy.hi));
        // The frame and ticks; their labels as invisible points placed off the frame (a strip's
        // label sits on the strip, over the frame and the next tick's).
        let mut strips = vec![vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]];
        let mut at = Vec::new();
        let mut labels = Vec::new();
        for t in sx.ticks() {
            let x = sx.at(t);
            strips.push(vec![[x, y0], [x, y0 + 12.0]]);
            at.push([x, y0 + 55.0]);
            labels.push(match (&numeric, manifest.axes.is_empty()) {
                (None, false) => distinct
                    .get(t.round() as usize)
                    .map_or(String::new(), |d| d.to_string()),
                _ => tick(t, sx.decimals()),
            });
        }
        for t in sy.ticks() {
            let y = sy.at(t);
            strips.push(vec![[x0 - 12.0, y], [x0, y]]);
            at.push([x0 - 90.0, y]);
            labels.push(tick(t, sy.decimals()));
        }
        at.push([0.5 * (x0 + x1), y0 + 115.0]);
        labels.push(axis_label(&x_name));
        log_static(
            rec,
            &format!("{base}/grid"),
            &LineStrips2D::new(strips)
                .with_colors([Color::from_rgb(90, 90, 100)])
                .with_radii([Radius::new_ui_points(0.5)]),
        )?;
        let n_labels = at.len();
        log_static(
            rec,
            &format!("{base}/grid/labels"),
            &Points2D::new(at)
                .with_labels(labels)
                .with_colors(std::iter::repeat_n(Color::from_rgb(170, 170, 180), n_labels))
                .with_radii(std::iter::repeat_n(Radius::new_ui_points(0.0), n_labels)),
        )?;
        // A critical-speed study's critical speeds, as vertical lines on its speed axis.
        let markers = critical_markers(manifest, rows);
        for (k, (v, label)) in markers.iter().enumerate() {
            if numeric.is_none() || *v < sx.lo || *v > sx.hi {
                continue;
            }
            let x = sx.at(*v);
            log_static(
                rec,
                &format!("{base}/critical_{k}"),
                &LineStrips2D::new([vec![[x, y0], [x, y1]]])
                    .with_colors([Color::from_rgb(220, 60, 60)])
                    .with_radii([Radius::new_ui_points(1.0)]),
            )?;
            // Each line's label at a height of its own (two lines a few m/s apart had their
            // labels drawn over each other at the lines' middles).
            let at = y1 + (y0 - y1) * (0.12 + 0.22 * (k % 4) as f32);
            log_static(
                rec,
                &format!("{base}/critical_{k}/label"),
                &Points2D::new([[x, at]])
                    .with_labels([label.clone()])
                    .with_colors([Color::from_rgb(220, 60, 60)])
                    .with_radii([Radius::new_ui_points(0.0)])
                    .with_show_labels(true),
            )?;
        }
        for (k, g) in groups.iter().enumerate() {
            let color = super::compare::colors(1, k)[0];
            let mut members: Vec<(f64, f64, &CaseResult)> = rows
                .iter()
                .zip(&xs)
                .zip(&ys)
                .filter(|((r, _), _)| group_of(r) == *g)
                .filter_map(|((r, x), y)| y.map(|y| (*x, y, r)))
                .collect();
            members.sort_by(|a, b| a.0.total_cmp(&b.0));
            if members.is_empty() {
                continue;
            }
            let entity = format!("{base}/group_{k}");
            let pts: Vec<[f32; 2]> = members.iter().map(|m| [sx.at(m.0), sy.at(m.1)]).collect();
            // A line is labelled only where there are several (the view's title names the
            // extract).
            let line = LineStrips2D::new([pts.clone()])
                .with_colors([color])
                .with_radii([Radius::new_ui_points(1.0)]);
            let line = if groups.len() > 1 && !g.is_empty() {
                line.with_labels([g.clone()])
            } else {
                line
            };
            log_static(rec, &entity, &line)?;
            log_static(
                rec,
                &format!("{entity}/points"),
                &Points2D::new(pts)
                    .with_colors(members.iter().map(|m| status_color(&m.2.status, color)))
                    .with_radii([Radius::new_ui_points(3.5)]),
            )?;
        }
    }
    for r in rows {
        let y = front_wheelset_y(out, r).map_err(|e| InspectError::Model(e.to_string()))?;
        if y.is_empty() {
            continue;
        }
        let varying = r.axes_text(&manifest.axes, |k| varies[k]);
        let label = if varying.is_empty() {
            format!("case {}", r.case)
        } else {
            format!("case {}: {varying}", r.case)
        };
        send_scalar_rows(
            rec,
            vec![TimeColumn::new_duration_secs(TIME, y.iter().map(|p| p.0))],
            y.len(),
            &format!("study/front_y/case_{:05}", r.case),
            y.iter().map(|p| p.1).collect(),
            &[label.as_str()],
            vec![status_color(&r.status, super::compare::colors(1, r.case)[0])],
        )?;
    }
    log_static(rec, "study/summary", &TextDocument::from_markdown(table))
}

#[cfg(test)]
mod label_tests {
    use super::*;

    #[test]
    fn keys_read_as_names_with_units() {
        assert_eq!(axis_label("simulation.speed_m_s"), "speed [m/s]");
        assert_eq!(axis_label("max_abs(w1.y_mm)"), "max_abs(w1.y) [mm]");
        assert_eq!(axis_label("contact_forces.friction"), "friction");
        assert_eq!(axis_label("rms(*.yaw_mrad)"), "rms(*.yaw) [mrad]");
    }

    /// Ticks at round values (a tick at 1.086e-5 read as noise), 3 to 6 of them, within the span.
    #[test]
    fn ticks_are_round() {
        for (lo, hi) in [
            (0.0, 1.0),
            (1.086e-5, 4.2e-5),
            (15.0, 45.0),
            (-7.5, 7.5),
            (0.37, 0.38),
        ] {
            let (t, step) = nice_ticks(lo, hi);
            assert!((3..=6).contains(&t.len()), "{lo}..{hi}: {t:?}");
            assert!(t.iter().all(|v| *v >= lo - 1e-12 && *v <= hi + 1e-12), "{t:?}");
            let m = step / 10f64.powf(step.log10().floor());
            assert!([1.0, 2.0, 5.0].iter().any(|x| (m - x).abs() < 1e-9), "{step}");
            for v in &t {
                assert!(((v / step) - (v / step).round()).abs() < 1e-9);
            }
        }
    }
}
