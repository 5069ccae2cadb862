//! `kecsim patch`: the contact patches of a wheelset at each lateral shift, Hertz beside the strip
//! model.
//!
//! Timeline `shift_step`: the lateral shift y in steps of 0.1 mm (tick = round(10 y/mm)).
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `patch/pmax_mpa/{side}` | Scalars on `shift_step` | pmax per model (kp: its largest patch's) |
//! | `patch/fn_kn/{side}` | Scalars | normal force per model and patch (kp patch 1, 2) |
//! | `patch/area_mm2/{side}` | Scalars | patch area per model (kp: all patches) |
//! | `patch/section/{side}/{rail,wheel}` | LineStrips2D per shift | the profiles on the track cross-section, mm (wheel at its pose) |
//! | `patch/section/{side}/{model}` | LineStrips2D per shift | each patch on the rail and its pressure p(0, s) drawn along the rail's normal, 1 mm per [`MPA_PER_MM`] MPa |
//! | `patch/shape/{side}/{model}` | LineStrips2D per shift | each patch seen from above: x rolling (right), lateral along the rail (up), mm |
//! | `patch/summary` | TextDocument, static | the table of every patch |

use rerun::{Color, LineStrips2D, Radius, RecordingStream, TextDocument};

use super::{log_static, send_scalar_columns, Container, InspectError, Layout, View};
use crate::contact::nonhertz::sweep::{PatchModel, PatchResult, ShiftPatches};
use crate::profile::placement::WheelRailPair;
use crate::track::Side;

/// The timeline of the shifts.
pub const TIMELINE: &str = "shift_step";
/// Pressure drawn along the rail normal: this many MPa per mm.
pub const MPA_PER_MM: f64 = 200.0;

/// Layout: the three plots on top, each side's cross-section and patch shapes below.
pub fn blueprint() -> Layout {
    let plot = |title: &str, origin: &str| View::time_series(title).origin(origin.to_string()).into();
    let side_views = |side: &str| -> Container {
        Container::vertical([
            View::spatial2d(format!("{side}: profiles, pressure (1 mm = {MPA_PER_MM} MPa)"))
                .origin(format!("/patch/section/{side}"))
                .into(),
            View::spatial2d(format!("{side}: patches from above [mm]"))
                .origin(format!("/patch/shape/{side}"))
                .into(),
        ])
    };
    Layout::new(
        Container::vertical([
            Container::horizontal([
                plot("pmax [MPa], left, vs shift y [0.1 mm]", "/patch/pmax_mpa/left"),
                plot("pmax [MPa], right, vs shift y [0.1 mm]", "/patch/pmax_mpa/right"),
                plot("N [kN], left, vs shift y [0.1 mm]", "/patch/fn_kn/left"),
                plot("N [kN], right, vs shift y [0.1 mm]", "/patch/fn_kn/right"),
            ])
            .into(),
            // The table whole: its panel as wide as both sides' views together.
            Container::horizontal([
                side_views("left").into(),
                side_views("right").into(),
                View::text_document("Patches").origin("/patch/summary").into(),
            ])
            .shares([1.0, 1.0, 2.0])
            .into(),
        ])
        .shares([1.0, 2.0]),
    )
    .timeline(TIMELINE)
    .play_state(super::layout::PlayState::Following)
}

fn color(model: PatchModel, patch: usize) -> Color {
    match (model, patch) {
        (PatchModel::Hertz, _) => Color::from_rgb(60, 120, 230),
        (PatchModel::Strips, 0) => Color::from_rgb(230, 130, 40),
        _ => Color::from_rgb(200, 60, 160),
    }
}

fn log(rec: &RecordingStream, entity: &str, what: &impl rerun::AsComponents) -> Result<(), InspectError> {
    rec.log(entity, what).map_err(|source| InspectError::Log {
        entity: entity.to_string(),
        source,
    })
}

/// The pressure along the rail (s_r, p(0, s_r)) of a patch: the strips, or Hertz's semi-ellipse.
fn pressure_line(p: &PatchResult) -> Vec<(f64, f64)> {
    match &p.strips {
        Some(sp) => {
            let mut v = vec![(sp.s_rail_range.0, 0.0)];
            v.extend(sp.strips.iter().map(|s| (s.s_rail, s.pressure)));
            v.push((sp.s_rail_range.1, 0.0));
            v
        }
        None => {
            let b = p.semi_axes.1 * p.contact_angle.cos().abs().max(0.2);
            (0..=40)
                .map(|i| {
                    let t = -1.0 + 2.0 * i as f64 / 40.0;
                    (p.s_rail + t * b, p.max_pressure * (1.0 - t * t).max(0.0).sqrt())
                })
                .collect()
        }
    }
}

/// The patch seen from above: outline (x, lateral) in mm, lateral along the surface from the
/// load centre.
fn shape_outline(p: &PatchResult) -> Vec<[f32; 2]> {
    match &p.strips {
        Some(sp) => {
            let w0 = sp
                .strips
                .iter()
                .map(|s| s.half_length * s.half_length * s.width * s.w)
                .sum::<f64>()
                / sp.strips
                    .iter()
                    .map(|s| s.half_length * s.half_length * s.width)
                    .sum::<f64>();
            let mut lat = Vec::with_capacity(sp.strips.len());
            let mut acc = -sp
                .strips
                .iter()
                .take_while(|s| s.w < w0)
                .map(|s| s.width)
                .sum::<f64>();
            for s in &sp.strips {
                lat.push((acc + 0.5 * s.width, s.half_length));
                acc += s.width;
            }
            let mut pts: Vec<[f32; 2]> = lat
                .iter()
                .map(|(y, l)| [(l * 1e3) as f32, (-y * 1e3) as f32])
                .collect();
            pts.extend(
                lat.iter()
                    .rev()
                    .map(|(y, l)| [(-l * 1e3) as f32, (-y * 1e3) as f32]),
            );
            if let Some(f) = pts.first().copied() {
                pts.push(f);
            }
            pts
        }
        None => (0..=72)
            .map(|i| {
                let t = i as f64 / 72.0 * std::f64::consts::TAU;
                [
                    (p.semi_axes.0 * t.cos() * 1e3) as f32,
                    (-p.semi_axes.1 * t.sin() * 1e3) as f32,
                ]
            })
            .collect(),
    }
}

/// Records every shift's patches and the summary.
pub fn record(
    rec: &RecordingStream,
    pair: &WheelRailPair,
    shifts: &[ShiftPatches],
    summary: &str,
) -> Result<(), InspectError> {
    let tick = |y: f64| (y * 1e4).round() as i64;
    let mut ys: Vec<i64> = shifts.iter().map(|s| tick(s.y)).collect();
    ys.sort_unstable();
    ys.dedup();
    let models: Vec<PatchModel> = PatchModel::ALL
        .into_iter()
        .filter(|m| shifts.iter().any(|s| s.model == *m))
        .collect();
    for (i, side) in Side::BOTH.iter().enumerate() {
        let names: Vec<String> = models
            .iter()
            .flat_map(|m| match m {
                PatchModel::Hertz => vec!["hertz".to_string()],
                PatchModel::Strips => vec!["kp patch 1".to_string(), "kp patch 2".to_string()],
            })
            .collect();
        let colors: Vec<Color> = models
            .iter()
            .flat_map(|m| match m {
                PatchModel::Hertz => vec![color(*m, 0)],
                PatchModel::Strips => vec![color(*m, 0), color(*m, 1)],
            })
            .collect();
        let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut pmax = Vec::new();
        let mut fnk = Vec::new();
        for &t in &ys {
            for m in &models {
                let wp = shifts
                    .iter()
                    .find(|s| tick(s.y) == t && s.model == *m)
                    .map(|s| &s.wheels[i]);
                let k = if *m == PatchModel::Hertz { 1 } else { 2 };
                for j in 0..k {
                    let p = wp.and_then(|w| w.patches.get(j));
                    pmax.push(p.map_or(f64::NAN, |p| p.max_pressure * 1e-6));
                    fnk.push(p.map_or(f64::NAN, |p| p.normal_force * 1e-3));
                }
            }
        }
        send_scalar_columns(
            rec,
            TIMELINE,
            &format!("patch/pmax_mpa/{}", side.name()),
            &ys,
            pmax,
            &name_refs,
            colors.clone(),
        )?;
        send_scalar_columns(
            rec,
            TIMELINE,
            &format!("patch/fn_kn/{}", side.name()),
            &ys,
            fnk,
            &name_refs,
            colors,
        )?;
    }
    for sh in shifts {
        rec.set_time_sequence(TIMELINE, tick(sh.y));
        for (i, side) in Side::BOTH.iter().enumerate() {
            let wp = &sh.wheels[i];
            let base = format!("patch/section/{}", side.name());
            // Profiles within ±40 mm of the contact, track frame, mm (stored [Y, −Z]).
            let (cy, _) = wp.rigid.position;
            let (s0, s1) = pair.rail.domain_side(*side);
            let rail: Vec<[f32; 2]> = (0..=400)
                .map(|k| s0 + (s1 - s0) * k as f64 / 400.0)
                .map(|s| pair.rail_placement.rail_point(&pair.rail, *side, s))
                .filter(|p| (p.0 - cy).abs() < 0.04)
                .map(|p| super::section_mm(p.0, p.1))
                .collect();
            let (w0, w1) = pair.wheel.domain_side(*side);
            let wheel: Vec<[f32; 2]> = (0..=600)
                .map(|k| w0 + (w1 - w0) * k as f64 / 600.0)
                .map(|s| {
                    pair.wheelset
                        .wheel_point(&pair.wheel, *side, s, sh.y, sh.z, sh.roll)
                })
                .filter(|p| (p.0 - cy).abs() < 0.04)
                .map(|p| super::section_mm(p.0, p.1))
                .collect();
            if sh.model == PatchModel::ALL[0] || !shifts.iter().any(|s| s.model == PatchModel::ALL[0]) {
                log(
                    rec,
                    &format!("{base}/rail"),
                    &LineStrips2D::new([rail]).with_colors([Color::from_rgb(150, 150, 150)]),
                )?;
                log(
                    rec,
                    &format!("{base}/wheel"),
                    &LineStrips2D::new([wheel]).with_colors([Color::from_rgb(110, 110, 120)]),
                )?;
            }
            // Each patch's pressure along the rail normal.
            let mut lines = Vec::new();
            let mut cols = Vec::new();
            let mut shapes = Vec::new();
            for (k, p) in wp.patches.iter().enumerate() {
                let line: Vec<[f32; 2]> = pressure_line(p)
                    .into_iter()
                    .map(|(s, pr)| {
                        let (y, z) = pair.rail_placement.rail_point(&pair.rail, *side, s);
                        let d = pair.rail.eval_side(*side, s).dz;
                        let beta = side.sign() * pair.inclination.angle_rad;
                        let ang = (-d).atan() + beta;
                        let off = pr * 1e-6 / MPA_PER_MM * 1e-3;
                        super::section_mm(y - off * ang.sin(), z + off * ang.cos())
                    })
                    .collect();
                lines.push(line);
                cols.push(color(sh.model, k));
                shapes.push(shape_outline(p));
            }
            let model = sh.model.name();
            log(
                rec,
                &format!("{base}/{model}"),
                &LineStrips2D::new(lines)
                    .with_colors(cols.clone())
                    .with_radii([Radius::new_ui_points(1.5)]),
            )?;
            log(
                rec,
                &format!("patch/shape/{}/{model}", side.name()),
                &LineStrips2D::new(shapes)
                    .with_colors(cols)
                    .with_radii([Radius::new_ui_points(1.5)]),
            )?;
        }
    }
    log_static(rec, "patch/summary", &TextDocument::from_markdown(summary))
}
