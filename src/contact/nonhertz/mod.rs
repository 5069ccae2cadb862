//! Contact patches beyond Hertz: the gap between the real profiles around a contact
//! (`gap`), the non-Hertzian strip model that makes one or more patches of it (`strips`), and
//! the measure of how far Hertz holds at a contact (`validity`).
//!
//! Hertz (`crate::contact::forces::hertz`) takes the profiles' curvatures at the contact point and
//! assumes them constant over the patch. Where the curvature changes within the patch (an arc
//! joint of the rail, a flange root) or the profiles are nearly conformal (a worn wheel on the
//! R80 arc), the gap is not the quadratic Hertz assumes, and its ellipse — and the p0, area and
//! Kalker coefficients made of it — are not the patch's. The strip model works from the gap
//! itself and reduces to Hertz on a quadratic gap.

pub(crate) mod dynamics;
pub(crate) mod gap;
pub(crate) mod strips;
pub mod sweep;
pub(crate) mod validity;

pub use dynamics::{DynamicPatches, PatchesMode};
pub use gap::{GapError, GapInput, GapSection};
pub use strips::{StripError, StripPatch, StripSettings};
pub use validity::{hertz_deviation, HERTZ_VALIDITY_LIMIT};
