//! The track in TOML: a `[track]` table, the same in a track file and in a scenario file.
//!
//! ```toml
//! schema_version = 1                 # track files only (a scenario has its own)
//! name = "Paper Tab. 6 test track"
//!
//! [track]
//! gauge_m = 1.435                    # optional, as in the scenario
//! gauge_measuring_depth_m = 0.014    # optional
//! start = { x_m = 0.0, y_m = 0.0, z_m = 0.0, heading_rad = 0.0 }   # optional
//! horizontal = [                     # Tab. 1 sections, consecutive, s in m
//!   { type = "straight",   from_m = 0.0,   to_m = 100.0 },
//!   { type = "transition", from_m = 100.0, to_m = 150.0, end_radius_m = 235.65, end_cant_rad = -0.07599 },
//!   { type = "curve",      from_m = 150.0, to_m = 600.0, radius_m = 235.65, cant_rad = -0.07599 },
//!   ...
//! ]
//! vertical = [                       # Tab. 2 sections; optional (level track)
//!   { type = "straight", from_m = 0.0, to_m = 1000.0, slope_rad = 0.0 },
//! ]
//! [track.irregularities]             # optional: either a PSD ...
//! psd = "german-low"                 # fra1 … fra6, german-low, german-high
//! seed = 1
//! wavelength_min_m = 1.0             # optional (default: the PSD's usual band)
//! wavelength_max_m = 80.0
//! # ... or a measured file: file = "irregularities.csv" (relative to this file)
//! [track.lateral_flexibility]        # optional (rigid rails without it): the track under each
//! stiffness_n_per_m = 40e6           # wheelset shifts laterally as a mass on a spring–damper
//! damping_n_s_per_m = 1.0e5          # (crate::track::LateralFlexibility)
//! mass_kg = 150
//! ```
//!
//! Radii are signed (> 0: left curve, ρ_h = 1/R); a transition's omitted start or end radius is
//! a straight (ρ_h = 0), its omitted cant zero. Slopes follow the paper: positive going down.
//! Errors: syntax, unknown keys and wrong types come from the TOML parser with line and column;
//! every validation problem is collected and names the file and the line of its section.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use super::centreline::{Centreline, Start};
use super::irregularity::{Generation, Irregularities};
use super::psd::Psd;
use super::rails::TrackGauge;
use super::sections::{
    check_horizontal, check_vertical, HorizontalSection, VerticalSection, MAX_CANT_RAD, SERVICE_CANT_RAD,
};
use super::{measured, Track, TrackError};

/// The paper's Tab. 6 track, embedded in the binary.
pub const TAB6_TRACK: &str = include_str!("../../assets/track/tab6.toml");
/// Its name in messages.
pub const TAB6_ORIGIN: &str = "<embedded assets/track/tab6.toml>";

/// The `[track]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    #[serde(default = "default_gauge")]
    pub gauge_m: f64,
    #[serde(default = "default_depth")]
    pub gauge_measuring_depth_m: f64,
    #[serde(default)]
    pub start: StartSpec,
    #[serde(default)]
    pub horizontal: Vec<Spanned<HorizontalSpec>>,
    #[serde(default)]
    pub vertical: Vec<Spanned<VerticalSpec>>,
    #[serde(default)]
    pub irregularities: Option<Spanned<IrregularitySpec>>,
    /// `[track.lateral_flexibility]`: optional (rigid rails without it).
    #[serde(default)]
    pub lateral_flexibility: Option<Spanned<super::LateralFlexibility>>,
}

impl Default for TrackSpec {
    fn default() -> Self {
        TrackSpec {
            gauge_m: default_gauge(),
            gauge_measuring_depth_m: default_depth(),
            start: StartSpec::default(),
            horizontal: Vec::new(),
            vertical: Vec::new(),
            irregularities: None,
            lateral_flexibility: None,
        }
    }
}

fn default_gauge() -> f64 {
    TrackGauge::default().gauge_m
}
fn default_depth() -> f64 {
    TrackGauge::default().measuring_depth_m
}

/// `start = { ... }`.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartSpec {
    #[serde(default)]
    pub x_m: f64,
    #[serde(default)]
    pub y_m: f64,
    #[serde(default)]
    pub z_m: f64,
    #[serde(default)]
    pub heading_rad: f64,
}

/// Section types of the horizontal profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HorizontalType {
    Straight,
    Curve,
    Transition,
}

/// Section types of the vertical profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VerticalType {
    Straight,
    Transition,
}

/// One horizontal section as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HorizontalSpec {
    #[serde(rename = "type")]
    pub kind: HorizontalType,
    pub from_m: f64,
    pub to_m: f64,
    /// Curve: signed radius.
    pub radius_m: Option<f64>,
    /// Straight or curve: cant.
    pub cant_rad: Option<f64>,
    /// Transition: radius at its start (omitted: straight).
    pub start_radius_m: Option<f64>,
    /// Transition: radius at its end (omitted: straight).
    pub end_radius_m: Option<f64>,
    pub start_cant_rad: Option<f64>,
    pub end_cant_rad: Option<f64>,
}

/// One vertical section as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerticalSpec {
    #[serde(rename = "type")]
    pub kind: VerticalType,
    pub from_m: f64,
    pub to_m: f64,
    /// Straight: slope (positive going down).
    pub slope_rad: Option<f64>,
    /// Transition: slopes at its ends.
    pub start_slope_rad: Option<f64>,
    pub end_slope_rad: Option<f64>,
}

/// `[track.irregularities]`: a PSD or a file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrregularitySpec {
    pub psd: Option<String>,
    pub seed: Option<u64>,
    pub wavelength_min_m: Option<f64>,
    pub wavelength_max_m: Option<f64>,
    pub cosines: Option<usize>,
    pub step_m: Option<f64>,
    pub file: Option<String>,
    /// Run-in length from the track's start over which the irregularities grow from zero, m.
    pub run_in_m: Option<f64>,
}

/// A track file: `schema_version`, `name`, `[track]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackFile {
    pub schema_version: u32,
    pub name: String,
    pub track: TrackSpec,
}

/// The `[track]` table of a scenario file (the rest of the scenario is the scenario's business:
/// `kecsim track` on a scenario file reads only its name and track).
#[derive(Debug, Clone, Deserialize)]
struct ScenarioTrack {
    name: String,
    #[serde(default)]
    track: TrackSpec,
}

/// 1-based line of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Where problems are reported: the file's name and text (for lines).
struct Loc<'a> {
    origin: &'a str,
    text: &'a str,
    problems: Vec<String>,
    /// The offsets where lines start, made at the first problem: a line is then a binary search,
    /// not a count from the file's start (100 000 sections with a problem each took 354 s).
    lines: Option<Vec<usize>>,
    /// Problems beyond [`MAX_LISTED_PROBLEMS`], counted, not listed.
    more: usize,
}

/// The most problems of a file listed one by one; the rest are counted.
const MAX_LISTED_PROBLEMS: usize = 50;

impl Loc<'_> {
    fn new<'a>(origin: &'a str, text: &'a str) -> Loc<'a> {
        Loc {
            origin,
            text,
            problems: Vec::new(),
            lines: None,
            more: 0,
        }
    }

    fn at(&mut self, offset: usize, problem: impl AsRef<str>) {
        if self.problems.len() >= MAX_LISTED_PROBLEMS {
            self.more += 1;
            return;
        }
        let text = self.text;
        let starts = self.lines.get_or_insert_with(|| {
            std::iter::once(0)
                .chain(
                    text.bytes()
                        .enumerate()
                        .filter(|(_, b)| *b == b'\n')
                        .map(|(i, _)| i + 1),
                )
                .collect()
        });
        let line = starts.partition_point(|&s| s <= offset.min(text.len()));
        self.problems
            .push(format!("{}:{line}: {}", self.origin, problem.as_ref()));
    }

    /// The problems, with the count of those not listed.
    fn take(&mut self) -> Vec<String> {
        let mut p = std::mem::take(&mut self.problems);
        if self.more > 0 {
            p.push(format!(
                "… and {} more problems (the first {MAX_LISTED_PROBLEMS} are listed)",
                self.more
            ));
            self.more = 0;
        }
        p
    }
}

impl HorizontalSpec {
    fn section(&self, loc: &mut Loc, offset: usize) -> HorizontalSection {
        let mut not_for = |field: &str, present: bool| {
            if present {
                loc.at(
                    offset,
                    format!("{field} does not apply to a {:?} section", self.kind).to_lowercase(),
                );
            }
        };
        let curvature = |r: Option<f64>| r.map_or(0.0, |r| 1.0 / r);
        match self.kind {
            HorizontalType::Straight => {
                not_for("radius_m", self.radius_m.is_some());
                not_for("start_radius_m", self.start_radius_m.is_some());
                not_for("end_radius_m", self.end_radius_m.is_some());
                not_for("start_cant_rad", self.start_cant_rad.is_some());
                not_for("end_cant_rad", self.end_cant_rad.is_some());
                let c = self.cant_rad.unwrap_or(0.0);
                HorizontalSection {
                    cant_rad: [c; 2],
                    ..HorizontalSection::straight(self.from_m, self.to_m)
                }
            }
            HorizontalType::Curve => {
                not_for("start_radius_m", self.start_radius_m.is_some());
                not_for("end_radius_m", self.end_radius_m.is_some());
                not_for("start_cant_rad", self.start_cant_rad.is_some());
                not_for("end_cant_rad", self.end_cant_rad.is_some());
                let r = self.radius_m.unwrap_or(f64::NAN);
                if !(r.is_finite() && r.abs() >= 10.0) {
                    loc.at(
                        offset,
                        format!(
                            "a curve needs radius_m with |radius_m| ≥ 10 m, found {:?}",
                            self.radius_m
                        ),
                    );
                }
                HorizontalSection::curve(self.from_m, self.to_m, r, self.cant_rad.unwrap_or(0.0))
            }
            HorizontalType::Transition => {
                not_for("radius_m", self.radius_m.is_some());
                not_for("cant_rad", self.cant_rad.is_some());
                for r in [self.start_radius_m, self.end_radius_m].into_iter().flatten() {
                    if !(r.is_finite() && r.abs() >= 10.0) {
                        loc.at(
                            offset,
                            format!("radius {r} m: expected |radius| ≥ 10 m (omit it for a straight end)"),
                        );
                    }
                }
                HorizontalSection::transition(
                    self.from_m,
                    self.to_m,
                    (curvature(self.start_radius_m), self.start_cant_rad.unwrap_or(0.0)),
                    (curvature(self.end_radius_m), self.end_cant_rad.unwrap_or(0.0)),
                )
            }
        }
    }
}

impl VerticalSpec {
    fn section(&self, loc: &mut Loc, offset: usize) -> VerticalSection {
        match self.kind {
            VerticalType::Straight => {
                if self.start_slope_rad.is_some() || self.end_slope_rad.is_some() {
                    loc.at(
                        offset,
                        "a vertical straight has one slope_rad (start/end slopes are for transitions)",
                    );
                }
                VerticalSection::straight(self.from_m, self.to_m, self.slope_rad.unwrap_or(0.0))
            }
            VerticalType::Transition => {
                if self.slope_rad.is_some() {
                    loc.at(
                        offset,
                        "a vertical transition has start_slope_rad and end_slope_rad, not slope_rad",
                    );
                }
                VerticalSection::transition(
                    self.from_m,
                    self.to_m,
                    self.start_slope_rad.unwrap_or(0.0),
                    self.end_slope_rad.unwrap_or(0.0),
                )
            }
        }
    }
}

/// What the irregularity table asks for, checked.
enum IrrPlan {
    Generate(Generation),
    File(PathBuf),
}

impl IrregularitySpec {
    fn plan(&self, loc: &mut Loc, offset: usize, base: &Path) -> Option<IrrPlan> {
        match (&self.psd, &self.file) {
            (Some(_), Some(_)) | (None, None) => {
                loc.at(
                    offset,
                    "[track.irregularities] needs either psd = \"...\" or file = \"...\" (not both)",
                );
                None
            }
            (None, Some(file)) => {
                let generator_keys = [
                    self.seed.is_some(),
                    self.wavelength_min_m.is_some(),
                    self.wavelength_max_m.is_some(),
                    self.cosines.is_some(),
                    self.step_m.is_some(),
                ];
                if generator_keys.iter().any(|&b| b) {
                    loc.at(
                        offset,
                        "seed, wavelength_*, cosines and step_m apply to psd = \"...\", not to a file",
                    );
                }
                let p = Path::new(file);
                Some(IrrPlan::File(if p.is_absolute() {
                    p.to_path_buf()
                } else {
                    base.join(p)
                }))
            }
            (Some(name), None) => {
                let psd = match name.parse::<Psd>() {
                    Ok(p) => p,
                    Err(e) => {
                        loc.at(offset, e);
                        return None;
                    }
                };
                let mut g = Generation::new(psd, self.seed.unwrap_or(1));
                if let Some(v) = self.wavelength_min_m {
                    g.wavelength_min_m = v;
                }
                if let Some(v) = self.wavelength_max_m {
                    g.wavelength_max_m = v;
                }
                g.cosines = self.cosines;
                g.step_m = self.step_m;
                let problems = g.problems();
                for p in &problems {
                    loc.at(offset, p);
                }
                problems.is_empty().then_some(IrrPlan::Generate(g))
            }
        }
    }
}

impl TrackSpec {
    /// Validates the table and builds the track. `origin` names the file, `text` is its content
    /// (for line numbers), `base` the directory relative paths start from.
    /// Possible but doubtful values (warnings, each with its file and line): a cant beyond the
    /// service cants ([`SERVICE_CANT_RAD`]) but within the accepted [`MAX_CANT_RAD`].
    pub fn doubtful(&self, origin: &str, text: &str) -> Vec<String> {
        let mut loc = Loc::new(origin, text);
        for (i, s) in self.horizontal.iter().enumerate() {
            let spec = s.get_ref();
            let worst = [spec.cant_rad, spec.start_cant_rad, spec.end_cant_rad]
                .into_iter()
                .flatten()
                .filter(|c| c.is_finite())
                .fold(0.0_f64, |m, c| m.max(c.abs()));
            if worst > SERVICE_CANT_RAD && worst <= MAX_CANT_RAD {
                loc.at(
                    s.span().start,
                    format!(
                        "horizontal section {}: cant {worst} rad ({:.0} mm on standard gauge) is beyond the service cants (180–200 mm, {SERVICE_CANT_RAD} rad); accepted up to {MAX_CANT_RAD} rad — is it meant, or a cant in another unit?",
                        i + 1,
                        1500.0 * worst.sin()
                    ),
                );
            }
        }
        loc.take()
    }

    pub fn build(&self, name: &str, origin: &str, text: &str, base: &Path) -> Result<Track, TrackError> {
        let mut loc = Loc::new(origin, text);
        let table_line = text.find("[track]").unwrap_or(0);
        for (name, v, lo, hi) in [
            ("track.gauge_m", self.gauge_m, 0.5, 2.0),
            (
                "track.gauge_measuring_depth_m",
                self.gauge_measuring_depth_m,
                0.001,
                0.03,
            ),
        ] {
            if !(v.is_finite() && v >= lo && v <= hi) {
                loc.at(
                    table_line,
                    format!("{name} = {v}: expected a value in [{lo}, {hi}]"),
                );
            }
        }
        if self.horizontal.is_empty() {
            loc.at(
                table_line,
                "the track has no horizontal sections (track.horizontal = [ ... ])",
            );
            return Err(TrackError::Invalid {
                path: origin.to_string(),
                problems: loc.take(),
            });
        }
        let horizontal: Vec<HorizontalSection> = self
            .horizontal
            .iter()
            .map(|s| s.get_ref().section(&mut loc, s.span().start))
            .collect();
        let vertical: Vec<VerticalSection> = self
            .vertical
            .iter()
            .map(|s| s.get_ref().section(&mut loc, s.span().start))
            .collect();
        for (i, p) in check_horizontal(&horizontal) {
            loc.at(
                self.horizontal[i.min(self.horizontal.len() - 1)].span().start,
                format!("horizontal section {}: {p}", i + 1),
            );
        }
        if !vertical.is_empty() {
            for (i, p) in check_vertical(&vertical) {
                loc.at(
                    self.vertical[i.min(self.vertical.len() - 1)].span().start,
                    format!("vertical section {}: {p}", i + 1),
                );
            }
        }
        let plan = self
            .irregularities
            .as_ref()
            .and_then(|s| s.get_ref().plan(&mut loc, s.span().start, base));
        if let Some(f) = &self.lateral_flexibility {
            for p in f.get_ref().problems() {
                loc.at(f.span().start, p);
            }
        }
        let st = self.start;
        for (name, v, limit) in [
            ("x_m", st.x_m, 1e7),
            ("y_m", st.y_m, 1e7),
            ("z_m", st.z_m, 1e4),
            ("heading_rad", st.heading_rad, 100.0),
        ] {
            if !(v.is_finite() && v.abs() <= limit) {
                loc.at(
                    table_line,
                    format!("track.start.{name} = {v:e}: expected |value| ≤ {limit:e} (plan coordinates in m, heading in rad)"),
                );
            }
        }
        if !loc.problems.is_empty() {
            return Err(TrackError::Invalid {
                path: origin.to_string(),
                problems: loc.take(),
            });
        }
        let start = Start {
            x_m: st.x_m,
            y_m: st.y_m,
            z_m: st.z_m,
            heading_rad: st.heading_rad,
        };
        let centreline = Centreline::new(start, &horizontal, &vertical).map_err(|e| TrackError::Invalid {
            path: origin.to_string(),
            problems: vec![e.to_string()],
        })?;
        let (a, b) = centreline.range();
        let source_files = match &plan {
            Some(IrrPlan::File(path)) => vec![path.clone()],
            _ => Vec::new(),
        };
        let irregularities = match plan {
            None => None,
            Some(IrrPlan::Generate(g)) => {
                // A band whose shortest wavelength does not fit on the line generates no
                // irregularity the vehicle feels as one (a length in km typed as m?).
                if g.wavelength_min_m >= b - a {
                    let offset = self.irregularities.as_ref().map_or(0, |s| s.span().start);
                    loc.at(
                        offset,
                        format!(
                            "track.irregularities.wavelength_min_m = {}: not shorter than the track ({} m), so no wavelength of the band fits on it (the standard band is 3–25 m or 3–70 m)",
                            g.wavelength_min_m,
                            b - a
                        ),
                    );
                    return Err(TrackError::Invalid {
                        path: origin.to_string(),
                        problems: loc.take(),
                    });
                }
                Some(Irregularities::generate(&g, a, b)?.0)
            }
            Some(IrrPlan::File(path)) => {
                let irr = measured::read_csv(&path)?;
                let (fa, fb) = irr.range();
                if fa > a + 1e-9 || fb < b - 1e-9 {
                    let offset = self.irregularities.as_ref().map_or(0, |s| s.span().start);
                    loc.at(
                        offset,
                        format!(
                            "{} covers s = {fa}..{fb} m, the track runs s = {a}..{b} m: the file must cover the track",
                            path.display()
                        ),
                    );
                    return Err(TrackError::Invalid {
                        path: origin.to_string(),
                        problems: loc.take(),
                    });
                }
                Some(irr)
            }
        };
        let run_in = self.irregularities.as_ref().and_then(|i| i.get_ref().run_in_m);
        let irregularities = match (irregularities, run_in) {
            (Some(mut irr), Some(l)) => {
                if !(l.is_finite() && l > 0.0 && l < b - a) {
                    let offset = self.irregularities.as_ref().map_or(0, |s| s.span().start);
                    loc.at(
                        offset,
                        format!("track.irregularities.run_in_m = {l}: expected 0 < run_in_m < the track's length {}", b - a),
                    );
                    return Err(TrackError::Invalid {
                        path: origin.to_string(),
                        problems: loc.take(),
                    });
                }
                irr.run_in = Some((a, l));
                Some(irr)
            }
            (irr, _) => irr,
        };
        Ok(Track {
            name: name.to_string(),
            centreline,
            irregularities,
            gauge: TrackGauge {
                gauge_m: self.gauge_m,
                measuring_depth_m: self.gauge_measuring_depth_m,
            },
            lateral_flexibility: self.lateral_flexibility.as_ref().map(|f| *f.get_ref()),
            source_files,
        })
    }
}

fn parse_err(origin: &str, e: toml::de::Error) -> TrackError {
    TrackError::Parse {
        path: origin.to_string(),
        message: e.to_string().trim_end().to_string(),
    }
}

/// Builds a track from the text of a track file or of a scenario file (recognised by its
/// `[profiles]` table); `origin` names it, `base` is where relative paths start.
pub fn track_from_text(text: &str, origin: &str, base: &Path) -> Result<Track, TrackError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let table: toml::Table = toml::from_str(text).map_err(|e| parse_err(origin, e))?;
    if table.contains_key("profiles") {
        let scenario: ScenarioTrack = toml::from_str(text).map_err(|e| parse_err(origin, e))?;
        return scenario.track.build(&scenario.name, origin, text, base);
    }
    let file: TrackFile = toml::from_str(text).map_err(|e| parse_err(origin, e))?;
    if file.schema_version != crate::SCHEMA_VERSION {
        return Err(TrackError::Invalid {
            path: origin.to_string(),
            problems: vec![format!(
                "{origin}:{}: schema_version = {}: this kecsim reads schema_version = {}",
                line_of(text, text.find("schema_version").unwrap_or(0)),
                file.schema_version,
                crate::SCHEMA_VERSION
            )],
        });
    }
    file.track.build(&file.name, origin, text, base)
}

/// Reads a track or scenario file.
pub fn read_track(path: &Path) -> Result<Track, TrackError> {
    let p = path.display().to_string();
    let text = crate::limits::read_text(path).map_err(|source| TrackError::Io {
        path: p.clone(),
        source,
    })?;
    track_from_text(&text, &p, path.parent().unwrap_or(Path::new(".")))
}

/// The paper's Tab. 6 track (embedded).
pub fn tab6() -> Result<Track, TrackError> {
    track_from_text(TAB6_TRACK, TAB6_ORIGIN, Path::new("."))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        track_from_text(text, "t.toml", Path::new("."))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn tab6_builds_with_the_papers_parameters() {
        let t = tab6().unwrap();
        let (h, _) = t.centreline.sections();
        assert_eq!(h.len(), 5);
        assert!((h[1].twist() + 1.5198e-3).abs() < 1e-12);
        assert!((h[1].curvature_rate() - 8.48716e-5).abs() < 1e-10);
        assert!((h[2].cant_rad[0] + 0.07599).abs() < 1e-15);
        assert!(t.irregularities.is_none());
    }

    #[test]
    fn validation_names_file_and_line_of_each_bad_section() {
        let text = TAB6_TRACK
            .replace("from_m = 150.0, to_m = 600.0", "from_m = 155.0, to_m = 600.0")
            .replace("start_radius_m = 235.65", "start_radius_m = 300.0");
        let e = err(&text);
        let line = |needle: &str| line_of(&text, text.find(needle).unwrap());
        assert!(
            e.contains(&format!(
                "t.toml:{}: horizontal section 3: gap",
                line("from_m = 155.0")
            )),
            "{e}"
        );
        assert!(
            e.contains(&format!(
                "t.toml:{}: horizontal section 4: mismatched curvature",
                line("start_radius_m = 300.0")
            )),
            "{e}"
        );
    }

    #[test]
    fn negative_length_and_unknown_keys() {
        let text = TAB6_TRACK.replace("from_m = 650.0, to_m = 1000.0", "from_m = 650.0, to_m = 640.0");
        assert!(err(&text).contains("negative length"), "{}", err(&text));
        let text = TAB6_TRACK.replace(
            "radius_m = 235.65, cant_rad",
            "radius_m = 235.65, radius_mm = 1, cant_rad",
        );
        let e = err(&text);
        assert!(
            e.starts_with("t.toml: ") && e.contains("unknown field `radius_mm`") && e.contains("line"),
            "{e}"
        );
    }

    #[test]
    fn irregularity_table_is_checked() {
        let with = |t: &str| format!("{TAB6_TRACK}\n[track.irregularities]\n{t}\n");
        assert!(err(&with("psd = \"fra9\"")).contains("unknown PSD 'fra9'"));
        assert!(err(&with("psd = \"fra4\"\nfile = \"x.csv\"")).contains("not both"));
        assert!(err(&with(
            "psd = \"fra4\"\nwavelength_min_m = 50.0\nwavelength_max_m = 10.0"
        ))
        .contains("0 < min < max"));
        let e = err(&with("file = \"no_such_file.csv\""));
        assert!(e.contains("no_such_file.csv"), "{e}");
        let t = track_from_text(
            &with("psd = \"german-low\"\nseed = 3\nwavelength_min_m = 2.0\nwavelength_max_m = 50.0"),
            "t.toml",
            Path::new("."),
        )
        .unwrap();
        assert_eq!(t.irregularities.unwrap().range(), (0.0, 1000.0));
    }
}
