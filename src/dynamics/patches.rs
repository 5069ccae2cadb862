//! The contact patches of a run's samples beyond Hertz: where Hertz's gap deviation D
//! ([`crate::contact::nonhertz::validity`]) says Hertz does not hold at a wheel's contact, the
//! strip model ([`crate::contact::nonhertz::strips`]) recomputes its patch(es) from the real
//! profiles at the sample's contact (s_w, s_r), approached along the contact normal under the
//! sample's normal force: pmax, area, number of patches ([`Sample::pmax`] …). The run's p0, its
//! shakedown map and wear (Tγ/A) read them ([`Sample::contact_pressure`],
//! [`Sample::patch_area`]).
//!
//! **Post-processing, not the dynamics**: the creep forces of the run still come from the Hertz
//! ellipse at the contact point (Kalker's coefficients at its a/b). The strip model costs
//! ~0.1–0.2 ms a contact (`kecsim bench patch`); applied to the samples only where Hertz does not
//! hold, on the output worker. The cross level's rotation of the rail is neglected in the gap
//! (< 0.5 mrad; the contact point pair fixes the placement).

use crate::contact::forces::Material;
use crate::contact::nonhertz::gap::{GapInput, GapSection, GAP_WINDOW_M};
use crate::contact::nonhertz::strips::{self, StripError, StripSettings};
use crate::contact::nonhertz::{hertz_deviation, HERTZ_VALIDITY_LIMIT};
use crate::profile::placement::WheelRailPair;
use crate::track::Side;

use super::sample::Sample;

/// The window tried first, each side of the contact, m.
pub const NARROW_WINDOW_M: f64 = 0.008;

/// What one wheelset's post-processing carries from sample to sample: each wheel's last approach
/// (the strip model's starting guess) and whether its last patch needed the wide window (where the
/// next sample's gap is sampled over both windows at once — a saving, not a difference: the
/// narrow window is tried first either way, on the same gap to the last bit).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PatchWarm {
    pub approach: [Option<f64>; 2],
    pub wide: [bool; 2],
}

/// What the samples' patches are recomputed with: the scene's wheel–rail pair and material.
#[derive(Debug, Clone)]
pub struct PatchPostProcess {
    pub pair: WheelRailPair,
    pub material: Material,
    pub strips: StripSettings,
    /// Recompute the patches outside Hertz's validity (false: only measure D — `[contact_forces]
    /// patches = "hertz"`).
    pub recompute: bool,
}

impl PartialEq for PatchPostProcess {
    fn eq(&self, o: &Self) -> bool {
        self.pair.wheel.name == o.pair.wheel.name
            && self.pair.rail.name == o.pair.rail.name
            && self.pair.inclination == o.pair.inclination
            && self.pair.wheelset == o.pair.wheelset
            && self.material == o.material
            && self.strips == o.strips
            && self.recompute == o.recompute
    }
}

impl PatchPostProcess {
    pub fn new(pair: WheelRailPair, material: Material) -> Self {
        PatchPostProcess {
            pair,
            material,
            strips: StripSettings::default(),
            recompute: true,
        }
    }

    /// Sets the sample's [`Sample::hertz_deviation`], and its pressure, area and patches from the
    /// model valid at each wheel's contact. A strip solution that fails (the overlap wider than
    /// the sampled window) keeps Hertz's and is counted in the return value.
    ///
    /// `warm`: each wheel's approach at its previous sample (the strip model's starting guess),
    /// updated.
    pub fn apply(&self, s: &mut Sample, warm: &mut [Option<f64>; 2]) -> usize {
        let mut w = PatchWarm {
            approach: *warm,
            wide: [false; 2],
        };
        let failed = self.apply_warm(s, &mut w);
        *warm = w.approach;
        failed
    }

    /// [`PatchPostProcess::apply`] with the window each wheel needed last kept too (what a run's
    /// output worker does): the same patches, a third less of the gap sampled on a run where half
    /// the patches need the wide window (`kecsim bench patch-run`).
    pub fn apply_warm(&self, s: &mut Sample, pw: &mut PatchWarm) -> usize {
        let warm = &mut pw.approach;
        let mut failed = 0;
        let hertz = s.max_pressure();
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let [a, b] = s.semi_axes[i];
            if !(s.normal[i] > 0.0 && a > 0.0 && b > 0.0) {
                continue;
            }
            let (sw, sr) = (s.s_wheel[i], s.s_rail[i]);
            let d = hertz_deviation(&self.pair.wheel, &self.pair.rail, side, sw, sr, b);
            s.hertz_deviation[i] = d;
            s.pmax[i] = hertz[i];
            s.contact_area[i] = std::f64::consts::PI * a * b;
            // Hertz's ellipse in the dynamics is clamped to B/A ≤ 31.6 (deep flange contact;
            // `RelativeCurvature::wheel_rail`): its p0 is then 20–35 % high, so such a contact is
            // recomputed too (the strip model reproduces the unclamped Hertz on a quadratic gap).
            let clamped = {
                let w = self.pair.wheel.eval_side(side, sw);
                let r = self.pair.rail.eval_side(side, sr);
                let radius = self.pair.wheelset.nominal_radius_m - w.z;
                let angle = r.dz.atan() + self.pair.inclination.angle_rad;
                let a_curv = 0.5 * angle.cos().abs() / radius;
                let b_curv = 0.5 * (w.curvature() - r.curvature());
                b_curv > a_curv * crate::contact::forces::hertz::MAX_CURVATURE_RATIO
            };
            if (d <= HERTZ_VALIDITY_LIMIT && !clamped) || !self.recompute {
                continue;
            }
            let e_star = self.material.contact_modulus(&self.material);
            // A narrow window first (most patches are a few mm wide), the full one if the overlap
            // reaches its end — both from one sampling of the profiles (`GapSection::nested`: the
            // same sections as two separate ones, to the last bit).
            let input = GapInput {
                side,
                s_wheel: sw,
                s_rail: sr,
                nominal_radius: self.pair.wheelset.nominal_radius_m,
                rail_angle: side.sign() * self.pair.inclination.angle_rad,
                approach_angle: GapInput::along_normal(&self.pair.rail, side, sr),
                half_window: GAP_WINDOW_M,
            };
            let narrow_input = GapInput {
                half_window: NARROW_WINDOW_M,
                ..input
            };
            let (wheel, rail) = (&self.pair.wheel, &self.pair.rail);
            let mut solve = |sec: &GapSection| {
                strips::solve_from(sec, s.normal[i], e_star, &self.strips, warm[i]).map_err(|e| {
                    if !matches!(e, StripError::Window(_)) {
                        warm[i] = None;
                    }
                })
            };
            let mut wide_used = false;
            let r = match pw.wide[i].then(|| GapSection::nested(wheel, rail, &input, NARROW_WINDOW_M)) {
                // The last sample needed the wide window: both from one sampling.
                Some(Ok((narrow, wide))) => {
                    narrow.map_err(|_| ()).and_then(|sec| solve(&sec)).or_else(|_| {
                        wide_used = true;
                        solve(&wide)
                    })
                }
                Some(Err(_)) => GapSection::new(wheel, rail, &narrow_input)
                    .map_err(|_| ())
                    .and_then(|sec| solve(&sec)),
                None => GapSection::new(wheel, rail, &narrow_input)
                    .map_err(|_| ())
                    .and_then(|sec| solve(&sec))
                    .or_else(|_| {
                        wide_used = true;
                        GapSection::new(wheel, rail, &input)
                            .map_err(|_| ())
                            .and_then(|sec| solve(&sec))
                    }),
            };
            pw.wide[i] = wide_used;
            let mut solved = None;
            if let Ok((p, delta)) = r {
                if !p.is_empty() {
                    warm[i] = Some(delta);
                    solved = Some(p);
                }
            }
            match solved {
                Some(patches) => {
                    s.pmax[i] = patches.iter().map(|p| p.max_pressure).fold(0.0, f64::max);
                    s.contact_area[i] = patches.iter().map(|p| p.area).sum();
                    s.patches[i] = patches.len().min(255) as u8;
                }
                None => failed += 1,
            }
        }
        failed
    }
}
