//! Benchmarks printed by `kecsim bench`: each speed figure is measured in the same run as the
//! error that goes with it, in release builds. Not timed assertions: numbers for people.

pub mod creep_accuracy;
pub mod dynamics;
pub mod hard;
pub mod patch_run;
pub mod precision;
pub mod rhs;
pub mod scaling;
pub mod study;

use std::hint::black_box;
use std::time::Instant;

use crate::profile::StandardProfile;

/// One row of a benchmark table.
#[derive(Debug, Clone)]
pub struct BenchRow {
    pub what: String,
    pub ns_per_call: f64,
    /// Max error against the independent reference named in `error_against`, in `error_unit`.
    pub max_error: f64,
    pub error_unit: &'static str,
    pub error_against: &'static str,
}

/// Deterministic pseudo-random points in [a, b] (SplitMix64), so runs are comparable.
fn points(n: usize, a: f64, b: f64) -> Vec<f64> {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n)
        .map(|_| {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            a + (b - a) * (z >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

/// Profile evaluation (value, slope, second derivative) of the runtime spline against the
/// published sectionwise definition: cost per call of both, and the spline's max deviation from it.
pub fn profiles(n: usize) -> Vec<BenchRow> {
    let mut rows = Vec::new();
    for std in StandardProfile::ALL {
        let profile = std.profile();
        let sections = std.sections();
        let (a, b) = sections.range();
        let xs_mm = points(n, a, b);
        let xs_m: Vec<f64> = xs_mm.iter().map(|x| x * 1e-3).collect();

        let t = Instant::now();
        let mut acc = 0.0;
        for &x in &xs_m {
            let p = profile.eval(black_box(x));
            acc += p.z + p.dz + p.d2z;
        }
        black_box(acc);
        let spline_ns = t.elapsed().as_secs_f64() * 1e9 / n as f64;

        let t = Instant::now();
        let mut acc = 0.0;
        for &x in &xs_mm {
            let (g, d1, d2) = sections.eval(black_box(x));
            acc += g + d1 + d2;
        }
        black_box(acc);
        let analytic_ns = t.elapsed().as_secs_f64() * 1e9 / n as f64;

        let max_err = xs_mm
            .iter()
            .take(200_000)
            .map(|&x| {
                let (g, dg, _) = sections.eval(x);
                // Normal distance: vertical deviation / sqrt(1 + slope²).
                (profile.eval(x * 1e-3).z * 1e3 + g).abs() / (1.0 + dg * dg).sqrt()
            })
            .fold(0.0, f64::max);
        rows.push(BenchRow {
            what: format!("{} spline eval (z, z', z'')", std.name()),
            ns_per_call: spline_ns,
            max_error: max_err,
            error_unit: "mm",
            error_against: "published sectionwise definition (normal distance)",
        });
        rows.push(BenchRow {
            what: format!("{} analytic sections eval", std.name()),
            ns_per_call: analytic_ns,
            max_error: 0.0,
            error_unit: "mm",
            error_against: "itself (reference)",
        });
    }
    rows
}

/// Formats rows as an aligned table.
pub fn table(rows: &[BenchRow]) -> String {
    let mut s = format!(
        "{:<36} {:>10} {:>12} {:>12}  {}\n",
        "what", "ns/call", "M calls/s", "max error", "error against"
    );
    for r in rows {
        s += &format!(
            "{:<36} {:>10.1} {:>12.1} {:>9.2e} {:<2}  {}\n",
            r.what,
            r.ns_per_call,
            1e3 / r.ns_per_call,
            r.max_error,
            r.error_unit,
            r.error_against
        );
    }
    s
}

/// One row of the contact benchmark: cost and error against the online solution.
#[derive(Debug, Clone)]
pub struct ContactBenchRow {
    pub what: String,
    pub micros_per_call: f64,
    /// Max |Δz| against the online (cold) solution, m.
    pub z_error: f64,
    /// Max |Δφ|, rad.
    pub phi_error: f64,
    /// Max |Δs| of the four surface parameters, m.
    pub s_error: f64,
    /// 95th percentile of |Δz|, m.
    pub z_p95: f64,
}

/// Errors of a method against a reference at the same points: x = [z, φ, s^lw, s^lr, s^rw, s^rr]
/// (the surface parameters compared only where both sides have them).
#[derive(Default)]
struct ErrorAcc {
    dz: Vec<f64>,
    phi: f64,
    s: Option<f64>,
}

impl ErrorAcc {
    fn add(&mut self, x: &[f64], reference: &[f64]) {
        self.dz.push((x[0] - reference[0]).abs());
        self.phi = self.phi.max((x[1] - reference[1]).abs());
        if x.len() == 6 && reference.len() == 6 {
            let ds = (2..6).map(|i| (x[i] - reference[i]).abs()).fold(0.0, f64::max);
            self.s = Some(self.s.unwrap_or(0.0).max(ds));
        }
    }

    fn row(self, what: &str, micros_per_call: f64) -> ContactBenchRow {
        ContactBenchRow {
            what: what.to_string(),
            micros_per_call,
            z_error: self.dz.iter().cloned().fold(0.0, f64::max),
            phi_error: self.phi,
            s_error: self.s.unwrap_or(f64::NAN),
            z_p95: p95(self.dz),
        }
    }
}

fn p95(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * 0.95).round() as usize]
}

/// Contact-geometry costs on S1002/60E1 at 1:40: online solve (cold: global search + Newton;
/// warm: Newton from the previous step's solution as in simulation), 1-entry and 2-entry table
/// look-ups, and table builds — each with its error against the cold online solution at the same
/// points. `n` random (y, gv) points, y within the 1-entry table, gv within ±10 mm.
pub fn contact(n: usize) -> Result<(Vec<ContactBenchRow>, String), crate::contact::lookup::TableError> {
    use crate::contact::geometry::ContactGeometry;
    use crate::contact::lookup::{LookupTable1, LookupTable2, TableSettings};
    use crate::profile::placement::WheelRailPair;
    use crate::track::RailOffsets;

    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40")
        .expect("standard pair places");
    let geom = ContactGeometry::with_defaults(pair);
    let settings = TableSettings::default();

    let t = Instant::now();
    let t1 = LookupTable1::build(&geom, &settings)?;
    let build1 = t.elapsed().as_secs_f64();
    let (lo, hi) = t1.range();
    let y_max = lo.abs().min(hi) - 1e-4;
    let gvs: Vec<f64> = (-5..=5).map(|k| k as f64 * 2e-3).collect();
    let t = Instant::now();
    // Every column over the same ±y_max (the points' y do not shrink with gv).
    let common = TableSettings {
        y_max_m: Some(y_max),
        ..settings
    };
    let t2 = LookupTable2::build(&geom, &gvs, &common)?;
    let build2 = t.elapsed().as_secs_f64();

    let ys = points(n, -y_max, y_max);
    let gv_pts = points(n + 7, -0.01, 0.01);
    let mut rows = Vec::new();

    // Online, cold.
    let m = n.min(400);
    let t = Instant::now();
    let cold: Vec<_> = ys[..m]
        .iter()
        .map(|&y| geom.solve(y, &RailOffsets::default()))
        .collect::<Result<_, _>>()?;
    let us_cold = t.elapsed().as_secs_f64() * 1e6 / m as f64;
    rows.push(ErrorAcc::default().row("online solve, cold (global search + Newton)", us_cold));
    // Online, warm: a wheelset moving laterally by ≤ 0.01 mm per call, Newton from the last state.
    let steps: Vec<f64> = points(n, -1e-5, 1e-5);
    let mut y = 0.0f64;
    let mut path = Vec::with_capacity(n);
    for d in &steps {
        y = (y + d).clamp(-y_max, y_max);
        path.push(y);
    }
    let mut prev = geom.solve(0.0, &RailOffsets::default())?;
    let t = Instant::now();
    let mut warm = Vec::with_capacity(n);
    for &y in &path {
        prev = geom.solve_from(y, &RailOffsets::default(), &prev)?;
        warm.push(prev.x());
    }
    let warm_us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let mut acc_warm = ErrorAcc::default();
    for (k, &y) in path.iter().enumerate().step_by((n / 200).max(1)) {
        acc_warm.add(&warm[k], &geom.solve(y, &RailOffsets::default())?.x());
    }
    rows.push(acc_warm.row("online solve, warm (Newton from last step)", warm_us));
    // Online, tracked: warm Newton plus the interpenetration check that keeps it on the contact.
    let mut prev = geom.solve(0.0, &RailOffsets::default())?;
    let t = Instant::now();
    let mut tracked = Vec::with_capacity(n);
    for &y in &path {
        prev = geom.solve_tracked(y, &RailOffsets::default(), &prev)?;
        tracked.push(prev.x());
    }
    let tracked_us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let mut acc_tracked = ErrorAcc::default();
    for (k, &y) in path.iter().enumerate().step_by((n / 200).max(1)) {
        acc_tracked.add(&tracked[k], &geom.solve(y, &RailOffsets::default())?.x());
    }
    rows.push(acc_tracked.row(
        "online solve, tracked (warm + interpenetration check)",
        tracked_us,
    ));
    // 1-entry look-up.
    let t = Instant::now();
    let mut acc = 0.0;
    for &y in &ys {
        acc += t1.lookup(black_box(y))?.x[0];
    }
    black_box(acc);
    let us1 = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let mut acc1 = ErrorAcc::default();
    for (k, c) in cold.iter().enumerate() {
        acc1.add(&t1.lookup(ys[k])?.x, &c.x());
    }
    rows.push(acc1.row("1-entry table look-up", us1));
    // 2-entry look-up, against online solves with that gauge variation.
    let t = Instant::now();
    let mut acc = 0.0;
    for k in 0..n {
        acc += t2.lookup(black_box(ys[k]), black_box(gv_pts[k]))?.x[0];
    }
    black_box(acc);
    let us2 = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let mut acc2 = ErrorAcc::default();
    for k in 0..m {
        let c = geom.solve(ys[k], &RailOffsets::gauge_variation(gv_pts[k]))?;
        acc2.add(&t2.lookup(ys[k], gv_pts[k])?.x, &c.x());
    }
    rows.push(acc2.row("2-entry table look-up (y, gv)", us2));

    let builds = format!(
        "table builds: 1-entry y = {:.2}..{:.2} mm, {} rows: {:.0} ms; 2-entry y = ±{:.2} mm × gv = −10..10 mm by 2 mm ({} columns, {} rows): {:.0} ms\n",
        lo * 1e3,
        hi * 1e3,
        t1.rows.len(),
        build1 * 1e3,
        y_max * 1e3,
        t2.columns.len(),
        t2.columns.iter().map(|c| c.rows.len()).sum::<usize>(),
        build2 * 1e3
    );
    Ok((rows, builds))
}

/// Formats contact rows as an aligned table.
pub fn contact_table(rows: &[ContactBenchRow]) -> String {
    let mut s = format!(
        "{:<46} {:>10} {:>14} {:>14} {:>14} {:>14}\n",
        "S1002/60E1 1:40", "µs/call", "p95 Δz [mm]", "max Δz [mm]", "max Δφ [mrad]", "max Δs [mm]"
    );
    for r in rows {
        let s_err = if r.s_error.is_nan() {
            "—".to_string()
        } else {
            format!("{:.2e}", r.s_error * 1e3)
        };
        s += &format!(
            "{:<46} {:>10.3} {:>14.2e} {:>14.2e} {:>14.2e} {:>14}\n",
            r.what,
            r.micros_per_call,
            r.z_p95 * 1e3,
            r.z_error * 1e3,
            r.phi_error * 1e3,
            s_err
        );
    }
    s += "errors against the cold online solution at the same points\n";
    s
}

/// The KEC solve against the tables (the 2-entry table's 1 mm columns and the per-wheel entry of
/// the centred table) and the online constraints on S1002/60E1 at 1:40, at
/// `n` random (y, gv) with gv within ±10 mm: cost per call and error against the online solution,
/// measured in one run. KEC cold starts from Eq. (51); warm from the previous step's solution.
pub fn kec(n: usize) -> Result<(Vec<ContactBenchRow>, String), String> {
    use crate::contact::geometry::ContactGeometry;
    use crate::contact::kec::KecModel;
    use crate::contact::lookup::{LookupTable1, LookupTable2, TableSettings};
    use crate::contact::per_wheel::contact_per_wheel;
    use crate::profile::placement::WheelRailPair;
    use crate::track::RailOffsets;

    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40")
        .expect("standard pair places");
    let l_w = pair.wheelset.l_w();
    let geom = ContactGeometry::with_defaults(pair);
    let settings = TableSettings::default();
    let t = Instant::now();
    let t1 = LookupTable1::build(&geom, &settings).map_err(|e| e.to_string())?;
    let model = KecModel::from_table(&t1, l_w).map_err(|e| e.to_string())?;
    let build_kec = t.elapsed().as_secs_f64();
    let (lo, hi) = t1.range();
    let y_flange = lo.abs().min(hi);
    let gvs: Vec<f64> = (-10..=10).map(|k| k as f64 * 1e-3).collect();
    let t = Instant::now();
    let t2 = LookupTable2::build(&geom, &gvs, &settings).map_err(|e| e.to_string())?;
    let build2 = t.elapsed().as_secs_f64();
    // Points: gv uniform in ±10 mm, y within the range where every method is defined.
    let gv = points(n + 3, -0.01, 0.01);
    let u = points(n, -1.0, 1.0);
    let ys: Vec<f64> = (0..n)
        .map(|k| u[k] * (y_flange - gv[k].abs() / 2.0 - 3e-4))
        .collect();
    let offs: Vec<RailOffsets> = gv.iter().map(|&g| RailOffsets::gauge_variation(g)).collect();

    let m = n.min(300);
    let online: Vec<_> = (0..m)
        .map(|k| geom.solve(ys[k], &offs[k]))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    let errors = |f: &dyn Fn(usize) -> (f64, f64)| {
        let mut acc = ErrorAcc::default();
        for (k, o) in online.iter().enumerate() {
            let (z, phi) = f(k);
            acc.add(&[z, phi], &[o.z, o.phi]);
        }
        acc
    };
    let mut rows = Vec::new();
    // Online (cold) cost.
    let t = Instant::now();
    for k in 0..m {
        black_box(geom.solve(ys[k], &offs[k]).map_err(|e| e.to_string())?);
    }
    rows.push(ErrorAcc::default().row(
        "online solve, cold (the reference)",
        t.elapsed().as_secs_f64() * 1e6 / m as f64,
    ));
    // KEC cold (Eq. 51).
    let t = Instant::now();
    let mut acc = 0.0;
    for k in 0..n {
        acc += model
            .solve(black_box(ys[k]), offs[k].to_array(), None)
            .map_err(|e| e.to_string())?
            .z;
    }
    black_box(acc);
    let us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let sol = |k: usize| {
        model
            .solve(ys[k], offs[k].to_array(), None)
            .map(|s| (s.z, s.phi))
            .unwrap_or((f64::NAN, f64::NAN))
    };
    rows.push(errors(&sol).row("KEC solve, cold (Eq. 51 start)", us));
    // KEC warm: a wheelset drifting (≤ 0.01 mm, ≤ 0.01 mm gv per call) from the last solution.
    let (dy, dg) = (points(n, -1e-5, 1e-5), points(n + 1, -1e-5, 1e-5));
    let (mut y, mut g) = (0.0f64, 0.0f64);
    let path: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            g = (g + dg[k]).clamp(-0.01, 0.01);
            let lim = y_flange - g.abs() / 2.0 - 3e-4;
            y = (y + dy[k]).clamp(-lim, lim);
            (y, g)
        })
        .collect();
    let mut x = None;
    let mut warm = Vec::with_capacity(n);
    let t = Instant::now();
    for &(y, g) in &path {
        let s = model
            .solve(y, RailOffsets::gauge_variation(g).to_array(), x)
            .map_err(|e| e.to_string())?;
        x = Some(s.x(model.r0));
        warm.push((s.z, s.phi));
    }
    let us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let mut acc_warm = ErrorAcc::default();
    for k in (0..n).step_by((n / 200).max(1)) {
        let (y, g) = path[k];
        let o = geom
            .solve(y, &RailOffsets::gauge_variation(g))
            .map_err(|e| e.to_string())?;
        acc_warm.add(&[warm[k].0, warm[k].1], &[o.z, o.phi]);
    }
    rows.push(acc_warm.row("KEC solve, warm (from last step)", us));
    // 2-entry look-up.
    let t = Instant::now();
    let mut acc = 0.0;
    for k in 0..n {
        acc += t2
            .contact(black_box(ys[k]), &offs[k])
            .map_err(|e| e.to_string())?
            .x[0];
    }
    black_box(acc);
    let us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let look = |k: usize| {
        t2.contact(ys[k], &offs[k])
            .map(|r| (r.z(), r.phi()))
            .unwrap_or((f64::NAN, f64::NAN))
    };
    rows.push(errors(&look).row("2-entry table look-up (y, gv), 1 mm gv step", us));
    // The per-wheel entry of the centred table (lookup2's default).
    let t = Instant::now();
    let mut acc = 0.0;
    for k in 0..n {
        acc += contact_per_wheel(&t1, black_box(ys[k]), &offs[k])
            .map_err(|e| e.to_string())?
            .x[0];
    }
    black_box(acc);
    let us = t.elapsed().as_secs_f64() * 1e6 / n as f64;
    let per_wheel = |k: usize| {
        contact_per_wheel(&t1, ys[k], &offs[k])
            .map(|r| (r.z(), r.phi()))
            .unwrap_or((f64::NAN, f64::NAN))
    };
    rows.push(errors(&per_wheel).row("table look-up per wheel (lookup2)", us));
    let builds = format!(
        "preprocessing: 1-entry table + KEC profiles {:.0} ms; 2-entry table (21 gauge variations) {:.0} ms\n(KEC warm: errors along its own drifting path)\n",
        build_kec * 1e3,
        build2 * 1e3
    );
    Ok((rows, builds))
}

/// The contact-force building blocks and the three creep-force models, measured in one run:
/// cost per call and the error that goes with it. Models are compared on `n` random creepage
/// triples (|ξx|, |ξy| ≤ 0.006, |φ| ≤ 1.5 1/m) on a 6 × 4 mm ellipse at 80 kN, μ = 0.3, against
/// FASTSIM at 200 × 200 elements (the converged simplified theory), and in pure ξx / ξy against
/// Johnson & Vermeulen's published curve 1 − (1 − β/3)³.
pub fn creep(n: usize) -> Result<String, crate::contact::forces::CreepForceError> {
    use crate::contact::forces::fastsim::FastsimSettings;
    use crate::contact::forces::hertz::{HertzContact, Material, RelativeCurvature};
    use crate::contact::forces::{ContactFrame, ContactPatch, CreepModel, Creepage, KalkerTable};
    use nalgebra::Vector3;

    let mut out = String::new();
    let steel = Material::STEEL;
    // Hertz: random curvature ratios 1..100; error: m, n against the classical table.
    let ratios = points(n.min(200_000), 0.0, 2.0);
    let t = Instant::now();
    let mut acc = 0.0;
    for &r in &ratios {
        let c = RelativeCurvature {
            a: 1.0,
            b: 10f64.powf(r),
        };
        if let Ok(h) = HertzContact::solve(black_box(c), 80e3, &steel, &steel) {
            acc += h.a + h.b;
        }
    }
    black_box(acc);
    let hertz_ns = t.elapsed().as_secs_f64() * 1e9 / ratios.len() as f64;
    let t = Instant::now();
    let mut acc = 0.0;
    let mut table_err: f64 = 0.0;
    for &r in &ratios {
        let c = RelativeCurvature {
            a: 1.0,
            b: 10f64.powf(r),
        };
        if let Ok(h) = HertzContact::solve_by_newton(black_box(c), 80e3, &steel, &steel) {
            acc += h.a + h.b;
            if let Ok(ht) = HertzContact::solve(c, 80e3, &steel, &steel) {
                table_err = table_err
                    .max(((ht.a - h.a) / h.a).abs())
                    .max(((ht.b - h.b) / h.b).abs());
            }
        }
    }
    black_box(acc);
    let newton_ns = t.elapsed().as_secs_f64() * 1e9 / ratios.len() as f64 - hertz_ns;
    let table_mn = [
        (30.0, 2.7306, 0.4931),
        (60.0, 1.4858, 0.7171),
        (80.0, 1.1278, 0.8927),
        (10.0, 6.6115, 0.3110),
    ];
    let mut mn_err: f64 = 0.0;
    for (theta, m, nn) in table_mn {
        let c = (theta * std::f64::consts::PI / 180.0_f64).cos();
        let h = HertzContact::solve(
            RelativeCurvature {
                a: 1.0 - c,
                b: 1.0 + c,
            },
            1e4,
            &steel,
            &steel,
        )
        .map_err(|e| crate::contact::forces::CreepForceError::Patch(e.to_string()))?;
        mn_err = mn_err.max((h.m - m).abs()).max((h.n - nn).abs());
    }
    let kalker = KalkerTable::new(steel.poisson);
    let ab = points(n, -1.0, 1.0);
    let t = Instant::now();
    let mut acc = 0.0;
    for &x in &ab {
        acc += kalker.at(black_box(10f64.powf(x))).c22;
    }
    black_box(acc);
    let kalker_ns = t.elapsed().as_secs_f64() * 1e9 / ab.len() as f64;
    let normal = Vector3::new(0.0, -0.05, 1.0);
    let frame_t = Instant::now();
    let mut acc = 0.0;
    for &x in &ab {
        if let Ok(f) = ContactFrame::new(black_box(normal), Vector3::new(x * 1e-3, 1.0, 0.0), Vector3::x()) {
            let c = Creepage::from_velocities(
                &f,
                Vector3::new(x * 1e-2, 1e-3, 0.0),
                Vector3::zeros(),
                Vector3::new(0.0, 43.0, x),
                Vector3::zeros(),
                20.0,
                0.1,
            );
            acc += c.longitudinal + c.spin;
        }
    }
    black_box(acc);
    let creep_ns = frame_t.elapsed().as_secs_f64() * 1e9 / ab.len() as f64;
    out += &format!(
        "{:<44} {:>10}  {}\n",
        "building block", "ns/call", "error (against)"
    );
    out += &format!(
        "{:<44} {:>10.1}  m, n within {:.1e} of the classical table (θ = 10, 30, 60, 80°); a, b within {:.1e} of Newton's\n",
        "Hertz ellipse (shape table in ln B/A)", hertz_ns, mn_err, table_err
    );
    out += &format!(
        "{:<44} {:>10.1}  the table's reference\n",
        "Hertz ellipse (eccentricity by Newton)", newton_ns
    );
    out += &format!(
        "{:<44} {:>10.1}  reproduces Kalker's Table E.3 at its nodes (unit test)\n",
        "Kalker C11, C22, C23 at a/b (PCHIP)", kalker_ns
    );
    out += &format!(
        "{:<44} {:>10.1}  first-order textbook creepages (unit test)\n\n",
        "contact frame + creepages (3D)", creep_ns
    );

    let patch = ContactPatch::new(6e-3, 4e-3, 80e3, steel.shear_modulus(), 0.3, &kalker)?;
    let mu_n = patch.friction * patch.normal_force;
    let xs = points(n.min(20_000), -0.006, 0.006);
    let ys = points(n.min(20_000) + 7, -0.006, 0.006);
    let ps = points(n.min(20_000) + 13, -1.5, 1.5);
    let cases: Vec<Creepage> = (0..xs.len())
        .map(|i| Creepage::new(xs[i], ys[i + 7], ps[i + 13]))
        .collect();
    let reference = CreepModel::Fastsim(FastsimSettings {
        strips: 200,
        elements: 200,
        ..FastsimSettings::default()
    });
    let n_ref = cases.len().min(2_000);
    let ref_forces: Vec<_> = cases[..n_ref]
        .iter()
        .map(|c| reference.forces(&patch, c, 20.0))
        .collect::<Result<_, _>>()?;
    let ref_forces_no_spin: Vec<_> = cases[..n_ref]
        .iter()
        .map(|c| reference.forces(&patch, &Creepage { spin: 0.0, ..*c }, 20.0))
        .collect::<Result<_, _>>()?;
    let mut models: Vec<(String, CreepModel)> = vec![
        (
            "Kalker linear + Shen–Hedrick–Elkins".into(),
            CreepModel::by_name("kalker").unwrap_or_default(),
        ),
        (
            "Polach (1999, with spin)".into(),
            CreepModel::by_name("polach").unwrap_or_default(),
        ),
        (
            "the exact theory tabulated (default)".into(),
            CreepModel::ExactTable,
        ),
        (
            "FaStrip 30 × 30".into(),
            CreepModel::by_name("fastrip").unwrap_or_default(),
        ),
    ];
    for k in [10, 25, 50] {
        models.push((
            format!("FASTSIM {k} × {k}{}", if k == 25 { " (default)" } else { "" }),
            CreepModel::Fastsim(FastsimSettings {
                strips: k,
                elements: k,
                ..FastsimSettings::default()
            }),
        ));
    }
    out += &format!(
        "{:<44} {:>10} {:>16} {:>16} {:>16}\n",
        "creep-force model (6 × 4 mm, 80 kN, μ 0.3)", "ns/call", "vs FS200", "vs FS200, φ = 0", "vs J–V"
    );
    for (what, model) in &models {
        // One call first: the table is read and its slices refined once per process, not per call.
        model.forces(&patch, &cases[0], 20.0)?;
        let t = Instant::now();
        let mut acc = 0.0;
        for c in &cases {
            let f = model.forces(&patch, black_box(c), 20.0)?;
            acc += f.fx + f.fy;
        }
        black_box(acc);
        let ns = t.elapsed().as_secs_f64() * 1e9 / cases.len() as f64;
        let mut err: f64 = 0.0;
        for (c, r) in cases[..n_ref].iter().zip(&ref_forces) {
            let f = model.forces(&patch, c, 20.0)?;
            err = err.max((f.fx - r.fx).hypot(f.fy - r.fy) / mu_n);
        }
        let mut err0: f64 = 0.0;
        for (c, r) in cases[..n_ref].iter().zip(&ref_forces_no_spin) {
            let c = Creepage { spin: 0.0, ..*c };
            let f = model.forces(&patch, &c, 20.0)?;
            err0 = err0.max((f.fx - r.fx).hypot(f.fy - r.fy) / mu_n);
        }
        let mut jv: f64 = 0.0;
        for lateral in [false, true] {
            let slope = patch.shear_modulus
                * patch.a
                * patch.b
                * if lateral {
                    patch.kalker.c22
                } else {
                    patch.kalker.c11
                };
            for i in 1..=60 {
                let beta = 0.1 * i as f64;
                let xi = beta * mu_n / slope;
                let c = if lateral {
                    Creepage::new(0.0, xi, 0.0)
                } else {
                    Creepage::new(xi, 0.0, 0.0)
                };
                let f = model.forces(&patch, &c, 20.0)?;
                let want = if beta < 3.0 {
                    1.0 - (1.0 - beta / 3.0).powi(3)
                } else {
                    1.0
                };
                jv = jv.max((f.saturation - want).abs());
            }
        }
        out += &format!("{what:<44} {ns:>10.1} {err:>16.4} {err0:>16.4} {jv:>16.4}\n");
    }
    out += "Errors: max |ΔF|/μN of the resultant. FS200: FASTSIM 200 × 200 on the same random creepages (combined ξx, ξy with |φ| ≤ 1.5 1/m, and with φ = 0); J–V: Johnson & Vermeulen's curve in pure ξx and ξy, β ≤ 6. Kalker, Polach, the exact theory and FaStrip against FS200 are model differences (different theories), FASTSIM n × n against FS200 is discretisation error. Every model against Kalker's exact theory: `kecsim bench creep-accuracy`.\n";
    Ok(out)
}

/// Mean and half-spread (max − min)/2 of `repeats` timings of `f` over all `xs`, ns per call.
fn time_ns(xs: &[f64], repeats: usize, f: &dyn Fn(f64) -> f64) -> (f64, f64) {
    let mut t_ns = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        let mut acc = 0.0;
        for &x in xs {
            acc += f(black_box(x));
        }
        black_box(acc);
        t_ns.push(t.elapsed().as_secs_f64() * 1e9 / xs.len() as f64);
    }
    let mean = t_ns.iter().sum::<f64>() / repeats as f64;
    let (lo, hi) = t_ns
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    (mean, 0.5 * (hi - lo))
}

/// Position on the Tab. 6 centreline by an independent quadrature: 5-point Gauss–Legendre on
/// 0.5 m panels of (cos ψ, sin ψ), ψ the integral of the sections' linear curvature.
fn tab6_reference_xy(sections: &[crate::track::sections::HorizontalSection], s: f64) -> (f64, f64, f64) {
    const X: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683_1,
        0.538_469_310_105_683_1,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.568_888_888_888_888_9,
        0.478_628_670_499_366_5,
        0.478_628_670_499_366_5,
        0.236_926_885_056_189_1,
        0.236_926_885_056_189_1,
    ];
    let (mut x, mut y, mut psi0) = (0.0, 0.0, 0.0);
    for sec in sections {
        let end = sec.to_m.min(s);
        if end <= sec.from_m {
            break;
        }
        let (k0, k1) = (sec.curvature_1pm[0], sec.curvature_rate());
        let psi = |u: f64| psi0 + k0 * u + 0.5 * k1 * u * u;
        let len = end - sec.from_m;
        let panels = (len / 0.5).ceil().max(1.0) as usize;
        let hp = len / panels as f64;
        for p in 0..panels {
            let mid = (p as f64 + 0.5) * hp;
            for j in 0..5 {
                let a = psi(mid + 0.5 * hp * X[j]);
                x += 0.5 * hp * W[j] * a.cos();
                y += 0.5 * hp * W[j] * a.sin();
            }
        }
        psi0 = psi(len);
    }
    (x, y, psi0)
}

/// Track evaluation on the paper's Tab. 6 track (with German low-disturbance irregularities, seed
/// 1, 1–80 m): cost per track-frame evaluation (R, A, curvatures), per irregularity evaluation
/// (four irregularities with first and second derivatives), and of both; each with its error
/// against an independent reference (quadrature of the heading; the exact sum of cosines).
pub fn track(n: usize) -> Result<(Vec<BenchRow>, String), crate::track::TrackError> {
    use crate::track::file::TAB6_TRACK;
    use crate::track::{file, Irregularities};

    let irregular = format!(
        "{TAB6_TRACK}\n[track.irregularities]\npsd = \"german-low\"\nseed = 1\nwavelength_min_m = 1.0\nwavelength_max_m = 80.0\n"
    );
    let t = Instant::now();
    let track = file::track_from_text(
        &irregular,
        "<bench: Tab. 6 + german-low>",
        std::path::Path::new("."),
    )?;
    let build = t.elapsed().as_secs_f64();
    let (a, b) = track.centreline.range();
    let xs = points(n.min(2_000_000), a, b);
    let repeats = 5;
    let mut rows = Vec::new();

    let (frame_ns, frame_spread) = time_ns(&xs, repeats, &|s| {
        track
            .centreline
            .frame(s)
            .map_or(0.0, |f| f.position.x + f.rotation[(0, 2)] + f.rho_h)
    });
    let (h, _) = track.centreline.sections();
    let mut pos_err: f64 = 0.0;
    let mut psi_err: f64 = 0.0;
    for &s in xs.iter().take(300) {
        let f = track.centreline.frame(s)?;
        let (x, y, psi) = tab6_reference_xy(h, s);
        pos_err = pos_err.max((f.position.x - x).hypot(f.position.y - y));
        psi_err = psi_err.max((f.heading_rad - psi).abs());
    }
    rows.push(BenchRow {
        what: "track frame R, A, ρ (Tab. 6)".into(),
        ns_per_call: frame_ns,
        max_error: pos_err,
        error_unit: "m",
        error_against: "Gauss–Legendre quadrature of the heading (position, 300 points)",
    });

    let Some(irr) = track.irregularities.as_ref() else {
        return Err(crate::track::TrackError::Irregularity(
            "bench track has none".into(),
        ));
    };
    let (irr_ns, irr_spread) = time_ns(&xs, repeats, &|s| {
        irr.eval(s).map_or(0.0, |st| st.value[0] + st.d1[1] + st.d2[3])
    });
    let crate::track::irregularity::Origin::Generated(g) = irr.origin else {
        return Err(crate::track::TrackError::Irregularity(
            "bench track is not generated".into(),
        ));
    };
    let (_, sums) = Irregularities::generate(&g, a, b)?;
    let (mut v_err, mut d2_err, mut d2_scale) = (0.0f64, 0.0f64, 0.0f64);
    for &s in xs.iter().take(300) {
        let st = irr.eval(s)?;
        for (c, sum) in sums.iter().enumerate() {
            let (v, _, d2) = sum.eval(s);
            v_err = v_err.max((st.value[c] - v).abs());
            d2_err = d2_err.max((st.d2[c] - d2).abs());
            d2_scale = d2_scale.max(d2.abs());
        }
    }
    rows.push(BenchRow {
        what: "irregularity eval (4 + derivatives)".into(),
        ns_per_call: irr_ns,
        max_error: v_err * 1e3,
        error_unit: "mm",
        error_against: "exact sum of cosines (value, 300 points)",
    });
    let (both_ns, both_spread) = time_ns(&xs, repeats, &|s| {
        track.eval(s).map_or(0.0, |(f, i)| f.position.y + i.value[2])
    });
    rows.push(BenchRow {
        what: "Track::eval (frame + irregularities)".into(),
        ns_per_call: both_ns,
        max_error: psi_err,
        error_unit: "rad",
        error_against: "heading vs ∫ρ_h ds of the sections (300 points)",
    });
    let notes = format!(
        "timing: mean of {repeats} passes over {} random s; spread (max − min)/2: frame ±{frame_spread:.1} ns, irregularities ±{irr_spread:.1} ns, both ±{both_spread:.1} ns\nirregularity d²/ds² max error {:.2e} 1/m ({:.1e} of its largest value {:.2e} 1/m); track + irregularities built in {:.0} ms ({} centreline nodes, {} irregularity nodes)\n",
        xs.len(),
        d2_err,
        d2_err / d2_scale,
        d2_scale,
        build * 1e3,
        track.centreline.node_count(),
        irr.len()
    );
    Ok((rows, notes))
}

/// The cost of one contact's patch: Hertz at the rigid contact point against the strip model (the
/// gap section, then the strips) — S1002/60E1 at 1:40, 50 kN along the normal, at the rigid
/// contacts of both wheels for y = −9 … 9 mm every 0.5 mm — with the gap deviation D and the strip
/// model's pmax against Hertz's, measured in one run. `n`: repetitions of the set.
pub fn patch(n: usize) -> Result<String, String> {
    use crate::contact::forces::hertz::{HertzContact, Material, RelativeCurvature};
    use crate::contact::geometry::ContactGeometry;
    use crate::contact::nonhertz::gap::{GapInput, GapSection, GAP_WINDOW_M};
    use crate::contact::nonhertz::strips::{self, StripSettings};
    use crate::contact::nonhertz::{hertz_deviation, HERTZ_VALIDITY_LIMIT};
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;
    use crate::track::{RailOffsets, Side};
    use std::time::Instant;
    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40")
        .map_err(|e| e.to_string())?;
    let geom = ContactGeometry::with_defaults(pair.clone());
    let m = Material::STEEL;
    let e_star = m.contact_modulus(&m);
    let load = 50e3;
    let mut points = Vec::new();
    for k in -18..=18 {
        let sol = geom
            .solve(k as f64 * 5e-4, &RailOffsets::default())
            .map_err(|e| e.to_string())?;
        for side in Side::BOTH {
            points.push((side, *sol.point(side)));
        }
    }
    let inputs: Vec<GapInput> = points
        .iter()
        .map(|(side, p)| GapInput {
            side: *side,
            s_wheel: p.s_wheel,
            s_rail: p.s_rail,
            nominal_radius: pair.wheelset.nominal_radius_m,
            rail_angle: side.sign() * pair.inclination.angle_rad,
            approach_angle: GapInput::along_normal(&pair.rail, *side, p.s_rail),
            half_window: GAP_WINDOW_M,
        })
        .collect();
    let reps = n.max(1);
    let t = Instant::now();
    let mut hz = Vec::new();
    for _ in 0..reps {
        hz = points
            .iter()
            .map(|(_, p)| {
                HertzContact::solve(RelativeCurvature::at_contact(p), load, &m, &m)
                    .map(|h| (h.max_pressure, h.b))
                    .unwrap_or((f64::NAN, f64::NAN))
            })
            .collect();
    }
    let t_hertz = t.elapsed().as_secs_f64() / (reps * points.len()) as f64;
    let t = Instant::now();
    let mut dev = Vec::new();
    for _ in 0..reps {
        dev = points
            .iter()
            .zip(&hz)
            .map(|((side, p), (_, b))| {
                hertz_deviation(&pair.wheel, &pair.rail, *side, p.s_wheel, p.s_rail, *b)
            })
            .collect();
    }
    let t_dev = t.elapsed().as_secs_f64() / (reps * points.len()) as f64;
    let t = Instant::now();
    let mut secs = Vec::new();
    for _ in 0..reps {
        secs = inputs
            .iter()
            .map(|i| GapSection::new(&pair.wheel, &pair.rail, i))
            .collect();
    }
    let t_gap = t.elapsed().as_secs_f64() / (reps * points.len()) as f64;
    let t = Instant::now();
    let mut kp = Vec::new();
    for _ in 0..reps {
        kp = secs
            .iter()
            .map(|s| {
                s.as_ref()
                    .ok()
                    .and_then(|s| strips::solve(s, load, e_star, &StripSettings::default()).ok())
                    .map(|p| p.iter().map(|q| q.max_pressure).fold(0.0, f64::max))
                    .unwrap_or(f64::NAN)
            })
            .collect();
    }
    let t_strips = t.elapsed().as_secs_f64() / (reps * points.len()) as f64;
    let (mut inside, mut outside, mut n_out) = (0.0f64, 0.0f64, 0);
    for ((h, _), (d, k)) in hz.iter().zip(dev.iter().zip(&kp)) {
        let e = (h / k - 1.0).abs();
        if *d <= HERTZ_VALIDITY_LIMIT {
            inside = inside.max(e);
        } else {
            outside = outside.max(e);
            n_out += 1;
        }
    }
    Ok(format!(
        "contact patches, S1002/60E1 1:40, {} rigid contacts (y −9…9 mm, both wheels), 50 kN along the normal, {reps} repetitions\n\
         {:<44} {:>10.2} µs\n{:<44} {:>10.2} µs\n{:<44} {:>10.2} µs\n{:<44} {:>10.2} µs\n\
         strip model / Hertz: {:.0}× per contact\n\
         Hertz's p0 against the strip model's pmax: within {:.1} % where D ≤ {HERTZ_VALIDITY_LIMIT}; up to {:.1} % on the {n_out} contacts beyond\n",
        points.len(),
        "Hertz (table shape)",
        t_hertz * 1e6,
        "Hertz's gap deviation D",
        t_dev * 1e6,
        "strip model: gap section (±25 mm at 0.1 mm)",
        t_gap * 1e6,
        "strip model: strips (24 × 8 nodes)",
        t_strips * 1e6,
        (t_gap + t_strips) / t_hertz,
        100.0 * inside,
        100.0 * outside,
    ))
}
