use kecsim::contact::models::kec::KecSettings;
use kecsim::profile::placement::WheelRailPair;
use kecsim::profile::{Side, StandardProfile};
fn main() {
    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
    let c = KecSettings::default().kec_contact(&pair).unwrap();
    let p = c.model.profile(Side::Left);
    println!("domain {:?} nodes {}", p.domain(), p.node_y().len());
    for k in -20..=20 {
        let s = k as f64 * 1e-4;
        let (f, d, dd) = p.eval(s);
        println!("{:.2} {:.9e} {:.6e} {:.4e}", s * 1e3, f, d, dd);
    }
}
