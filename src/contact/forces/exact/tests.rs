use super::*;
use crate::contact::forces::kalker::KalkerTable;

fn patch(a_mm: f64, b_mm: f64) -> ContactPatch {
    let t = KalkerTable::new(0.28);
    ContactPatch::new(a_mm * 1e-3, b_mm * 1e-3, 80e3, 82e9, 0.3, &t).unwrap()
}

/// At small creepage the exact theory is Kalker's linear theory: the solver reproduces his
/// published C₁₁, C₂₂, C₂₃ (`super::kalker`, an independent source): the 32-element grid within
/// its first-order error (≤ 11 %), Richardson's extrapolation from 16 and 32 within 1.6 %; Mz from
/// η tends to Fy from φ (the linear theory's reciprocity, exact in the continuum).
#[test]
fn small_creepage_gives_kalkers_coefficients() {
    let p = patch(6.0, 6.0);
    let (g, ab) = (p.shear_modulus, p.a * p.b);
    let k = p.kalker;
    let coefficients = |s: &ExactSettings| {
        let fx = forces(&p, &Creepage::new(1e-6, 0.0, 0.0), s).unwrap();
        let fy = forces(&p, &Creepage::new(0.0, 1e-6, 0.0), s).unwrap();
        let fs = forces(&p, &Creepage::new(0.0, 0.0, 1e-4), s).unwrap();
        let c23 = -fs.fy / (g * ab.powf(1.5) * 1e-4);
        [
            -fx.fx / (g * ab * 1e-6) / k.c11 - 1.0,
            -fy.fy / (g * ab * 1e-6) / k.c22 - 1.0,
            c23 / k.c23 - 1.0,
            fy.mz / (g * ab.powf(1.5) * 1e-6) / c23 - 1.0,
        ]
    };
    let plain = coefficients(&ExactSettings {
        richardson: false,
        tolerance: 1e-8,
        ..ExactSettings::default()
    });
    let extrapolated = coefficients(&ExactSettings {
        tolerance: 1e-8,
        ..ExactSettings::default()
    });
    assert!(plain.iter().all(|e| e.abs() < 0.11), "32 elements: {plain:?}");
    assert!(
        extrapolated.iter().all(|e| e.abs() < 0.016),
        "Richardson 16/32: {extrapolated:?}"
    );
    for (e, p) in extrapolated.iter().zip(&plain) {
        assert!(e.abs() < p.abs(), "{extrapolated:?} vs {plain:?}");
    }
}

/// CONTACT's traction curve (its example `tractcurv`, first series): the same grid, the normal
/// problem solved on it, steady rolling at 30 creepages from 1e-5 to 0.25.
#[test]
fn reproduces_contacts_traction_curve() {
    let text = include_str!("../../../../tests/data/contact/tractcurv.csv");
    let (mx, my) = (48, 44);
    let (xl, yl) = (6.934e-3, 13.87e-3);
    let grid = Grid::new(mx, my, (-xl, xl), (-yl, yl)).unwrap();
    let (a1, b1) = (0.8, 0.2814); // 1/m
    let mut gap = Vec::new();
    for j in 0..my {
        for i in 0..mx {
            gap.push(a1 * grid.x(i).powi(2) + b1 * grid.y(j).powi(2));
        }
    }
    let (g, nu, fn_, mu) = (82e9, 0.28, 106.7e3, 0.33);
    let normal = normal::solve(grid, &gap, fn_, g, nu, 1e-10).unwrap();
    let pmax = normal.pressure.max_pressure();
    let nc = normal.pressure.contact_elements();
    println!(
        "contact elements {nc} (CONTACT 1384), pmax {pmax:e}, approach {:e}, iterations {}",
        normal.approach, normal.iterations
    );
    assert!(
        (nc as f64 / 1384.0 - 1.0).abs() < 0.005,
        "{nc} elements in contact"
    );
    assert!((pmax / 640.7e6 - 1.0).abs() < 1e-3, "pmax {pmax}");
    assert!(
        (normal.approach / 7.651e-5 - 1.0).abs() < 1e-3,
        "approach {}",
        normal.approach
    );
    let op = RollingOperator::for_grid(&normal.pressure, g, nu);
    let it = IterationSettings {
        tolerance: 1e-6,
        ..IterationSettings::default()
    };
    let mut worst: f64 = 0.0;
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let v: Vec<&str> = line.split(',').collect();
        let cksi: f64 = v[1].parse().unwrap();
        let reference: f64 = v[3].parse().unwrap();
        let sol = op
            .solve(&normal.pressure, mu, &Creepage::new(cksi, 0.0, 0.0), &it, None)
            .unwrap();
        let f = sol.fx / (mu * fn_);
        let (na, ns) = sol.counts();
        let err = (f - reference).abs() / reference.abs();
        println!(
            "case {}: ξ {cksi:e}: {f:.5} vs {reference} ({:+.3} %), A/S {na}/{ns} vs {}/{}",
            v[0],
            100.0 * err,
            v[7],
            v[8]
        );
        worst = worst.max(err);
    }
    assert!(worst < 0.005, "worst relative difference {worst}");
}

/// One row of `tests/data/contact/hertz_spin.csv` solved on CONTACT's own grid, its normal problem
/// included: (fx, fy, mz, μN) and CONTACT's (fx, fy, mz).
fn contact_case(line: &str) -> ([f64; 3], [f64; 3], f64) {
    let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap_or(f64::NAN)).collect();
    let (n_force, xi, eta, phi, mu) = (v[0], v[3], v[4], v[5], v[6]);
    let (a1, b1, gx, gy) = (v[14], v[15], v[16] * 1e-3, v[17] * 1e-3);
    let (mx, my) = (v[18] as usize, v[19] as usize);
    let grid = Grid::new(mx, my, (-gx, gx), (-gy, gy)).unwrap();
    let mut gap = Vec::new();
    for j in 0..my {
        for i in 0..mx {
            gap.push(a1 * grid.x(i).powi(2) + b1 * grid.y(j).powi(2));
        }
    }
    let normal = normal::solve(grid, &gap, n_force, 82e9, 0.28, 1e-10).unwrap();
    let op = RollingOperator::for_grid(&normal.pressure, 82e9, 0.28);
    let it = IterationSettings {
        tolerance: 1e-6,
        ..IterationSettings::default()
    };
    let sol = op
        .solve(&normal.pressure, mu, &Creepage::new(xi, eta, phi), &it, None)
        .unwrap();
    ([sol.fx, sol.fy, sol.mz], [v[9], v[10], v[11]], mu * n_force)
}

/// CONTACT's steady rolling with spin (93 cases, a/b 0.5–2, φ up to 4 1/m, combined creepages):
/// the same grid and normal problem give the same forces within CONTACT's printed digits.
#[test]
#[ignore = "slow: 93 exact solutions (~15 s); the fast suite runs every eighth"]
fn reproduces_contact_with_spin_all() {
    spin_cases(1);
}

#[test]
fn reproduces_contact_with_spin() {
    spin_cases(8);
}

fn spin_cases(every: usize) {
    let text = include_str!("../../../../tests/data/contact/hertz_spin.csv");
    let mut worst: f64 = 0.0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .step_by(every)
    {
        let (f, r, mun) = contact_case(line);
        let df = (f[0] - r[0]).hypot(f[1] - r[1]) / mun;
        println!(
            "{line}\n  kecsim ({:.1}, {:.1}, {:.3}) |ΔF|/μN {df:.2e}",
            f[0], f[1], f[2]
        );
        worst = worst.max(df);
    }
    assert!(worst < 1e-3, "worst |ΔF|/μN {worst}");
}
