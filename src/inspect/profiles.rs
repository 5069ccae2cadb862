//! `kecsim profiles`: the real wheel and rail profiles of both sides on the track cross-section.
//!
//! Entities (all static, mm, points stored as `[Y, −Z]`, see [`super`]):
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `profiles/real/{left,right}/rail` | LineStrips2D | rail head, inclined and gauged |
//! | `profiles/real/{left,right}/wheel` | LineStrips2D | wheel, wheelset centred at nominal height |
//! | `profiles/real/{left,right}/markers` | Points2D | gauge point, highest point of the rail, taping line (labelled) |
//! | `profiles/summary` | TextDocument | profiles, sources, placement figures, notes |

use super::{Container, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument};

use super::{log_static, section_mm, InspectError};
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;

const RAIL_RGB: [u8; 3] = [150, 150, 160];
const WHEEL_RGB: [u8; 3] = [70, 140, 230];
const MARKER_RGB: [[u8; 3]; 3] = [[230, 60, 60], [240, 190, 40], [60, 200, 90]];

fn color([r, g, b]: [u8; 3]) -> Color {
    Color::from_rgb(r, g, b)
}

/// The layout: both sides side by side (right rail on the left of the screen, as seen from ahead
/// of the vehicle), the summary below.
pub fn blueprint() -> Layout {
    let side_view = |side: Side| {
        let title = match side {
            Side::Left => "Left wheel and rail (+Y)",
            Side::Right => "Right wheel and rail (−Y)",
        };
        View::spatial2d(title)
            .origin(format!("/profiles/real/{}", side.name()))
            .into()
    };
    Layout::new(
        Container::vertical([
            Container::horizontal([side_view(Side::Right), side_view(Side::Left)]).into(),
            View::text_document("Summary").origin("/profiles/summary").into(),
        ])
        .shares([3.0, 2.0]),
    )
    // Everything here is static: no timeline to show.
}

/// Markdown summary of a placed pair.
pub fn summary_markdown(pair: &WheelRailPair) -> String {
    let rp = &pair.rail_placement;
    let ws = &pair.wheelset;
    let mut md = String::new();
    md += "# kecsim profiles\n\n";
    md += "Cross-section seen from ahead of the vehicle; mm; vertical axis = depth below the top-of-rail plane.\n\n";
    md += &format!("* **wheel** `{}` — {}\n", pair.wheel.name, pair.wheel.source);
    md += &format!("* **rail** `{}` — {}\n", pair.rail.name, pair.rail.source);
    md += &format!(
        "* gauge {:.2} mm (measured {:.1} mm below the top), inclination {} (β = {:.5} rad)\n",
        rp.gauge.gauge_m * 1e3,
        rp.gauge.measuring_depth_m * 1e3,
        pair.inclination,
        rp.inclination_rad
    );
    let (yg, _) = rp.gauge_point(&pair.rail, Side::Left);
    let (yt, _) = rp.top_point(&pair.rail, Side::Left);
    md += &format!(
        "* rail profile origin at Y = ±{:.3} mm, Z = {:.4} mm; highest point {:.3} mm outboard of the gauge point\n",
        rp.lateral_m * 1e3,
        rp.vertical_m * 1e3,
        (yt - yg) * 1e3
    );
    md += &format!(
        "* wheelset: back-to-back {:.1} mm, taping line {:.1} mm from the flange back (L_w = {:.1} mm), r0 = {:.1} mm\n",
        ws.back_to_back_m * 1e3,
        ws.rolling_circle_from_back_m * 1e3,
        ws.l_w() * 1e3,
        ws.nominal_radius_m * 1e3
    );
    for (what, p) in [("wheel", &pair.wheel), ("rail", &pair.rail)] {
        for n in &p.notes {
            md += &format!("* note ({what}): {n}\n");
        }
    }
    md
}

/// Records the placed pair.
pub fn record(rec: &RecordingStream, pair: &WheelRailPair) -> Result<(), InspectError> {
    let strip = |entity: String, pts: Vec<(f64, f64)>, rgb: [u8; 3]| {
        let mm: Vec<[f32; 2]> = pts.into_iter().map(|(y, z)| section_mm(y, z)).collect();
        let strips = LineStrips2D::new([mm])
            .with_colors([color(rgb)])
            .with_radii([Radius::new_ui_points(1.5)]);
        log_static(rec, &entity, &strips)
    };
    for side in Side::BOTH {
        let base = format!("profiles/real/{}", side.name());
        strip(format!("{base}/rail"), pair.rail_positions(side), RAIL_RGB)?;
        strip(
            format!("{base}/wheel"),
            pair.centred_wheel_positions(side),
            WHEEL_RGB,
        )?;
        let rp = &pair.rail_placement;
        let (yg, zg) = rp.gauge_point(&pair.rail, side);
        let (yt, zt) = rp.top_point(&pair.rail, side);
        let tape =
            pair.wheelset
                .wheel_point(&pair.wheel, side, 0.0, 0.0, pair.wheelset.nominal_radius_m, 0.0);
        log_static(
            rec,
            &format!("{base}/markers"),
            &Points2D::new([section_mm(yg, zg), section_mm(yt, zt), section_mm(tape.0, tape.1)])
                .with_labels(["gauge point", "rail top", "taping line"])
                .with_colors(MARKER_RGB.map(color))
                .with_radii([Radius::new_ui_points(4.0)]),
        )?;
    }
    log_static(
        rec,
        "profiles/summary",
        &TextDocument::from_markdown(summary_markdown(pair)),
    )
}
