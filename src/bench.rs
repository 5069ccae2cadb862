//! Benchmarks printed by `kecsim bench`: each speed figure is measured in the same run as the
//! error that goes with it, in release builds. Not timed assertions: numbers for people.

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
