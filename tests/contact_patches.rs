//! Contact patches against CONTACT (E. Vollebregt's rolling-contact code, the exact half-space
//! solution) on the Manchester contact benchmark: S1002 on UIC60 at 1:40, flange back
//! 1360 mm, r0 460 mm, 10 kN per wheel, y 0…10 mm with yaw 2.4 mrad per mm, μ 0.3, both wheels.
//! The reference (`tests/data/contact/mbench_a22.csv`, from CONTACT's `examples/*.ref_out`) and the
//! profiles are CONTACT's own files. Each case is run as `kecsim patch` runs it, at the benchmark's
//! rolling rate (CONTACT's VPITCH per case).
//!
//! `cargo test --release --test contact_patches -- --nocapture` prints the comparison table that
//! docs/validation.md quotes.

use kecsim::contact::forces::{ContactForceSettings, CreepModel, Material};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::nonhertz::sweep::{patches_at, PatchModel, PatchSweepSettings, ShiftPatches};
use kecsim::contact::nonhertz::StripSettings;
use kecsim::profile::placement::{Inclination, WheelRailPair, WheelsetGeometry};
use kecsim::profile::{Profile, ProfileKind};
use kecsim::track::TrackGauge;

/// One of CONTACT's patches.
#[derive(Debug, Clone)]
struct Reference {
    side: usize,
    method: String,
    y_mm: f64,
    vpitch: f64,
    delta: f64,
    ycp_w: f64,
    fn_n: f64,
    fx_n: f64,
    fs_n: f64,
    pmax: f64,
    area_mm2: f64,
}

fn reference() -> Vec<Reference> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/contact/mbench_a22.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |name: &str| f[col(name)].parse::<f64>().unwrap();
            Reference {
                side: if f[col("wheel")] == "left" { 0 } else { 1 },
                method: f[col("method")].to_string(),
                y_mm: num("y_mm"),
                vpitch: num("vpitch_rad_s"),
                delta: num("deltcp_rad"),
                ycp_w: num("ycp_w_mm"),
                fn_n: num("fn_n"),
                fx_n: num("fx_n"),
                fs_n: num("fs_n"),
                pmax: num("pmax_mpa"),
                area_mm2: num("ncon") * 0.04,
            }
        })
        .collect()
}

fn pair() -> WheelRailPair {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/profiles/");
    let wheel = Profile::resolve(&format!("{dir}MBench_S1002_v3.prw"), ProfileKind::Wheel).unwrap();
    let rail = Profile::resolve(&format!("{dir}MBench_UIC60_v3.prr"), ProfileKind::Rail).unwrap();
    WheelRailPair::new(
        wheel,
        rail,
        Inclination::UPRIGHT,
        TrackGauge::default(),
        WheelsetGeometry::default(),
    )
    .unwrap()
}

fn settings(pitch_rate: Option<f64>) -> PatchSweepSettings {
    PatchSweepSettings {
        yaw_per_m: 2.4,
        load: 10e3,
        speed: 2.0,
        forces: ContactForceSettings::new(CreepModel::by_name("fastsim").unwrap(), 0.3, Material::STEEL).unwrap(),
        strips: StripSettings::default(),
        window_m: 0.04,
        pitch_rate,
    }
}

/// Relative error.
fn rel(x: f64, reference: f64) -> f64 {
    x / reference - 1.0
}

/// The benchmark's 21 shifts on both wheels, both models: pmax, normal force, contact angle, the
/// load's centre on the wheel and the creep force, against CONTACT's full solution.
#[test]
fn manchester_benchmark_against_contact() {
    let pair = pair();
    let geometry = ContactGeometry::with_defaults(pair.clone());
    let refs: Vec<Reference> = reference().into_iter().filter(|r| r.method == "full").collect();
    assert_eq!(refs.len(), 2 * 21 + 3);
    let mut ys: Vec<f64> = refs.iter().map(|r| r.y_mm).collect();
    ys.sort_by(f64::total_cmp);
    ys.dedup();
    println!("| y mm | wheel | angle ° C/kp | N kN C/kp | pmax MPa CONTACT | kp | Hertz | D | area mm² C/kp | s_w mm C/kp | |Ft| N C/kp |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut worst = [(0.0f64, 0.0f64); 2]; // (kp tread, kp flange) |rel| for pmax, per class
    let mut worst_hertz: f64 = 0.0;
    let mut worst_hertz_valid: f64 = 0.0;
    for &y in &ys {
        let vpitch = refs.iter().find(|r| r.y_mm == y).unwrap().vpitch.abs();
        let run = |model| -> ShiftPatches {
            patches_at(&pair, &geometry, -y * 1e-3, model, &settings(Some(vpitch))).unwrap()
        };
        let (kp, hz) = (run(PatchModel::Strips), run(PatchModel::Hertz));
        for side in 0..2 {
            let r = refs.iter().find(|r| r.y_mm == y && r.side == side).unwrap();
            let k = &kp.wheels[side].patches;
            let h = &hz.wheels[side].patches[0];
            // CONTACT combines patches closer than 4 mm into one; here, the largest.
            assert!(!k.is_empty());
            let kmain = k.iter().max_by(|a, b| a.normal_force.total_cmp(&b.normal_force)).unwrap();
            let kp_pmax = k.iter().map(|p| p.max_pressure).fold(0.0, f64::max) * 1e-6;
            let flange = r.delta.abs() > 10f64.to_radians();
            let e = rel(kp_pmax, r.pmax).abs();
            let cls = usize::from(flange);
            worst[cls].0 = worst[cls].0.max(e);
            let eh = rel(h.max_pressure * 1e-6, r.pmax).abs();
            worst_hertz = worst_hertz.max(eh);
            // Where Hertz's gap deviation says it holds, Hertz must agree with CONTACT too (a clamp
            // of the curvature ratio once raised its flange pmax by 20–35 % here).
            let dev = hz.wheels[side].hertz_deviation;
            if dev <= kecsim::contact::nonhertz::HERTZ_VALIDITY_LIMIT {
                worst_hertz_valid = worst_hertz_valid.max(eh);
                assert!(eh < if flange { 0.20 } else { 0.15 }, "y = {y} side {side}: Hertz valid (D = {dev:.2}) but pmax {:.0} vs CONTACT {:.0}", h.max_pressure * 1e-6, r.pmax);
            }
            let ft_c = r.fx_n.hypot(r.fs_n);
            let ft_k = kmain.creep.fx.hypot(kmain.creep.fy);
            println!(
                "| {y:.1} | {} | {:.2}/{:.2} | {:.2}/{:.2} | {:.0} | {:.0} ({:+.1} %) | {:.0} ({:+.1} %) | {:.2} | {:.1}/{:.1} | {:.2}/{:.2} | {:.0}/{:.0} |",
                ["left", "right"][side],
                r.delta.abs().to_degrees(),
                kmain.contact_angle.abs().to_degrees(),
                r.fn_n * 1e-3,
                kmain.normal_force * 1e-3,
                r.pmax,
                kp_pmax,
                100.0 * rel(kp_pmax, r.pmax),
                h.max_pressure * 1e-6,
                100.0 * rel(h.max_pressure * 1e-6, r.pmax),
                hz.wheels[side].hertz_deviation,
                r.area_mm2,
                k.iter().map(|p| p.area).sum::<f64>() * 1e6,
                -r.ycp_w,
                kmain.s_wheel * 1e3,
                ft_c,
                ft_k
            );
            // The bounds on pmax: 15 % on the tread, 20 % in flange contact.
            let bound = if flange { 0.20 } else { 0.15 };
            assert!(e < bound, "y = {y} mm {}: kp pmax {kp_pmax:.0} MPa vs CONTACT {:.0} ({:+.1} %)", ["left", "right"][side], r.pmax, 100.0 * rel(kp_pmax, r.pmax));
            // Where the load sits: contact angle within 1.5°, the wheel's load centre within 1 mm.
            assert!(
                (kmain.contact_angle.abs() - r.delta.abs()).abs() < 1.5f64.to_radians(),
                "y = {y} mm side {side}: angle {:.2}° vs {:.2}°",
                kmain.contact_angle.abs().to_degrees(),
                r.delta.abs().to_degrees()
            );
            assert!(
                (kmain.s_wheel * 1e3 - (-r.ycp_w)).abs() < 1.0,
                "y = {y} mm side {side}: s_w {:.2} vs {:.2} mm",
                kmain.s_wheel * 1e3,
                -r.ycp_w
            );
            // The normal force (the vertical balance with the creep forces' share) within 15 %,
            // the creep force's magnitude within 15 % of μN.
            assert!(rel(kmain.normal_force, r.fn_n).abs() < 0.15, "y = {y} side {side}: N {} vs {}", kmain.normal_force, r.fn_n);
            assert!((ft_k - ft_c).abs() < 0.15 * 0.3 * r.fn_n, "y = {y} side {side}: |Ft| {ft_k:.0} vs {ft_c:.0} N");
        }
    }
    println!(
        "worst |pmax − CONTACT|/CONTACT: kp tread {:.1} %, kp flange {:.1} %, Hertz {:.1} % (where its deviation D ≤ {}: {:.1} %)",
        100.0 * worst[0].0,
        100.0 * worst[1].0,
        100.0 * worst_hertz,
        kecsim::contact::nonhertz::HERTZ_VALIDITY_LIMIT,
        100.0 * worst_hertz_valid
    );
    // Where Hertz is flagged invalid it misses CONTACT by more than the strip model does.
    assert!(worst_hertz > worst[0].0.max(worst[1].0), "Hertz's worst {worst_hertz}");
}
