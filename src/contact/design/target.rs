//! The design-target file of `kecsim design-wheel` (TOML, mm and degrees as a profile file's
//! boundary; converted to SI once, here):
//!
//! ```toml
//! name = "my-wheel"
//! # the left wheel's contact angle against the wheelset's lateral displacement towards it
//! contact_angle = [
//!   { y_mm = -10.0, angle_deg = 0.0 },
//!   { y_mm =   0.0, angle_deg = 2.86 },
//!   { y_mm =   6.0, angle_deg = 70.0 },   # the last: the flank
//! ]
//! flange_height_mm = 28.0
//! flange_tip_radius_mm = 10.0
//! field_end_mm = 60.0
//! # optional: how fast the wheel's curvature may follow a jump of the rail's, 1/rad (of ln ρ_w
//! # per rad of contact angle; default 220)
//! curvature_ramp_per_rad = 220.0
//! # optional: spacing of the designed part's points, mm (default 0.1; finer for fast ramps)
//! output_step_mm = 0.1
//! # where the wheel will run (each optional; the command line's flags override them)
//! rail = "54e1"
//! inclination = "1:20"
//! gauge_mm = 1435.0
//! back_to_back_mm = 1366.0
//! nominal_radius_mm = 295.0
//! ```
//!
//! Errors name the file, the line and the value.

use serde::Deserialize;

use super::DesignTarget;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetFile {
    name: String,
    contact_angle: Vec<toml::Spanned<AnglePoint>>,
    flange_height_mm: f64,
    flange_tip_radius_mm: f64,
    #[serde(default = "default_field_end")]
    field_end_mm: f64,
    #[serde(default = "default_ramp")]
    curvature_ramp_per_rad: f64,
    #[serde(default = "default_step")]
    output_step_mm: f64,
    rail: Option<String>,
    inclination: Option<String>,
    gauge_mm: Option<f64>,
    back_to_back_mm: Option<f64>,
    nominal_radius_mm: Option<f64>,
}

/// Where the designed wheel will run, as the target file gives it (mm as written; `None` where
/// the file is silent).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlacementSpec {
    pub rail: Option<String>,
    pub inclination: Option<String>,
    pub gauge_mm: Option<f64>,
    pub back_to_back_mm: Option<f64>,
    pub nominal_radius_mm: Option<f64>,
}

fn default_field_end() -> f64 {
    60.0
}

fn default_step() -> f64 {
    super::OUTPUT_STEP_M * 1e3
}

fn default_ramp() -> f64 {
    super::CURVATURE_RAMP_PER_RAD
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AnglePoint {
    y_mm: f64,
    angle_deg: f64,
}

/// 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].bytes().filter(|&b| b == b'\n').count() + 1
}

/// Parses a design target; `origin` names it in errors. Every problem is reported, each with its
/// line where it has one.
pub fn parse_target(text: &str, origin: &str) -> Result<(DesignTarget, PlacementSpec), String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let f: TargetFile = toml::from_str(text).map_err(|e| {
        let line = e
            .span()
            .map(|s| format!(":{}", line_of(text, s.start)))
            .unwrap_or_default();
        format!("{origin}{line}: {}", e.message())
    })?;
    let target = DesignTarget {
        name: f.name.clone(),
        contact_angle: f
            .contact_angle
            .iter()
            .map(|p| (p.get_ref().y_mm * 1e-3, p.get_ref().angle_deg.to_radians()))
            .collect(),
        flange_height_m: f.flange_height_mm * 1e-3,
        flange_tip_radius_m: f.flange_tip_radius_mm * 1e-3,
        field_end_m: f.field_end_mm * 1e-3,
        curvature_ramp_per_rad: f.curvature_ramp_per_rad,
        output_step_m: f.output_step_mm * 1e-3,
    };
    let mut problems = Vec::new();
    if f.name.is_empty()
        || f.name.starts_with('.')
        || !f
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
    {
        problems.push(format!(
            "line {}: name = {:?}: expected letters, digits, '-', '_' and '.' only, not starting with '.' (it names the profile and its file, NAME.csv)",
            line_of(text, text.find("name").unwrap_or(0)),
            f.name
        ));
    }
    if !f.contact_angle.iter().any(|p| p.get_ref().y_mm == 0.0) {
        problems.push(format!(
            "contact_angle: no point at y_mm = 0 (of {} points): the centred position's contact angle anchors the design (the taping line); give it",
            f.contact_angle.len()
        ));
    }
    // Where the wheel will run: each value given in its range (a NaN was reported as the
    // command line's "--gauge NaN").
    use crate::profile::placement::{GAUGE_RANGE_M, NOMINAL_RADIUS_RANGE_M};
    for (key, v, (lo, hi)) in [
        ("gauge_mm", f.gauge_mm, GAUGE_RANGE_M),
        ("back_to_back_mm", f.back_to_back_mm, (0.4, 2.0)),
        ("nominal_radius_mm", f.nominal_radius_mm, NOMINAL_RADIUS_RANGE_M),
    ] {
        let Some(v) = v else { continue };
        if !(v.is_finite() && v >= lo * 1e3 && v <= hi * 1e3) {
            let line = text
                .find(&format!("{key} "))
                .or_else(|| text.find(&format!("{key}=")))
                .map(|o| format!("line {}: ", line_of(text, o)))
                .unwrap_or_default();
            problems.push(format!(
                "{line}{key} = {v}: expected {} ..= {} mm",
                lo * 1e3,
                hi * 1e3
            ));
        }
    }
    for p in target.problems() {
        // "contact_angle point K ..." / "points K and L ...": the line of point K.
        let line = p
            .strip_prefix("contact_angle point")
            .map(|rest| rest.trim_start_matches('s'))
            .and_then(|rest| rest.trim_start().split(|c: char| !c.is_ascii_digit()).next())
            .and_then(|k| k.parse::<usize>().ok())
            .and_then(|k| f.contact_angle.get(k.wrapping_sub(1)))
            .map(|sp| format!("line {}: ", line_of(text, sp.span().start)))
            .unwrap_or_default();
        problems.push(format!("{line}{p}"));
    }
    let placement = PlacementSpec {
        rail: f.rail,
        inclination: f.inclination,
        gauge_mm: f.gauge_mm,
        back_to_back_mm: f.back_to_back_mm,
        nominal_radius_mm: f.nominal_radius_mm,
    };
    if problems.is_empty() {
        Ok((target, placement))
    } else {
        Err(format!(
            "{origin}: invalid design target:\n  - {}",
            problems.join("\n  - ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "name = \"w\"\ncontact_angle = [\n  { y_mm = -8.0, angle_deg = 1.0 },\n  { y_mm = 0.0, angle_deg = 3.0 },\n  { y_mm = 6.0, angle_deg = 70.0 },\n]\nflange_height_mm = 28\nflange_tip_radius_mm = 10\n";

    #[test]
    fn a_target_reads_in_si() {
        let (t, p) = parse_target(GOOD, "t.toml").unwrap();
        assert_eq!(p, PlacementSpec::default());
        assert_eq!(t.contact_angle.len(), 3);
        assert!((t.contact_angle[2].0 - 0.006).abs() < 1e-15);
        assert!((t.contact_angle[2].1 - 70f64.to_radians()).abs() < 1e-15);
        assert_eq!(t.field_end_m, 0.06);
    }

    #[test]
    fn bad_targets_name_file_line_and_value() {
        let falling = GOOD.replace("angle_deg = 3.0", "angle_deg = 0.5");
        let e = parse_target(&falling, "t.toml").unwrap_err();
        assert!(
            e.contains("t.toml") && e.contains("line 3") && e.contains("non-monotone contact"),
            "{e}"
        );
        let unknown = GOOD
            .replace("field", "flield")
            .replace("flange_height_mm", "flange_height_mm = 28\nfield_end");
        let e = parse_target(&unknown, "t.toml").unwrap_err();
        assert!(e.contains("t.toml:"), "{e}");
        let typo = GOOD.replace("y_mm = 6.0", "y = 6.0");
        let e = parse_target(&typo, "t.toml").unwrap_err();
        assert!(e.contains("t.toml:5") && e.contains("unknown field `y`"), "{e}");
        let no_centre = GOOD
            .replace("y_mm = -8.0", "y_mm = 0.5")
            .replace("y_mm = 0.0", "y_mm = 1.0");
        let e = parse_target(&no_centre, "t.toml").unwrap_err();
        assert!(e.contains("must include the centred position"), "{e}");
    }

    /// Issue 66, class 13/14: a target spanning y = 0 without a point there, a name that is no
    /// file name (ESC, CR), a NaN placement value — each refused naming the file and the key.
    #[test]
    fn absurd_targets_are_refused_naming_the_key() {
        let no_zero = GOOD.replace("{ y_mm = 0.0, angle_deg = 3.0 },\n", "");
        let e = parse_target(&no_zero, "t.toml").unwrap_err();
        assert!(e.contains("t.toml") && e.contains("no point at y_mm = 0"), "{e}");
        // (As written in TOML: ESC and CR escaped.)
        for bad in ["w\\u001b[31m", "w\\rx", "../w", ".hidden", "a b"] {
            let named = GOOD.replace("name = \"w\"", &format!("name = \"{bad}\""));
            let e = parse_target(&named, "t.toml").unwrap_err();
            assert!(
                e.contains("t.toml") && e.contains("line 1: name =") && e.contains("letters, digits"),
                "{bad:?}: {e}"
            );
        }
        let ok = GOOD.replace("name = \"w\"", "name = \"my-wheel_2.1\"");
        assert!(parse_target(&ok, "t.toml").is_ok());
        for (key, v) in [
            ("gauge_mm", "nan"),
            ("back_to_back_mm", "1e9"),
            ("nominal_radius_mm", "-inf"),
        ] {
            let e = parse_target(&format!("{GOOD}{key} = {v}\n"), "t.toml").unwrap_err();
            assert!(
                e.contains("t.toml") && e.contains("line 9:") && e.contains(&format!("{key} = ")),
                "{key}: {e}"
            );
        }
    }
}
