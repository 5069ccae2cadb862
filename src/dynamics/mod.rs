//! Dynamics (paper §2.4–2.5, §5, §7): the contact model as the equations of motion see it, the
//! wheelset equations with their normal-force reactions, the single-wheelset and multibody
//! systems, the time integrators, and running a scene.

pub mod bench;
pub mod contact_model;
pub mod integrator;
pub mod multibody;
pub mod run;
pub mod single_wheelset;
pub mod spec;
pub mod wheelset;
