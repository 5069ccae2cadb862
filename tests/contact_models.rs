//! The contact models of the dynamics on irregular track, through the one interface the dynamics
//! uses (`ContactModel::configuration`), against the online approximate constraints solved on the
//! displaced rails directly (independent of the tables and of the equivalent profiles): z, φ, the
//! real contact points and their contact angles (the normals), for each irregularity alone and
//! combined, at 81 lateral displacements each.
//!
//! Issue 13, defects 1–2: the tables returned the contact points of the undisplaced track and
//! normals not turned by the rails' roll, KEC normals ignored the cross level. Contact jumps make a
//! few points of every sweep differ by the jump itself (the models place a jump a little apart), so
//! the checks are on quantiles over the sweep; KEC is taken with the paper's rigid kinks.

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::models::kec::KecSettings;
use kecsim::contact::{ContactModel, ContactModelSpec, WarmStart};
use kecsim::profile::placement::WheelRailPair;
use kecsim::profile::StandardProfile;
use kecsim::track::RailOffsets;

/// Per model and case: quantiles (median, 90 %) of |Δz|, |Δφ|, |ΔY|, |ΔZ| (both contacts) and
/// |Δγ| (both sides) against the online solution.
#[derive(Debug, Clone, Copy)]
struct Errors {
    z: [f64; 2],
    phi: [f64; 2],
    y: [f64; 2],
    zc: [f64; 2],
    gamma: [f64; 2],
}

fn errors(model: &dyn ContactModel, online: &ContactGeometry, off: &RailOffsets) -> Errors {
    let mut e: Vec<[f64; 5]> = Vec::new();
    let (al, ..) = off.combinations();
    for k in 0..81 {
        let y = al - 5e-3 + 10e-3 * k as f64 / 80.0;
        let o = online.solve(y, off).unwrap();
        let c = match model.configuration(y, off, &mut WarmStart::default()) {
            Ok(c) => c,
            // Near flange contact on a narrowed gauge the models' range ends (their tables stop
            // at the ideal track's flange contact); inside ±4.5 mm none may fail.
            Err(err) => {
                assert!((y - al).abs() > 4.5e-3, "y = {:.2} mm: {err}", y * 1e3);
                continue;
            }
        };
        let mut r = [(c.z - o.z).abs(), (c.phi - o.phi).abs(), 0.0, 0.0, 0.0];
        for (q, p) in c.contacts.iter().zip([&o.left, &o.right]) {
            r[2] = r[2].max((q.position.0 - p.position.0).abs());
            r[3] = r[3].max((q.position.1 - p.position.1).abs());
            r[4] = r[4].max((q.contact_angle - p.contact_angle).abs());
            // The normal is the contact angle's: (−σ sin γ, cos γ).
            assert!((q.normal.1 - q.contact_angle.cos()).abs() < 1e-12);
        }
        e.push(r);
    }
    let q = |j: usize| {
        let mut v: Vec<f64> = e.iter().map(|r| r[j]).collect();
        v.sort_by(f64::total_cmp);
        [v[v.len() / 2], v[v.len() * 9 / 10]]
    };
    Errors {
        z: q(0),
        phi: q(1),
        y: q(2),
        zc: q(3),
        gamma: q(4),
    }
}

#[test]
#[ignore = "slow: the online reference on irregular track (~24 s)"]
fn contact_models_against_the_online_solution_on_irregular_track() {
    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
    let online = ContactGeometry::with_defaults(pair.clone());
    // KEC with the paper's rigid kinks: its two-point transitions (as wide as the elastic load
    // sharing, up to 2 mm at the jumps near the centre) depart from the rigid contact on purpose,
    // checked against the elastic model instead (tests/elastic.rs); the tables' default is rigid.
    let rigid_kec = ContactModelSpec::Kec(KecSettings {
        two_point_approach_m: 0.0,
        ..KecSettings::default()
    });
    let models: Vec<(&str, std::sync::Arc<dyn ContactModel>)> = ["kec", "lookup", "lookup2", "lookup2-paper"]
        .iter()
        .map(|&n| {
            let spec = match n {
                "kec" => rigid_kec.clone(),
                _ => ContactModelSpec::default_for(n).unwrap(),
            };
            (n, spec.build(&pair, None).unwrap())
        })
        .collect();
    // (al, vp, gv, cl), m.
    let cases = [
        ("alignment 2 mm", 2e-3, 0.0, 0.0, 0.0),
        ("vertical profile 1 mm", 0.0, 1e-3, 0.0, 0.0),
        ("cross level 2 mm", 0.0, 0.0, 0.0, 2e-3),
        ("cross level −4 mm", 0.0, 0.0, 0.0, -4e-3),
        ("gauge variation 3 mm", 0.0, 0.0, 3e-3, 0.0),
        ("all four", 1.5e-3, 0.5e-3, -2e-3, 3e-3),
    ];
    println!(
        "| case | model | Δz med / p90 [mm] | Δφ [mrad] | ΔY contact [mm] | ΔZ contact [mm] | Δγ [mrad] |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (label, al, vp, gv, cl) in cases {
        let off = RailOffsets::from_irregularities(al, vp, gv, cl);
        for (name, m) in &models {
            let e = errors(m.as_ref(), &online, &off);
            let f = |v: [f64; 2], s: f64| format!("{:.3} / {:.3}", v[0] * s, v[1] * s);
            println!(
                "| {label} | {name} | {} | {} | {} | {} | {} |",
                f(e.z, 1e3),
                f(e.phi, 1e3),
                f(e.y, 1e3),
                f(e.zc, 1e3),
                f(e.gamma, 1e3)
            );
            let exact = |what: &str, v: [f64; 2], tol: f64| {
                assert!(
                    v[1] < tol,
                    "{label}, {name}: {what} {v:?} (90 % quantile ≥ {tol})"
                )
            };
            match (label, *name) {
                // Alignment and vertical profile move the rails rigidly: every model carries the
                // contact with them (the tables had the undisplaced points: 2 mm / 1 mm off).
                ("alignment 2 mm" | "vertical profile 1 mm", _) => {
                    exact("ΔY", e.y, 2e-6);
                    exact("ΔZ", e.zc, 2e-6);
                    exact("Δγ", e.gamma, 1e-5);
                    exact("Δz", e.z, 1e-6);
                }
                // A cross level turns the rails by δ = cl/(2 L_r): KEC's normals turn with them
                // (they were δ = 1.3 / 2.7 mrad off) and its contact points stay on the online ones.
                ("cross level 2 mm" | "cross level −4 mm", "kec") => {
                    exact("Δγ", e.gamma, 0.5e-3);
                    exact("ΔY", e.y, 0.05e-3);
                    exact("ΔZ", e.zc, 0.02e-3);
                }
                // The tables entered by the rail pair's rigid motion (`cross_level_entry =
                // "rotated"`): the printed Eq. 44–46 kept the centred contact under cross level,
                // which moves the real contact by millimetres on S1002/60E1; entered in the
                // turned rails' frame the contact is the online one (measured at −4 mm: z 2 µm,
                // contact points 3 µm, normals 0.05 mrad).
                ("cross level 2 mm" | "cross level −4 mm", _) => {
                    exact("Δz", e.z, 0.01e-3);
                    exact("ΔY", e.y, 0.01e-3);
                    exact("ΔZ", e.zc, 0.005e-3);
                    exact("Δγ", e.gamma, 0.2e-3);
                }
                // The paper's 2-entry table on one of its columns (gv = ±2, 3 mm): exact there.
                ("all four", "lookup2-paper") => {
                    exact("Δz", e.z, 0.01e-3);
                    exact("ΔY", e.y, 0.02e-3);
                    exact("Δγ", e.gamma, 0.2e-3);
                }
                ("gauge variation 3 mm", "lookup2-paper") => {
                    exact("ΔY", e.y, 2e-6);
                    exact("Δγ", e.gamma, 1e-5);
                }
                // The per-wheel entry (lookup2's default) reads each wheel from the centred table
                // at its own offset from its rail, exact in z to first order in the roll it
                // corrects; the contact point is its row's, like KEC's.
                ("gauge variation 3 mm" | "all four", "lookup2") => {
                    exact("Δz", e.z, 0.01e-3);
                    exact("ΔY", e.y, 0.2e-3);
                    exact("Δγ", e.gamma, 0.5e-3);
                }
                ("gauge variation 3 mm" | "all four", "kec") => {
                    exact("ΔY", e.y, 0.2e-3);
                    exact("Δγ", e.gamma, 0.5e-3);
                }
                // The 1-entry table is blind to the gauge variation (Eq. 43–46 have no entry for
                // it): asserted below as its configuration being the one without it.
                ("gauge variation 3 mm" | "all four", "lookup") => {
                    blind_to_gauge_variation(m.as_ref(), &off, &online);
                }
                (label, name) => panic!("{label}, {name}: no expectation stated"),
            }
        }
    }
}

/// The 1-entry table under a gauge variation: the same configuration as with the gauge variation
/// removed, so its error against the online solution is the online solution's own response to
/// the gauge variation — millimetres of contact point and tens of mrad of contact angle near the
/// flanges on S1002/60E1, which is why the 2-entry table is the paper's fair baseline. Exactly the
/// same without cross level; with one, the gauge only enters through the span of the turned rail
/// pair (δ = cl / span): a roll change of |cl·gv| / span² (2.7 µrad for "all four").
fn blind_to_gauge_variation(model: &dyn ContactModel, off: &RailOffsets, online: &ContactGeometry) {
    let (al, vp, gv, cl) = off.combinations();
    let without = RailOffsets::from_irregularities(al, vp, 0.0, cl);
    // The span of the rail pair is ~1.5 m: the bound taken at 1.4 m.
    let dphi = (cl * gv).abs() / (1.4 * 1.4) + 1e-12;
    let mut online_moves = 0.0f64;
    for k in 0..81 {
        let y = al - 4.5e-3 + 9e-3 * k as f64 / 80.0;
        let (Ok(a), Ok(b)) = (
            model.configuration(y, off, &mut WarmStart::default()),
            model.configuration(y, &without, &mut WarmStart::default()),
        ) else {
            continue;
        };
        let (dz, dp) = ((a.z - b.z).abs(), (a.phi - b.phi).abs());
        assert!(
            dz <= 0.75 * dphi && dp <= dphi,
            "y {y}: Δz {dz}, Δφ {dp} ({off:?})"
        );
        // The contact points slide along the profiles with the roll's change (γ by up to 7 δ's
        // change on S1002's tread–flange curvatures): asserted exactly without cross level.
        if cl == 0.0 {
            for (p, q) in a.contacts.iter().zip(&b.contacts) {
                assert!((p.contact_angle - q.contact_angle).abs() < 1e-12, "y {y}");
                assert!((p.position.0 - q.position.0).abs() < 1e-12, "y {y}");
            }
        }
        let (o, o0) = (online.solve(y, off).unwrap(), online.solve(y, &without).unwrap());
        online_moves = online_moves.max((o.left.position.0 - o0.left.position.0).abs());
    }
    // And the gauge variation does move the real contact: the blindness costs something.
    assert!(
        online_moves > 1e-3,
        "online contact moved by {online_moves} m at most"
    );
}
