//! Dynamics (paper §2.4–2.5, §5, §7): the vehicle systems behind one interface, the wheelset
//! equations with their normal-force reactions, the time integrators, and one run loop.
//!
//! * [`system`]: the [`VehicleModel`] interface (model apart from run state), samples, errors;
//! * [`single_wheelset`], [`multibody`]: the two vehicle systems;
//! * [`wheelset`]: Newton–Euler of one wheelset with its contact constraints (Eq. 53), its
//!   10×10 system solved by its structure in `reactions.rs`;
//! * `elastic`: a free wheelset on elastic contacts (the elastic contact model);
//! * `kinematics`: a wheelset's contact kinematics, constrained or free, and each kind's
//!   equations behind one interface (the vehicle systems use it, not the two above);
//! * [`reference`](mod@reference): the reference motion along the track and the frames it gives;
//! * [`traction`]: what drives the vehicle along the track (the speed loop on the motored wheels,
//!   coasting, a given force, a tie to the track frame); `resistance`: the run's traction
//!   summary and each curve's curving resistance;
//! * [`integrator`]: DOPRI5, ROS3, ROS34PW2, BDF with dense output and diagnosed failures;
//! * [`sample`]: a wheelset's output sample and the one table of what a run records of it (the
//!   CSV's columns, the recording's series and layout are made from it);
//! * [`run`](mod@run): the run loop, its threads, stop conditions; [`output`]: summary,
//!   observers, CSV; `safety`: running safety (EN 14363) from the samples; `cancel`: the stop
//!   request a run honours (Ctrl-C in the binary);
//! * what an engineer reads off a run besides safety: `wear` (the USFD wear function over the
//!   wear number, where on the profiles), `contact_stress` (p0 on Johnson's shakedown map),
//!   [`ride`] (EN 12299's comfort and Sperling's Wz at the carbodies' floor points, from the
//!   weightings and spectra of `comfort`).
//!
//! The contact models are [`crate::contact::ContactModel`]s; the dynamics never knows which one.

pub(crate) mod cancel;
pub(crate) mod comfort;
pub(crate) mod contact_stress;
pub(crate) mod elastic;
pub mod integrator;
pub(crate) mod kinematics;
pub mod linear;
pub mod multibody;
pub mod output;
pub(crate) mod patches;
mod reactions;
pub mod reference;
pub(crate) mod resistance;
pub mod ride;
pub mod run;
pub(crate) mod safety;
pub mod sample;
pub mod single_wheelset;
pub mod system;
pub mod traction;
pub(crate) mod wear;
pub mod wheelset;

pub use cancel::CancelToken;
pub use output::{RunObserver, RunSummary};
pub use reference::{Reference, SpeedProfile};
pub use run::{
    run, RunEnd, RunLabels, RunOutput, RunPool, RunSettings, Stop, StopConditions, Threads, OUTPUT_QUEUE,
};
pub use sample::Sample;
pub use system::{DynamicsError, FloorPoint, InitialDisturbance, Settling, VehicleModel, VehicleSample};
