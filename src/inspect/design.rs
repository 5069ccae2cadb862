//! `kecsim design-wheel`: the designed wheel beside the reference wheel on the rail, and both
//! pairs' contact geometry against the lateral displacement y (the paper's Fig. 14–16).
//!
//! Timeline `y_um` (as `kecsim contact`). Entities (mm; cross-sections stored as `[Y, −Z]`):
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `design/profiles/{rail,designed,reference}` | LineStrips2D, static | the left rail and both wheels centred on it, Y from the taping line |
//! | `design/section/{designed,reference}/{left,right}/…` | as `kecsim contact` | each pair's wheels and contact points at every y |
//! | `design/plots/{s_wheel_mm,s_rail_mm,contact_angle_deg,dr_mm}/{designed,reference}` | Scalars (left, right) on `y_um` | contact on wheel and rail, contact angles, Δr |
//! | `design/figures/{s_wheel_mm,s_rail_mm,contact_angle_deg,dr_mm}` | [`super::xyplot`], static | both pairs' plots above against y in mm, as the layout shows them |
//! | `design/summary` | TextDocument | target, flange measures, jumps, conicity |

use super::{Container, Layout, View};
use rerun::{Color, LineStrips2D, Radius, RecordingStream, TextDocument};

use super::contact::{log_real_sections, sweep_plot, TIMELINE};
use super::{log_static, section_mm, InspectError};
use crate::contact::design::DesignReport;
use crate::contact::lookup::{LookupTable1, TableRow};
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;

/// Layout: the profiles and the designed pair's sections on top, the functions of y below.
pub fn blueprint() -> Layout {
    let plot = sweep_plot;
    Layout::new(
        Container::vertical([
            Container::horizontal([
                View::spatial2d("Wheels on the left rail (designed blue, reference grey)")
                    .origin("/design/profiles")
                    .into(),
                View::spatial2d("Designed pair, right")
                    .origin("/design/section/designed/right")
                    .into(),
                View::spatial2d("Designed pair, left")
                    .origin("/design/section/designed/left")
                    .into(),
            ])
            .into(),
            Container::horizontal([
                plot(
                    "contact on wheel s^w [mm] (Fig. 14 left)",
                    "/design/plots/s_wheel_mm",
                    true,
                ),
                plot(
                    "contact on rail s^r [mm] (Fig. 14 right)",
                    "/design/plots/s_rail_mm",
                    true,
                ),
            ])
            .into(),
            Container::horizontal([
                plot("contact angle [deg]", "/design/plots/contact_angle_deg", true),
                plot("Δr = r_left − r_right [mm]", "/design/plots/dr_mm", true),
                View::text_document("Summary").origin("/design/summary").into(),
            ])
            .into(),
        ])
        .shares([3.0, 2.0, 2.0]),
    )
    .timeline(TIMELINE)
}

/// The left rail and a wheel centred on it, Y measured from the taping line.
fn strip(points: Vec<(f64, f64)>, l_w: f64, color: [u8; 3]) -> LineStrips2D {
    let pts: Vec<[f32; 2]> = points.into_iter().map(|(y, z)| section_mm(y - l_w, z)).collect();
    LineStrips2D::new([pts])
        .with_colors([Color::from_rgb(color[0], color[1], color[2])])
        .with_radii([Radius::new_ui_points(1.5)])
}

/// The designed pair's colours (full) and the reference's (pale): left, right.
fn pair_colors(name: &str) -> [Color; 2] {
    let c = if name == "designed" {
        [[230, 120, 40], [60, 140, 230]]
    } else {
        [[240, 190, 150], [160, 190, 225]]
    };
    c.map(|c| Color::from_rgb(c[0], c[1], c[2]))
}

/// Both pairs' functions of y drawn as the layout's figures (`design/figures/*`): the designed
/// pair in full colour, the reference pale, y in mm.
fn figures(rec: &RecordingStream, pairs: [(&LookupTable1, &str); 2]) -> Result<(), InspectError> {
    type Of = fn(&TableRow) -> Vec<f64>;
    let quantities: [(&str, Of, &[&str]); 4] = [
        (
            "s_wheel_mm",
            |r| vec![r.x[2] * 1e3, r.x[4] * 1e3],
            &["left", "right"],
        ),
        (
            "s_rail_mm",
            |r| vec![r.x[3] * 1e3, r.x[5] * 1e3],
            &["left", "right"],
        ),
        (
            "contact_angle_deg",
            |r| vec![r.contact_angle[0].to_degrees(), r.contact_angle[1].to_degrees()],
            &["left", "right"],
        ),
        ("dr_mm", |r| vec![r.delta_r() * 1e3], &["Δr"]),
    ];
    for (quantity, of, wheels) in quantities {
        let mut series = Vec::new();
        for (table, pair) in pairs {
            for (k, wheel) in wheels.iter().enumerate() {
                series.push(super::xyplot::OwnedSeries {
                    name: format!("{pair} {wheel}"),
                    color: pair_colors(pair)[k],
                    width: 1.5,
                    points: table.rows.iter().map(|r| (r.y * 1e3, of(r)[k])).collect(),
                });
            }
        }
        super::xyplot::log_owned(
            rec,
            &format!("design/figures/{quantity}"),
            &series,
            super::xyplot::Extras {
                legend: true,
                ..Default::default()
            },
        )?;
    }
    Ok(())
}

/// One pair's functions of y under `design/plots/*/{name}`.
fn plots(rec: &RecordingStream, table: &LookupTable1, name: &str) -> Result<(), InspectError> {
    let ys: Vec<i64> = table.rows.iter().map(|r| (r.y * 1e6).round() as i64).collect();
    // Each line named by its pair and wheel: the designed pair in full colour, the reference
    // pale (both pairs share each plot).
    let (left, right, dr) = (
        format!("{name} left"),
        format!("{name} right"),
        format!("{name} Δr"),
    );
    let colors = |n: usize| -> Vec<Color> { pair_colors(name).into_iter().take(n).collect() };
    let send_series = |rec: &RecordingStream, entity: &str, ys: &[i64], values: Vec<f64>, names: &[&str]| {
        super::send_scalar_columns(rec, TIMELINE, entity, ys, values, names, colors(names.len()))
    };
    let col = |f: &dyn Fn(&TableRow) -> Vec<f64>| table.rows.iter().flat_map(f).collect::<Vec<f64>>();
    send_series(
        rec,
        &format!("design/plots/s_wheel_mm/{name}"),
        &ys,
        col(&|r| vec![r.x[2] * 1e3, r.x[4] * 1e3]),
        &[left.as_str(), right.as_str()],
    )?;
    send_series(
        rec,
        &format!("design/plots/s_rail_mm/{name}"),
        &ys,
        col(&|r| vec![r.x[3] * 1e3, r.x[5] * 1e3]),
        &[left.as_str(), right.as_str()],
    )?;
    send_series(
        rec,
        &format!("design/plots/contact_angle_deg/{name}"),
        &ys,
        col(&|r| vec![r.contact_angle[0].to_degrees(), r.contact_angle[1].to_degrees()]),
        &[left.as_str(), right.as_str()],
    )?;
    send_series(
        rec,
        &format!("design/plots/dr_mm/{name}"),
        &ys,
        col(&|r| vec![r.delta_r() * 1e3]),
        &[dr.as_str()],
    )
}

/// Records the design report: profiles, sections and functions of y of both pairs, the summary.
pub fn record(
    rec: &RecordingStream,
    report: &DesignReport,
    designed: &WheelRailPair,
    reference: &WheelRailPair,
    summary: &str,
) -> Result<(), InspectError> {
    let l_w = designed.wheelset.l_w();
    log_static(
        rec,
        "design/profiles/rail",
        &strip(designed.rail_positions(Side::Left), l_w, [150, 150, 160]),
    )?;
    log_static(
        rec,
        "design/profiles/reference",
        &strip(
            reference.centred_wheel_positions(Side::Left),
            l_w,
            [120, 120, 120],
        ),
    )?;
    log_static(
        rec,
        "design/profiles/designed",
        &strip(designed.centred_wheel_positions(Side::Left), l_w, [70, 140, 230]),
    )?;
    log_real_sections(rec, "design/section/designed", designed, &report.table)?;
    log_real_sections(
        rec,
        "design/section/reference",
        reference,
        &report.reference_table,
    )?;
    plots(rec, &report.table, "designed")?;
    plots(rec, &report.reference_table, "reference")?;
    figures(
        rec,
        [
            (&report.table, "designed"),
            (&report.reference_table, "reference"),
        ],
    )?;
    log_static(
        rec,
        "design/summary",
        &TextDocument::from_markdown(summary.to_string()),
    )
}
