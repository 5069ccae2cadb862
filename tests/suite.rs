//! kecsim's scene tests, one binary (one link of the Rerun SDK), one module per topic; the
//! helpers that run the binary or a scene are in `common`. Unit tests live beside the code.
//!
//! `cargo test --release` runs the fast suite. The long studies (the online reference over many
//! seconds of a vehicle, the whole hard-case suite, critical speeds with the elastic model) are
//! `#[ignore = "slow: …"]` with their reason: `cargo test --release -- --include-ignored` runs
//! everything, as `.ci/run` does.

mod common;
mod contact_geometry;
mod contact_models;
mod contact_patches;
mod creep_forces;
mod dynamics;
mod elastic;
mod fuzz_parsers;
mod hard_cases;
mod integrators;
mod kec_accuracy;
mod lift;
mod lookup_entry;
mod paper;
mod readme;
mod recording;
mod reference_profiles;
mod reliability;
mod reliability_files;
mod reliability_four;
mod reliability_misc;
mod speed;
mod study;
mod track;
mod track_flexibility;
mod vehicle;
