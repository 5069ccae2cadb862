//! Online solution of the approximate contact constraints (paper §4.2, Eq. 35–42).
//!
//! Both contact points are assumed to lie in the wheelset's track cross-section and on the wheels'
//! lowest generator line (this neglects the effect of yaw on the contact location). Per side
//! σ = ±1 (left/right), in the wheelset-track frame (Y, Z), with the wheel radius
//! h^w(s^w) = r0 − z_w(s^w) and the rail head h^r(s^r) of the placed profiles:
//!
//! ```text
//! wheel point   W = [ y + (σL_w + s^w) + φ h^w,   z + φ(σL_w + s^w) − h^w ]          (Eq. 37)
//! rail point    R = [σL_r + y_ir, z_r + z_ir] + A(α) [s^r, h^r],  α = σβ + δ          (Eq. 38)
//! wheel tangent t = [1 + φ h^w',  φ − h^w']                                          (Eq. 39)
//! rail normal   n = A(α) [−h^r', 1]                                                 (Eq. 40)
//! constraints   W − R = 0 (2 eqs, Eq. 35),   t · n = 0 (1 eq, Eq. 36)
//! ```
//!
//! Six equations F(x; y) = 0 in x = [z, φ, s^lw, s^lr, s^rw, s^rr] for a given lateral
//! displacement y and rail offsets (irregularities); the yaw drops out (Eq. 41–42). They are solved
//! by Newton's method with the analytic Jacobian J = ∂F/∂x. Sensitivities follow from the implicit
//! function theorem: dx/dy = −J⁻¹ ∂F/∂y.
//!
//! **The right solution.** Newton converges to *a* solution; the contact is the one where the
//! profiles touch without interpenetrating anywhere else. [`ContactGeometry::solve`] therefore
//! seeds Newton from a global search: for a roll φ, the minimum vertical gap G_σ(φ) between wheel
//! and rail on each side (wheel sampled every [`ContactSettings::sample_step_m`], rail as an upper
//! envelope on a fine lateral grid) is what the wheelset would sink before touching; both sides
//! touch when G_L(φ) = G_R(φ), a monotone equation in φ solved by bisection, with z = −G_L. At the
//! converged solution the gap is checked again everywhere: an interpenetration beyond
//! [`ContactSettings::penetration_tolerance_m`] is reported as an error, never returned.
//!
//! **Two-point contact and jumps.** Every other local minimum of the gap on a side within
//! [`ContactSettings::two_point_tolerance_m`] is returned as a secondary point with its gap: where a
//! secondary point reaches zero gap, the contact jumps to it (tread → flange root → flange).

use nalgebra::{Matrix6, Vector6};

use super::point::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::track::RailOffsets;

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// Lateral sampling of the wheel in the global gap search, m.
    pub sample_step_m: f64,
    /// Newton stops when the largest correction is below this, m or rad.
    pub newton_tolerance: f64,
    /// Newton iteration limit.
    pub max_iterations: usize,
    /// Largest Newton step on a surface parameter, m (damps steps across profile features).
    pub max_step_m: f64,
    /// Secondary points with a gap below this are reported (two-point contact), m.
    pub two_point_tolerance_m: f64,
    /// Interpenetration accepted at the solution by the sampled check, m. The rail envelope is
    /// linear between samples 0.02 mm apart, which can only overstate a gap (by ≲ 1e-8 m on the
    /// R13 gauge corner), so this can be tight: in near-conformal contact a Newton solution that
    /// penetrates by 1 µm elsewhere is already 5 µm off in z.
    pub penetration_tolerance_m: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            sample_step_m: 5e-5,
            newton_tolerance: 1e-13,
            max_iterations: 40,
            max_step_m: 2e-3,
            two_point_tolerance_m: 1e-4,
            penetration_tolerance_m: 5e-8,
        }
    }
}

/// Contact-geometry errors.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    #[error("y = {y_mm:.4} mm: Newton did not converge in {iterations} iterations (last correction {last_step:.3e})")]
    NoConvergence {
        y_mm: f64,
        iterations: usize,
        last_step: f64,
    },
    #[error("y = {y_mm:.4} mm: the {side} wheel and rail never touch (no lateral overlap: gauge too wide or y too large)")]
    NoOverlap { y_mm: f64, side: &'static str },
    #[error("y = {y_mm:.4} mm: the {side} contact runs off the {what} profile (s = {s_mm:.3} mm, profile spans {lo_mm:.3}..{hi_mm:.3} mm)")]
    OffProfile {
        y_mm: f64,
        side: &'static str,
        what: &'static str,
        s_mm: f64,
        lo_mm: f64,
        hi_mm: f64,
    },
    #[error("y = {y_mm:.4} mm: Newton found a contact where the {side} profiles interpenetrate by {depth_mm:.4} mm elsewhere (a local solution)")]
    Interpenetration {
        y_mm: f64,
        side: &'static str,
        depth_mm: f64,
    },
    #[error("y = {y_mm:.4} mm: no roll angle in ±{limit_rad} rad lets both wheels touch")]
    NoRollBracket { y_mm: f64, limit_rad: f64 },
}

/// A secondary point of a side within the two-point tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondaryPoint {
    pub s_wheel: f64,
    pub s_rail: f64,
    /// Vertical gap at the point, m (≥ 0 up to the sampling accuracy).
    pub gap: f64,
}

/// The contact configuration of a wheelset at one lateral displacement.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSolution {
    /// Lateral displacement y, m.
    pub y: f64,
    /// Rail offsets used.
    pub offsets: RailOffsets,
    /// Height of the wheelset centre above the top-of-rail plane, m.
    pub z: f64,
    /// Roll angle φ, rad.
    pub phi: f64,
    pub left: ContactPoint,
    pub right: ContactPoint,
    /// Other local minima of the gap within the two-point tolerance, left and right (empty
    /// without the global check).
    pub secondary: [Vec<SecondaryPoint>; 2],
    /// dx/dy for x = [z, φ, s^lw, s^lr, s^rw, s^rr].
    pub dx_dy: [f64; 6],
    /// dx/dgv: sensitivity to a gauge variation (rails moved apart by gv/2 each).
    pub dx_dgv: [f64; 6],
    /// Newton iterations used.
    pub iterations: usize,
}

impl ContactSolution {
    /// The unknown vector x = [z, φ, s^lw, s^lr, s^rw, s^rr].
    pub fn x(&self) -> [f64; 6] {
        [
            self.z,
            self.phi,
            self.left.s_wheel,
            self.left.s_rail,
            self.right.s_wheel,
            self.right.s_rail,
        ]
    }

    /// A side's contact point.
    pub fn point(&self, side: Side) -> &ContactPoint {
        match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        }
    }

    /// Rolling radius difference Δr = r_left − r_right, m.
    pub fn delta_r(&self) -> f64 {
        self.left.rolling_radius - self.right.rolling_radius
    }
}

/// Rail upper envelope on a uniform lateral grid, for the global gap search.
struct Envelope {
    y0: f64,
    inv_dy: f64,
    z: Vec<f64>,
    s: Vec<f64>,
}

impl Envelope {
    /// (Z, s^r) of the rail at lateral position `y`, `None` off the rail.
    #[inline]
    fn at(&self, y: f64) -> Option<(f64, f64)> {
        let u = (y - self.y0) * self.inv_dy;
        if u < 0.0 {
            return None;
        }
        let k = u as usize;
        if k + 1 >= self.z.len() {
            return None;
        }
        let (za, zb) = (self.z[k], self.z[k + 1]);
        if za == f64::NEG_INFINITY || zb == f64::NEG_INFINITY {
            return None;
        }
        let t = u - k as f64;
        Some((za + t * (zb - za), self.s[k] + t * (self.s[k + 1] - self.s[k])))
    }
}

/// The gap scan of one side: sampled vertical gap along the wheel.
struct GapScan {
    /// (s^w, s^r below it, gap) per wheel sample over the rail.
    samples: Vec<(f64, f64, f64)>,
    /// Index of the smallest gap.
    min: usize,
}

/// The approximate contact constraints of a placed wheel/rail pair.
#[derive(Debug, Clone)]
pub struct ContactGeometry {
    pub pair: WheelRailPair,
    pub settings: ContactSettings,
    /// Wheel samples per side: (s^w, h^w), paper convention.
    wheel_samples: [Vec<(f64, f64)>; 2],
    /// Rail samples (s, h^r) in the left orientation.
    rail_samples: Vec<(f64, f64)>,
}

fn idx(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// Lateral grid of the rail envelope, m.
const ENVELOPE_STEP_M: f64 = 2e-5;
/// Roll search range, rad.
const ROLL_LIMIT_RAD: f64 = 0.1;
/// The largest lateral shift of a wheel's points by the roll of the search's bracket, φ r0, m:
/// the linearised roll moves a wheel's points sideways by φ times their radius, and at 0.1 rad a
/// wheel of r0 ≥ 0.85 m left its rail altogether at the bracket's ends ("never touch" for the
/// documented r0 = 1 m). The roll bracket is min(0.1, 0.05 / r0): unchanged up to r0 = 0.5 m,
/// and still twice any real roll (flange height over the gauge, ~0.02 rad) at 1 m.
const ROLL_SHIFT_LIMIT_M: f64 = 0.05;

impl ContactGeometry {
    /// Prepares the constraints of `pair`.
    pub fn new(pair: WheelRailPair, settings: ContactSettings) -> Self {
        let step = settings.sample_step_m;
        let mut wheel_samples = [Vec::new(), Vec::new()];
        for side in Side::BOTH {
            let (a, b) = pair.wheel.domain_side(side);
            let n = ((b - a) / step).ceil() as usize;
            wheel_samples[idx(side)] = (0..=n)
                .map(|k| {
                    let s = a + (b - a) * k as f64 / n as f64;
                    (
                        s,
                        pair.wheelset.nominal_radius_m - pair.wheel.eval_side(side, s).z,
                    )
                })
                .collect();
        }
        let (a, b) = pair.rail.domain();
        let n = ((b - a) / (0.5 * step)).ceil() as usize;
        let rail_samples = (0..=n)
            .map(|k| {
                let s = a + (b - a) * k as f64 / n as f64;
                (s, pair.rail.eval(s).z)
            })
            .collect();
        ContactGeometry {
            pair,
            settings,
            wheel_samples,
            rail_samples,
        }
    }

    /// With default settings.
    pub fn with_defaults(pair: WheelRailPair) -> Self {
        Self::new(pair, ContactSettings::default())
    }

    pub(crate) fn l_w(&self) -> f64 {
        self.pair.wheelset.l_w()
    }

    /// Rotation angle α = σβ + δ of a side's rail profile frame.
    pub(crate) fn alpha(&self, side: Side, off: &RailOffsets) -> f64 {
        side.sign() * self.pair.rail_placement.inclination_rad + off.delta(self.pair.rail_placement.lateral_m)
    }

    /// Origin of a side's rail profile frame in the wheelset-track frame.
    pub(crate) fn rail_origin(&self, side: Side, off: &RailOffsets) -> (f64, f64) {
        let rp = &self.pair.rail_placement;
        let (dy, dz) = off.side(side);
        (side.sign() * rp.lateral_m + dy, rp.vertical_m + dz)
    }

    /// Wheel radius h^w and its first two derivatives at s^w (paper convention).
    #[inline]
    pub(crate) fn wheel(&self, side: Side, s: f64) -> (f64, f64, f64) {
        self.pair.wheelset.wheel_radius(&self.pair.wheel, side, s)
    }

    /// Rail head h^r and derivatives at s^r (paper convention).
    #[inline]
    pub(crate) fn rail(&self, side: Side, s: f64) -> (f64, f64, f64) {
        let p = self.pair.rail.eval_side(side, s);
        (p.z, p.dz, p.d2z)
    }

    /// Residual F (Eq. 35–36 for both sides) and Jacobian ∂F/∂x.
    pub fn residual(&self, y: f64, off: &RailOffsets, x: &[f64; 6]) -> (Vector6<f64>, Matrix6<f64>) {
        let (z, phi) = (x[0], x[1]);
        let mut f = Vector6::zeros();
        let mut j = Matrix6::zeros();
        for side in Side::BOTH {
            let (r0, c0) = (3 * idx(side), 2 + 2 * idx(side));
            let (sw, sr) = (x[c0], x[c0 + 1]);
            let sig = side.sign();
            let (hw, hw1, hw2) = self.wheel(side, sw);
            let (hr, hr1, hr2) = self.rail(side, sr);
            let (sa, ca) = self.alpha(side, off).sin_cos();
            let (oy, oz) = self.rail_origin(side, off);
            let lat = sig * self.l_w() + sw;
            // Eq. 35: wheel point − rail point.
            f[r0] = y + lat + phi * hw - (oy + ca * sr - sa * hr);
            f[r0 + 1] = z + phi * lat - hw - (oz + sa * sr + ca * hr);
            // Eq. 36: wheel tangent · rail normal.
            let (ty, tz) = (1.0 + phi * hw1, phi - hw1);
            let (ny, nz) = (-ca * hr1 - sa, -sa * hr1 + ca);
            f[r0 + 2] = ty * ny + tz * nz;
            // Jacobian.
            j[(r0, 1)] = hw;
            j[(r0, c0)] = 1.0 + phi * hw1;
            j[(r0, c0 + 1)] = -(ca - sa * hr1);
            j[(r0 + 1, 0)] = 1.0;
            j[(r0 + 1, 1)] = lat;
            j[(r0 + 1, c0)] = phi - hw1;
            j[(r0 + 1, c0 + 1)] = -(sa + ca * hr1);
            j[(r0 + 2, 1)] = hw1 * ny + nz;
            j[(r0 + 2, c0)] = phi * hw2 * ny - hw2 * nz;
            j[(r0 + 2, c0 + 1)] = -ty * ca * hr2 - tz * sa * hr2;
        }
        (f, j)
    }

    /// Newton's method from `x0`.
    pub fn newton(
        &self,
        y: f64,
        off: &RailOffsets,
        x0: [f64; 6],
    ) -> Result<([f64; 6], Matrix6<f64>, usize), ContactError> {
        let mut x = x0;
        let mut last = f64::INFINITY;
        for it in 1..=self.settings.max_iterations {
            let (f, j) = self.residual(y, off, &x);
            let dx = j.lu().solve(&(-f)).ok_or(ContactError::NoConvergence {
                y_mm: y * 1e3,
                iterations: it,
                last_step: last,
            })?;
            // Damp steps on the surface parameters so that Newton cannot leap across a profile feature.
            let biggest = (2..6).map(|k| dx[k].abs()).fold(0.0, f64::max);
            let scale = if biggest > self.settings.max_step_m {
                self.settings.max_step_m / biggest
            } else {
                1.0
            };
            for k in 0..6 {
                x[k] += scale * dx[k];
            }
            last = dx.amax();
            if !last.is_finite() {
                break;
            }
            if last < self.settings.newton_tolerance || (scale == 1.0 && last < 1e-11 && f.amax() < 1e-14) {
                let (_, j) = self.residual(y, off, &x);
                return Ok((x, j, it));
            }
        }
        Err(ContactError::NoConvergence {
            y_mm: y * 1e3,
            iterations: self.settings.max_iterations,
            last_step: last,
        })
    }

    fn envelope(&self, side: Side, off: &RailOffsets) -> Envelope {
        let (sa, ca) = self.alpha(side, off).sin_cos();
        let (oy, oz) = self.rail_origin(side, off);
        let pts: Vec<(f64, f64, f64)> = self
            .rail_samples
            .iter()
            .map(|&(s_left, h)| {
                let s = side.sign() * s_left; // paper convention on this side
                (oy + ca * s - sa * h, oz + sa * s + ca * h, s)
            })
            .collect();
        let (ymin, ymax) = pts
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        let n = ((ymax - ymin) / ENVELOPE_STEP_M).ceil() as usize + 1;
        let mut z = vec![f64::NEG_INFINITY; n + 1];
        let mut s = vec![0.0; n + 1];
        for w in pts.windows(2) {
            let (a, b) = if w[0].0 <= w[1].0 {
                (w[0], w[1])
            } else {
                (w[1], w[0])
            };
            let k0 = ((a.0 - ymin) / ENVELOPE_STEP_M).ceil() as usize;
            let k1 = (((b.0 - ymin) / ENVELOPE_STEP_M).floor() as usize).min(n);
            for k in k0..=k1 {
                let yk = ymin + k as f64 * ENVELOPE_STEP_M;
                let t = if b.0 > a.0 { (yk - a.0) / (b.0 - a.0) } else { 0.0 };
                let zk = a.1 + t * (b.1 - a.1);
                if zk > z[k] {
                    z[k] = zk;
                    s[k] = a.2 + t * (b.2 - a.2);
                }
            }
        }
        Envelope {
            y0: ymin,
            inv_dy: 1.0 / ENVELOPE_STEP_M,
            z,
            s,
        }
    }

    fn scan(&self, side: Side, env: &Envelope, y: f64, z: f64, phi: f64) -> Option<GapScan> {
        let sig = side.sign();
        let l_w = self.l_w();
        let mut samples: Vec<(f64, f64, f64)> = Vec::with_capacity(self.wheel_samples[idx(side)].len());
        let mut min = 0;
        for &(sw, hw) in &self.wheel_samples[idx(side)] {
            let lat = sig * l_w + sw;
            let (wy, wz) = (y + lat + phi * hw, z + phi * lat - hw);
            if let Some((rz, sr)) = env.at(wy) {
                let gap = wz - rz;
                if samples.is_empty() || gap < samples[min].2 {
                    min = samples.len();
                }
                samples.push((sw, sr, gap));
            }
        }
        (!samples.is_empty()).then_some(GapScan { samples, min })
    }

    fn no_overlap(y: f64, side: Side) -> ContactError {
        ContactError::NoOverlap {
            y_mm: y * 1e3,
            side: side.name(),
        }
    }

    /// Exact vertical gap at wheel parameter `sw` (wheelset at height 0, roll `phi`): the rail
    /// height under the wheel point, found by Newton on R_Y(s^r) = W_Y from `sr_guess`.
    fn exact_gap(
        &self,
        side: Side,
        off: &RailOffsets,
        y: f64,
        phi: f64,
        sw: f64,
        sr_guess: f64,
    ) -> (f64, f64) {
        let (hw, _, _) = self.wheel(side, sw);
        let lat = side.sign() * self.l_w() + sw;
        let (wy, wz) = (y + lat + phi * hw, phi * lat - hw);
        let (sa, ca) = self.alpha(side, off).sin_cos();
        let (oy, oz) = self.rail_origin(side, off);
        let mut sr = sr_guess;
        for _ in 0..12 {
            let (hr, hr1, _) = self.rail(side, sr);
            let f = oy + ca * sr - sa * hr - wy;
            let d = ca - sa * hr1;
            if d.abs() < 1e-6 {
                break;
            }
            let step = f / d;
            sr -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let (hr, _, _) = self.rail(side, sr);
        (wz - (oz + sa * sr + ca * hr), sr)
    }

    /// Smallest gap of a side at roll `phi` (wheelset at height 0): `(gap, s^w, s^r)`, from the
    /// sampled scan, and with `refine` polished by golden-section search on the exact gap.
    fn min_gap(
        &self,
        side: Side,
        env: &Envelope,
        off: &RailOffsets,
        y: f64,
        phi: f64,
        refine: bool,
    ) -> Result<(f64, f64, f64), ContactError> {
        let scan = self
            .scan(side, env, y, 0.0, phi)
            .ok_or_else(|| Self::no_overlap(y, side))?;
        let (sw, sr, gap) = scan.samples[scan.min];
        if !refine {
            return Ok((gap, sw, sr));
        }
        let k = scan.min;
        let (mut lo, mut hi) = (
            scan.samples[k.saturating_sub(1)].0,
            scan.samples[(k + 1).min(scan.samples.len() - 1)].0,
        );
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let f = |s: f64| self.exact_gap(side, off, y, phi, s, sr);
        while hi - lo > 1e-11 {
            let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if f(c).0 < f(d).0 {
                hi = d
            } else {
                lo = c
            }
        }
        let s = 0.5 * (lo + hi);
        let (gap_exact, sr_exact) = f(s);
        Ok((gap_exact.min(gap), s, sr_exact))
    }

    /// Global search: the roll at which both sides touch (bisection on G_L(φ) = G_R(φ) to
    /// `phi_tolerance`), with z and the surface parameters at the minimum gaps. Unrefined, it is the
    /// seed of Newton; refined, the minimum-gap solution itself.
    fn search(
        &self,
        y: f64,
        off: &RailOffsets,
        refine: bool,
        phi_tolerance: f64,
    ) -> Result<[f64; 6], ContactError> {
        let envs = [self.envelope(Side::Left, off), self.envelope(Side::Right, off)];
        let g = |side: Side, phi: f64| self.min_gap(side, &envs[idx(side)], off, y, phi, refine);
        let d =
            |phi: f64| -> Result<f64, ContactError> { Ok(g(Side::Left, phi)?.0 - g(Side::Right, phi)?.0) };
        let limit = ROLL_LIMIT_RAD.min(ROLL_SHIFT_LIMIT_M / self.pair.wheelset.nominal_radius_m.max(1e-3));
        let (mut lo, mut hi) = (-limit, limit);
        if d(lo)? > 0.0 || d(hi)? < 0.0 {
            return Err(ContactError::NoRollBracket {
                y_mm: y * 1e3,
                limit_rad: limit,
            });
        }
        while hi - lo > phi_tolerance {
            let m = 0.5 * (lo + hi);
            if d(m)? > 0.0 {
                hi = m
            } else {
                lo = m
            }
        }
        let phi = 0.5 * (lo + hi);
        let (gl, lw, lr) = g(Side::Left, phi)?;
        let (_, rw, rr) = g(Side::Right, phi)?;
        Ok([-gl, phi, lw, lr, rw, rr])
    }

    /// The smallest vertical gap between one wheel and its rail with the wheelset at (y, z, φ) (z
    /// the centre height as [`ContactSolution::z`] gives it): the global scan of the real
    /// profiles, polished (golden section on the exact gap). Negative: the profiles
    /// interpenetrate. For independent checks of a lifted or penetrating wheel.
    pub fn vertical_gap(
        &self,
        side: Side,
        off: &RailOffsets,
        y: f64,
        z: f64,
        phi: f64,
    ) -> Result<f64, ContactError> {
        let env = self.envelope(side, off);
        Ok(self.min_gap(side, &env, off, y, phi, true)?.0 + z)
    }

    /// The seed of Newton: the sampled global search to 1e-7 rad in roll.
    pub fn seed(&self, y: f64, off: &RailOffsets) -> Result<[f64; 6], ContactError> {
        self.search(y, off, false, 1e-7)
    }

    /// Solves the contact at lateral displacement `y` with rail offsets `off`: global seed, Newton,
    /// interpenetration check, secondary points, sensitivities.
    ///
    /// Where the wheel is locally more concave than the rail is convex (near-conformal flange-root
    /// contact), the tangency condition Eq. (36) also holds at a local *maximum* of the gap, and
    /// Newton may converge there with the profiles interpenetrating by a few µm on either side.
    /// The check catches it (or Newton fails to settle between the two), and the solution is then
    /// the refined minimum-gap search itself
    /// (golden section on the exact gap, roll bisected to 1e-13 rad), which is the contact by
    /// definition.
    pub fn solve(&self, y: f64, off: &RailOffsets) -> Result<ContactSolution, ContactError> {
        let x0 = self.seed(y, off)?;
        let newton = self
            .newton(y, off, x0)
            .and_then(|(x, j, it)| self.finish(y, off, x, j, it, true));
        match newton {
            Err(ContactError::Interpenetration { .. } | ContactError::NoConvergence { .. }) => {
                let x = self.search(y, off, true, 1e-13)?;
                let (_, j) = self.residual(y, off, &x);
                self.finish(y, off, x, j, 0, true)
            }
            other => other,
        }
    }

    /// Warm-started solve for simulation: Newton from a previous solution, without the global
    /// search or the interpenetration check; where Newton fails from there (the previous branch
    /// ceased to exist past a contact jump), the full [`ContactGeometry::solve`]. A warm start can
    /// stay on a branch past a jump while it still exists: `kecsim bench contact` measures it.
    pub fn solve_from(
        &self,
        y: f64,
        off: &RailOffsets,
        previous: &ContactSolution,
    ) -> Result<ContactSolution, ContactError> {
        match self.newton(y, off, previous.x()) {
            Ok((x, j, iterations)) => self.finish(y, off, x, j, iterations, false),
            Err(ContactError::NoConvergence { .. }) => self.solve(y, off),
            Err(e) => Err(e),
        }
    }

    /// Warm-started solve that stays on the true contact: Newton from a previous solution, then the
    /// interpenetration check of [`ContactGeometry::solve`]; where the previous branch has ceased
    /// to be the contact (past a contact-point jump the old branch survives a while as a local
    /// tangency with the profiles interpenetrating elsewhere) or Newton fails, the full solve.
    /// This is what a simulation with the `online` contact model needs: without the check the
    /// contact point jumps late, z jumps with it, and the normal force spikes.
    pub fn solve_tracked(
        &self,
        y: f64,
        off: &RailOffsets,
        previous: &ContactSolution,
    ) -> Result<ContactSolution, ContactError> {
        let checked = |x0: [f64; 6]| {
            self.newton(y, off, x0)
                .and_then(|(x, j, it)| self.finish(y, off, x, j, it, true))
        };
        match checked(previous.x()) {
            Err(ContactError::Interpenetration { .. }) => {
                // Re-seed each side at its deepest point (the other branch), Newton from there.
                let mut x0 = previous.x();
                for side in Side::BOTH {
                    let env = self.envelope(side, off);
                    let scan = self
                        .scan(side, &env, y, x0[0], x0[1])
                        .ok_or_else(|| Self::no_overlap(y, side))?;
                    let (sw, sr, gap) = scan.samples[scan.min];
                    if gap < 0.0 {
                        let c0 = 2 + 2 * idx(side);
                        x0[c0] = sw;
                        x0[c0 + 1] = sr;
                    }
                }
                match checked(x0) {
                    Err(ContactError::Interpenetration { .. } | ContactError::NoConvergence { .. }) => {
                        self.solve(y, off)
                    }
                    other => other,
                }
            }
            Err(ContactError::NoConvergence { .. }) => self.solve(y, off),
            other => other,
        }
    }

    fn finish(
        &self,
        y: f64,
        off: &RailOffsets,
        x: [f64; 6],
        j: Matrix6<f64>,
        iterations: usize,
        global_check: bool,
    ) -> Result<ContactSolution, ContactError> {
        let (z, phi) = (x[0], x[1]);
        let mut points = Vec::with_capacity(2);
        let mut secondaries: [Vec<SecondaryPoint>; 2] = [Vec::new(), Vec::new()];
        for side in Side::BOTH {
            let c0 = 2 + 2 * idx(side);
            let (sw, sr) = (x[c0], x[c0 + 1]);
            self.check_on_profile(y, side, sw, sr)?;
            if global_check {
                let env = self.envelope(side, off);
                let scan = self
                    .scan(side, &env, y, z, phi)
                    .ok_or_else(|| Self::no_overlap(y, side))?;
                let deepest = scan.samples[scan.min].2;
                if deepest < -self.settings.penetration_tolerance_m {
                    return Err(ContactError::Interpenetration {
                        y_mm: y * 1e3,
                        side: side.name(),
                        depth_mm: -deepest * 1e3,
                    });
                }
                secondaries[idx(side)] = self.secondary_points(&scan, sw);
            }
            points.push(self.contact_point(side, off, y, z, phi, sw, sr));
        }
        // Sensitivities (implicit function theorem, dx/dp = −J⁻¹ ∂F/∂p): ∂F/∂y = 1 in both
        // lateral position rows; a gauge variation gv moves the rails by ±gv/2, ∂F/∂gv = ∓1/2.
        let lu = j.lu();
        let singular = || ContactError::NoConvergence {
            y_mm: y * 1e3,
            iterations,
            last_step: f64::NAN,
        };
        let dx = lu
            .solve(&Vector6::new(-1.0, 0.0, 0.0, -1.0, 0.0, 0.0))
            .ok_or_else(singular)?;
        let dg = lu
            .solve(&Vector6::new(0.5, 0.0, 0.0, -0.5, 0.0, 0.0))
            .ok_or_else(singular)?;
        let right = points.pop().expect("two sides");
        let left = points.pop().expect("two sides");
        Ok(ContactSolution {
            y,
            offsets: *off,
            z,
            phi,
            left,
            right,
            secondary: secondaries,
            dx_dy: [dx[0], dx[1], dx[2], dx[3], dx[4], dx[5]],
            dx_dgv: [dg[0], dg[1], dg[2], dg[3], dg[4], dg[5]],
            iterations,
        })
    }

    fn check_on_profile(&self, y: f64, side: Side, sw: f64, sr: f64) -> Result<(), ContactError> {
        for (what, s, (lo, hi)) in [
            ("wheel", sw, self.pair.wheel.domain_side(side)),
            ("rail", sr, self.pair.rail.domain_side(side)),
        ] {
            if s < lo || s > hi {
                return Err(ContactError::OffProfile {
                    y_mm: y * 1e3,
                    side: side.name(),
                    what,
                    s_mm: s * 1e3,
                    lo_mm: lo * 1e3,
                    hi_mm: hi * 1e3,
                });
            }
        }
        Ok(())
    }

    /// Local minima of the sampled gap other than the contact itself (more than 1 mm away on the
    /// wheel), within the two-point tolerance.
    fn secondary_points(&self, scan: &GapScan, s_contact: f64) -> Vec<SecondaryPoint> {
        let s = &scan.samples;
        let mut out: Vec<SecondaryPoint> = Vec::new();
        for k in 1..s.len().saturating_sub(1) {
            let g = s[k].2;
            if g <= s[k - 1].2
                && g < s[k + 1].2
                && g < self.settings.two_point_tolerance_m
                && (s[k].0 - s_contact).abs() > 1e-3
            {
                out.push(SecondaryPoint {
                    s_wheel: s[k].0,
                    s_rail: s[k].1,
                    gap: g.max(0.0),
                });
            }
        }
        out
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn contact_point(
        &self,
        side: Side,
        off: &RailOffsets,
        y: f64,
        z: f64,
        phi: f64,
        sw: f64,
        sr: f64,
    ) -> ContactPoint {
        let sig = side.sign();
        let (hw, _, _) = self.wheel(side, sw);
        let (_, hr1, _) = self.rail(side, sr);
        let (sa, ca) = self.alpha(side, off).sin_cos();
        let lat = sig * self.l_w() + sw;
        let (ny, nz) = (-ca * hr1 - sa, -sa * hr1 + ca);
        let norm = (ny * ny + nz * nz).sqrt();
        let normal = (ny / norm, nz / norm);
        let wp = self.pair.wheel.eval_side(side, sw);
        let rp = self.pair.rail.eval_side(side, sr);
        ContactPoint {
            s_wheel: sw,
            s_rail: sr,
            position: (y + lat + phi * hw, z + phi * lat - hw),
            normal,
            contact_angle: (-sig * normal.0).atan2(normal.1),
            rolling_radius: hw,
            // The wheel's material lies above its running surface: convex where z_w'' > 0.
            wheel_curvature: wp.curvature(),
            // The rail's material lies below its head: convex where h_r'' < 0.
            rail_curvature: -rp.curvature(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::StandardProfile;

    fn geometry(incl: &str) -> ContactGeometry {
        let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, incl).unwrap();
        ContactGeometry::with_defaults(pair)
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let g = geometry("1:40");
        let off = RailOffsets::from_irregularities(0.001, 0.002, 0.003, -0.002);
        let sol = g.solve(0.003, &off).unwrap();
        let mut x = sol.x();
        x[2] += 1e-4; // off the solution, so that every term matters
        x[1] += 1e-3;
        let (f0, j) = g.residual(0.003, &off, &x);
        for c in 0..6 {
            let h = 1e-7;
            let mut xp = x;
            xp[c] += h;
            let (fp, _) = g.residual(0.003, &off, &xp);
            let mut xm = x;
            xm[c] -= h;
            let (fm, _) = g.residual(0.003, &off, &xm);
            for r in 0..6 {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!(
                    (fd - j[(r, c)]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "J[{r},{c}] = {} vs fd {fd}",
                    j[(r, c)]
                );
            }
        }
        assert!(f0.amax() > 0.0);
    }

    #[test]
    fn centred_wheelset_is_symmetric() {
        let g = geometry("1:40");
        let s = g.solve(0.0, &RailOffsets::default()).unwrap();
        assert!(s.phi.abs() < 1e-12, "phi {}", s.phi);
        assert!((s.left.s_wheel + s.right.s_wheel).abs() < 1e-9);
        assert!((s.left.s_rail + s.right.s_rail).abs() < 1e-9);
        assert!(s.delta_r().abs() < 1e-12);
        assert!((s.left.contact_angle - s.right.contact_angle).abs() < 1e-9);
    }

    #[test]
    fn sensitivities_match_finite_differences() {
        let g = geometry("1:40");
        let off = RailOffsets::default();
        let (y, h) = (0.002, 1e-7);
        let s = g.solve(y, &off).unwrap();
        let (sp, sm) = (
            g.solve_from(y + h, &off, &s).unwrap(),
            g.solve_from(y - h, &off, &s).unwrap(),
        );
        for k in 0..6 {
            let fd = (sp.x()[k] - sm.x()[k]) / (2.0 * h);
            assert!(
                (fd - s.dx_dy[k]).abs() < 1e-5 * (1.0 + fd.abs()),
                "dx{k}/dy {} vs {fd}",
                s.dx_dy[k]
            );
        }
    }

    #[test]
    fn gauge_variation_sensitivity_matches_finite_differences() {
        let g = geometry("1:40");
        let (y, h) = (0.002, 1e-7);
        let s = g.solve(y, &RailOffsets::gauge_variation(0.001)).unwrap();
        let sp = g
            .solve_from(y, &RailOffsets::gauge_variation(0.001 + h), &s)
            .unwrap();
        let sm = g
            .solve_from(y, &RailOffsets::gauge_variation(0.001 - h), &s)
            .unwrap();
        for k in 0..6 {
            let fd = (sp.x()[k] - sm.x()[k]) / (2.0 * h);
            assert!(
                (fd - s.dx_dgv[k]).abs() < 1e-5 * (1.0 + fd.abs()),
                "dx{k}/dgv {} vs {fd}",
                s.dx_dgv[k]
            );
        }
    }

    #[test]
    fn flange_contact_has_a_steep_contact_angle_and_larger_radius() {
        let g = geometry("1:40");
        let s = g.solve(0.0075, &RailOffsets::default()).unwrap();
        assert!(
            s.left.contact_angle.to_degrees() > 55.0,
            "left angle {}",
            s.left.contact_angle.to_degrees()
        );
        assert!(s.right.contact_angle.to_degrees().abs() < 10.0);
        assert!(s.delta_r() > 0.004, "Δr {}", s.delta_r());
        assert!(s.phi > 0.0, "the left wheel climbs: phi {}", s.phi);
    }

    #[test]
    fn wheels_off_the_rails_are_reported() {
        let g = geometry("1:40");
        let e = g.solve(0.1, &RailOffsets::default()).unwrap_err();
        assert!(
            matches!(
                e,
                ContactError::NoOverlap { .. }
                    | ContactError::OffProfile { .. }
                    | ContactError::NoRollBracket { .. }
            ),
            "{e}"
        );
        let wide = RailOffsets::gauge_variation(0.2);
        assert!(g.solve(0.0, &wide).is_err());
    }
}
