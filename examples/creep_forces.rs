//! From a wheelset's motion to the creep forces at its real contact points — the chain the dynamics
//! runs for every wheel at every evaluation: contact geometry → Hertz ellipse → creepages →
//! creep-force model.
//!
//! ```sh
//! cargo run --release --example creep_forces -- 3.0 2.0   # y = 3 mm, yaw = 2 mrad
//! ```

use kecsim::contact::forces::creepage::REGULARISATION_SPEED;
use kecsim::contact::forces::{
    ContactFrame, ContactPatch, CreepModel, Creepage, HertzContact, KalkerTable, Material, RelativeCurvature,
};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::profile::placement::WheelRailPair;
use kecsim::profile::{Side, StandardProfile};
use kecsim::track::RailOffsets;
use nalgebra::{Rotation3, Vector3};

fn main() -> anyhow::Result<()> {
    let args: Vec<f64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let y = args.first().copied().unwrap_or(3.0) * 1e-3;
    let yaw = args.get(1).copied().unwrap_or(2.0) * 1e-3;
    let (speed, normal_force, mu) = (20.0, 80e3, 0.3);

    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40")?;
    let r0 = pair.wheelset.nominal_radius_m;
    let geom = ContactGeometry::with_defaults(pair);
    let sol = geom.solve(y, &RailOffsets::default())?;

    // Wheelset kinematics in a ground frame (rails at rest): centre, axle, angular velocity.
    let centre = Vector3::new(0.0, y, sol.z);
    let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), sol.phi);
    let axle = rot * Vector3::y();
    let omega = axle * (speed / r0);
    let v_centre = Vector3::new(speed, 0.0, 0.0);

    let steel = Material::STEEL;
    let table = KalkerTable::new(steel.poisson);
    println!(
        "S1002 / 60E1 1:40, y = {:.1} mm, yaw = {:.1} mrad, V = {speed} m/s, N = {:.0} kN per wheel",
        y * 1e3,
        yaw * 1e3,
        normal_force * 1e-3
    );
    println!(
        "z − r0 = {:.4} mm, roll = {:.4} mrad\n",
        (sol.z - r0) * 1e3,
        sol.phi * 1e3
    );
    for side in Side::BOTH {
        let p = sol.point(side);
        let hertz = HertzContact::solve(RelativeCurvature::at_contact(p), normal_force, &steel, &steel)?;
        let patch = ContactPatch::from_hertz(&hertz, &steel, mu, &table)?;
        let point = Vector3::new(0.0, p.position.0, p.position.1);
        let normal = Vector3::new(0.0, p.normal.0, p.normal.1);
        let frame = ContactFrame::new(normal, axle, Vector3::x())?;
        let v_wheel = v_centre + omega.cross(&(point - centre));
        let creep = Creepage::from_velocities(
            &frame,
            v_wheel,
            Vector3::zeros(),
            omega,
            Vector3::zeros(),
            speed,
            REGULARISATION_SPEED,
        );
        println!(
            "{} wheel: contact angle {:.2}°, r = {:.2} mm; ellipse a = {:.2} mm, b = {:.2} mm, p0 = {:.0} MPa",
            side.name(),
            p.contact_angle.to_degrees(),
            p.rolling_radius * 1e3,
            hertz.a * 1e3,
            hertz.b * 1e3,
            hertz.max_pressure * 1e-6
        );
        println!(
            "  creepages ξx = {:+.3e}, ξy = {:+.3e}, φ = {:+.4} 1/m",
            creep.longitudinal, creep.lateral, creep.spin
        );
        for name in CreepModel::NAMES {
            let model = CreepModel::by_name(name).expect("known model");
            let f = model.forces(&patch, &creep, speed)?;
            let global = frame.force_to_global(f.fx, f.fy, 0.0);
            println!(
                "  {name:<8} Fx = {:+9.0} N  Fy = {:+9.0} N  Mz = {:+7.1} N·m  (|F|/μN = {:.3}; global X {:+.0} Y {:+.0} Z {:+.0} N)",
                f.fx, f.fy, f.mz, f.saturation, global.x, global.y, global.z
            );
        }
    }
    Ok(())
}
