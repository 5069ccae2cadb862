//! The track's lateral flexibility under each wheelset ([track.lateral_flexibility]): checked by
//! force balances that do not go through the wheelset's equations (the output's Y forces come
//! from the normal and creep forces at the contact points), and its bad values reported.

use crate::common;
use common::{kecsim, tmpdir};

use kecsim::dynamics::reference::G;
use kecsim::scenario::{RunOptions, Scenario};

/// A single wheelset on a straight with cant: its weight's lateral component and the tie's
/// spring are carried by the rails, which shift by d = −(Y_l + Y_r) / k_t in the steady state.
fn scene(flexibility: &str) -> String {
    format!(
        r#"
schema_version = 1
name = "canted straight"

[profiles]
wheel = "s1002"
rail = "60e1"
inclination = "1:40"

[contact_forces]
friction = 0.3

[track]
horizontal = [{{ type = "straight", from_m = 0.0, to_m = 300.0, cant_rad = 0.08 }}]
{flexibility}

[simulation]
speed_m_s = 10.0
duration_s = 8.0
record_rate_hz = 100.0

[simulation.contact]
model = "kec"

[simulation.integrator]
method = "ros34pw2"
rtol = 1e-7
atol = 1e-9

[vehicle]
kind = "wheelset-on-frame"
axle_load_n = 100000.0

[vehicle.wheelset]
mass_kg = 1813.0
inertia_kg_m2 = [1120.0, 112.0, 1120.0]

[vehicle.tie]
longitudinal_stiffness_n_per_m = 1.0e6
lateral_stiffness_n_per_m = 5.0e5
longitudinal_damping_n_s_per_m = 2.0e4
lateral_damping_n_s_per_m = 2.0e4
half_spacing_m = 1.0
"#
    )
}

const FLEXIBLE: &str =
    "[track.lateral_flexibility]\nstiffness_n_per_m = 40e6\ndamping_n_s_per_m = 1.0e5\nmass_kg = 150\n";

#[test]
fn the_track_carries_the_lateral_load_by_its_shift() {
    let k_t = 40e6;
    let mut shifts = Vec::new();
    for flex in ["", FLEXIBLE] {
        let text = scene(flex);
        let sc = Scenario::parse(&text, "s.toml")
            .unwrap()
            .compile("s.toml", std::path::Path::new("."))
            .unwrap();
        let out = sc.build_run(&RunOptions::default()).unwrap().run(&mut []);
        assert_eq!(out.summary.outcome, "completed", "{:?}", out.summary.error);
        let last = *out.samples().last().unwrap();
        let y_sum = last.y_force[0] + last.y_force[1];
        // The wheelset's balance: its weight's lateral component (cant φ raises the left rail:
        // gravity −g sin φ along Y), the tie's two springs at y and the wheels' Y forces.
        let balance = -1813.0 * G * 0.08_f64.sin() - 2.0 * 5.0e5 * last.y + y_sum;
        println!(
            "flexible {}: y {:.4} mm, ΣY {:.1} N, balance {:.2} N, track shift {:.5} mm (−ΣY/k_t {:.5} mm)",
            !flex.is_empty(),
            last.y * 1e3,
            y_sum,
            balance,
            last.track_shift * 1e3,
            -y_sum / k_t * 1e3
        );
        assert!(balance.abs() < 2e-3 * y_sum.abs(), "wheelset balance {balance} N");
        if flex.is_empty() {
            assert_eq!(last.track_shift, 0.0);
        } else {
            assert!(
                (last.track_shift + y_sum / k_t).abs() < 1e-3 * (y_sum / k_t).abs(),
                "track shift {} vs {}",
                last.track_shift,
                -y_sum / k_t
            );
        }
        shifts.push((last.y, last.track_shift));
    }
    // The contact depends on y − d: relative to its rails the wheelset stands about where it
    // stood on the rigid track (the tie, anchored to the frame, pulls it back by 2 k y: a few
    // per cent).
    let (rigid, flex) = (shifts[0], shifts[1]);
    assert!(
        ((flex.0 - flex.1) - rigid.0).abs() < 0.05 * rigid.0.abs(),
        "{rigid:?} vs {flex:?}"
    );
}

#[test]
fn bad_flexibility_values_are_reported_with_their_line() {
    let dir = tmpdir("flexibility");
    let text = scene(
        "[track.lateral_flexibility]\nstiffness_n_per_m = -5\ndamping_n_s_per_m = 1.0e5\nmass_kg = 0\n",
    );
    std::fs::write(dir.join("bad.toml"), &text).unwrap();
    let out = kecsim(&["run", "bad.toml", "--save", "bad.rrd"], &dir);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let line = 1 + text[..text.find("[track.lateral_flexibility]").unwrap()]
        .matches('\n')
        .count();
    for want in [
        "bad.toml".to_string(),
        "stiffness_n_per_m = -5".to_string(),
        "mass_kg = 0".to_string(),
        format!("bad.toml:{line}"),
    ] {
        assert!(err.contains(&want), "missing {want:?} in {err}");
    }
}
