//! `kecsim paper`: the paper's §8 in one recording, a tab per figure laid out as the paper's
//! ([`crate::paper`] assembles the data): Fig. 14–16 (contact geometry), Fig. 17 (track
//! irregularities), Fig. 18 (the front bogie's kinematics), Fig. 19 (its normal forces), and
//! Tab. 7 with the summary.
//!
//! Timelines:
//! * `y_um` — the wheelset lateral displacement in µm (a sequence, one step per table row, as
//!   [`super::contact`]): Fig. 14 and 16;
//! * `distance_mm` — the distance along the track in mm (a sequence, as [`super::run`]'s): Fig. 17
//!   on the track's arc length, Fig. 18–19 on the front wheelset's arc length in the KEC run (a
//!   track feature of Fig. 17 at s lines up with the front wheelset passing it). Not a duration
//!   whose "seconds" are metres: the viewer writes durations past 60 s in minutes (600 m would
//!   read `+10m`, ten minutes), and a sequence in whole metres would put several of the 100 Hz
//!   samples (0.19 m apart at 19 m/s) on one tick;
//! * `time` — simulated time, s: Fig. 18–19 too.
//!
//! A time-series view plots the time panel's timeline only (Rerun 0.36 views cannot choose their
//! own, rerun-io/rerun#6828) and labels a sequence's ticks as they are (`#123 848`, mm): every
//! figure is therefore shown as a static x–y plot ([`super::xyplot`]) — Fig. 14 and 16 against y
//! in mm, Fig. 17–19 against the distance in m, each at round ticks — so that every tab opens
//! full whatever the timeline; the series stay on their timelines too. Fig. 15 is static.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `paper/fig14/{s_wheel_mm, s_rail_mm}` | Scalars (left, right) on `y_um` | contact on the real wheel s^w(y), rail s^r(y) |
//! | `paper/fig15/{real, equivalent, rail}` | LineStrips2D, static | right wheel real and KEC-equivalent, right rail (mm, `[Y, −Z]`) |
//! | `paper/fig15/knife_edge` | Points2D, static | the knife edge |
//! | `paper/fig16/{z_mm, roll_mrad}` | Scalars (real, KEC) on `y_um` | z − r0 and roll φ |
//! | `paper/fig14/plot_{wheel,rail}`, `paper/fig16/plot_{z,roll}` | static x–y plots ([`super::xyplot`]) | Fig. 14 and 16 as shown |
//! | `paper/fig17/{al,vp,gv,cl}_mm` | Scalars on `distance_mm` | irregularities |
//! | `paper/fig17/plot_*`, `paper/fig18/plot_{y,yaw,dy,dyaw}`, `paper/fig19/plot_{normal,dnormal}/NAME` | static x–y plots ([`super::xyplot`]) | Fig. 17–19 as shown: against the distance in m at round ticks |
//! | `paper/fig18/{y_mm, yaw_mrad}/NAME` | Scalars (NAME kec, NAME TABLES) | y, ψ of the front bogie's bodies |
//! | `paper/fig18/{dy_mm, dyaw_mrad}/NAME` | Scalars | \|KEC − tables\| |
//! | `paper/fig18/{dy_mm, dyaw_mrad}/bound` | Scalars | the paper's bounds, 1 mm and 0.5 mrad |
//! | `paper/fig19/normal_kn/NAME` | Scalars (left kec, left TABLES, right kec, right TABLES) | normal forces |
//! | `paper/fig19/dnormal_kn/NAME` | Scalars (left, right) | \|KEC − tables\| |
//! | `paper/summary` | TextDocument | Tab. 7, Fig. 18's summary |

use super::{Container, Item, Layout, View};
use rerun::{Color, LineStrips2D, Points2D, Radius, RecordingStream, SeriesLines, TextDocument, TimeColumn};

use super::contact::TIMELINE as Y_TIMELINE;
use super::track::IRREGULARITIES;
use super::xyplot::OwnedSeries;
use super::{
    log_static, section_mm, send_scalar_columns, send_scalar_rows, send_scalar_values, InspectError,
};
use crate::paper::{Both, PaperFigures};

/// The distance timeline, mm (see the module doc).
pub const DISTANCE: &str = super::run::DISTANCE;

/// A distance (m) on [`DISTANCE`].
fn distance_mm(s: f64) -> i64 {
    (s * 1e3).round() as i64
}

/// The simulated-time timeline.
pub const TIME: &str = super::run::TIME;

/// Left and right (the paper's Fig. 14: green left, blue right).
const LEFT: (u8, u8, u8) = (40, 160, 70);
const RIGHT: (u8, u8, u8) = (40, 110, 220);
/// Fig. 18's bodies: front wheelset, rear wheelset, frame; KEC in the full colour, the tables in
/// a light tint of it.
const BODY: [(u8, u8, u8); 3] = [(40, 110, 220), (210, 60, 40), (40, 150, 70)];

fn rgb(c: (u8, u8, u8)) -> Color {
    Color::from_rgb(c.0, c.1, c.2)
}

/// A light tint of `c` (the tables' line beside KEC's).
fn tint(c: (u8, u8, u8)) -> Color {
    let t = |v: u8| (v as f64 + 0.5 * (255.0 - v as f64)).round() as u8;
    Color::from_rgb(t(c.0), t(c.1), t(c.2))
}

/// Line widths, UI points: KEC (or the real profiles) drawn wide, the tables (or KEC) thin on
/// top of it, so that both show where they coincide (the paper: solid and dashed).
const WIDE: f32 = 3.0;
const THIN: f32 = 1.25;

/// Styles the series of `entity`.
fn style(
    rec: &RecordingStream,
    entity: &str,
    names: &[String],
    colors: Vec<Color>,
    widths: Vec<f32>,
) -> Result<(), InspectError> {
    log_static(
        rec,
        entity,
        &SeriesLines::new()
            .with_names(names.iter().map(String::as_str))
            .with_colors(colors)
            .with_widths(widths),
    )
}

/// A static x–y plot of a sweep over y ([`super::xyplot`]): it shows whatever the time panel's
/// timeline, so that the recording opens on the distance figures with this tab full too.
fn sweep_plot(title: impl Into<String>, origin: impl Into<String>) -> Item {
    let (x, y) = super::xyplot::BOUNDS;
    View::spatial2d(title).origin(origin.into()).bounds(x, y).into()
}

/// Fig. 14 (the wheel and the rail side by side, as the paper's) above, Fig. 15 and Fig. 16
/// below.
pub fn contact_tab() -> Item {
    Container::vertical([
        Container::horizontal([
            sweep_plot(
                "Fig. 14: contact on the wheel s^w [mm] vs y [mm]; green left, blue right",
                "/paper/fig14/plot_wheel",
            ),
            sweep_plot(
                "Fig. 14: contact on the rail s^r [mm] vs y [mm]; green left, blue right",
                "/paper/fig14/plot_rail",
            ),
        ])
        .into(),
        Container::horizontal([
            View::spatial2d(
                "Fig. 15: right wheel, real (white) and KEC-equivalent (orange) on the knife edge; rail (grey) [mm]",
            )
            .origin("/paper/fig15")
            .into(),
            Container::vertical([
                sweep_plot(
                    "Fig. 16: z − r0 [mm] vs y [mm]; real (white), KEC (orange)",
                    "/paper/fig16/plot_z",
                ),
                sweep_plot(
                    "Fig. 16: roll φ [mrad] vs y [mm]; real (white), KEC (orange)",
                    "/paper/fig16/plot_roll",
                ),
            ])
            .into(),
        ])
        .shares([1.6, 1.0])
        .into(),
    ])
    .shares([1.0, 1.4])
    .named("Fig. 14–16: contact geometry")
    .into()
}

/// A static x–y figure along the distance ([`super::xyplot`]: s in m at round ticks), its legend
/// right of the plot where it has one.
fn distance_plot(title: impl Into<String>, origin: impl Into<String>, legend: bool) -> Item {
    let (x, y) = if legend {
        super::xyplot::BOUNDS_WITH_LEGEND
    } else {
        super::xyplot::BOUNDS
    };
    View::spatial2d(title).origin(origin.into()).bounds(x, y).into()
}

/// Fig. 17: the four irregularities, two by two.
pub fn irregularity_tab() -> Item {
    Container::grid(
        2,
        IRREGULARITIES.iter().map(|(name, title, _)| {
            distance_plot(
                format!("Fig. 17: {title} [mm] along s [m]"),
                format!("/paper/fig17/plot_{name}"),
                false,
            )
        }),
    )
    .named("Fig. 17: irregularities")
    .into()
}

/// Fig. 18: y and ψ above, their differences below (the paper's layout).
pub fn kinematics_tab(tables: &str) -> Item {
    kinematics_tab_scaled(tables, None)
}

/// [`kinematics_tab`], the difference plots' titles giving their largest values `largest` (|Δy|
/// mm, |Δψ| mrad) beside the paper's bounds: each plot is scaled to its data (a 0.007 mm
/// difference lay flat on zero in a plot scaled to the paper's 1 mm).
pub fn kinematics_tab_scaled(tables: &str, largest: Option<(f64, f64)>) -> Item {
    let diff = |what: &str, unit: &str, bound: f64, largest: Option<f64>| -> Item {
        let origin = format!("/paper/fig18/plot_d{what}");
        let sym = if what == "y" { "Δy" } else { "Δψ" };
        let max = largest.map_or(String::new(), |m| format!(" (max {})", significant(m)));
        distance_plot(
            format!("Fig. 18: |{sym}| [{unit}]{max}; the paper's bound {bound} {unit}"),
            origin,
            true,
        )
    };
    Container::grid(
        2,
        [
            distance_plot(
                format!("Fig. 18: lateral displacement y [mm], kec and {tables}, along s [m]"),
                "/paper/fig18/plot_y",
                true,
            ),
            distance_plot(
                format!("Fig. 18: yaw ψ [mrad], kec and {tables}, along s [m]"),
                "/paper/fig18/plot_yaw",
                true,
            ),
            diff("y", "mm", 1.0, largest.map(|l| l.0)),
            diff("yaw", "mrad", 0.5, largest.map(|l| l.1)),
        ],
    )
    .named("Fig. 18: front bogie")
    .into()
}

/// A value to three significant digits (`0.00712`, `0.412`, `12.3`).
fn significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let decimals = (2 - v.abs().log10().floor() as i64).max(0) as usize;
    format!("{v:.decimals$}")
}

/// Fig. 19: a column per wheelset, the forces above, the differences below.
pub fn forces_tab(tables: &str, wheelsets: &[String]) -> Item {
    let top = wheelsets.iter().map(|w| {
        distance_plot(
            format!("Fig. 19: {w} normal forces [kN], kec and {tables}, along s [m]"),
            format!("/paper/fig19/plot_normal/{w}"),
            true,
        )
    });
    let bottom = wheelsets.iter().map(|w| {
        distance_plot(
            format!("Fig. 19: {w} |ΔN| [kN] along s [m]"),
            format!("/paper/fig19/plot_dnormal/{w}"),
            true,
        )
    });
    Container::grid(
        wheelsets.len().max(1) as u32,
        top.chain(bottom).collect::<Vec<_>>(),
    )
    .named("Fig. 19: normal forces")
    .into()
}

/// Tab. 7 and the summary.
pub fn summary_tab() -> Item {
    View::text_document("Tab. 7 and summary")
        .origin("/paper/summary")
        .into()
}

/// The layout: a tab per figure in the paper's order, Tab. 7 last; the time panel on the first
/// tab's timeline, `y_um` (see the module doc).
pub fn blueprint_for(tables: &str, wheelsets: &[String]) -> Layout {
    Layout::new(Container::tabs([
        contact_tab(),
        irregularity_tab(),
        kinematics_tab(tables),
        forces_tab(tables, wheelsets),
        Container::vertical([summary_tab()]).named("Tab. 7: cost").into(),
    ]))
    .timeline(DISTANCE)
    .play_state(super::layout::PlayState::Paused)
}

/// The front bogie's wheelsets of the figures (Fig. 19's columns).
fn wheelsets(f: &PaperFigures) -> Vec<String> {
    let mut w = Vec::new();
    for n in &f.figures.normal_forces {
        if !w.contains(&n.wheelset) {
            w.push(n.wheelset.clone());
        }
    }
    w
}

/// The layout for `f`.
pub fn blueprint(f: &PaperFigures) -> Layout {
    let (dy, dpsi) = f.max_differences();
    let tables = f.tables_model.as_str();
    Layout::new(Container::tabs([
        contact_tab(),
        irregularity_tab(),
        kinematics_tab_scaled(tables, Some((dy * 1e3, dpsi * 1e3))),
        forces_tab(tables, &wheelsets(f)),
        Container::vertical([summary_tab()]).named("Tab. 7: cost").into(),
    ]))
    .timeline(DISTANCE)
    .play_state(super::layout::PlayState::Paused)
}

/// Records every figure and the summary `summary` (see the module doc).
pub fn record(rec: &RecordingStream, f: &PaperFigures, summary: &str) -> Result<(), InspectError> {
    record_contact(rec, f)?;
    record_irregularities(rec, f)?;
    record_bogie(rec, f)?;
    log_static(
        rec,
        "paper/summary",
        &TextDocument::from_markdown(summary.to_string()),
    )
}

/// Fig. 14–16.
fn record_contact(rec: &RecordingStream, f: &PaperFigures) -> Result<(), InspectError> {
    let ticks: Vec<i64> = f.sweep.iter().map(|r| (r.y * 1e6).round() as i64).collect();
    let lr = vec![rgb(LEFT), rgb(RIGHT)];
    let pairs = |g: &dyn Fn(&crate::paper::SweepRow) -> [f64; 2]| -> Vec<f64> {
        f.sweep.iter().flat_map(g).collect()
    };
    send_scalar_columns(
        rec,
        Y_TIMELINE,
        "paper/fig14/s_wheel_mm",
        &ticks,
        pairs(&|r| [r.s_wheel[0] * 1e3, r.s_wheel[1] * 1e3]),
        &["left wheel", "right wheel"],
        lr.clone(),
    )?;
    send_scalar_columns(
        rec,
        Y_TIMELINE,
        "paper/fig14/s_rail_mm",
        &ticks,
        pairs(&|r| [r.s_rail[0] * 1e3, r.s_rail[1] * 1e3]),
        &["left rail", "right rail"],
        lr,
    )?;
    let names = ["real profiles".to_string(), "KEC-equivalent".to_string()];
    for (entity, values) in [
        ("paper/fig16/z_mm", pairs(&|r| [r.z_real * 1e3, r.z_kec * 1e3])),
        (
            "paper/fig16/roll_mrad",
            pairs(&|r| [r.roll_real * 1e3, r.roll_kec * 1e3]),
        ),
    ] {
        style(
            rec,
            entity,
            &names,
            vec![Color::from_rgb(235, 235, 235), Color::from_rgb(240, 110, 50)],
            vec![WIDE, THIN],
        )?;
        send_scalar_values(
            rec,
            vec![TimeColumn::new_sequence(Y_TIMELINE, ticks.iter().copied())],
            ticks.len(),
            entity,
            values,
            2,
        )?;
    }
    // The same sweeps as static plots (what the layout shows, whatever the timeline).
    let curve = |g: &dyn Fn(&crate::paper::SweepRow) -> f64| -> Vec<(f64, f64)> {
        f.sweep.iter().map(|r| (r.y * 1e3, g(r))).collect()
    };
    let white = Color::from_rgb(235, 235, 235);
    let orange = Color::from_rgb(240, 110, 50);
    for (entity, a, b, names, colors, widths) in [
        (
            "paper/fig14/plot_wheel",
            curve(&|r| r.s_wheel[0] * 1e3),
            curve(&|r| r.s_wheel[1] * 1e3),
            ["left wheel", "right wheel"],
            [rgb(LEFT), rgb(RIGHT)],
            [2.0, 2.0],
        ),
        (
            "paper/fig14/plot_rail",
            curve(&|r| r.s_rail[0] * 1e3),
            curve(&|r| r.s_rail[1] * 1e3),
            ["left rail", "right rail"],
            [rgb(LEFT), rgb(RIGHT)],
            [2.0, 2.0],
        ),
        (
            "paper/fig16/plot_z",
            curve(&|r| r.z_real * 1e3),
            curve(&|r| r.z_kec * 1e3),
            ["real", "KEC"],
            [white, orange],
            [WIDE, THIN],
        ),
        (
            "paper/fig16/plot_roll",
            curve(&|r| r.roll_real * 1e3),
            curve(&|r| r.roll_kec * 1e3),
            ["real", "KEC"],
            [white, orange],
            [WIDE, THIN],
        ),
    ] {
        super::xyplot::log(
            rec,
            entity,
            &[
                super::xyplot::Series {
                    name: names[0],
                    color: colors[0],
                    width: widths[0],
                    points: &a,
                },
                super::xyplot::Series {
                    name: names[1],
                    color: colors[1],
                    width: widths[1],
                    points: &b,
                },
            ],
        )?;
    }
    let p = &f.profiles;
    // Light lines on the viewer's dark background; the legend is the view's title.
    let strip = |entity: &str, pts: &[(f64, f64)], color: Color, width: f32| {
        let pts: Vec<[f32; 2]> = pts.iter().map(|&(y, z)| section_mm(y, z)).collect();
        log_static(
            rec,
            entity,
            &LineStrips2D::new([pts])
                .with_colors([color])
                .with_radii([Radius::new_ui_points(width)]),
        )
    };
    strip("paper/fig15/rail", &p.rail, Color::from_rgb(120, 120, 130), 1.0)?;
    let rail: Vec<[f32; 2]> = p.rail.iter().map(|&(y, z)| section_mm(y, z)).collect();
    super::log_scale_bar(rec, "paper/fig15/scale", &rail, 10.0, "10 mm")?;
    strip("paper/fig15/real", &p.real, Color::from_rgb(235, 235, 235), 1.5)?;
    strip(
        "paper/fig15/equivalent",
        &p.equivalent,
        Color::from_rgb(240, 110, 50),
        1.5,
    )?;
    log_static(
        rec,
        "paper/fig15/knife_edge",
        &Points2D::new([section_mm(p.knife_edge.0, p.knife_edge.1)])
            .with_colors([Color::from_rgb(240, 110, 50)])
            .with_radii([Radius::new_ui_points(3.0)])
            .with_labels(["knife edge"]),
    )
}

/// Fig. 17.
fn record_irregularities(rec: &RecordingStream, f: &PaperFigures) -> Result<(), InspectError> {
    let n = f.irregularities.len();
    if n == 0 {
        return Ok(());
    }
    for (c, (name, _, color)) in IRREGULARITIES.iter().enumerate() {
        send_scalar_rows(
            rec,
            vec![TimeColumn::new_sequence(
                DISTANCE,
                f.irregularities.iter().map(|r| distance_mm(r.0)),
            )],
            n,
            &format!("paper/fig17/{name}_mm"),
            f.irregularities.iter().map(|r| r.1[c] * 1e3).collect(),
            &[name],
            vec![Color::from_rgb(color[0], color[1], color[2])],
        )?;
        let points: Vec<(f64, f64)> = f.irregularities.iter().map(|r| (r.0, r.1[c] * 1e3)).collect();
        figure(
            rec,
            &format!("paper/fig17/plot_{name}"),
            vec![series(
                name.to_string(),
                Color::from_rgb(color[0], color[1], color[2]),
                1.0,
                points,
            )],
        )?;
    }
    Ok(())
}

/// A figure's series: name, colour, width, points (distance m, value).
fn series(name: String, color: Color, width: f32, points: Vec<(f64, f64)>) -> OwnedSeries {
    OwnedSeries {
        name,
        color,
        width,
        points,
    }
}

/// Logs a static x–y figure along the distance ([`super::xyplot`]), with a legend where it has
/// several series.
fn figure(rec: &RecordingStream, entity: &str, series: Vec<OwnedSeries>) -> Result<(), InspectError> {
    super::xyplot::log_owned(
        rec,
        entity,
        &series,
        super::xyplot::Extras {
            legend: series.len() > 1,
            ..Default::default()
        },
    )
}

/// Fig. 18–19.
fn record_bogie(rec: &RecordingStream, f: &PaperFigures) -> Result<(), InspectError> {
    let g = &f.figures;
    let n = g.t.len();
    if n == 0 {
        return Ok(());
    }
    let timelines = || {
        vec![
            TimeColumn::new_sequence(DISTANCE, g.distance_m.iter().map(|&s| distance_mm(s))),
            TimeColumn::new_duration_secs(TIME, g.t.iter().copied()),
        ]
    };
    let tables = f.tables_model.as_str();
    // KEC and the tables interleaved per sample, scaled.
    let pair = |b: &Both, scale: f64| -> Vec<f64> {
        b.kec
            .iter()
            .zip(&b.tables)
            .flat_map(|(k, t)| [k * scale, t * scale])
            .collect()
    };
    let along = |v: &[f64], scale: f64| -> Vec<(f64, f64)> {
        g.distance_m
            .iter()
            .zip(v)
            .map(|(&s, &v)| (s, v * scale))
            .collect()
    };
    // Fig. 18's figures: y, ψ, |Δy|, |Δψ|.
    let mut fig18: [Vec<OwnedSeries>; 4] = Default::default();
    for (k, b) in g.kinematics.iter().enumerate() {
        let c = BODY[k % BODY.len()];
        for (j, both) in [&b.y, &b.yaw].into_iter().enumerate() {
            fig18[j].push(series(
                format!("{} ({}) kec", b.name, b.role.name()),
                rgb(c),
                WIDE,
                along(&both.kec, 1e3),
            ));
            fig18[j].push(series(
                format!("{} {tables}", b.name),
                tint(c),
                THIN,
                along(&both.tables, 1e3),
            ));
            fig18[2 + j].push(series(
                format!("{} ({})", b.name, b.role.name()),
                rgb(c),
                1.5,
                along(&both.abs_difference(), 1e3),
            ));
        }
        let names = [
            format!("{} ({}) kec", b.name, b.role.name()),
            format!("{} {tables}", b.name),
        ];
        for (quantity, both, scale) in [("y_mm", &b.y, 1e3), ("yaw_mrad", &b.yaw, 1e3)] {
            let entity = format!("paper/fig18/{quantity}/{}", b.name);
            style(rec, &entity, &names, vec![rgb(c), tint(c)], vec![WIDE, THIN])?;
            send_scalar_values(rec, timelines(), n, &entity, pair(both, scale), 2)?;
            let entity = format!("paper/fig18/d{quantity}/{}", b.name);
            let diff: Vec<f64> = both.abs_difference().into_iter().map(|d| d * scale).collect();
            send_scalar_rows(
                rec,
                timelines(),
                n,
                &entity,
                diff,
                &[&format!("{} ({})", b.name, b.role.name())],
                vec![rgb(c)],
            )?;
        }
    }
    for (series, what) in fig18.into_iter().zip(["y", "yaw", "dy", "dyaw"]) {
        figure(rec, &format!("paper/fig18/plot_{what}"), series)?;
    }
    // The paper's bounds on |Δy| and |Δψ| (1 mm, 0.5 mrad) over the run.
    for (quantity, bound) in super::PAPER_BOUNDS {
        let ends = [0, n - 1];
        super::log_bound(
            rec,
            vec![
                TimeColumn::new_sequence(DISTANCE, ends.map(|i| distance_mm(g.distance_m[i]))),
                TimeColumn::new_duration_secs(TIME, ends.map(|i| g.t[i])),
            ],
            &format!("paper/fig18/{quantity}/bound"),
            bound,
            "the paper's bound",
        )?;
    }
    for w in wheelsets(f) {
        let wheels: Vec<&crate::paper::WheelNormal> =
            g.normal_forces.iter().filter(|x| x.wheelset == w).collect();
        let mut values = Vec::with_capacity(2 * wheels.len() * n);
        let mut diffs = Vec::with_capacity(wheels.len() * n);
        for i in 0..n {
            for x in &wheels {
                values.extend([x.normal.kec[i] * 1e-3, x.normal.tables[i] * 1e-3]);
                diffs.push((x.normal.kec[i] - x.normal.tables[i]).abs() * 1e-3);
            }
        }
        let mut names = Vec::new();
        let mut colors = Vec::new();
        let mut short = Vec::new();
        for x in &wheels {
            let c = if x.side == crate::profile::Side::Left {
                LEFT
            } else {
                RIGHT
            };
            names.extend([
                format!("{} kec", x.side.name()),
                format!("{} {tables}", x.side.name()),
            ]);
            colors.extend([rgb(c), tint(c)]);
            short.push((x.side.name(), rgb(c)));
        }
        let mut normal = Vec::new();
        let mut dnormal = Vec::new();
        for (k, x) in wheels.iter().enumerate() {
            normal.push(series(
                names[2 * k].clone(),
                colors[2 * k],
                WIDE,
                along(&x.normal.kec, 1e-3),
            ));
            normal.push(series(
                names[2 * k + 1].clone(),
                colors[2 * k + 1],
                THIN,
                along(&x.normal.tables, 1e-3),
            ));
            let d: Vec<f64> = x
                .normal
                .kec
                .iter()
                .zip(&x.normal.tables)
                .map(|(a, b)| (a - b).abs())
                .collect();
            dnormal.push(series(short[k].0.to_string(), short[k].1, 1.5, along(&d, 1e-3)));
        }
        figure(rec, &format!("paper/fig19/plot_normal/{w}"), normal)?;
        figure(rec, &format!("paper/fig19/plot_dnormal/{w}"), dnormal)?;
        let entity = format!("paper/fig19/normal_kn/{w}");
        let widths = (0..names.len())
            .map(|k| if k % 2 == 0 { WIDE } else { THIN })
            .collect();
        style(rec, &entity, &names, colors, widths)?;
        send_scalar_values(rec, timelines(), n, &entity, values, names.len())?;
        let names: Vec<&str> = short.iter().map(|s| s.0).collect();
        send_scalar_rows(
            rec,
            timelines(),
            n,
            &format!("paper/fig19/dnormal_kn/{w}"),
            diffs,
            &names,
            short.iter().map(|s| s.1).collect(),
        )?;
    }
    Ok(())
}
