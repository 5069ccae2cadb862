//! `kecsim contact`: the contact-geometry sweep over the lateral displacement y (paper Fig. 10/14).
//!
//! Timeline `y_um`: the wheelset lateral displacement in µm (a sequence timeline; one step per
//! table row). Entities (mm, cross-sections stored as `[Y, −Z]`, see [`super`]):
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `contact/section/{left,right}/rail` | LineStrips2D, static | rail head |
//! | `contact/section/{left,right}/wheel` | LineStrips2D, per y | wheel at (y, z, φ) |
//! | `contact/section/{left,right}/contact` | Points2D, per y | contact point (red) and two-point candidates (orange) |
//! | `contact/plots/z_mm`, `roll_mrad`, `dr_mm` | Scalars on `y_um` | wheelset height z − r0, roll φ, Δr = r_left − r_right |
//! | `contact/plots/s_wheel_mm`, `s_rail_mm` | Scalars (left, right) | contact position on wheel and rail (paper convention) |
//! | `contact/plots/contact_angle_deg` | Scalars (left, right) | contact angles |
//! | `contact/figures/*` | [`super::xyplot`], static; a cursor on `y_um` | the plots above drawn against y in mm, as the layout shows them |
//! | `contact/summary` | TextDocument | conicity, jumps, interpolation error |

use super::{Container, Item, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, TextDocument};

use super::{log_static, section_mm, InspectError};
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::LookupTable1;
use crate::profile::Side;

/// The timeline of the sweep.
pub const TIMELINE: &str = "y_um";

/// Layout: both sides' cross-sections on top, the plots below, the summary at the bottom.
pub fn blueprint() -> Layout {
    let side_view = |side: Side, title: &str| {
        View::spatial2d(title)
            .origin(format!("/contact/section/{}", side.name()))
            .into()
    };
    let plot = sweep_plot;
    Layout::new(
        Container::vertical([
            Container::horizontal([
                side_view(Side::Right, "Right wheel and rail (−Y)"),
                side_view(Side::Left, "Left wheel and rail (+Y)"),
            ])
            .into(),
            Container::horizontal([
                plot("z − r0 [mm]", "/contact/plots/z_mm", false),
                plot("roll [mrad]", "/contact/plots/roll_mrad", false),
                plot("Δr = r_left − r_right [mm]", "/contact/plots/dr_mm", false),
            ])
            .into(),
            Container::horizontal([
                plot("contact on wheel s^w [mm]", "/contact/plots/s_wheel_mm", true),
                plot("contact on rail s^r [mm]", "/contact/plots/s_rail_mm", true),
                plot("contact angle [deg]", "/contact/plots/contact_angle_deg", true),
                View::text_document("Summary").origin("/contact/summary").into(),
            ])
            .into(),
        ])
        .shares([3.0, 2.0, 2.0]),
    )
    .timeline(TIMELINE)
}

pub(crate) fn log_err(entity: &str) -> impl FnOnce(rerun::RecordingStreamError) -> InspectError + '_ {
    move |source| InspectError::Log {
        entity: entity.to_string(),
        source,
    }
}

/// The entity of the figure drawn from the series at `entity` (`…/plots/NAME` →
/// `…/figures/NAME`).
pub(crate) fn figure_entity(entity: &str) -> String {
    entity.trim_start_matches('/').replacen("/plots/", "/figures/", 1)
}

/// A plot of a sweep's function of y: the static x–y figure of the series at `origin` (drawn by
/// [`send_series`]; y in mm at round ticks, a marker at the time panel's y), its legend right of
/// the plot where it has one, its title naming the axes.
pub(crate) fn sweep_plot(title: &str, origin: &str, legend: bool) -> Item {
    let (x, y) = if legend {
        super::xyplot::BOUNDS_WITH_LEGEND
    } else {
        super::xyplot::BOUNDS
    };
    View::spatial2d(format!("{title} against y [mm]"))
        .origin(format!("/{}", figure_entity(origin)))
        .bounds(x, y)
        .into()
}

/// The sweeps' two colours (left or real orange, right or KEC blue).
const COLORS: [[u8; 3]; 2] = [[230, 120, 40], [60, 140, 230]];

/// One scalar series (or a pair left/right) against y: the Scalars on [`TIMELINE`] at `entity`
/// and their figure ([`sweep_plot`]).
pub(crate) fn send_series(
    rec: &RecordingStream,
    entity: &str,
    ys: &[i64],
    values: Vec<f64>,
    names: &[&str],
) -> Result<(), InspectError> {
    let colors: Vec<Color> = COLORS
        .iter()
        .take(names.len())
        .map(|c| Color::from_rgb(c[0], c[1], c[2]))
        .collect();
    send_figure(rec, &figure_entity(entity), ys, &values, names, &colors)?;
    super::send_scalar_columns(rec, TIMELINE, entity, ys, values, names, colors)
}

/// The x–y figure of series against y (µm ticks `ys`, values interleaved by row as
/// [`super::send_scalar_columns`] takes them): y in mm, a legend where there are several.
pub(crate) fn send_figure(
    rec: &RecordingStream,
    entity: &str,
    ys: &[i64],
    values: &[f64],
    names: &[&str],
    colors: &[Color],
) -> Result<(), InspectError> {
    let n = names.len().max(1);
    let series: Vec<super::xyplot::OwnedSeries> = names
        .iter()
        .zip(colors)
        .enumerate()
        // The first line wider, so that one lying on another (real under KEC) still shows.
        .map(|(k, (&name, &color))| super::xyplot::OwnedSeries {
            name: name.to_string(),
            color,
            width: if k == 0 && n > 1 { 3.0 } else { 1.5 },
            points: ys
                .iter()
                .zip(values.iter().skip(k).step_by(n))
                .map(|(&y, &v)| (y as f64 * 1e-3, v))
                .collect(),
        })
        .collect();
    super::xyplot::log_owned(
        rec,
        entity,
        &series,
        super::xyplot::Extras {
            legend: names.len() > 1,
            cursor: Some((TIMELINE, ys)),
            ..Default::default()
        },
    )
}

/// Logs the real cross-sections of a sweep under `base` (`{base}/{left,right}/{rail,wheel,contact}`):
/// static rails, and per table row on the `y_um` timeline the wheel at (y, z, φ) and the contact
/// point labelled with its contact angle.
pub(crate) fn log_real_sections(
    rec: &RecordingStream,
    base: &str,
    pair: &crate::profile::placement::WheelRailPair,
    table: &LookupTable1,
) -> Result<(), InspectError> {
    for side in Side::BOTH {
        let entity = format!("{base}/{}/rail", side.name());
        let pts: Vec<[f32; 2]> = pair
            .rail_positions(side)
            .into_iter()
            .map(|(y, z)| section_mm(y, z))
            .collect();
        super::log_scale_bar(rec, &format!("{base}/{}/scale", side.name()), &pts, 10.0, "10 mm")?;
        let strip = LineStrips2D::new([pts])
            .with_colors([Color::from_rgb(150, 150, 160)])
            .with_radii([Radius::new_ui_points(1.5)]);
        log_static(rec, &entity, &strip)?;
    }
    let (knots, _) = pair.wheel.knots();
    let every = (knots.len() / 600).max(1);
    for row in &table.rows {
        rec.set_time_sequence(TIMELINE, (row.y * 1e6).round() as i64);
        let (y, z, phi) = (row.y, row.z(), row.phi());
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let wheel: Vec<[f32; 2]> = knots
                .iter()
                .step_by(every)
                .map(|&s| {
                    let (wy, wz) = pair
                        .wheelset
                        .wheel_point(&pair.wheel, side, side.sign() * s, y, z, phi);
                    section_mm(wy, wz)
                })
                .collect();
            let entity = format!("{base}/{}/wheel", side.name());
            let strip = LineStrips2D::new([wheel])
                .with_colors([Color::from_rgb(70, 140, 230)])
                .with_radii([Radius::new_ui_points(1.5)]);
            rec.log(entity.as_str(), &strip).map_err(log_err(&entity))?;
            let contact = section_mm(row.position[2 * i], row.position[2 * i + 1]);
            let entity = format!("{base}/{}/contact", side.name());
            let point = Points2D::new([contact])
                .with_colors([Color::from_rgb(230, 50, 50)])
                .with_radii([Radius::new_ui_points(5.0)])
                .with_labels([format!("{:.1}°", row.contact_angle[i].to_degrees())]);
            rec.log(entity.as_str(), &point).map_err(log_err(&entity))?;
        }
    }
    Ok(())
}

/// Records the sweep of `table` (built from `geom`) and the `summary` text.
pub fn record(
    rec: &RecordingStream,
    geom: &ContactGeometry,
    table: &LookupTable1,
    summary: &str,
) -> Result<(), InspectError> {
    let r0 = geom.pair.wheelset.nominal_radius_m;
    log_real_sections(rec, "contact/section", &geom.pair, table)?;
    // Plots.
    let ys: Vec<i64> = table.rows.iter().map(|r| (r.y * 1e6).round() as i64).collect();
    let col = |f: &dyn Fn(&crate::contact::lookup::TableRow) -> Vec<f64>| {
        table.rows.iter().flat_map(f).collect::<Vec<f64>>()
    };
    send_series(
        rec,
        "contact/plots/z_mm",
        &ys,
        col(&|r| vec![(r.z() - r0) * 1e3]),
        &["z − r0"],
    )?;
    send_series(
        rec,
        "contact/plots/roll_mrad",
        &ys,
        col(&|r| vec![r.phi() * 1e3]),
        &["roll"],
    )?;
    send_series(
        rec,
        "contact/plots/dr_mm",
        &ys,
        col(&|r| vec![r.delta_r() * 1e3]),
        &["Δr"],
    )?;
    send_series(
        rec,
        "contact/plots/s_wheel_mm",
        &ys,
        col(&|r| vec![r.x[2] * 1e3, r.x[4] * 1e3]),
        &["left", "right"],
    )?;
    send_series(
        rec,
        "contact/plots/s_rail_mm",
        &ys,
        col(&|r| vec![r.x[3] * 1e3, r.x[5] * 1e3]),
        &["left", "right"],
    )?;
    send_series(
        rec,
        "contact/plots/contact_angle_deg",
        &ys,
        col(&|r| vec![r.contact_angle[0].to_degrees(), r.contact_angle[1].to_degrees()]),
        &["left", "right"],
    )?;
    log_static(
        rec,
        "contact/summary",
        &TextDocument::from_markdown(summary.to_string()),
    )
}
