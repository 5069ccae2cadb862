//! Creep forces at given points, for scripts (`kecsim creep --at POINTS.csv --csv OUT.csv`).
//!
//! A points file is CSV with a header naming the columns `n_n,a_mm,b_mm,xi,eta,phi_per_m,mu` (in
//! any order; other columns are ignored; `#` starts a comment): the normal force N, the Hertz
//! ellipse's semi-axes a (rolling direction) and b in mm, the creepages ξ, η, the spin φ in 1/m
//! and the friction μ. The answer repeats each point's seven values and adds, per model, the
//! columns `model,fx_n,fy_n,mz_n_m` (forces on the wheel in the contact frame, opposing the
//! creepage, N; the spin moment, N·m).

use std::path::Path;

use rayon::prelude::*;
use thiserror::Error;

use super::creepage::Creepage;
use super::kalker::KalkerTable;
use super::patch::{ContactPatch, CreepForce};
use super::{CreepForceError, CreepModel};

/// The columns a points file must name.
pub const POINT_COLUMNS: [&str; 7] = ["n_n", "a_mm", "b_mm", "xi", "eta", "phi_per_m", "mu"];

/// The columns added to each point in the answer.
pub const FORCE_COLUMNS: [&str; 4] = ["model", "fx_n", "fy_n", "mz_n_m"];

/// A points file that cannot be used: the file and line, and what is wrong.
#[derive(Debug, Error)]
pub enum PointsError {
    #[error("{path}: {message}")]
    File { path: String, message: String },
    #[error("{path}, line {line}: {message}")]
    Line {
        path: String,
        line: usize,
        message: String,
    },
    #[error("{path}, line {line}: {source}")]
    Force {
        path: String,
        line: usize,
        #[source]
        source: CreepForceError,
    },
}

/// One point of a points file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepPoint {
    /// Line of the file it was read from (1-based).
    pub line: usize,
    pub normal_force_n: f64,
    pub a_mm: f64,
    pub b_mm: f64,
    pub xi: f64,
    pub eta: f64,
    pub phi_per_m: f64,
    pub mu: f64,
}

impl CreepPoint {
    /// The point's values in the order of [`POINT_COLUMNS`] (Rust's shortest round-trip form:
    /// read back, the same numbers).
    pub fn csv_fields(&self) -> [String; 7] {
        [
            self.normal_force_n,
            self.a_mm,
            self.b_mm,
            self.xi,
            self.eta,
            self.phi_per_m,
            self.mu,
        ]
        .map(|v| format!("{v}"))
    }

    pub fn creepage(&self) -> Creepage {
        Creepage::new(self.xi, self.eta, self.phi_per_m)
    }

    /// The contact patch for shear modulus G (Pa) and Kalker's table.
    pub fn patch(&self, shear_modulus: f64, table: &KalkerTable) -> Result<ContactPatch, CreepForceError> {
        ContactPatch::new(
            self.a_mm * 1e-3,
            self.b_mm * 1e-3,
            self.normal_force_n,
            shear_modulus,
            self.mu,
            table,
        )
    }
}

/// Reads a points file (at most 64 MiB), every value checked, the first bad one named by line.
pub fn read_points(path: &Path) -> Result<Vec<CreepPoint>, PointsError> {
    let name = path.display().to_string();
    let file = |message: String| PointsError::File {
        path: name.clone(),
        message,
    };
    let bytes =
        crate::files::read_bounded(path, 64 << 20, false).map_err(|e| file(format!("cannot read: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|_| file("not UTF-8 text".into()))?;
    parse_points(&name, &text)
}

/// [`read_points`] on text already read (`path` names it in errors).
pub fn parse_points(path: &str, text: &str) -> Result<Vec<CreepPoint>, PointsError> {
    let at = |line: usize, message: String| PointsError::Line {
        path: path.to_string(),
        line,
        message,
    };
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut columns: Option<[usize; 7]> = None;
    let mut points = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map(|p| p.line() as usize).unwrap_or(0);
            at(line, format!("malformed CSV: {e}"))
        })?;
        let line = rec.position().map(|p| p.line() as usize).unwrap_or(0);
        if rec.iter().all(|c| c.is_empty()) {
            continue;
        }
        let Some(cols) = columns else {
            let mut cols = [0; 7];
            for (k, want) in POINT_COLUMNS.iter().enumerate() {
                cols[k] = rec.iter().position(|c| c == *want).ok_or_else(|| {
                    at(
                        line,
                        format!(
                            "the header `{}` has no column `{want}` (expected the columns {})",
                            rec.iter().collect::<Vec<_>>().join(","),
                            POINT_COLUMNS.join(",")
                        ),
                    )
                })?;
            }
            columns = Some(cols);
            continue;
        };
        let mut v = [0.0; 7];
        for (k, &c) in cols.iter().enumerate() {
            let cell = rec.get(c).ok_or_else(|| {
                at(
                    line,
                    format!("{} columns, `{}` missing", rec.len(), POINT_COLUMNS[k]),
                )
            })?;
            v[k] = cell
                .parse::<f64>()
                .map_err(|_| at(line, format!("{} = `{cell}`: not a number", POINT_COLUMNS[k])))?;
            if !v[k].is_finite() {
                return Err(at(line, format!("{} = {}: not finite", POINT_COLUMNS[k], v[k])));
            }
        }
        let [n, a, b, xi, eta, phi, mu] = v;
        let bad = |m: String| Err(at(line, m));
        if n <= 0.0 {
            return bad(format!(
                "n_n = {n}: expected a positive normal force in N (a wheel without load has no creep forces)"
            ));
        }
        if n > 1e7 {
            return bad(format!("n_n = {n}: above 10 MN, not a wheel load"));
        }
        for (x, what) in [(a, "a_mm"), (b, "b_mm")] {
            if !(x > 0.0 && x <= 1000.0) {
                return bad(format!("{what} = {x}: expected a semi-axis in (0, 1000] mm"));
            }
        }
        if !(mu > 0.0 && mu <= 1.5) {
            return bad(format!(
                "mu = {mu}: expected a coefficient of friction in (0, 1.5]"
            ));
        }
        for (x, what) in [(xi, "xi"), (eta, "eta")] {
            if x.abs() > 1.0 {
                return bad(format!("{what} = {x}: expected a creepage in [−1, 1]"));
            }
        }
        if phi.abs() > 1e4 {
            return bad(format!("phi_per_m = {phi}: expected a spin in [−10⁴, 10⁴] 1/m"));
        }
        points.push(CreepPoint {
            line,
            normal_force_n: n,
            a_mm: a,
            b_mm: b,
            xi,
            eta,
            phi_per_m: phi,
            mu,
        });
    }
    if columns.is_none() {
        return Err(PointsError::File {
            path: path.to_string(),
            message: format!("empty: expected a header naming {}", POINT_COLUMNS.join(",")),
        });
    }
    Ok(points)
}

/// One answer: a point, a model and its force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointForce {
    pub point: CreepPoint,
    pub model: &'static str,
    pub force: CreepForce,
}

/// Every model at every point (points in parallel; `done` is called after each point).
pub fn evaluate(
    path: &str,
    points: &[CreepPoint],
    models: &[CreepModel],
    shear_modulus: f64,
    table: &KalkerTable,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<PointForce>, PointsError> {
    let per_point: Result<Vec<Vec<PointForce>>, PointsError> = points
        .par_iter()
        .map(|p| {
            let err = |source| PointsError::Force {
                path: path.to_string(),
                line: p.line,
                source,
            };
            let patch = p.patch(shear_modulus, table).map_err(err)?;
            let out = models
                .iter()
                .map(|m| {
                    Ok(PointForce {
                        point: *p,
                        model: m.name(),
                        force: m.forces(&patch, &p.creepage(), 0.0).map_err(err)?,
                    })
                })
                .collect::<Result<Vec<_>, PointsError>>();
            done();
            out
        })
        .collect();
    Ok(per_point?.into_iter().flatten().collect())
}

/// A model's answer in the order of [`FORCE_COLUMNS`] (`+ 0.0`: no "-0").
pub fn force_fields(model: &str, f: &CreepForce) -> [String; 4] {
    [
        model.to_string(),
        format!("{:.6}", f.fx + 0.0),
        format!("{:.6}", f.fy + 0.0),
        format!("{:.6}", f.mz + 0.0),
    ]
}

/// Writes the answers as CSV: the point's columns, then `model,fx_n,fy_n,mz_n_m`.
pub fn write_forces<W: std::io::Write>(
    w: &mut csv::Writer<W>,
    rows: &[PointForce],
) -> Result<(), csv::Error> {
    w.write_record(POINT_COLUMNS.iter().chain(FORCE_COLUMNS.iter()))?;
    for r in rows {
        w.write_record(
            r.point
                .csv_fields()
                .iter()
                .chain(&force_fields(r.model, &r.force)),
        )?;
    }
    w.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_columns_by_name_and_names_the_bad_line() {
        let ok = "# comment\nmu,n_n,a_mm,b_mm,xi,eta,phi_per_m,extra\n0.3,80000,6,4,1e-3,0,0.5,x\n";
        let p = parse_points("p.csv", ok).unwrap();
        assert_eq!(p.len(), 1);
        assert_eq!((p[0].mu, p[0].normal_force_n, p[0].b_mm), (0.3, 80000.0, 4.0));
        assert_eq!(p[0].line, 3);
        let header = "n_n,a_mm,b_mm,xi,eta,phi_per_m,mu\n";
        for (row, what) in [
            ("NaN,6,4,0,0,0,0.3", "n_n = NaN: not finite"),
            ("-5,6,4,0,0,0,0.3", "n_n = -5: expected a positive normal force"),
            ("8e4,6,0,0,0,0,0.3", "b_mm = 0"),
            ("8e4,6,4,2,0,0,0.3", "xi = 2"),
            ("8e4,6,4,0,0,0,x", "mu = `x`: not a number"),
            ("8e4,6,4,0,0", "missing"),
        ] {
            let e = parse_points("p.csv", &format!("{header}8e4,6,4,0,0,0,0.3\n{row}\n"))
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("p.csv, line 3: "), "{e}");
            assert!(e.contains(what), "{e} lacks {what}");
        }
        let e = parse_points("p.csv", "n_n,a_mm,b_mm,xi,eta,mu\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no column `phi_per_m`"), "{e}");
        assert!(parse_points("p.csv", "")
            .unwrap_err()
            .to_string()
            .contains("empty"));
    }
}
