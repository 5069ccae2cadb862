//! Irregularity files: CSV with a header row, s in m and the irregularities in mm (the units track
//! recording cars report), converted to SI once here.
//!
//! Columns (any order, extra columns ignored, `#` comment lines allowed): `s_m` and either the four
//! combinations `al_mm`, `vp_mm`, `gv_mm`, `cl_mm` or the four rail displacements `y_left_mm`,
//! `z_left_mm`, `y_right_mm`, `z_right_mm` (METHOD.md §2; converted with the contact code's
//! definitions al = (y_l + y_r)/2, …). The CSV that `kecsim track --csv` writes has these columns
//! too, so it reads back as an irregularity file.
//!
//! Checks, each naming the file and the line: unreadable file, no header, missing columns, a cell
//! that is not a number, NaN or infinite values, s not strictly increasing, fewer than 4 rows.

use std::path::Path;

use super::error::TrackError;
use super::irregularity::{Irregularities, Origin};
use super::rails::RailOffsets;
use crate::spline::CubicSpline;

/// The columns of the combinations, in channel order.
pub const COMBINATION_COLUMNS: [&str; 4] = ["al_mm", "vp_mm", "gv_mm", "cl_mm"];
/// The columns of the rail displacements.
pub const RAIL_COLUMNS: [&str; 4] = ["y_left_mm", "z_left_mm", "y_right_mm", "z_right_mm"];

fn at(path: &str, line: usize, problem: impl Into<String>) -> TrackError {
    TrackError::AtLine {
        path: path.to_string(),
        line,
        problem: problem.into(),
    }
}

/// Largest irregularity value accepted in a file, mm (FRA class 1, the worst, stays within ±30 mm
/// of alignment; a larger value is a unit or column mistake).
pub const MAX_IRREGULARITY_MM: f64 = 50.0;
/// The largest distance between two rows of an irregularity file, m: five times the longest
/// wavelength track geometry is measured at (EN 13848-1's D3 band ends at 200 m); rows farther
/// apart leave the spline to invent the track between them (a gap of 1e6 m was accepted without
/// a word). Sparse hand-written files (rows every few hundred metres) stay within it.
pub const MAX_IRREGULARITY_GAP_M: f64 = 1000.0;

/// Reads an irregularity CSV (see the module doc).
pub fn read_csv(path: &Path) -> Result<Irregularities, TrackError> {
    let p = path.display().to_string();
    let text = crate::limits::read_text(path).map_err(|source| TrackError::Io {
        path: p.clone(),
        source,
    })?;
    parse_csv(&text, &p)
}

/// Parses irregularity CSV text; `origin` names it in errors.
pub fn parse_csv(text: &str, origin: &str) -> Result<Irregularities, TrackError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header_line = text
        .lines()
        .position(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map_or(1, |k| k + 1);
    let headers = rdr
        .headers()
        .map_err(|e| at(origin, header_line, format!("malformed header: {e}")))?
        .clone();
    let find = |name: &str| headers.iter().position(|h| h == name);
    let s_col = find("s_m");
    let comb: Vec<Option<usize>> = COMBINATION_COLUMNS.iter().map(|c| find(c)).collect();
    let rail: Vec<Option<usize>> = RAIL_COLUMNS.iter().map(|c| find(c)).collect();
    let (cols, rails) = if comb.iter().all(Option::is_some) {
        (comb.clone(), false)
    } else if rail.iter().all(Option::is_some) {
        (rail.clone(), true)
    } else {
        let missing: Vec<&str> = COMBINATION_COLUMNS
            .iter()
            .zip(&comb)
            .filter(|(_, c)| c.is_none())
            .map(|(n, _)| *n)
            .collect();
        return Err(at(
            origin,
            header_line,
            format!(
                "missing columns {} (the header needs s_m and either {} or {}; found: {})",
                missing.join(", "),
                COMBINATION_COLUMNS.join(", "),
                RAIL_COLUMNS.join(", "),
                headers.iter().collect::<Vec<_>>().join(", ")
            ),
        ));
    };
    let Some(s_col) = s_col else {
        return Err(at(origin, header_line, "missing column s_m"));
    };
    let cols: Vec<usize> = cols.into_iter().flatten().collect();
    // Both sets given (as `kecsim track --csv` writes them): the combinations are read, and the
    // rails' displacements must say the same, row by row.
    let both: Option<Vec<usize>> =
        (!rails && rail.iter().all(Option::is_some)).then(|| rail.iter().flatten().copied().collect());
    let mut s = Vec::new();
    let mut values: Vec<[f64; 4]> = Vec::new();
    let mut last_line = header_line;
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            at(origin, line, format!("malformed CSV: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        last_line = line;
        if rec.iter().all(str::is_empty) {
            continue;
        }
        let cell = |col: usize, name: &str| -> Result<f64, TrackError> {
            let c = rec.get(col).unwrap_or("");
            let v: f64 = c
                .parse()
                .map_err(|_| at(origin, line, format!("column {name}: '{c}' is not a number")))?;
            if !v.is_finite() {
                return Err(at(
                    origin,
                    line,
                    format!("column {name}: {v} is not a finite number"),
                ));
            }
            Ok(v)
        };
        let sv = cell(s_col, "s_m")?;
        if let Some(&prev) = s.last() {
            if sv <= prev {
                return Err(at(
                    origin,
                    line,
                    format!("s_m = {sv} does not increase (previous row: {prev})"),
                ));
            }
            if sv - prev > MAX_IRREGULARITY_GAP_M {
                return Err(at(
                    origin,
                    line,
                    format!(
                        "s_m = {sv}: {:.6e} m after the previous row (s_m = {prev}); rows may be at most {MAX_IRREGULARITY_GAP_M} m apart (five times the longest wavelength measured, EN 13848-1 D3: 200 m): between them the irregularity would be invented — is s_m in mm, or rows missing?",
                        sv - prev
                    ),
                ));
            }
        }
        let names = if rails { RAIL_COLUMNS } else { COMBINATION_COLUMNS };
        let mut v = [0.0; 4];
        for c in 0..4 {
            let mm = cell(cols[c], names[c])?;
            if mm.abs() > MAX_IRREGULARITY_MM {
                return Err(at(
                    origin,
                    line,
                    format!(
                        "column {}: {mm} mm is no track irregularity (the worst track classes stay within ±30 mm; the limit is ±{MAX_IRREGULARITY_MM} mm): is the file in mm?",
                        names[c]
                    ),
                ));
            }
            v[c] = mm * 1e-3;
        }
        if rails {
            v = combinations(v);
        }
        if let Some(rc) = &both {
            let mut r = [0.0; 4];
            for c in 0..4 {
                r[c] = cell(rc[c], RAIL_COLUMNS[c])? * 1e-3;
            }
            for (c, from_rails) in combinations(r).into_iter().enumerate() {
                // 1 µm: the files kecsim writes carry 1e-9 mm.
                if (from_rails - v[c]).abs() > 1e-6 {
                    return Err(at(
                        origin,
                        line,
                        format!(
                            "column {} = {:.6} mm contradicts the rails' columns ({:.6} mm from {}): give one set, or both consistent",
                            COMBINATION_COLUMNS[c],
                            v[c] * 1e3,
                            from_rails * 1e3,
                            RAIL_COLUMNS.join(", ")
                        ),
                    ));
                }
            }
        }
        s.push(sv);
        values.push(v);
    }
    if s.len() < 4 {
        return Err(at(
            origin,
            last_line,
            format!("{} data rows: an irregularity file needs at least 4", s.len()),
        ));
    }
    from_samples(
        s,
        &values,
        Origin::Measured {
            path: origin.to_string(),
        },
    )
    .map_err(|e| TrackError::InFile {
        path: origin.to_string(),
        problem: e.to_string(),
    })
}

/// Irregularities through samples (SI): a not-a-knot cubic spline per irregularity gives the node
/// derivatives (the quintic interpolant then reproduces that spline).
pub fn from_samples(s: Vec<f64>, values: &[[f64; 4]], origin: Origin) -> Result<Irregularities, TrackError> {
    let mut nodes = vec![[[0.0; 4]; 3]; s.len()];
    for c in 0..4 {
        let col: Vec<f64> = values.iter().map(|v| v[c]).collect();
        let spline = CubicSpline::new(s.clone(), col)
            .map_err(|e| TrackError::Irregularity(format!("cannot interpolate: {e:?}")))?;
        for (k, &x) in s.iter().enumerate() {
            let p = spline.eval(x);
            nodes[k][0][c] = values[k][c];
            nodes[k][1][c] = p.dz;
            nodes[k][2][c] = p.d2z;
        }
    }
    Irregularities::from_nodes(s, nodes, origin)
}

/// The combinations [al, vp, gv, cl] of the rails' displacements [y_left, z_left, y_right,
/// z_right] (m), as [`RailOffsets::combinations`] gives them.
fn combinations(r: [f64; 4]) -> [f64; 4] {
    let (al, vp, gv, cl) = RailOffsets {
        y_left: r[0],
        z_left: r[1],
        y_right: r[2],
        z_right: r[3],
    }
    .combinations();
    [al, vp, gv, cl]
}

/// Writes the irregularities at their nodes: `s_m`, `al_mm`, `vp_mm`, `gv_mm`, `cl_mm`.
pub fn write_csv(irr: &Irregularities, path: &Path) -> Result<(), TrackError> {
    let io = |source: std::io::Error| TrackError::Write {
        path: path.display().to_string(),
        source,
    };
    let mut w = crate::files::csv_writer(path).map_err(io)?;
    let mut header = vec!["s_m"];
    header.extend(COMBINATION_COLUMNS);
    w.write_record(&header).map_err(|e| io(e.into()))?;
    for (s, v) in irr.node_values() {
        let mut row = vec![format!("{s:.6}")];
        row.extend(v.iter().map(|x| format!("{:.9}", x * 1e3)));
        w.write_record(&row).map_err(|e| io(e.into()))?;
    }
    crate::files::commit_csv(w).map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_csv(text, "irr.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_combinations_and_rails_alike() {
        let comb =
            "# measured\ns_m,al_mm,vp_mm,gv_mm,cl_mm\n0,1,2,4,-3\n1,1,2,4,-3\n2,1,2,4,-3\n3,1,2,4,-3\n";
        let a = parse_csv(comb, "a.csv").unwrap().eval(1.5).unwrap();
        let rails = "s_m,y_left_mm,z_left_mm,y_right_mm,z_right_mm,extra\n0,3,0.5,-1,3.5,x\n1,3,0.5,-1,3.5,x\n2,3,0.5,-1,3.5,x\n3,3,0.5,-1,3.5,x\n";
        let b = parse_csv(rails, "b.csv").unwrap().eval(1.5).unwrap();
        for c in 0..4 {
            assert!((a.value[c] - b.value[c]).abs() < 1e-15, "{a:?} {b:?}");
        }
        assert!((a.value[0] - 1e-3).abs() < 1e-15 && (a.value[3] + 3e-3).abs() < 1e-15);
    }

    #[test]
    fn bad_files_name_the_line() {
        let head = "s_m,al_mm,vp_mm,gv_mm,cl_mm\n";
        let e = err(&format!("{head}0,0,0,0,0\n1,0,0,0,0\n1,0,0,0,0\n"));
        assert!(
            e.starts_with("irr.csv:4: ") && e.contains("does not increase"),
            "{e}"
        );
        let e = err(&format!("{head}0,0,0,0,0\n1,0,NaN,0,0\n"));
        assert!(
            e.starts_with("irr.csv:3: ") && e.contains("vp_mm") && e.contains("finite"),
            "{e}"
        );
        let e = err("s_m,al_mm,vp_mm,gv_mm\n0,0,0,0\n");
        assert!(
            e.starts_with("irr.csv:1: ") && e.contains("missing columns cl_mm"),
            "{e}"
        );
        let e = err(&format!("{head}0,0,0,0,0\n1,0,abc,0,0\n"));
        assert!(e.starts_with("irr.csv:3: ") && e.contains("'abc'"), "{e}");
        let e = err(&format!("{head}0,0,0,0,0\n1,0,0,0,0\n"));
        assert!(e.contains("at least 4"), "{e}");
    }
}
