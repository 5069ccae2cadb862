use super::*;
use crate::contact::forces::kalker::KalkerTable;

fn patch(a_mm: f64, b_mm: f64) -> ContactPatch {
    let t = KalkerTable::new(0.28);
    ContactPatch::new(a_mm * 1e-3, b_mm * 1e-3, 80e3, 82e9, 0.3, &t).unwrap()
}

/// At small creepage the exact theory is Kalker's linear theory: the solver reproduces his
/// published C₁₁, C₂₂, C₂₃ (`super::kalker`, an independent source) within its grid's error, which
/// shrinks as the grid is refined; Mz from η equals Fy from φ (the linear theory's reciprocity).
#[test]
fn small_creepage_gives_kalkers_coefficients() {
    let p = patch(6.0, 6.0);
    let (g, ab) = (p.shear_modulus, p.a * p.b);
    let k = p.kalker;
    let mut last = [f64::INFINITY; 3];
    for n in [20, 40] {
        let s = ExactSettings {
            elements_x: n,
            elements_y: n,
            tolerance: 1e-8,
        };
        let fx = forces(&p, &Creepage::new(1e-6, 0.0, 0.0), &s).unwrap();
        let fy = forces(&p, &Creepage::new(0.0, 1e-6, 0.0), &s).unwrap();
        let fs = forces(&p, &Creepage::new(0.0, 0.0, 1e-4), &s).unwrap();
        let c = [
            -fx.fx / (g * ab * 1e-6),
            -fy.fy / (g * ab * 1e-6),
            -fs.fy / (g * ab.powf(1.5) * 1e-4),
        ];
        let reciprocal = fy.mz / (g * ab.powf(1.5) * 1e-6);
        assert!(
            (reciprocal / c[2] - 1.0).abs() < 1e-6,
            "Mz/η {reciprocal} vs C23 {}",
            c[2]
        );
        let err = [c[0] / k.c11 - 1.0, c[1] / k.c22 - 1.0, c[2] / k.c23 - 1.0];
        for (e, l) in err.iter().zip(&last) {
            assert!(
                e.abs() < l.abs(),
                "n = {n}: errors {err:?} (coarser grid {last:?})"
            );
        }
        if n == 40 {
            assert!(err.iter().all(|e| e.abs() < 0.016), "40 × 40: {err:?}");
        }
        last = err;
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
