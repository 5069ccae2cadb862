//! Dynamics (issue 7, in progress): the time integrators. Bodies, wheelsets, force elements and
//! scenes build on them.

pub mod integrator;
pub mod contact_model;
pub mod single_wheelset;
pub mod wheelset;
pub mod spec;
