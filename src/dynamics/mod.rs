//! Dynamics (issue 7, in progress): the time integrators. Bodies, wheelsets, force elements and
//! scenes build on them.

pub mod contact_model;
pub mod integrator;
pub mod run;
pub mod single_wheelset;
pub mod spec;
pub mod wheelset;
