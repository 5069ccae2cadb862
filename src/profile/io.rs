//! Profile files: reading (plain CSV, two-column `.dat`, SIMPACK `.prw`/`.prr`) and writing CSV.
//!
//! All formats are read into points (y, z) in mm, z **up**, lateral y increasing towards the
//! field side of a left-side profile (see [`super`]), then checked and converted to SI once:
//!
//! | format | recognised by | columns | vertical |
//! |---|---|---|---|
//! | CSV | `.csv` | `y,z` in mm; optional header row; `#` comment lines | z up |
//! | columns | any other extension (`.dat`, `.txt`) | two numbers per line, whitespace/comma separated; `#`, `!`, `%` comments | z up |
//! | SIMPACK | `.prw` (wheel), `.prr` (rail) | `point.begin` … `point.end`, `y z [weight]`; `!` comments | z down (SIMPACK); `units.len.f`, `shift.y/z`, `mirror.y/z` applied |
//!
//! Checks (each error names the file and, where it applies, the line): unreadable or empty file,
//! non-numeric cell, NaN/inf, fewer than 4 points, a lateral extent under 1 mm (data apparently in
//! metres), a lateral coordinate that goes back (self-overlapping or undercut profile).
//! Exactly vertical (or steeper than [`MAX_END_SLOPE`]) runs at either *end* — the vertical sides
//! of a rail head, a wheel's flange back — cannot be a function z(y) and carry no contact: they
//! are trimmed, and the profile's notes say so. A wheel profile is shifted vertically so that its
//! taping line (y = 0) is at z = 0 (the nominal radius is then r0 at y = 0).

use std::io::Write;
use std::path::Path;

use super::curve::{Profile, ProfileKind};
use super::error::ProfileError;
use crate::spline::SplineError;

/// End segments steeper than this |dz/dy| (88.9°) are trimmed.
pub const MAX_END_SLOPE: f64 = 50.0;
/// Smallest lateral extent accepted, mm; less means the file is probably in metres.
pub const MIN_EXTENT_MM: f64 = 1.0;
/// Largest lateral or vertical extent accepted, mm; more means a wrong length unit.
pub const MAX_EXTENT_MM: f64 = 400.0;

/// A point as read, mm, with its 1-based line number.
#[derive(Debug, Clone, Copy)]
struct RawPoint {
    y: f64,
    z: f64,
    line: usize,
}

/// Reads a profile file of any supported format.
pub fn read_profile(path: &Path, expected: ProfileKind) -> Result<Profile, ProfileError> {
    let p = path.display().to_string();
    let text = crate::limits::read_text(path).map_err(|source| ProfileError::Io {
        path: p.clone(),
        source,
    })?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("profile");
    parse_profile(&text, &ext, name, &p, expected)
}

/// Parses profile text in the format of the file extension `ext` (`csv`, `prw`/`prr`, anything
/// else: columns); `origin` names it in errors and as its source.
pub fn parse_profile(
    text: &str,
    ext: &str,
    name: &str,
    origin: &str,
    expected: ProfileKind,
) -> Result<Profile, ProfileError> {
    let p = origin.to_string();
    // A byte-order mark (editors on Windows write one) is not part of the first number.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Line endings of classic Mac OS (CR alone): lines all the same (issue 66: "empty file").
    let unix;
    let text = if text.contains('\r') && !text.contains('\n') {
        unix = text.replace('\r', "\n");
        unix.as_str()
    } else {
        text
    };
    let (points, mut notes) = match ext {
        "prw" | "prr" => read_simpack(&p, text, expected)?,
        "csv" => (read_csv(&p, text)?, Vec::new()),
        _ => (read_columns(&p, text)?, Vec::new()),
    };
    let CheckedPoints { s, z, notes: more } = check_points(&p, points, expected)?;
    notes.extend(more);
    let mut profile = Profile::from_points(name, expected, &p, s, z).map_err(|e| ProfileError::InFile {
        path: p.clone(),
        problem: match e {
            SplineError::TooFewPoints(n) => format!("only {n} usable points; a profile needs at least 4"),
            other => format!("invalid points: {other:?}"),
        },
    })?;
    profile.notes = notes;
    Ok(profile)
}

fn at(path: &str, line: usize, problem: impl Into<String>) -> ProfileError {
    ProfileError::AtLine {
        path: path.to_string(),
        line,
        problem: problem.into(),
    }
}

fn parse_number(path: &str, line: usize, col: usize, cell: &str) -> Result<f64, ProfileError> {
    let v: f64 = cell.trim().parse().map_err(|_| {
        at(
            path,
            line,
            format!("column {col}: '{}' is not a number", cell.trim()),
        )
    })?;
    if !v.is_finite() {
        return Err(at(
            path,
            line,
            format!("column {col}: {v} is not a finite number"),
        ));
    }
    Ok(v)
}

/// A profile CSV header's column: `y`/`z`, with or without `_mm`, `mm`, `[mm]`, `(mm)`, any case
/// (`Some('y')`, `Some('z')`); a length in another unit or any other name: None.
fn header_axis(cell: &str) -> Option<char> {
    let c: String = cell
        .to_ascii_lowercase()
        .chars()
        .filter(|c| !c.is_whitespace() && !"[]()_".contains(*c))
        .collect();
    match c.as_str() {
        "y" | "ymm" => Some('y'),
        "z" | "zmm" => Some('z'),
        _ => None,
    }
}

/// Plain CSV, `y,z` in mm, z up; `#` comments. An optional header row (the first record, not a
/// number) names the columns, which are then read by name, in any order (`y_mm`, `z_mm`; `y`, `z`
/// with or without a unit in mm); a header that names no y and z column in mm is refused.
fn read_csv(path: &str, text: &str) -> Result<Vec<RawPoint>, ProfileError> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut pts = Vec::new();
    let (mut yc, mut zc) = (0, 1);
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| {
            let line = e.position().map(|p| p.line() as usize).unwrap_or(0);
            at(path, line, format!("malformed CSV: {e}"))
        })?;
        let line = rec.position().map(|p| p.line() as usize).unwrap_or(0);
        if rec.iter().all(|c| c.is_empty()) {
            continue;
        }
        if k == 0 && rec.get(0).is_some_and(|c| c.parse::<f64>().is_err()) {
            // The header row: the columns by name.
            let find = |axis: char| rec.iter().position(|c| header_axis(c) == Some(axis));
            match (find('y'), find('z')) {
                (Some(y), Some(z)) => (yc, zc) = (y, z),
                _ => {
                    return Err(at(
                        path,
                        line,
                        format!(
                            "header `{}` names no y and z column in mm (expected y_mm, z_mm in any order; a profile file is in mm)",
                            rec.iter().collect::<Vec<_>>().join(", ")
                        ),
                    ))
                }
            }
            continue;
        }
        if rec.len() < 2 {
            return Err(at(
                path,
                line,
                format!("expected 2 columns (y_mm, z_mm), found {}", rec.len()),
            ));
        }
        if rec.len() <= yc.max(zc) {
            return Err(at(
                path,
                line,
                format!(
                    "expected {} columns as the header names, found {}",
                    yc.max(zc) + 1,
                    rec.len()
                ),
            ));
        }
        let y = parse_number(path, line, yc + 1, &rec[yc])?;
        let z = parse_number(path, line, zc + 1, &rec[zc])?;
        pts.push(RawPoint { y, z, line });
    }
    Ok(pts)
}

/// Two numeric columns per line, whitespace or comma separated; `#`, `!`, `%` start comments.
fn read_columns(path: &str, text: &str) -> Result<Vec<RawPoint>, ProfileError> {
    let mut pts = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let body = raw.split(['#', '!', '%']).next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let cells: Vec<&str> = body
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|c| !c.is_empty())
            .collect();
        if cells.len() < 2 {
            return Err(at(
                path,
                line,
                format!("expected 2 columns (y z in mm), found {}", cells.len()),
            ));
        }
        let y = parse_number(path, line, 1, cells[0])?;
        let z = parse_number(path, line, 2, cells[1])?;
        pts.push(RawPoint { y, z, line });
    }
    Ok(pts)
}

/// SIMPACK `.prw`/`.prr` profile: header `type` (0 rail, 1 wheel), spline block settings, and
/// the `point.begin`…`point.end` list. Applies `shift.y/z`, `mirror.y/z` and `units.len.f`
/// (length units per metre); converts SIMPACK's downward z to kecsim's upward z.
fn read_simpack(
    path: &str,
    text: &str,
    expected: ProfileKind,
) -> Result<(Vec<RawPoint>, Vec<String>), ProfileError> {
    let mut in_points = false;
    let mut in_header = false;
    let mut seen_points = false;
    let mut kind: Option<(ProfileKind, usize)> = None;
    let (mut shift_y, mut shift_z, mut mirror_y, mut mirror_z) = (0.0, 0.0, false, false);
    let mut len_factor = 1000.0;
    let mut pts = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let body = raw.split('!').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        if body == "header.begin" || body == "header.end" {
            in_header = body == "header.begin";
            continue;
        }
        if body == "point.begin" {
            in_points = true;
            seen_points = true;
            continue;
        }
        if body == "point.end" {
            in_points = false;
            continue;
        }
        if in_points {
            let cells: Vec<&str> = body.split_whitespace().collect();
            if cells.len() < 2 {
                return Err(at(
                    path,
                    line,
                    format!("expected 'y z [weight]', found {}", cells.len()),
                ));
            }
            let y = parse_number(path, line, 1, cells[0])?;
            let z = parse_number(path, line, 2, cells[1])?;
            pts.push(RawPoint { y, z, line });
            continue;
        }
        if let Some((key, value)) = body.split_once('=') {
            let (key, value) = (key.trim(), value.trim().trim_matches('\''));
            let num = || parse_number(path, line, 1, value);
            match key {
                // `type` in the header is the profile type; in the spline block it is the
                // original data-file type, which does not concern us.
                "type" if in_header => {
                    let k = match num()? as i64 {
                        0 => ProfileKind::Rail,
                        1 => ProfileKind::Wheel,
                        t => {
                            return Err(at(
                                path,
                                line,
                                format!("unknown profile type {t} (0 = rail, 1 = wheel)"),
                            ))
                        }
                    };
                    kind = Some((k, line));
                }
                "shift.y" => shift_y = num()?,
                "shift.z" => shift_z = num()?,
                "mirror.y" => mirror_y = num()? != 0.0,
                "mirror.z" => mirror_z = num()? != 0.0,
                "units.len.f" => {
                    len_factor = num()?;
                    if len_factor <= 0.0 {
                        return Err(at(path, line, "units.len.f must be positive"));
                    }
                }
                "rotate" if num()? != 0.0 => {
                    return Err(at(
                        path,
                        line,
                        "rotate ≠ 0 is not supported: give the profile unrotated and set the rail inclination in kecsim",
                    ));
                }
                _ => {}
            }
        }
    }
    if !seen_points {
        return Err(ProfileError::InFile {
            path: path.into(),
            problem: "no 'point.begin' block: not a SIMPACK profile".into(),
        });
    }
    if let Some((k, _)) = kind {
        if k != expected {
            return Err(ProfileError::WrongKind {
                path: path.into(),
                expected,
                found: k,
            });
        }
    }
    let mut notes = Vec::new();
    if mirror_y {
        notes.push("SIMPACK mirror.y applied".to_string());
    }
    let to_mm = 1000.0 / len_factor;
    for p in &mut pts {
        let (mut y, mut z) = (p.y + shift_y, p.z + shift_z);
        if mirror_y {
            y = -y;
        }
        if mirror_z {
            z = -z;
        }
        p.y = y * to_mm;
        p.z = -z * to_mm; // SIMPACK z points down
    }
    Ok((pts, notes))
}

/// Points that passed the checks, SI, increasing s, with what was done to them.
struct CheckedPoints {
    s: Vec<f64>,
    z: Vec<f64>,
    notes: Vec<String>,
}

/// Checks raw points and converts them to SI.
fn check_points(
    path: &str,
    mut pts: Vec<RawPoint>,
    kind: ProfileKind,
) -> Result<CheckedPoints, ProfileError> {
    let mut notes = Vec::new();
    if pts.is_empty() {
        return Err(ProfileError::InFile {
            path: path.into(),
            problem: "no profile points (empty file)".into(),
        });
    }
    let last_line = pts[pts.len() - 1].line;
    if pts.len() < 4 {
        return Err(at(
            path,
            last_line,
            format!("only {} points; a profile needs at least 4", pts.len()),
        ));
    }
    let (ymin, ymax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.y), b.max(p.y)));
    if ymax - ymin < MIN_EXTENT_MM {
        return Err(at(
            path,
            pts[0].line,
            format!(
                "lateral extent is only {:.4} mm: the file looks like metres; profile files are in mm",
                ymax - ymin
            ),
        ));
    }
    let (zmin, zmax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.z), b.max(p.z)));
    if ymax - ymin > MAX_EXTENT_MM || zmax - zmin > MAX_EXTENT_MM {
        return Err(at(
            path,
            pts[0].line,
            format!(
                "the profile spans {:.1} mm laterally and {:.1} mm vertically: no wheel or rail profile is larger than {MAX_EXTENT_MM} mm, so the length unit looks wrong (profile files are in mm; SIMPACK files scale by units.len.f)",
                ymax - ymin,
                zmax - zmin
            ),
        ));
    }
    if pts[pts.len() - 1].y < pts[0].y {
        pts.reverse();
    }
    // Drop exact duplicates (repeated points are common in exported files).
    let before = pts.len();
    pts.dedup_by(|b, a| b.y == a.y && b.z == a.z);
    if pts.len() < before {
        notes.push(format!("{} repeated points dropped", before - pts.len()));
    }
    // Trim vertical (or steeper than MAX_END_SLOPE) runs at both ends.
    let steep = |a: &RawPoint, b: &RawPoint| {
        let dy = b.y - a.y;
        dy <= 0.0 || ((b.z - a.z) / dy).abs() > MAX_END_SLOPE
    };
    let mut lo = 0;
    while lo + 1 < pts.len() && steep(&pts[lo], &pts[lo + 1]) {
        lo += 1;
    }
    let mut hi = pts.len() - 1;
    while hi > lo && steep(&pts[hi - 1], &pts[hi]) {
        hi -= 1;
    }
    if lo > 0 {
        notes.push(format!(
            "{lo} points of a vertical end trimmed (lines {}–{})",
            pts[0].line,
            pts[lo - 1].line
        ));
    }
    if hi < pts.len() - 1 {
        notes.push(format!(
            "{} points of a vertical end trimmed (lines {}–{})",
            pts.len() - 1 - hi,
            pts[hi + 1].line,
            pts[pts.len() - 1].line
        ));
    }
    let pts = &pts[lo..=hi];
    for w in pts.windows(2) {
        if w[1].y <= w[0].y {
            return Err(at(
                path,
                w[1].line,
                format!(
                    "lateral coordinate goes back from y = {} mm (line {}) to y = {} mm: the profile overlaps itself or is undercut, and is not a function z(y)",
                    w[0].y, w[0].line, w[1].y
                ),
            ));
        }
    }
    if pts.len() < 4 {
        return Err(at(
            path,
            last_line,
            format!(
                "only {} usable points after trimming vertical ends; a profile needs at least 4",
                pts.len()
            ),
        ));
    }
    let s: Vec<f64> = pts.iter().map(|p| p.y * 1e-3).collect();
    let mut z: Vec<f64> = pts.iter().map(|p| p.z * 1e-3).collect();
    if kind == ProfileKind::Wheel {
        if s[0] > 0.0 || s[s.len() - 1] < 0.0 {
            return Err(ProfileError::InFile {
                path: path.into(),
                problem: format!(
                    "wheel profile spans y = {:.3}..{:.3} mm and does not contain its taping line y = 0",
                    s[0] * 1e3,
                    s[s.len() - 1] * 1e3
                ),
            });
        }
        // Height of the taping line by the same spline the profile will use.
        let z0 = super::CubicSpline::new(s.clone(), z.clone())
            .map_err(|e| ProfileError::InFile {
                path: path.into(),
                problem: format!("invalid points: {e:?}"),
            })?
            .eval(0.0)
            .z;
        if z0 != 0.0 {
            z.iter_mut().for_each(|v| *v -= z0);
            notes.push(format!(
                "shifted {:.4} mm vertically so the taping line y = 0 is at z = 0",
                -z0 * 1e3
            ));
        }
    }
    if let Some(problem) = shape_problem(kind, &s, &z) {
        return Err(ProfileError::InFile {
            path: path.into(),
            problem,
        });
    }
    Ok(CheckedPoints { s, z, notes })
}

/// Narrowest profile accepted, m: wheel running surfaces and rail heads span 60–150 mm, so a
/// much narrower one is in another unit (inches: 2.4–6; cm: 6–15).
pub const MIN_PROFILE_SPAN_M: f64 = 0.015;

/// Smallest flange height accepted on a wheel profile, m (S1002: 28 mm; worn and tram wheels
/// 20–25 mm).
pub const MIN_FLANGE_HEIGHT_M: f64 = 0.010;

/// Whether the points have the shape of their kind (left-side orientation, s towards the field
/// side, z up; a wheel's taping line at s = z = 0): a wheel has a flange — a point at least
/// [`MIN_FLANGE_HEIGHT_M`] below the taping line on the inner side (s < 0) — and its field side
/// (s > 0) does not fall away like a rail head's side; a rail head's highest point lies inside the
/// profile, with the profile falling from it on both sides. A rail profile given as the wheel (or
/// a wheel as the rail) is then named as such instead of giving nonsense results.
pub fn shape_problem(kind: ProfileKind, s: &[f64], z: &[f64]) -> Option<String> {
    let pts = || s.iter().zip(z);
    // A wheel's running surface and a rail head span 60–150 mm: one of 2–6 "mm" is in inches
    // (or cm), and its flange or head would be named as missing.
    let span = s.iter().copied().fold(f64::MIN, f64::max) - s.iter().copied().fold(f64::MAX, f64::min);
    if span < MIN_PROFILE_SPAN_M {
        return Some(format!(
            "the profile spans only {:.2} mm across (a {kind} profile spans 60–150 mm): is it in inches (× 25.4) or cm (× 10)? Profile files are in mm",
            span * 1e3
        ));
    }
    match kind {
        ProfileKind::Wheel => {
            let flange = pts()
                .filter(|(s, _)| **s < 0.0)
                .map(|(_, z)| *z)
                .fold(0.0, f64::min);
            let field = pts()
                .filter(|(s, _)| **s > 0.0)
                .map(|(_, z)| *z)
                .fold(0.0, f64::min);
            let up = pts()
                .filter(|(s, _)| **s < 0.0)
                .map(|(_, z)| *z)
                .fold(0.0, f64::max);
            if flange > -MIN_FLANGE_HEIGHT_M && up >= MIN_FLANGE_HEIGHT_M {
                return Some(format!(
                    "the flange points up: the inner side (y < 0) rises {:.1} mm above the taping line and never falls below it — the profile is flipped in z (z must be up, the flange below the taping line: z = r0 − radius); negate its z column",
                    up * 1e3
                ));
            }
            if flange > -MIN_FLANGE_HEIGHT_M && field <= -MIN_FLANGE_HEIGHT_M {
                return Some(format!(
                    "the flange is on the wrong side: the profile's lowest point, {:.1} mm below the taping line, lies on the field side (y > 0) and the inner side has none — the profile is mirrored (y must increase towards the field side of a left wheel, the flange at negative y); negate its y column",
                    -field * 1e3
                ));
            }
            if flange > -MIN_FLANGE_HEIGHT_M {
                return Some(format!(
                    "this does not look like a wheel profile: it has no flange (its lowest point on the inner side, y < 0, is {:.1} mm below the taping line; a flange is at least {:.0} mm) — is it a rail profile?",
                    -flange * 1e3,
                    MIN_FLANGE_HEIGHT_M * 1e3
                ));
            }
            if field < -0.5 * MIN_FLANGE_HEIGHT_M {
                return Some(format!(
                    "this does not look like a wheel profile: its field side (y > 0) falls {:.1} mm below the taping line, as a rail head's side does (a wheel's tread rises towards the field side) — is it a rail profile?",
                    -field * 1e3
                ));
            }
            None
        }
        ProfileKind::Rail => {
            let (k_top, z_top) =
                pts().enumerate().fold(
                    (0, f64::MIN),
                    |best, (k, (_, z))| if *z > best.1 { (k, *z) } else { best },
                );
            let n = s.len();
            let (w_in, w_out) = (s[k_top] - s[0], s[n - 1] - s[k_top]);
            let (d_in, d_out) = (z_top - z[0], z_top - z[n - 1]);
            if w_in < 0.005 || w_out < 0.005 || d_in < 0.001 || d_out < 0.001 {
                return Some(format!(
                    "this does not look like a rail profile: a rail head's highest point lies inside the profile with the head falling away on both sides, but here it is {:.1} mm from the inner end and {:.1} mm from the outer end, {:.1} and {:.1} mm above them — is it a wheel profile?",
                    w_in * 1e3,
                    w_out * 1e3,
                    d_in * 1e3,
                    d_out * 1e3
                ));
            }
            None
        }
    }
}

/// Writes a profile as CSV (`y_mm,z_mm`, z up, left-side orientation) with `#` comment lines
/// naming its source; the points are the spline's knots, so reading the file back gives the same
/// profile.
pub fn write_csv(profile: &Profile, path: &Path) -> std::io::Result<()> {
    write_csv_with_header(profile, path, &[])
}

/// [`write_csv`] with more `#` lines after the source (a designed profile's target and result).
pub fn write_csv_with_header(profile: &Profile, path: &Path, header: &[String]) -> std::io::Result<()> {
    let f = crate::files::AtomicFile::create(path)?;
    crate::files::commit_csv(csv_into(f, profile, header)?)
}

/// The bytes [`write_csv`] writes for `profile` (to compare a file with what it would become).
pub fn csv_bytes(profile: &Profile) -> std::io::Result<Vec<u8>> {
    csv_into(Vec::new(), profile, &[])?
        .into_inner()
        .map_err(|e| std::io::Error::other(e.to_string()))
}

/// The profile's CSV written into `f` (the writer returned, to be flushed by the caller).
fn csv_into<W: Write>(mut f: W, profile: &Profile, header: &[String]) -> std::io::Result<csv::Writer<W>> {
    writeln!(f, "# kecsim {} profile '{}'", profile.kind, profile.name)?;
    writeln!(f, "# source: {}", profile.source)?;
    for line in header {
        writeln!(f, "# {}", line.replace('\n', " "))?;
    }
    writeln!(
        f,
        "# y lateral towards the field side of a left-side profile, z up, both in mm"
    )?;
    if profile.kind == ProfileKind::Wheel {
        writeln!(
            f,
            "# wheel: y = 0 is the taping line (nominal rolling circle), radius = r0 - z"
        )?;
    }
    let mut w = csv::Writer::from_writer(f);
    w.write_record(["y_mm", "z_mm"])?;
    let (s, z) = profile.knots();
    for (a, b) in s.iter().zip(z) {
        w.write_record([format!("{:.9}", a * 1e3), format!("{:.9}", b * 1e3)])?;
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::StandardProfile;
    use std::fs;

    /// Issue 35, item 7: a wheel flipped in z and a wheel in inches are named as such (before:
    /// "is it a rail profile?"); a mirrored wheel is still named mirrored.
    #[test]
    fn flipped_mirrored_and_inch_profiles_are_named_as_such() {
        let rows: Vec<(f64, f64)> = include_str!("../../profiles/s1002.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('y'))
            .filter_map(|l| l.split_once(','))
            .map(|(y, z)| (y.parse().unwrap(), z.parse().unwrap()))
            .collect();
        let read = |f: &dyn Fn(f64, f64) -> (f64, f64)| {
            let mut t = String::from("y_mm,z_mm\n");
            let mut pts: Vec<(f64, f64)> = rows.iter().map(|&(y, z)| f(y, z)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (y, z) in pts {
                t.push_str(&format!("{y},{z}\n"));
            }
            parse_profile(&t, "csv", "w", "w.csv", ProfileKind::Wheel)
                .unwrap_err()
                .to_string()
        };
        let e = read(&|y, z| (y, -z));
        assert!(e.contains("w.csv") && e.contains("flipped in z"), "{e}");
        let e = read(&|y, z| (y / 25.4, z / 25.4));
        assert!(e.contains("w.csv") && e.contains("inches"), "{e}");
        let e = read(&|y, z| (-y, z));
        assert!(e.contains("w.csv") && e.contains("mirrored"), "{e}");
    }

    /// Issue 35, item 7: a CSV header names the columns, read by name in any order (before: by
    /// position, so `z_mm,y_mm` gave a profile turned by 90°); a header that names no y and z
    /// column in mm is refused at its line.
    #[test]
    fn csv_columns_are_read_by_their_header_names() {
        let rows: Vec<(&str, &str)> = include_str!("../../profiles/60e1.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('y'))
            .filter_map(|l| l.split_once(','))
            .collect();
        let text = |header: &str, swap: bool| {
            let mut t = format!("{header}\n");
            for (y, z) in &rows {
                let (a, b) = if swap { (z, y) } else { (y, z) };
                t.push_str(&format!("{a},{b}\n"));
            }
            t
        };
        let read = |t: &str| parse_profile(t, "csv", "p", "p.csv", ProfileKind::Rail);
        let straight = read(&text("y_mm,z_mm", false)).unwrap();
        let swapped = read(&text("z_mm,y_mm", true)).unwrap();
        assert_eq!(straight.knots(), swapped.knots());
        let spaced = read(&text("Z [mm], Y [mm]", true)).unwrap();
        assert_eq!(straight.knots(), spaced.knots());
        for bad in ["a,b", "y_m,z_m", "y_in,z_in"] {
            let e = read(&text(bad, false)).unwrap_err().to_string();
            assert!(
                e.contains("p.csv:1:") && e.contains("names no y and z column"),
                "{e}"
            );
        }
    }

    fn tmp(name: &str, content: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("kecsim-io-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        fs::write(&p, content).unwrap();
        p
    }

    fn err(name: &str, content: &str, kind: ProfileKind) -> String {
        read_profile(&tmp(name, content), kind).unwrap_err().to_string()
    }

    #[test]
    fn csv_round_trip_reproduces_the_profile() {
        let p = StandardProfile::Rail60E1.profile();
        let path = std::env::temp_dir().join(format!("kecsim-rt-{}.csv", std::process::id()));
        write_csv(&p, &path).unwrap();
        let q = read_profile(&path, ProfileKind::Rail).unwrap();
        for k in 0..1000 {
            let s = -0.035 + 0.07 * k as f64 / 999.0;
            assert!((p.eval(s).z - q.eval(s).z).abs() < 1e-9, "at {s}");
        }
    }

    #[test]
    fn bad_input_names_file_line_and_problem() {
        let missing = read_profile(Path::new("/nonexistent/x.csv"), ProfileKind::Rail)
            .unwrap_err()
            .to_string();
        assert!(
            missing.contains("/nonexistent/x.csv") && missing.contains("cannot read"),
            "{missing}"
        );

        let e = err("empty.csv", "", ProfileKind::Rail);
        assert!(e.contains("empty.csv") && e.contains("empty file"), "{e}");

        let e = err("cell.csv", "y_mm,z_mm\n0,0\n1,abc\n2,0\n3,0\n", ProfileKind::Rail);
        assert!(
            e.contains("cell.csv:3:") && e.contains("'abc' is not a number"),
            "{e}"
        );

        let e = err("few.csv", "y,z\n0,0\n1,0\n2,0\n", ProfileKind::Rail);
        assert!(e.contains("few.csv:4:") && e.contains("only 3 points"), "{e}");

        let e = err("nan.dat", "0 0\n1 NaN\n2 0\n3 0\n", ProfileKind::Rail);
        assert!(
            e.contains("nan.dat:2:") && e.contains("not a finite number"),
            "{e}"
        );
        let e = err("inf.csv", "0,0\n1,0\n2,inf\n3,0\n", ProfileKind::Rail);
        assert!(e.contains("inf.csv:3:") && e.contains("not a finite"), "{e}");

        let e = err(
            "back.csv",
            "0,0\n1,0\n2,0.1\n1.5,0.2\n3,0\n4,0\n",
            ProfileKind::Rail,
        );
        assert!(e.contains("back.csv:4:") && e.contains("goes back"), "{e}");

        let e = err(
            "metres.csv",
            "-0.03,0\n-0.01,0.001\n0,0.0012\n0.01,0.001\n0.03,0\n",
            ProfileKind::Rail,
        );
        assert!(
            e.contains("metres.csv:1:") && e.contains("looks like metres"),
            "{e}"
        );

        let e = err("wheel.dat", "5 0\n6 0\n7 0\n8 0\n", ProfileKind::Wheel);
        assert!(e.contains("taping line"), "{e}");

        let e = err("cols.dat", "0 0\n1\n", ProfileKind::Rail);
        assert!(
            e.contains("cols.dat:2:") && e.contains("expected 2 columns"),
            "{e}"
        );
    }

    #[test]
    fn simpack_kind_mismatch_and_rotation_are_reported() {
        let body = "header.begin\n type = 0\nheader.end\nspline.begin\n point.begin\n -1 0\n 0 0\n 1 0\n 2 0\n point.end\nspline.end\n";
        let e = err("r.prr", body, ProfileKind::Wheel);
        assert!(e.contains("r.prr") && e.contains("holds a rail profile"), "{e}");
        let rot = body.replace("spline.begin\n", "spline.begin\n rotate = 0.1\n");
        let e = err("rot.prr", &rot, ProfileKind::Rail);
        assert!(e.contains("rot.prr:5:") && e.contains("rotate"), "{e}");
        let e = err(
            "nopts.prr",
            "header.begin\n type = 0\nheader.end\n",
            ProfileKind::Rail,
        );
        assert!(e.contains("no 'point.begin'"), "{e}");
    }

    #[test]
    fn a_mirrored_wheel_is_named_so() {
        // S1002 with y negated: the flange on the field side.
        let p = StandardProfile::S1002.profile();
        let (s, z) = p.knots();
        let text: String = std::iter::once("y_mm,z_mm".to_string())
            .chain(
                s.iter()
                    .zip(z)
                    .rev()
                    .map(|(s, z)| format!("{},{}", -s * 1e3, z * 1e3)),
            )
            .collect::<Vec<_>>()
            .join("\n");
        let e = err("mirrored.csv", &text, ProfileKind::Wheel);
        assert!(
            e.contains("mirrored.csv") && e.contains("flange is on the wrong side") && e.contains("28.0 mm"),
            "{e}"
        );
    }

    #[test]
    fn vertical_ends_are_trimmed_with_a_note() {
        // Vertical side (constant y) then a parabola head.
        let mut t = String::new();
        for k in 0..5 {
            t += &format!("-10 {}\n", -10.0 + k as f64);
        }
        for k in 0..=20 {
            let y = -10.0 + k as f64;
            t += &format!("{y} {}\n", -0.01 * y * y);
        }
        let p = read_profile(&tmp("side.dat", &t), ProfileKind::Rail).unwrap();
        assert!((p.domain().0 + 0.010).abs() < 1e-12);
        assert!(
            p.notes.iter().any(|n| n.contains("vertical end trimmed")),
            "{:?}",
            p.notes
        );
    }
}
