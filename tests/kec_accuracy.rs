//! The KEC-method against the online approximate constraints (an independent solution of the real
//! profiles' contact) under gauge variation and cross level — the paper only claims "good
//! agreement"; this measures it and guards it. Run with `-- --nocapture` for the table.

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::kec::KecModel;
use kecsim::contact::lookup::{LookupTable1, LookupTable2, TableSettings};
use kecsim::contact::report::{kec_error_markdown, kec_irregularity_errors, MeasuredTables};
use kecsim::profile::placement::WheelRailPair;
use kecsim::profile::StandardProfile;

#[test]
fn kec_agrees_with_the_online_constraints_under_irregularities() {
    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
    let l_w = pair.wheelset.l_w();
    let geom = ContactGeometry::with_defaults(pair);
    let settings = TableSettings::default();
    let table = LookupTable1::build(&geom, &settings).unwrap();
    let model = KecModel::from_table(&table, l_w).unwrap();
    let gvs: Vec<f64> = (-5..=5).map(|k| k as f64 * 1e-3).collect();
    let table2 = LookupTable2::build(&geom, &gvs, &settings).unwrap();
    let cases = [
        (-4.5e-3, 0.0),
        (4.5e-3, 0.0),
        (0.0, -5e-3),
        (0.0, 5e-3),
        (3.5e-3, 4e-3),
    ];
    let tables = MeasuredTables {
        table1: &table,
        table2: &table2,
        table2_fine: None,
    };
    let rows = kec_irregularity_errors(&geom, &model, &tables, &cases, 31).unwrap();
    println!("{}", kec_error_markdown(&rows, None));
    for r in &rows {
        assert_eq!(r.points, 31);
        assert!(
            r.kec.z < 1e-5,
            "gv {} cl {}: KEC z error {} m",
            r.gv,
            r.cl,
            r.kec.z
        );
        assert!(
            r.kec.phi < 3e-5,
            "gv {} cl {}: KEC roll error {} rad",
            r.gv,
            r.cl,
            r.kec.phi
        );
        // A 1-entry table cannot see the gauge variation: KEC must do better than it wherever
        // there is one.
        if r.gv != 0.0 {
            assert!(
                r.kec.z < r.table1.z,
                "gv {}: KEC {} vs 1-entry {}",
                r.gv,
                r.kec.z,
                r.table1.z
            );
        }
    }
}
