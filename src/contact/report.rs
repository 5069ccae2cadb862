//! What `kecsim contact` computes and prints: the 1-entry table of a wheel/rail pair, its contact
//! jumps, its interpolation error against the online solution, and the equivalent conicity.

use std::time::Instant;

use super::conicity::{ConicityError, RollingRadiusDifference};
use super::geometry::ContactGeometry;
use super::kec::KecModel;
use super::lookup::{CrossLevelEntry, LookupTable1, TableError, TableRow, TableSettings};
use crate::track::RailOffsets;

/// Largest deviation of table look-ups from the online solution, at points between the nodes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterpolationError {
    /// Points compared.
    pub points: usize,
    /// Max |Δz|, m.
    pub z: f64,
    /// Max |Δφ|, rad.
    pub phi: f64,
    /// Max |Δs| over the four surface parameters, m.
    pub s: f64,
    /// Max |Δ(Δr)|, m.
    pub delta_r: f64,
    /// Points where a surface parameter misses by more than 0.01 mm, and the |y| range they span:
    /// near-conformal contact, where the gap is flat to < 1 µm over a stretch of profile and the
    /// contact location is ill-conditioned (z and φ stay accurate there).
    pub s_outliers: usize,
    pub s_outlier_range: (f64, f64),
}

/// Compares look-ups with online solves at the fractions `fractions` of every table interval
/// (jumps excluded). Use fractions other than 1/2 for an independent check: the builder refines
/// on midpoints.
pub fn interpolation_error(
    geom: &ContactGeometry,
    table: &LookupTable1,
    fractions: &[f64],
) -> Result<InterpolationError, TableError> {
    let off = RailOffsets::gauge_variation(table.gv);
    let mut e = InterpolationError::default();
    for w in table.rows.windows(2) {
        if w[1].y <= w[0].y {
            continue;
        }
        for &f in fractions {
            let y = w[0].y + f * (w[1].y - w[0].y);
            let online = geom.solve(y, &off)?;
            let l = table.lookup(y)?;
            e.points += 1;
            e.z = e.z.max((l.z() - online.z).abs());
            e.phi = e.phi.max((l.phi() - online.phi).abs());
            let ds = (2..6).map(|k| (l.x[k] - online.x()[k]).abs()).fold(0.0, f64::max);
            e.s = e.s.max(ds);
            if ds > 1e-5 {
                if e.s_outliers == 0 {
                    e.s_outlier_range = (y.abs(), y.abs());
                }
                e.s_outliers += 1;
                e.s_outlier_range = (e.s_outlier_range.0.min(y.abs()), e.s_outlier_range.1.max(y.abs()));
            }
            e.delta_r = e.delta_r.max((l.delta_r() - online.delta_r()).abs());
        }
    }
    Ok(e)
}

/// KEC against the online solution between the table's nodes (ideal track): (max |Δz|, max |Δφ|).
pub fn interpolation_error_kec(
    geom: &ContactGeometry,
    table: &LookupTable1,
    model: &KecModel,
    fractions: &[f64],
) -> Result<(f64, f64), String> {
    let (mut ez, mut ep) = (0.0f64, 0.0f64);
    for w in table.rows.windows(2) {
        if w[1].y <= w[0].y {
            continue;
        }
        for &f in fractions {
            let y = w[0].y + f * (w[1].y - w[0].y);
            let o = geom
                .solve(y, &RailOffsets::default())
                .map_err(|e| e.to_string())?;
            let k = model.solve(y, [0.0; 4], None).map_err(|e| e.to_string())?;
            ez = ez.max((k.z - o.z).abs());
            ep = ep.max((k.phi - o.phi).abs());
        }
    }
    Ok((ez, ep))
}

/// Equivalent conicity at one amplitude by both methods.
#[derive(Debug, Clone, PartialEq)]
pub struct ConicityRow {
    /// Amplitude ŷ, m.
    pub amplitude: f64,
    /// EN 15302 Annex B.
    pub annex_b: Result<f64, ConicityError>,
    /// Linear regression.
    pub regression: Result<f64, ConicityError>,
}

/// Equivalent conicity of the table's Δr at the given amplitudes (m).
pub fn conicity(table: &LookupTable1, amplitudes: &[f64]) -> Vec<ConicityRow> {
    let (lo, hi) = table.range();
    let f = RollingRadiusDifference::sample(lo, hi, 1e-6, |y| {
        table.lookup(y).map(|r| r.delta_r()).unwrap_or(f64::NAN)
    });
    amplitudes
        .iter()
        .map(|&a| ConicityRow {
            amplitude: a,
            annex_b: f.conicity_annex_b(a),
            regression: f.conicity_regression(a),
        })
        .collect()
}

/// The full report of a pair.
#[derive(Debug, Clone)]
pub struct ContactReport {
    pub table: LookupTable1,
    pub build_seconds: f64,
    pub interpolation: InterpolationError,
    pub conicity: Vec<ConicityRow>,
}

impl ContactReport {
    /// Builds the 1-entry table, measures its interpolation error at 1/3 and 2/3 of every interval,
    /// and computes the conicity for ŷ = 1..6 mm.
    pub fn new(geom: &ContactGeometry, settings: &TableSettings) -> Result<Self, TableError> {
        let t = Instant::now();
        let table = LookupTable1::build(geom, settings)?;
        let build_seconds = t.elapsed().as_secs_f64();
        let interpolation = interpolation_error(geom, &table, &[1.0 / 3.0, 2.0 / 3.0])?;
        let amplitudes: Vec<f64> = (1..=6).map(|k| k as f64 * 1e-3).collect();
        let conicity = conicity(&table, &amplitudes);
        Ok(ContactReport {
            table,
            build_seconds,
            interpolation,
            conicity,
        })
    }

    /// Plain-text/markdown summary (also the recording's summary document).
    pub fn summary(&self, title: &str) -> String {
        let t = &self.table;
        let (lo, hi) = t.range();
        let mut s = format!("# {title}\n\n");
        s += &format!(
            "1-entry table: y = {:.3} .. {:.3} mm (flange contact to flange contact), {} rows, built in {:.2} s\n\n",
            lo * 1e3,
            hi * 1e3,
            t.rows.len(),
            self.build_seconds
        );
        s += "Equivalent conicity tan γe (EN 15302):\n\n| ŷ [mm] | Annex B | regression |\n|---|---|---|\n";
        let fmt = |r: &Result<f64, ConicityError>| match r {
            Ok(v) => format!("{v:.4}"),
            Err(_) => "out of range".to_string(),
        };
        for c in &self.conicity {
            s += &format!(
                "| {:.1} | {} | {} |\n",
                c.amplitude * 1e3,
                fmt(&c.annex_b),
                fmt(&c.regression)
            );
        }
        s += &format!("\nContact jumps ({}):\n\n", t.jumps.len());
        for j in &t.jumps {
            s += &format!(
                "* y = {:+.4} mm, {} wheel: s^w {:+.3} → {:+.3} mm\n",
                j.y * 1e3,
                if j.left { "left" } else { "right" },
                j.s_wheel_before * 1e3,
                j.s_wheel_after * 1e3
            );
        }
        let e = &self.interpolation;
        s += &format!(
            "\nInterpolation error against the online solution ({} points at 1/3 and 2/3 of every interval): z {:.2e} mm, roll {:.2e} mrad, Δr {:.2e} mm, surface parameters {:.2e} mm\n",
            e.points,
            e.z * 1e3,
            e.phi * 1e3,
            e.delta_r * 1e3,
            e.s * 1e3
        );
        if e.s_outliers > 0 {
            s += &format!(
                "({} points with a surface-parameter error over 0.01 mm, all at |y| = {:.4} .. {:.4} mm: near-conformal contact, where the gap is flat and the contact location ill-conditioned)\n",
                e.s_outliers,
                e.s_outlier_range.0 * 1e3,
                e.s_outlier_range.1 * 1e3
            );
        }
        s
    }
}

/// Largest distance of one contact model from the online approximate constraints over one case:
/// |Δz| (m), |Δφ| (rad) and the contact angle |Δγ| of either wheel (rad).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EntryError {
    pub z: f64,
    pub phi: f64,
    pub angle: f64,
}

impl EntryError {
    fn update(&mut self, z: f64, phi: f64, angles: [f64; 2], o: &super::geometry::ContactSolution) {
        self.z = self.z.max((z - o.z).abs());
        self.phi = self.phi.max((phi - o.phi).abs());
        let oa = [o.left.contact_angle, o.right.contact_angle];
        for i in 0..2 {
            self.angle = self.angle.max((angles[i] - oa[i]).abs());
        }
    }
}

/// The tables measured by [`kec_irregularity_errors`] beside KEC: the centred 1-entry table (its
/// per-wheel entry is `lookup2`'s default), gauge columns (the paper's literal 2-entry table,
/// `lookup2-paper`) and, optionally, finer columns (`lookup2` with `gauge_entry = "columns"`).
pub struct MeasuredTables<'a> {
    pub table1: &'a LookupTable1,
    /// The paper's 2-entry table (1 mm columns).
    pub table2: &'a super::lookup::LookupTable2,
    /// Finer gauge columns, with their spacing (m): tables each covering some of the cases' gauge
    /// variations (a case is measured on the first whose columns bracket its gv with a column
    /// either side — what the Catmull–Rom interpolation across gv reads of a table with columns
    /// everywhere).
    pub table2_fine: Option<(&'a [super::lookup::LookupTable2], f64)>,
}

/// Error of the KEC model and of the lookup tables against the online approximate constraints for
/// one irregularity case, over a set of y.
#[derive(Debug, Clone, PartialEq)]
pub struct KecErrorRow {
    /// Gauge variation and cross level, m.
    pub gv: f64,
    pub cl: f64,
    /// |y| range compared, m.
    pub y_max: f64,
    pub points: usize,
    /// KEC, against the online solution.
    pub kec: EntryError,
    /// The per-wheel entry of the centred table (`lookup2`'s default,
    /// [`crate::contact::per_wheel`]).
    pub per_wheel: EntryError,
    /// The paper's 2-entry table (1 mm gauge columns, `lookup2-paper`).
    pub table2: EntryError,
    /// Finer gauge columns ([`MeasuredTables::table2_fine`]), where measured.
    pub table2_fine: Option<EntryError>,
    /// The 1-entry table (blind to gv).
    pub table1: EntryError,
    /// The 2-entry and 1-entry tables entered by Eq. (44)–(46) as printed
    /// ([`crate::contact::lookup::CrossLevelEntry::Paper`]; the same as the above without cross
    /// level). The others are entered by the rail pair's rigid motion
    /// ([`crate::contact::lookup::CrossLevelEntry::Rotated`]).
    pub table2_printed: EntryError,
    pub table1_printed: EntryError,
}

/// KEC against the online approximate constraints and the tables under gauge variation and cross
/// level. The y range of a case shrinks by |gv|/2 (a narrower gauge brings flange contact closer, a
/// wider one moves the knife edges outwards along the equivalent profiles, which only extend as
/// far as the table) and by r0·|cl|/(2 L_r) (the roll that follows a cross level moves the contact
/// points sideways by r0 φ): every case stays short of flange climb.
pub fn kec_irregularity_errors(
    geom: &ContactGeometry,
    model: &KecModel,
    tables: &MeasuredTables,
    cases: &[(f64, f64)],
    points: usize,
) -> Result<Vec<KecErrorRow>, String> {
    let table1 = tables.table1;
    let (lo, hi) = table1.range();
    let y_flange = lo.abs().min(hi);
    let mut rows = Vec::new();
    for &(gv, cl) in cases {
        let y_max = (y_flange - gv.abs() / 2.0 - table1.r0 * cl.abs() / (2.0 * table1.l_r) - 3e-4).max(5e-4);
        let off = RailOffsets::from_irregularities(0.0, 0.0, gv, cl);
        let mut row = KecErrorRow {
            gv,
            cl,
            y_max,
            points: 0,
            kec: EntryError::default(),
            per_wheel: EntryError::default(),
            table2: EntryError::default(),
            table2_fine: tables.table2_fine.map(|_| EntryError::default()),
            table1: EntryError::default(),
            table2_printed: EntryError::default(),
            table1_printed: EntryError::default(),
        };
        let at = |acc: &mut EntryError, r: &TableRow, o: &super::geometry::ContactSolution| {
            acc.update(r.z(), r.phi(), r.contact_angle, o)
        };
        // The fine columns around this case's gv, once per case.
        let fine = match tables.table2_fine {
            Some((fine, _)) => {
                let covers = |t: &&super::lookup::LookupTable2| {
                    let g = t.gvs();
                    g.len() >= 4 && g[1] <= gv && gv <= g[g.len() - 2]
                };
                Some(
                    fine.iter()
                        .find(covers)
                        .ok_or_else(|| format!("no fine gauge columns around gv {} mm", gv * 1e3))?,
                )
            }
            None => None,
        };
        for k in 0..points {
            let y = -y_max + 2.0 * y_max * k as f64 / (points - 1) as f64;
            let case = |what: &str, e: &dyn std::fmt::Display| {
                format!(
                    "{what}, gv {} mm, cl {} mm, y {:.3} mm: {e}",
                    gv * 1e3,
                    cl * 1e3,
                    y * 1e3
                )
            };
            let o = geom.solve(y, &off).map_err(|e| case("online", &e))?;
            let kec = model
                .solve(y, off.to_array(), None)
                .map_err(|e| case("KEC", &e))?;
            row.kec.update(
                kec.z,
                kec.phi,
                [kec.real[0].contact_angle, kec.real[1].contact_angle],
                &o,
            );
            let pw = super::per_wheel::contact_per_wheel(table1, y, &off)
                .map_err(|e| case("per-wheel table", &e))?;
            at(&mut row.per_wheel, &pw, &o);
            let t2 = tables
                .table2
                .contact(y, &off)
                .map_err(|e| case("2-entry table", &e))?;
            at(&mut row.table2, &t2, &o);
            if let (Some(t), Some(acc)) = (fine, row.table2_fine.as_mut()) {
                let f = t.contact(y, &off).map_err(|e| case("fine 2-entry table", &e))?;
                at(acc, &f, &o);
            }
            let t1 = table1.contact(y, &off).map_err(|e| case("1-entry table", &e))?;
            at(&mut row.table1, &t1, &o);
            let paper = CrossLevelEntry::Paper;
            let t2p = tables
                .table2
                .contact_with(y, &off, paper)
                .map_err(|e| case("2-entry table", &e))?;
            at(&mut row.table2_printed, &t2p, &o);
            let t1p = table1
                .contact_with(y, &off, paper)
                .map_err(|e| case("1-entry table", &e))?;
            at(&mut row.table1_printed, &t1p, &o);
            row.points += 1;
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The error table as markdown: per case and model, max |Δz| (mm) / |Δφ| (mrad) / |Δγ| (°)
/// against the online constraints.
pub fn kec_error_markdown(rows: &[KecErrorRow], fine_step_m: Option<f64>) -> String {
    let fine = rows.first().is_some_and(|r| r.table2_fine.is_some());
    let mut s = String::from("| gv [mm] | cl [mm] | \\|y\\| ≤ [mm] | KEC | lookup2 (per wheel) |");
    if fine {
        s += &format!(
            " gauge columns {} mm |",
            fine_step_m.map_or("fine".to_string(), |d| format!("{}", d * 1e3))
        );
    }
    s += " lookup2-paper (1 mm columns) | 1-entry | printed Eq. 44–46: 2-entry | printed: 1-entry |\n|---|---|---|---|---|";
    if fine {
        s += "---|";
    }
    s += "---|---|---|---|\n";
    let e = |v: &EntryError| {
        format!(
            "{:.3} / {:.3} / {:.2}",
            v.z * 1e3,
            v.phi * 1e3,
            v.angle.to_degrees()
        )
    };
    for r in rows {
        let (p2, p1) = if r.cl == 0.0 {
            ("same".to_string(), "same".to_string())
        } else {
            (e(&r.table2_printed), e(&r.table1_printed))
        };
        s += &format!(
            "| {:+.2} | {:+.1} | {:.2} | {} | {} |",
            r.gv * 1e3,
            r.cl * 1e3,
            r.y_max * 1e3,
            e(&r.kec),
            e(&r.per_wheel)
        );
        if let Some(f) = &r.table2_fine {
            s += &format!(" {} |", e(f));
        }
        s += &format!(" {} | {} | {p2} | {p1} |\n", e(&r.table2), e(&r.table1));
    }
    s
}

/// Summary of a KEC model: kinks and reproduction accuracy.
pub fn kec_summary(
    title: &str,
    geom: &ContactGeometry,
    table: &LookupTable1,
    model: &KecModel,
) -> Result<String, String> {
    let (lo, hi) = table.range();
    let mut s = format!("# {title}\n\n");
    s += &format!(
        "Equivalent profiles from the 1-entry table over y = {:.3} .. {:.3} mm ({} rows): left s^k = {:.3} .. {:.3} mm, right s^k = {:.3} .. {:.3} mm\n\n",
        lo * 1e3,
        hi * 1e3,
        table.rows.len(),
        model.left.domain().0 * 1e3,
        model.left.domain().1 * 1e3,
        model.right.domain().0 * 1e3,
        model.right.domain().1 * 1e3
    );
    s += "Kinks (the real contact jumps; the equivalent profile stays continuous). At a kink the knife edge touches a corner: the KEC normal, and so the split of the normal force between the two real contact points, is undetermined there (paper §9) — the constraint reaction is one force, applied at the real point of whichever side of the kink the solution lies on.\n\n";
    s += "| side | y [mm] | s^k [mm] | slope before → after | real s^w [mm] before → after | contact angle [°] before → after |\n|---|---|---|---|---|---|\n";
    for k in model.kinks.iter().filter(|k| k.real_jump) {
        s += &format!(
            "| {} | {:+.4} | {:+.4} | {:+.4} → {:+.4} | {:+.3} → {:+.3} | {:.1} → {:.1} |\n",
            k.side.name(),
            k.y * 1e3,
            k.s_k * 1e3,
            k.slope_before,
            k.slope_after,
            k.s_wheel_before * 1e3,
            k.s_wheel_after * 1e3,
            k.angle_before.to_degrees(),
            k.angle_after.to_degrees()
        );
    }
    let others = model.kinks.iter().filter(|k| !k.real_jump).count();
    s += &format!("\n({others} more kinks where the other side's contact jumps: the roll has a kink, this side's real contact moves on continuously.)\n");
    let (ez, ep) = super::kec::reproduction_error(model, &table.rows).map_err(|e| e.to_string())?;
    let interp = interpolation_error_kec(geom, table, model, &[1.0 / 3.0, 2.0 / 3.0])?;
    s += &format!(
        "\nIdeal track: KEC reproduces the table at its {} y values to z {:.1e} mm, roll {:.1e} mrad; between them (at 1/3 and 2/3 of every interval) it differs from the online solution by z {:.2e} mm, roll {:.2e} mrad.\n",
        table.rows.len(),
        ez * 1e3,
        ep * 1e3,
        interp.0 * 1e3,
        interp.1 * 1e3
    );
    Ok(s)
}
