//! `kecsim kec`: real against knife-edge-equivalent profiles (paper Fig. 10, 15–16).
//!
//! Timeline `y_um` as in [`super::contact`]. Entities (mm, cross-sections stored as `[Y, −Z]`):
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `kec/real/{left,right}/{rail,wheel,contact}` | LineStrips2D, Points2D | real profiles and contact, per y |
//! | `kec/equivalent/{left,right}/wheel` | LineStrips2D, per y | equivalent wheel profile at (y, z, φ) |
//! | `kec/equivalent/{left,right}/knife_edge` | Points2D, static | the knife-edge rail (the contact, always) |
//! | `kec/profiles/{left,right}` | LineStrips2D + Points2D, static | f^k(s^k) in its own frame, kinks marked |
//! | `kec/plots/z_mm`, `kec/plots/roll_mrad` | Scalars (real, KEC) on `y_um` | kinematics from the real profiles and from KEC |
//! | `kec/figures/z_mm`, `kec/figures/roll_mrad` | [`super::xyplot`], static; a cursor on `y_um` | the same against y in mm, as the layout shows them |
//! | `kec/summary` | TextDocument | kinks, accuracy |

use super::{Container, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument};

use super::contact::{log_err, log_real_sections, send_series, TIMELINE};
use super::{log_static, section_mm, InspectError};
use crate::contact::kec::KecModel;
use crate::contact::lookup::LookupTable1;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;

/// Layout: real sections on top, equivalent sections below them, then plots and summary.
pub fn blueprint() -> Layout {
    let view = |title: String, origin: String| View::spatial2d(title).origin(origin).into();
    let row = |what: &str, title: &str| {
        Container::horizontal([
            view(format!("{title}: right (−Y)"), format!("/kec/{what}/right")),
            view(format!("{title}: left (+Y)"), format!("/kec/{what}/left")),
        ])
        .into()
    };
    Layout::new(
        Container::vertical([
            row("real", "Real profiles"),
            row("equivalent", "Knife-edge-equivalent profile"),
            Container::horizontal([
                super::contact::sweep_plot("z − r0 [mm], real and KEC,", "/kec/plots/z_mm", true),
                super::contact::sweep_plot("roll [mrad], real and KEC,", "/kec/plots/roll_mrad", true),
                View::spatial2d("Equivalent profiles f^k(s^k) [mm]")
                    .origin("/kec/profiles")
                    .into(),
                View::text_document("Summary").origin("/kec/summary").into(),
            ])
            .into(),
        ])
        .shares([2.0, 2.0, 2.0]),
    )
    .timeline(TIMELINE)
}

/// Records the real sweep, the equivalent profiles and the overlaid kinematics.
pub fn record(
    rec: &RecordingStream,
    pair: &WheelRailPair,
    table: &LookupTable1,
    model: &KecModel,
    summary: &str,
) -> Result<(), InspectError> {
    log_real_sections(rec, "kec/real", pair, table)?;
    let (r0, l_w) = (model.r0, model.l_w);
    // Static: knife edges and the equivalent profiles in their own frame.
    for side in Side::BOTH {
        let sig = side.sign();
        let entity = format!("kec/equivalent/{}/knife_edge", side.name());
        let knife = Points2D::new([section_mm(sig * l_w, 0.0)])
            .with_colors([Color::from_rgb(230, 50, 50)])
            .with_radii([Radius::new_ui_points(5.0)])
            .with_labels(["knife edge"]);
        log_static(rec, &entity, &knife)?;
        let p = model.profile(side);
        let nodes: Vec<[f32; 2]> = p
            .nodes()
            .map(|(s, f)| [(s * 1e3) as f32, (f * 1e3) as f32])
            .collect();
        let color = if side == Side::Left {
            Color::from_rgb(230, 120, 40)
        } else {
            Color::from_rgb(60, 140, 230)
        };
        let entity = format!("kec/profiles/{}", side.name());
        log_static(
            rec,
            &entity,
            &LineStrips2D::new([nodes])
                .with_colors([color])
                .with_radii([Radius::new_ui_points(1.5)]),
        )?;
        let kinks: Vec<[f32; 2]> = model
            .kinks
            .iter()
            .filter(|k| k.side == side && k.real_jump)
            .map(|k| [(k.s_k * 1e3) as f32, (p.eval(k.s_k).0 * 1e3) as f32])
            .collect();
        let entity = format!("kec/profiles/{}/kinks", side.name());
        log_static(
            rec,
            &entity,
            &Points2D::new(kinks)
                .with_colors([color])
                .with_radii([Radius::new_ui_points(4.0)]),
        )?;
    }
    // Per y: the equivalent wheel (a short stretch of the profile around the knife edge).
    for row in &table.rows {
        rec.set_time_sequence(TIMELINE, (row.y * 1e6).round() as i64);
        let (y, zt, phi) = (row.y, row.z() - r0, row.phi());
        for side in Side::BOTH {
            let sig = side.sign();
            let p = model.profile(side);
            let (a, b) = p.domain();
            let pts: Vec<[f32; 2]> = (0..=200)
                .map(|k| {
                    let s = a + (b - a) * k as f64 / 200.0;
                    let f = p.eval(s).0;
                    // Equivalent wheel point: Y = y + σL_w + s + φ(r0 + f), Z = z̃ + φ(σL_w + s) − f.
                    section_mm(y + sig * l_w + s + phi * (r0 + f), zt + phi * (sig * l_w + s) - f)
                })
                .collect();
            let entity = format!("kec/equivalent/{}/wheel", side.name());
            let strip = LineStrips2D::new([pts])
                .with_colors([Color::from_rgb(70, 140, 230)])
                .with_radii([Radius::new_ui_points(1.5)]);
            rec.log(entity.as_str(), &strip).map_err(log_err(&entity))?;
        }
    }
    // Kinematics: real (the table) and KEC at the same y.
    let ys: Vec<i64> = table.rows.iter().map(|r| (r.y * 1e6).round() as i64).collect();
    let mut z = Vec::with_capacity(2 * ys.len());
    let mut roll = Vec::with_capacity(2 * ys.len());
    let mut start = None;
    for r in &table.rows {
        let k = model
            .solve(r.y, [0.0; 4], start)
            .map_err(|e| InspectError::Model(e.to_string()))?;
        start = Some(k.x(r0));
        z.extend([(r.z() - r0) * 1e3, (k.z - r0) * 1e3]);
        roll.extend([r.phi() * 1e3, k.phi * 1e3]);
    }
    send_series(rec, "kec/plots/z_mm", &ys, z, &["real", "KEC"])?;
    send_series(rec, "kec/plots/roll_mrad", &ys, roll, &["real", "KEC"])?;
    log_static(
        rec,
        "kec/summary",
        &TextDocument::from_markdown(summary.to_string()),
    )
}
