//! The contact models of the dynamics, one file each, and the one list of them.
//!
//! A scenario chooses a model and its settings in `[simulation.contact]`:
//!
//! ```toml
//! [simulation.contact]
//! model = "kec"                   # kec | lookup | lookup2 | lookup2-paper | online | elastic
//! two_point_approach_m = 5e-5     # that model's own keys (see each model's settings)
//! ```
//!
//! **Adding a model**: write one file here with its settings (a serde struct with
//! `deny_unknown_fields`, `Default`, and [`ContactModelSettings`]: `problems` and `build` from the
//! wheel–rail pair) and its [`ContactModel`] implementation (`configuration`; `kinematics` and
//! `history_dependent` if needed), then add one line to the list below. The scenario files, the
//! command line (`--contact`), the runs and `kecsim bench dynamics` take it from there.

pub mod elastic;
pub mod kec;
pub(crate) mod lookup;
pub(crate) mod lookup2;
pub(crate) mod online;

use std::fmt::Debug;
use std::sync::Arc;

use serde::Deserialize;
use thiserror::Error;

use super::cache::TableCache;
use super::kec::KecError;
use super::lookup::TableError;
use super::model::ContactModel;
use crate::profile::placement::WheelRailPair;

/// Building a contact model failed (the preprocessing: tables, equivalent profiles).
#[derive(Debug, Error)]
pub enum ContactBuildError {
    #[error("contact lookup table: {0}")]
    Table(#[from] TableError),
    #[error("KEC-equivalent profiles: {0}")]
    Kec(#[from] KecError),
    #[error("invalid contact-model settings:\n  - {}", .0.join("\n  - "))]
    Invalid(Vec<String>),
}

/// A model's settings table: validation and the constructor from the wheel–rail pair.
pub trait ContactModelSettings: Debug {
    /// Problems with the values (empty when valid), each naming its key under
    /// `simulation.contact`.
    fn problems(&self) -> Vec<String>;
    /// Builds the model for the placed wheel–rail pair (the preprocessing: tables, equivalent
    /// profiles), its tables from `cache` where given ([`TableCache`]).
    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError>;
}

/// Declares the list of models: the `[simulation.contact]` table (`model = NAME` and that model's
/// keys), the names, and the dispatch to each model's settings.
macro_rules! contact_models {
    ($($(#[$doc:meta])* $variant:ident = $name:literal => $settings:path),* $(,)?) => {
        /// `[simulation.contact]`: the contact model (`model = ...`) and its settings.
        #[derive(Debug, Clone, PartialEq, Deserialize)]
        #[serde(tag = "model", deny_unknown_fields)]
        pub enum ContactModelSpec {
            $($(#[$doc])* #[serde(rename = $name)] $variant($settings),)*
        }

        impl ContactModelSpec {
            /// The models' names, as scenario files and `--contact` spell them.
            pub const NAMES: &'static [&'static str] = &[$($name),*];

            /// This model's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(_) => $name,)*
                }
            }

            /// The model called `name` with its default settings.
            pub fn default_for(name: &str) -> Option<Self> {
                match name {
                    $($name => Some(Self::$variant(Default::default())),)*
                    _ => None,
                }
            }

            /// The model's settings.
            pub fn settings(&self) -> &dyn ContactModelSettings {
                match self {
                    $(Self::$variant(s) => s,)*
                }
            }
        }
    };
}

contact_models! {
    /// The KEC constraints (Eq. 49–51) on the knife-edge-equivalent profiles, analytic derivatives.
    Kec = "kec" => kec::KecSettings,
    /// The 1-entry contact lookup table over y (Eq. 44–46; gauge variation not in it).
    Lookup = "lookup" => lookup::LookupSettings,
    /// The contact lookup table under gauge variation: each wheel from the centred table at its
    /// own offset from its rail (default), or gauge columns every 0.1 mm.
    Lookup2 = "lookup2" => lookup2::Lookup2Settings,
    /// The paper's literal 2-entry table over (y, gauge variation): columns every 1 mm.
    Lookup2Paper = "lookup2-paper" => lookup2::Lookup2PaperSettings,
    /// The approximate contact constraints (Eq. 35–42) solved at every evaluation.
    Online = "online" => online::OnlineSettings,
    /// The wheelset free, Hertz normal forces wherever the real profiles interpenetrate.
    Elastic = "elastic" => elastic::ElasticSettings,
}

impl Default for ContactModelSpec {
    fn default() -> Self {
        ContactModelSpec::Kec(kec::KecSettings::default())
    }
}

impl ContactModelSpec {
    /// Problems with the settings (empty when valid).
    pub fn problems(&self) -> Vec<String> {
        self.settings().problems()
    }

    /// The two-point transition settings (elastic approach, largest width), m, of the models
    /// that have them (KEC and the tables); None for the others.
    pub fn two_point(&self) -> Option<(f64, f64)> {
        match self {
            Self::Kec(k) => Some((k.two_point_approach_m, k.two_point_max_width_m)),
            Self::Lookup(l) => Some((l.two_point_approach_m, l.two_point_max_width_m)),
            Self::Lookup2(l) => Some((l.two_point_approach_m, l.two_point_max_width_m)),
            Self::Lookup2Paper(l) => Some((l.two_point_approach_m, l.two_point_max_width_m)),
            Self::Online(_) | Self::Elastic(_) => None,
        }
    }

    /// This model with the two-point transitions `(approach, width)` — a scene's treatment of the
    /// contact jumps carried to another model (`--contact`): the same physics for every model.
    /// Err says why a model cannot honour them (the online constraints follow a jump rigidly, the
    /// elastic model has no jumps to treat).
    pub fn with_two_point(self, (approach, width): (f64, f64)) -> Result<Self, String> {
        match self {
            Self::Kec(mut k) => {
                (k.two_point_approach_m, k.two_point_max_width_m) = (approach, width);
                Ok(Self::Kec(k))
            }
            Self::Lookup(mut l) => {
                (l.two_point_approach_m, l.two_point_max_width_m) = (approach, width);
                Ok(Self::Lookup(l))
            }
            Self::Lookup2(mut l) => {
                (l.two_point_approach_m, l.two_point_max_width_m) = (approach, width);
                Ok(Self::Lookup2(l))
            }
            Self::Lookup2Paper(mut l) => {
                (l.two_point_approach_m, l.two_point_max_width_m) = (approach, width);
                Ok(Self::Lookup2Paper(l))
            }
            Self::Online(_) => Err(
                "the online constraints have no two-point transition: they follow a contact jump rigidly (the branch they are on kept until it closes)"
                    .into(),
            ),
            Self::Elastic(_) => Err(
                "the elastic model has no two-point transition: it finds every contact of the real profiles, a jump included".into(),
            ),
        }
    }

    /// Builds the model for the wheel–rail pair.
    pub fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let problems = self.problems();
        if !problems.is_empty() {
            return Err(ContactBuildError::Invalid(problems));
        }
        self.settings().build(pair, cache)
    }
}

/// The pair's 1-entry table on the ideal track ([`LookupTable1::build`] with the default
/// settings), from `cache` where given.
pub(crate) fn table1(
    geometry: &crate::contact::geometry::ContactGeometry,
    cache: Option<&TableCache>,
) -> Result<crate::contact::lookup::LookupTable1, TableError> {
    let settings = crate::contact::lookup::TableSettings::default();
    match cache {
        Some(c) => Ok(c.table1(geometry, &settings)?.0),
        None => crate::contact::lookup::LookupTable1::build(geometry, &settings),
    }
}

/// A value check for the settings' `problems`: `simulation.contact.NAME = v: expected ...`.
pub(crate) fn check_range(problems: &mut Vec<String>, name: &str, v: f64, lo: f64, hi: f64) {
    if !(v.is_finite() && v >= lo && v <= hi) {
        problems.push(format!(
            "simulation.contact.{name} = {v}: expected a value in [{lo}, {hi}]"
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_has_a_name_default_settings_and_a_table() {
        for &name in ContactModelSpec::NAMES {
            let spec = ContactModelSpec::default_for(name).unwrap();
            assert_eq!(spec.name(), name);
            assert!(spec.problems().is_empty(), "{name}: {:?}", spec.problems());
            let parsed: ContactModelSpec = toml::from_str(&format!("model = \"{name}\"")).unwrap();
            assert_eq!(parsed, spec);
        }
        assert!(ContactModelSpec::default_for("nonsense").is_none());
    }

    #[test]
    fn settings_tables_reject_unknown_keys_and_bad_values() {
        let s: ContactModelSpec = toml::from_str("model = \"kec\"\ntwo_point_approach_m = 0.0").unwrap();
        assert_eq!(
            s,
            ContactModelSpec::Kec(kec::KecSettings {
                two_point_approach_m: 0.0,
                ..kec::KecSettings::default()
            })
        );
        // The tables take the two-point keys too (default 0: rigid), not KEC's others.
        let l: ContactModelSpec = toml::from_str("model = \"lookup\"\ntwo_point_approach_m = 5e-4").unwrap();
        assert!(matches!(l, ContactModelSpec::Lookup(ref t) if t.two_point_approach_m == 5e-4));
        // Both tables take the cross-level entry (default: the rail pair's rigid motion).
        use crate::contact::lookup::CrossLevelEntry;
        assert!(
            matches!(l, ContactModelSpec::Lookup(ref t) if t.cross_level_entry == CrossLevelEntry::Rotated)
        );
        let p: ContactModelSpec =
            toml::from_str("model = \"lookup2\"\ncross_level_entry = \"paper\"").unwrap();
        assert!(
            matches!(p, ContactModelSpec::Lookup2(ref t) if t.cross_level_entry == CrossLevelEntry::Paper)
        );
        // lookup2: the per-wheel entry by default, gauge columns (0.1 mm) on request; the
        // paper's 1 mm columns under their own name.
        use lookup2::GaugeEntry;
        assert!(matches!(p, ContactModelSpec::Lookup2(ref t) if t.gauge_entry == GaugeEntry::PerWheel));
        let c: ContactModelSpec = toml::from_str("model = \"lookup2\"\ngauge_entry = \"columns\"").unwrap();
        assert!(
            matches!(c, ContactModelSpec::Lookup2(ref t) if t.gauge_entry == GaugeEntry::Columns && t.gauge_variations().len() == 201)
        );
        let paper: ContactModelSpec = toml::from_str("model = \"lookup2-paper\"").unwrap();
        assert!(matches!(paper, ContactModelSpec::Lookup2Paper(ref t) if t.gauge_variations().len() == 21));
        let e = toml::from_str::<ContactModelSpec>("model = \"lookup2\"\ngauge_entry = \"blend\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("per_wheel") && e.contains("columns"), "{e}");
        let e = toml::from_str::<ContactModelSpec>("model = \"lookup2-paper\"\ngauge_entry = \"columns\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("gauge_entry"), "{e}");
        let e = toml::from_str::<ContactModelSpec>("model = \"lookup\"\ncross_level_entry = \"tilted\"")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tilted") && e.contains("rotated") && e.contains("paper"),
            "{e}"
        );
        let e = toml::from_str::<ContactModelSpec>("model = \"kec\"\ncross_level_entry = \"paper\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("cross_level_entry"), "{e}");
        let e = toml::from_str::<ContactModelSpec>("model = \"lookup\"\ngv_step_m = 0.001")
            .unwrap_err()
            .to_string();
        assert!(e.contains("gv_step_m"), "{e}");
        let bad: ContactModelSpec =
            toml::from_str("model = \"lookup2\"\ntwo_point_approach_m = 0.5").unwrap();
        assert!(
            bad.problems()
                .iter()
                .any(|p| p.contains("simulation.contact.two_point_approach_m = 0.5")),
            "{:?}",
            bad.problems()
        );
        let e = toml::from_str::<ContactModelSpec>("model = \"magic\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("magic") && e.contains("kec"), "{e}");
        let bad: ContactModelSpec = toml::from_str("model = \"kec\"\ntwo_point_approach_m = -1.0").unwrap();
        assert!(bad.problems()[0].contains("simulation.contact.two_point_approach_m = -1"));
        let wide: ContactModelSpec = toml::from_str("model = \"kec\"\ntwo_point_max_width_m = 0.01").unwrap();
        assert!(
            wide.problems()
                .iter()
                .any(|p| p.contains("simulation.contact.two_point_max_width_m = 0.01")),
            "{:?}",
            wide.problems()
        );
    }
}
