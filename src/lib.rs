//! # kecsim
//!
//! Railway vehicle dynamics with the **knife-edge-equivalent contact constraint method**
//! (KEC-method), inspected in Rerun. Modules follow the paper's order and use one another one
//! way, each only those below it (from the top; a test, `layering`, checks it and that no source
//! files use one another in a circle): the binary (`cli`) → [`bench`](mod@bench) → [`inspect`] →
//! [`paper`] → [`compare`], [`study`] → [`scenario`] → [`dynamics`] → [`contact`] → [`profile`] →
//! [`track`] → [`vehicle`], `spline`, `interpolation`, [`limits`].
//!
//! * [`contact`]: contact geometry (approximate constraints, Eq. 35–42) and what builds on it.
//! * [`profile`]: wheel and rail profiles as C² curves, standard profiles, files, placement (§3).
//! * [`track`]: the track centreline from sections and its irregularities (§2.2–2.3).
//! * [`vehicle`]: bodies, wheelsets and force elements of a vehicle (§2.4–2.5).
//! * [`dynamics`]: equations of motion, contact reactions, integrators, runs.
//! * [`scenario`]: scenario files (TOML) compiled into scenes.
//! * [`compare`]: the same scene with several contact models, their differences and costs.
//! * [`paper`]: the paper's §8 (Fig. 14–19, Tab. 7) for a scene, from the contact preprocessing,
//!   the track and a KEC-against-tables comparison.
//! * [`bench`](mod@bench): measured speed with its error, printed by `kecsim bench`.
//! * `spline`, `interpolation`: the C² profile spline and the Hermite interpolation helpers
//!   (values and slopes at nodes) beside it.
//! * [`inspect`]: Rerun recordings (the physics never depends on it).

/// The schema version of the scenario and track files this build reads (`schema_version`).
pub const SCHEMA_VERSION: u32 = 1;

pub mod api;
#[cfg(feature = "rerun")]
pub mod bench;
pub mod compare;
pub mod contact;
pub mod dynamics;
pub mod files;
#[cfg(feature = "rerun")]
pub mod inspect;
pub(crate) mod interpolation;
#[cfg(test)]
mod layering;
pub mod limits;
pub mod paper;
pub mod profile;
pub mod scenario;
pub(crate) mod spline;
pub mod study;
pub mod track;
pub mod vehicle;
