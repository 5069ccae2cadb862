//! Load a wheel and a rail profile, place them on the track cross-section, and print where the
//! gauge points, rail tops and taping lines are — the numbers behind `kecsim profiles`.
//!
//! ```sh
//! cargo run --release --example place_profiles -- s1002 54e1 1:20
//! ```

use kecsim::profile::placement::{WheelRailPair, WheelsetGeometry};
use kecsim::profile::{Profile, ProfileKind, Side};
use kecsim::track::TrackGauge;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let wheel = Profile::resolve(args.first().map_or("s1002", |s| s.as_str()), ProfileKind::Wheel)?;
    let rail = Profile::resolve(args.get(1).map_or("60e1", |s| s.as_str()), ProfileKind::Rail)?;
    let inclination = args
        .get(2)
        .map_or("1:40", |s| s.as_str())
        .parse()
        .map_err(anyhow::Error::msg)?;
    let pair = WheelRailPair::new(
        wheel,
        rail,
        inclination,
        TrackGauge::default(),
        WheelsetGeometry::default(),
    )?;

    let rp = &pair.rail_placement;
    println!(
        "{} on {} at {}",
        pair.wheel.name, pair.rail.name, pair.inclination
    );
    for side in Side::BOTH {
        let (yg, zg) = rp.gauge_point(&pair.rail, side);
        let (yt, zt) = rp.top_point(&pair.rail, side);
        let r0 = pair.wheelset.nominal_radius_m;
        let (yw, zw) = pair.wheelset.wheel_point(&pair.wheel, side, 0.0, 0.0, r0, 0.0);
        println!(
            "{:>5}: gauge point ({:8.3}, {:7.3}) mm, rail top ({:8.3}, {:7.3}) mm, taping line ({:8.3}, {:7.3}) mm",
            side.name(),
            yg * 1e3,
            zg * 1e3,
            yt * 1e3,
            zt * 1e3,
            yw * 1e3,
            zw * 1e3
        );
    }
    // Profile functions with derivatives, as the contact equations use them (SI).
    let p = pair.wheel.eval(0.0);
    println!(
        "wheel at the taping line: z = {:.3e} m, dz/ds = {:.5}, curvature = {:.4} 1/m",
        p.z,
        p.dz,
        p.curvature()
    );
    Ok(())
}
