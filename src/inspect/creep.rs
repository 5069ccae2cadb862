//! `kecsim creep`: creep-force curves and the contact patch.
//!
//! Timeline `creepage_step`: the swept creepage (ξx on the longitudinal curves, ξy on the lateral
//! ones) in steps of the sweep, ξ = step · Δξ with Δξ = 2 ξmax / (points − 1) (10⁻⁴ by default, so
//! the step reads as ξ in units of 10⁻⁴). A sequence timeline of a few hundred steps: the viewer's
//! time-series plots open on a window of about a thousand ticks around the time cursor, so a finer
//! unit (e.g. 10⁻⁶) would show only a sliver of each curve.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `creep/longitudinal/fx_n/{model}` | Scalars on `creepage_step` | Fx vs ξx, one line per normal load (½N, N, 1½N; a, b ∝ N^⅓) |
//! | `creep/lateral/fy_n/{model}` | Scalars | Fy vs ξy at N, one line per spin |
//! | `creep/lateral/mz_nm/{model}` | Scalars | spin moment Mz vs ξy at N, one line per spin (FASTSIM and the linear theory) |
//! | `creep/figures/{fx,fy,mz}` | [`super::xyplot`], static; a cursor on `creepage_step` | the curves above against ξ in %, kN and N·m, as the layout shows them (legend: the models; a model's lines its shades) |
//! | `creep/patch/ellipse` | LineStrips2D, static | the contact ellipse, mm (x rolling direction to the right, y lateral up) |
//! | `creep/patch/{longitudinal,lateral}` | Points2D per step | FASTSIM traction distribution of each curve: adhesion (green) and slip (red) elements, size ∝ |p| |
//! | `creep/summary` | TextDocument, static | inputs, Kalker coefficients, model parameters |

use super::{Container, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument};

use super::xyplot::{log_owned, OwnedSeries};
use super::{log_static, send_scalar_columns, InspectError};
use crate::contact::forces::fastsim::{distribution, FastsimSettings};
use crate::contact::forces::sweep::{curve, Curve, SweepSettings};
use crate::contact::forces::{ContactPatch, CreepModel, Creepage};

/// The timeline of the sweep.
pub const TIMELINE: &str = "creepage_step";

/// Layout: the three plots on top, the patch views and the summary below; the time cursor follows
/// the data (opens at the end of the sweep: full sliding).
pub fn blueprint() -> Layout {
    // Static x–y figures (ξ in % at round ticks), the models named right of each plot.
    let plot = |title: &str, origin: &str| {
        let (x, y) = super::xyplot::BOUNDS_WITH_LEGEND;
        View::spatial2d(title)
            .origin(origin.to_string())
            .bounds(x, y)
            .into()
    };
    Layout::new(
        Container::vertical([
            Container::horizontal([
                plot(
                    "Fx [kN] vs ξx [%] at N/2, N, 3N/2 (larger |Fx| at larger N)",
                    "/creep/figures/fx",
                ),
                plot("Fy [kN] vs ξy [%], spins 0 and φ (φ darker)", "/creep/figures/fy"),
                plot(
                    "Mz [N·m] vs ξy [%], spins 0 and φ (φ darker)",
                    "/creep/figures/mz",
                ),
            ])
            .into(),
            Container::horizontal([
                View::spatial2d("FASTSIM patch, longitudinal curve (green adhesion, red slip)")
                    .origin("/creep/patch")
                    .contents(["/creep/patch/ellipse", "/creep/patch/longitudinal"])
                    .into(),
                View::spatial2d("FASTSIM patch, lateral curve")
                    .origin("/creep/patch")
                    .contents(["/creep/patch/ellipse", "/creep/patch/lateral"])
                    .into(),
                View::text_document("Summary").origin("/creep/summary").into(),
            ])
            .into(),
        ])
        .shares([3.0, 2.0]),
    )
    .timeline(TIMELINE)
    .play_state(super::layout::PlayState::Following)
}

fn model_color(name: &str, shade: usize) -> Color {
    let base: [f32; 3] = match name {
        "kalker" => [60.0, 120.0, 230.0],
        "polach" => [230.0, 130.0, 40.0],
        "fastrip" => [150.0, 80.0, 200.0],
        "exact" => [200.0, 200.0, 190.0],
        "exact-table" => [200.0, 50.0, 120.0],
        _ => [40.0, 170.0, 80.0],
    };
    let k = [1.0, 0.65, 1.35][shade % 3];
    let c = base.map(|v| (v * k).min(255.0) as u8);
    Color::from_rgb(c[0], c[1], c[2])
}

/// The spins shown on the lateral curves: 0 and the chosen one (0, 1, 2 1/m when it is 0).
pub fn spins(spin: f64) -> Vec<f64> {
    if spin == 0.0 {
        vec![0.0, 1.0, 2.0]
    } else {
        vec![0.0, spin]
    }
}

/// Records the curves of `models` on `patch` (at spin `spin` for the longitudinal curves), the
/// patch and the `summary`.
pub fn record(
    rec: &RecordingStream,
    models: &[CreepModel],
    patch: &ContactPatch,
    spin: f64,
    settings: &SweepSettings,
    summary: &str,
) -> Result<(), InspectError> {
    let xis = settings.creepages();
    let half = (xis.len() as i64 - 1) / 2;
    let ticks: Vec<i64> = (0..xis.len() as i64).map(|i| i - half).collect();
    let err = |e: crate::contact::forces::CreepForceError| InspectError::Model(e.to_string());
    let n0 = patch.normal_force;
    // The figures' series (name, colour, points (ξ %, value)), every model's.
    let mut figures: [Vec<OwnedSeries>; 3] = Default::default();
    // Series k of `values` (interleaved by row, n a row) against ξ in %, scaled.
    let series = |name: &str, color: Color, values: &[f64], k: usize, n: usize, scale: f64| OwnedSeries {
        name: name.to_string(),
        color,
        width: 1.5,
        points: xis
            .iter()
            .zip(values.iter().skip(k).step_by(n))
            .map(|(&xi, &v)| (xi * 100.0, v * scale))
            .collect(),
    };
    for model in models {
        let name = model.name();
        // Fx vs ξx for three loads.
        let loads = [0.5 * n0, n0, 1.5 * n0];
        let mut values = vec![0.0; xis.len() * loads.len()];
        for (k, &n) in loads.iter().enumerate() {
            for (i, p) in curve(model, &patch.scaled(n), Curve::Longitudinal, spin, settings)
                .map_err(err)?
                .iter()
                .enumerate()
            {
                values[i * loads.len() + k] = p.force.fx;
            }
        }
        let names: Vec<String> = loads
            .iter()
            .map(|n| format!("{name} N = {:.0} kN", n * 1e-3))
            .collect();
        let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let colors: Vec<Color> = (0..loads.len()).map(|k| model_color(name, k)).collect();
        for (k, (label, &color)) in names.iter().zip(&colors).enumerate() {
            figures[0].push(series(label, color, &values, k, loads.len(), 1e-3));
        }
        send_scalar_columns(
            rec,
            TIMELINE,
            &format!("creep/longitudinal/fx_n/{name}"),
            &ticks,
            values,
            &name_refs,
            colors,
        )?;

        // Fy and Mz vs ξy for the spins.
        let spins = spins(spin);
        let mut fy = vec![0.0; xis.len() * spins.len()];
        let mut mz = vec![0.0; xis.len() * spins.len()];
        for (k, &s) in spins.iter().enumerate() {
            for (i, p) in curve(model, patch, Curve::Lateral, s, settings)
                .map_err(err)?
                .iter()
                .enumerate()
            {
                fy[i * spins.len() + k] = p.force.fy;
                mz[i * spins.len() + k] = p.force.mz;
            }
        }
        let names: Vec<String> = spins.iter().map(|s| format!("{name} φ = {s} 1/m")).collect();
        let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let colors = || {
            (0..spins.len())
                .map(|k| model_color(name, k))
                .collect::<Vec<Color>>()
        };
        // Spin 0 in the model's colour, the others darker (shade 1).
        let shade = |k: usize| model_color(name, if k == 0 { 0 } else { 1 });
        for (k, label) in names.iter().enumerate() {
            figures[1].push(series(label, shade(k), &fy, k, spins.len(), 1e-3));
            if name != "polach" {
                figures[2].push(series(label, shade(k), &mz, k, spins.len(), 1.0));
            }
        }
        send_scalar_columns(
            rec,
            TIMELINE,
            &format!("creep/lateral/fy_n/{name}"),
            &ticks,
            fy,
            &name_refs,
            colors(),
        )?;
        if name != "polach" {
            send_scalar_columns(
                rec,
                TIMELINE,
                &format!("creep/lateral/mz_nm/{name}"),
                &ticks,
                mz,
                &name_refs,
                colors(),
            )?;
        }
    }

    // The figures: the legend names each model once, in its base colour.
    let legend: Vec<(&str, Color)> = models
        .iter()
        .map(|m| (m.name(), model_color(m.name(), 0)))
        .collect();
    for (figure, entity) in figures.iter().zip(["fx", "fy", "mz"]) {
        log_owned(
            rec,
            &format!("creep/figures/{entity}"),
            figure,
            super::xyplot::Extras {
                legend: true,
                legend_entries: &legend,
                cursor: Some((TIMELINE, &ticks)),
            },
        )?;
    }

    // The ellipse, mm: x to the right, y up (Rerun's 2D view is Y-down).
    let ellipse: Vec<[f32; 2]> = (0..=120)
        .map(|i| {
            let t = i as f64 / 120.0 * std::f64::consts::TAU;
            [
                (patch.a * t.cos() * 1e3) as f32,
                (-patch.b * t.sin() * 1e3) as f32,
            ]
        })
        .collect();
    log_static(
        rec,
        "creep/patch/ellipse",
        &LineStrips2D::new([ellipse])
            .with_colors([Color::from_rgb(150, 150, 160)])
            .with_radii([Radius::new_ui_points(1.5)]),
    )?;

    // FASTSIM's traction distribution along each curve (the model whose elements these are).
    let fast = models
        .iter()
        .find_map(|m| match m {
            CreepModel::Fastsim(s) => Some(*s),
            _ => None,
        })
        .unwrap_or_default();
    let fast = FastsimSettings {
        strips: fast.strips.min(40),
        elements: fast.elements.min(40),
        ..fast
    };
    let pmax =
        3.0 * patch.friction * patch.normal_force.max(0.0) / (std::f64::consts::PI * patch.a * patch.b);
    let cell = 2.0 * patch.a.min(patch.b) * 1e3 / fast.strips.max(fast.elements).max(1) as f64;
    for c in Curve::BOTH {
        let entity = format!("creep/patch/{}", c.name());
        for (&xi, &tick) in xis.iter().zip(&ticks) {
            let creep = match c {
                Curve::Longitudinal => Creepage::new(xi, 0.0, spin),
                Curve::Lateral => Creepage::new(0.0, xi, spin),
            };
            let (_, elems) = distribution(patch, &creep, &fast);
            rec.set_time_sequence(TIMELINE, tick);
            let pts: Vec<[f32; 2]> = elems
                .iter()
                .map(|e| [(e.x * 1e3) as f32, (-e.y * 1e3) as f32])
                .collect();
            let colors: Vec<Color> = elems
                .iter()
                .map(|e| {
                    if e.slip {
                        Color::from_rgb(220, 60, 50)
                    } else {
                        Color::from_rgb(50, 170, 80)
                    }
                })
                .collect();
            let radii: Vec<Radius> = elems
                .iter()
                .map(|e| {
                    let f = if pmax > 0.0 {
                        (e.px.hypot(e.py) / pmax).min(1.0)
                    } else {
                        0.0
                    };
                    Radius::new_scene_units((0.1 + 0.4 * f.sqrt()) as f32 * cell as f32)
                })
                .collect();
            let points = Points2D::new(pts).with_colors(colors).with_radii(radii);
            rec.log(entity.as_str(), &points)
                .map_err(|source| InspectError::Log {
                    entity: entity.clone(),
                    source,
                })?;
        }
    }
    log_static(rec, "creep/summary", &TextDocument::from_markdown(summary))?;
    Ok(())
}
