//! The ideal track centreline (paper §2.2): global position R^t(s), rotation A^t(s) (Eq. 2), the
//! curvatures ρ_h, ρ_v, ρ_tw and their s-derivatives, and the motion of a frame sliding along it
//! (Eq. 3–4, or the whole motion derived from the rotation: [`FrameModel`]).
//!
//! Arc length: s is measured along the horizontal profile (as the paper's Tab. 1 defines ρ_h
//! against s) and the position follows the linearised Eq. (2) exactly, dR/ds = [cos ψ, sin ψ, −θ]:
//! the 3D length of ds is √(1 + θ²) ds, a relative difference of θ²/2 (6e-4 at the steepest 3.5 %
//! slope) that the paper's small-slope model neglects too.
//!
//! **Rotation (departure from Eq. 2, stated).** The track frame's rotation is the exact Euler
//! sequence A^t = R_z(ψ) R_y(θ) R_x(φ) (azimuth, slope, cant), whose first-order expansion in θ and φ
//! is the paper's Eq. (2). The cant of a tight curve is not small to second order: 76 mrad on the
//! Tab. 6 curve, where cos φ = 0.9971. Eq. (2)'s linearisation makes gravity's component normal to
//! the track plane g instead of g cos φ (+0.29 %) and the curve's lateral acceleration κV² instead
//! of κV² cos φ, so that the quasi-static lateral balance m (κV² cos φ − g sin φ) comes out 0.47 %
//! high at 19 m/s — a model error, not a tolerance. [`FrameModel::Paper`] keeps Eq. (2)–(4) as
//! printed.
//!
//! **Motion (departure from Eq. 3–4, stated).** Differentiating the rotation along the track at
//! ṡ = V gives the frame's angular velocity in its own components (ψ' = ρ_h, θ' = ρ_v, φ' = ρ_tw)
//!
//! ```text
//! ω = V w,   w = [ρ_tw − ρ_h sin θ,  ρ_v cos φ + ρ_h cos θ sin φ,  ρ_h cos θ cos φ − ρ_v sin φ]
//! α = V̇ w + V² w'                                     (components in the rotating frame: α = dω/dt)
//! a = Aᵀ R̈ = V̇ Aᵀ R' + V² Aᵀ R'',   Aᵀ R'' = [ρ_v sin θ,  ρ_h cos φ − ρ_v cos θ sin φ,  −ρ_h sin φ − ρ_v cos θ cos φ]
//! ```
//!
//! To first order: ω = V [ρ_tw − θ ρ_h, ρ_v + φ ρ_h, ρ_h], a = [V̇, ρ_h V², −(ρ_v + φ ρ_h) V²].
//! The paper's Eq. (3)–(4) drop the products φ ρ_h and θ ρ_h although they keep gravity's −φ g,
//! of the same order: in the Tab. 6 curve at 19 m/s the frame's pitch rate κ φ V is −6.1 mrad/s and
//! its acceleration normal to the canted plane −κ φ V² = 0.116 m/s² (1.2 % of g) — every wheel
//! load 1.2 % light without it. Both are in the default model ([`FrameModel::Whole`]).
//!
//! Precomputation: each horizontal section is cut into nodes close enough that the Fresnel
//! series of [`super::clothoid`] converges in ~9 terms (|ρ_h h|, |ρ'_h h²/2| ≤ 0.05, h ≤ 10 m);
//! every node stores its exact position, heading and the heading's cosine and sine. An evaluation
//! is then a binary search over section starts (O(log n)), an O(1) node index, one series, and
//! the sines and cosines of the (small) slope and cant.

use nalgebra::{Matrix3, Vector3};

use super::clothoid::{local_step, MAX_PHASE_STEP};
use super::error::TrackError;
use super::sections::{check_horizontal, check_vertical, HorizontalSection, VerticalSection};

/// Largest node spacing, m.
const MAX_NODE_SPACING: f64 = 10.0;

/// Where the centreline starts (s = first section's `from_m`) and which way it points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Start {
    pub x_m: f64,
    pub y_m: f64,
    pub z_m: f64,
    /// Azimuth ψ^t at the start, rad (from global X towards global Y).
    pub heading_rad: f64,
}

/// A precomputed horizontal section.
#[derive(Debug, Clone, Copy)]
struct HSeg {
    s0: f64,
    kappa0: f64,
    kappa1: f64,
    cant0: f64,
    twist: f64,
    psi0: f64,
    first_node: usize,
    nodes: usize,
    spacing: f64,
    inv_spacing: f64,
}

/// A node inside a horizontal section.
#[derive(Debug, Clone, Copy)]
struct Node {
    x: f64,
    y: f64,
    cos: f64,
    sin: f64,
    kappa: f64,
}

/// A precomputed vertical section: θ = θ0 + ρ_v u, Z = z0 − (θ0 u + ρ_v u²/2).
#[derive(Debug, Clone, Copy)]
struct VSeg {
    s0: f64,
    theta0: f64,
    rho_v: f64,
    z0: f64,
}

/// The centreline, ready to evaluate.
#[derive(Debug, Clone)]
pub struct Centreline {
    h_starts: Vec<f64>,
    hsegs: Vec<HSeg>,
    nodes: Vec<Node>,
    v_starts: Vec<f64>,
    vsegs: Vec<VSeg>,
    range: (f64, f64),
    horizontal: Vec<HorizontalSection>,
    vertical: Vec<VerticalSection>,
}

/// Which motion of the track frame the dynamics see (`[simulation] track_frame`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrameModel {
    /// The exact rotation R_z(ψ) R_y(θ) R_x(φ) and the motion derived from it (the module's
    /// documentation): the default, a stated departure from Eq. (2)–(4).
    #[default]
    Whole,
    /// Eq. (2) linearised in slope and cant, and Eq. (3)–(4) as printed.
    Paper,
}

impl FrameModel {
    /// Its name in a scenario.
    pub fn name(self) -> &'static str {
        match self {
            FrameModel::Whole => "whole",
            FrameModel::Paper => "paper",
        }
    }
}

/// The track frame at one arc length, with everything the dynamics needs from the ideal track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackFrame {
    pub s: f64,
    /// R^t(s), global, m (Eq. 1).
    pub position: Vector3<f64>,
    /// A^t(s), track frame → global: the exact R_z(ψ) R_y(θ) R_x(φ), whose linearisation is
    /// Eq. (2) ([`Self::rotation_of`] gives either).
    pub rotation: Matrix3<f64>,
    /// ψ^t, rad.
    pub heading_rad: f64,
    /// θ^t (= θ_v), rad, positive going down.
    pub slope_rad: f64,
    /// φ^t, rad, positive raising the left rail.
    pub cant_rad: f64,
    /// ρ_h = dψ/ds, 1/m.
    pub rho_h: f64,
    /// ρ_v = dθ/ds, 1/m.
    pub rho_v: f64,
    /// ρ_tw = dφ/ds, rad/m.
    pub rho_tw: f64,
    /// ρ'_h, 1/m².
    pub drho_h: f64,
    /// ρ'_v, 1/m² (zero inside every Tab. 2 section).
    pub drho_v: f64,
    /// ρ'_tw, rad/m² (zero inside every Tab. 1 section).
    pub drho_tw: f64,
    /// (cos ψ, sin ψ), from the same series as the position.
    pub heading_cos_sin: (f64, f64),
    /// (sin θ, cos θ) and (sin φ, cos φ), computed once for the rotation and the motion.
    pub slope_sin_cos: (f64, f64),
    pub cant_sin_cos: (f64, f64),
}

/// Motion of a frame sliding along the centreline at speed V with acceleration V̇, components in
/// the track frame (Eq. 3–4, or the whole motion: [`FrameModel`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameMotion {
    /// Ṙ in track components, m/s: Eq. (3) [V, 0, 0]; whole: V Aᵀ R' = V [cos θ + θ sin θ,
    /// e sin φ, e cos φ], e = sin θ − θ cos θ (≈ [V (1 + θ²/2), 0, 0]: s is the horizontal arc
    /// length).
    pub velocity: Vector3<f64>,
    /// R̈ in track components, m/s²: Eq. (3) [V̇, ρ_h V², −ρ_v V²]; whole: Aᵀ (V̇ R' + V² R'').
    pub acceleration: Vector3<f64>,
    /// ω, rad/s: Eq. (4) [ρ_tw V, ρ_v V, ρ_h V]; whole: V w (module documentation).
    pub angular_velocity: Vector3<f64>,
    /// α = dω/dt, rad/s²: Eq. (4) [ρ_tw V̇ + ρ'_tw V², ρ_v V̇ + ρ'_v V², ρ_h V̇ + ρ'_h V²];
    /// whole: V̇ w + V² w'.
    pub angular_acceleration: Vector3<f64>,
}

impl TrackFrame {
    /// The frame's motion at forward speed `v` (m/s) and forward acceleration `v_dot` (m/s²) in
    /// the model `model`.
    pub fn motion_of(&self, model: FrameModel, v: f64, v_dot: f64) -> FrameMotion {
        match model {
            FrameModel::Whole => self.motion(v, v_dot),
            FrameModel::Paper => self.motion_eq3_4(v, v_dot),
        }
    }

    /// The whole motion derived from the exact rotation (module documentation): ω = V w,
    /// α = V̇ w + V² w', a = Aᵀ (V̇ R' + V² R'') with R' = [cos ψ, sin ψ, −θ] and
    /// R'' = [−ρ_h sin ψ, ρ_h cos ψ, −ρ_v].
    pub fn motion(&self, v: f64, v_dot: f64) -> FrameMotion {
        let (st, ct) = self.slope_sin_cos;
        let (sp, cp) = self.cant_sin_cos;
        let (th, rh, rv, rt) = (self.slope_rad, self.rho_h, self.rho_v, self.rho_tw);
        let (drh, drv, drt) = (self.drho_h, self.drho_v, self.drho_tw);
        let w = Vector3::new(rt - rh * st, rv * cp + rh * ct * sp, rh * ct * cp - rv * sp);
        // w' with θ' = ρ_v, φ' = ρ_tw.
        let dw = Vector3::new(
            drt - drh * st - rh * ct * rv,
            drv * cp - rv * sp * rt + drh * ct * sp - rh * st * rv * sp + rh * ct * cp * rt,
            drh * ct * cp - rh * st * rv * cp - rh * ct * sp * rt - drv * sp - rv * cp * rt,
        );
        let e = st - th * ct;
        let u = Vector3::new(ct + th * st, sp * e, cp * e);
        let c = Vector3::new(rv * st, rh * cp - rv * ct * sp, -rh * sp - rv * ct * cp);
        FrameMotion {
            velocity: v * u,
            acceleration: v_dot * u + v * v * c,
            angular_velocity: v * w,
            angular_acceleration: v_dot * w + v * v * dw,
        }
    }

    /// Eq. (3)–(4) as printed, at forward speed `v` (m/s) and forward acceleration `v_dot` (m/s²).
    pub fn motion_eq3_4(&self, v: f64, v_dot: f64) -> FrameMotion {
        let v2 = v * v;
        FrameMotion {
            velocity: Vector3::new(v, 0.0, 0.0),
            acceleration: Vector3::new(v_dot, self.rho_h * v2, -self.rho_v * v2),
            angular_velocity: Vector3::new(self.rho_tw * v, self.rho_v * v, self.rho_h * v),
            angular_acceleration: Vector3::new(
                self.rho_tw * v_dot + self.drho_tw * v2,
                self.rho_v * v_dot + self.drho_v * v2,
                self.rho_h * v_dot + self.drho_h * v2,
            ),
        }
    }

    /// The rotation track frame → global in the model `model`: the exact one, or Eq. (2).
    pub fn rotation_of(&self, model: FrameModel) -> Matrix3<f64> {
        match model {
            FrameModel::Whole => self.rotation,
            FrameModel::Paper => {
                let (c, s) = self.heading_cos_sin;
                rotation_eq2(c, s, self.slope_rad, self.cant_rad)
            }
        }
    }

    /// Unit tangent of the frame, A^t e_x, global.
    pub fn tangent(&self) -> Vector3<f64> {
        self.rotation.column(0).into_owned()
    }

    /// dR/ds = [cos ψ, sin ψ, −θ], global (the position's derivative along the horizontal arc
    /// length).
    pub fn position_derivative(&self) -> Vector3<f64> {
        let (c, s) = self.heading_cos_sin;
        Vector3::new(c, s, -self.slope_rad)
    }

    /// Gravity (magnitude `g`, pointing down in the global frame) in track-frame components:
    /// [g sin θ, −g cos θ sin φ, −g cos θ cos φ] — with the Tab. 6 cant (φ < 0) its lateral
    /// component points to +Y, the centre of the left curve.
    pub fn gravity(&self, g: f64) -> Vector3<f64> {
        self.rotation.transpose() * Vector3::new(0.0, 0.0, -g)
    }

    /// Gravity in the model `model`: the exact one, or from Eq. (2), [θ g, −φ g, −g].
    pub fn gravity_of(&self, model: FrameModel, g: f64) -> Vector3<f64> {
        self.rotation_of(model).transpose() * Vector3::new(0.0, 0.0, -g)
    }
}

/// The exact rotation R_z(ψ) R_y(θ) R_x(φ) from the azimuth (as cos, sin), slope and cant (as
/// sin, cos); its first-order expansion in θ, φ is Eq. (2) ([`rotation_eq2`]).
#[inline]
pub fn rotation_exact(
    cos_psi: f64,
    sin_psi: f64,
    (st, ct): (f64, f64),
    (sp, cp): (f64, f64),
) -> Matrix3<f64> {
    Matrix3::new(
        cos_psi * ct,
        cos_psi * st * sp - sin_psi * cp,
        cos_psi * st * cp + sin_psi * sp,
        sin_psi * ct,
        sin_psi * st * sp + cos_psi * cp,
        sin_psi * st * cp - cos_psi * sp,
        -st,
        ct * sp,
        ct * cp,
    )
}

/// Eq. (2): the linearised track-frame rotation from azimuth (as cos, sin), slope and cant.
#[inline]
pub fn rotation_eq2(cos_psi: f64, sin_psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    Matrix3::new(
        cos_psi,
        -sin_psi,
        theta * cos_psi + phi * sin_psi,
        sin_psi,
        cos_psi,
        theta * sin_psi - phi * cos_psi,
        -theta,
        phi,
        1.0,
    )
}

/// Index of the section containing `s` given the sorted section starts (the last section also
/// owns its end point).
#[inline]
fn section_index(starts: &[f64], s: f64) -> usize {
    starts.partition_point(|&a| a <= s).saturating_sub(1)
}

impl Centreline {
    /// Builds the centreline from checked sections. An empty `vertical` means flat and level over
    /// the horizontal profile's range. Problems name the section by its index (0-based); the
    /// track file reports them with their lines instead.
    pub fn new(
        start: Start,
        horizontal: &[HorizontalSection],
        vertical: &[VerticalSection],
    ) -> Result<Self, TrackError> {
        let mut problems: Vec<String> = check_horizontal(horizontal)
            .into_iter()
            .map(|(i, p)| format!("horizontal section {i}: {p}"))
            .collect();
        let flat;
        let vertical = if vertical.is_empty() && !horizontal.is_empty() {
            flat = [VerticalSection::straight(
                horizontal[0].from_m,
                horizontal[horizontal.len() - 1].to_m,
                0.0,
            )];
            &flat[..]
        } else {
            vertical
        };
        problems.extend(
            check_vertical(vertical)
                .into_iter()
                .map(|(i, p)| format!("vertical section {i}: {p}")),
        );
        if let (Some(h0), Some(h1), Some(v0), Some(v1)) = (
            horizontal.first(),
            horizontal.last(),
            vertical.first(),
            vertical.last(),
        ) {
            if (h0.from_m - v0.from_m).abs() > 1e-9 || (h1.to_m - v1.to_m).abs() > 1e-9 {
                problems.push(format!(
                    "the vertical profile runs s = {}..{} m, the horizontal one s = {}..{} m: they must cover the same range",
                    v0.from_m, v1.to_m, h0.from_m, h1.to_m
                ));
            }
        }
        let start_values = [start.x_m, start.y_m, start.z_m, start.heading_rad];
        if start_values.iter().any(|v| !v.is_finite()) {
            problems.push(format!("start {start:?}: expected finite numbers"));
        }
        if !problems.is_empty() {
            return Err(TrackError::Sections(problems));
        }

        let mut hsegs = Vec::with_capacity(horizontal.len());
        let mut nodes = Vec::new();
        let (mut x, mut y, mut psi) = (start.x_m, start.y_m, start.heading_rad);
        for sec in horizontal {
            let len = sec.length_m();
            let kappa0 = sec.curvature_1pm[0];
            let kappa1 = sec.curvature_rate();
            let kmax = sec.curvature_1pm[0].abs().max(sec.curvature_1pm[1].abs());
            let mut h_max = MAX_NODE_SPACING;
            if kmax > 0.0 {
                h_max = h_max.min(MAX_PHASE_STEP / kmax);
            }
            if kappa1 != 0.0 {
                h_max = h_max.min((2.0 * MAX_PHASE_STEP / kappa1.abs()).sqrt());
            }
            let n = ((len / h_max).ceil() as usize).max(1);
            let spacing = len / n as f64;
            let first_node = nodes.len();
            let psi0 = psi;
            for k in 0..n {
                let u = k as f64 * spacing;
                let psi_k = psi0 + kappa0 * u + 0.5 * kappa1 * u * u;
                let (sin, cos) = psi_k.sin_cos();
                nodes.push(Node {
                    x,
                    y,
                    cos,
                    sin,
                    kappa: kappa0 + kappa1 * u,
                });
                // Step to the next node (or the section's end) with the exact integral.
                let (_, i) = local_step(kappa0 + kappa1 * u, kappa1, spacing);
                x += cos * i.0 - sin * i.1;
                y += sin * i.0 + cos * i.1;
            }
            psi = psi0 + kappa0 * len + 0.5 * kappa1 * len * len;
            hsegs.push(HSeg {
                s0: sec.from_m,
                kappa0,
                kappa1,
                cant0: sec.cant_rad[0],
                twist: sec.twist(),
                psi0,
                first_node,
                nodes: n,
                spacing,
                inv_spacing: 1.0 / spacing,
            });
        }
        let mut vsegs = Vec::with_capacity(vertical.len());
        let mut z = start.z_m;
        for sec in vertical {
            let (theta0, rho_v, len) = (sec.slope_rad[0], sec.curvature(), sec.length_m());
            vsegs.push(VSeg {
                s0: sec.from_m,
                theta0,
                rho_v,
                z0: z,
            });
            z -= theta0 * len + 0.5 * rho_v * len * len;
        }
        Ok(Centreline {
            h_starts: horizontal.iter().map(|s| s.from_m).collect(),
            hsegs,
            nodes,
            v_starts: vertical.iter().map(|s| s.from_m).collect(),
            vsegs,
            range: (horizontal[0].from_m, horizontal[horizontal.len() - 1].to_m),
            horizontal: horizontal.to_vec(),
            vertical: vertical.to_vec(),
        })
    }

    /// The arc-length range `[s_start, s_end]`, m.
    pub fn range(&self) -> (f64, f64) {
        self.range
    }

    /// The sections it was built from (the vertical ones include the implicit level straight).
    pub fn sections(&self) -> (&[HorizontalSection], &[VerticalSection]) {
        (&self.horizontal, &self.vertical)
    }

    /// Number of precomputed nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The track frame at arc length `s` (Eq. 1–2 and the curvatures of Tab. 1–2). At a vertex
    /// the section that starts there is used (curvature rates and twist are one-sided there).
    #[inline]
    pub fn frame(&self, s: f64) -> Result<TrackFrame, TrackError> {
        let (a, b) = self.range;
        if !(s >= a && s <= b) {
            return Err(TrackError::OutOfRange { s, from: a, to: b });
        }
        let seg = &self.hsegs[section_index(&self.h_starts, s)];
        let u = s - seg.s0;
        let k = ((u * seg.inv_spacing) as usize).min(seg.nodes - 1);
        let node = &self.nodes[seg.first_node + k];
        let h = u - k as f64 * seg.spacing;
        let (f, i) = local_step(node.kappa, seg.kappa1, h);
        let x = node.x + node.cos * i.0 - node.sin * i.1;
        let y = node.y + node.sin * i.0 + node.cos * i.1;
        let cos_psi = node.cos * f.0 - node.sin * f.1;
        let sin_psi = node.sin * f.0 + node.cos * f.1;
        let psi = seg.psi0 + u * (seg.kappa0 + 0.5 * seg.kappa1 * u);
        let rho_h = seg.kappa0 + seg.kappa1 * u;
        let phi = seg.cant0 + seg.twist * u;

        let vs = &self.vsegs[section_index(&self.v_starts, s)];
        let w = s - vs.s0;
        let theta = vs.theta0 + vs.rho_v * w;
        let z = vs.z0 - w * (vs.theta0 + 0.5 * vs.rho_v * w);
        let sin_cos = |a: f64| if a == 0.0 { (0.0, 1.0) } else { a.sin_cos() };
        let (slope_sin_cos, cant_sin_cos) = (sin_cos(theta), sin_cos(phi));
        Ok(TrackFrame {
            s,
            position: Vector3::new(x, y, z),
            rotation: rotation_exact(cos_psi, sin_psi, slope_sin_cos, cant_sin_cos),
            heading_rad: psi,
            slope_rad: theta,
            cant_rad: phi,
            rho_h,
            rho_v: vs.rho_v,
            rho_tw: seg.twist,
            drho_h: seg.kappa1,
            drho_v: 0.0,
            drho_tw: 0.0,
            heading_cos_sin: (cos_psi, sin_psi),
            slope_sin_cos,
            cant_sin_cos,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::sections::HorizontalSection as H;

    fn tab6() -> Centreline {
        let k = 1.0 / 235.65;
        let c = -0.07599;
        Centreline::new(
            Start::default(),
            &[
                H::straight(0.0, 100.0),
                H::transition(100.0, 150.0, (0.0, 0.0), (k, c)),
                H::curve(150.0, 600.0, 235.65, c),
                H::transition(600.0, 650.0, (k, c), (0.0, 0.0)),
                H::straight(650.0, 1000.0),
            ],
            &[],
        )
        .unwrap()
    }

    #[test]
    fn heading_at_end_is_the_integral_of_curvature() {
        let t = tab6().frame(1000.0).unwrap();
        assert!(
            (t.heading_rad - 500.0 / 235.65).abs() < 1e-12,
            "{:e}",
            t.heading_rad - 500.0 / 235.65
        );
        // The tangent from the series agrees with the heading.
        assert!((t.rotation[(0, 0)] - t.heading_rad.cos()).abs() < 1e-13);
        assert!((t.rotation[(1, 0)] - t.heading_rad.sin()).abs() < 1e-13);
    }

    #[test]
    fn circle_closed_form_in_the_curve() {
        // In the curve the centreline is a circle of radius R about the centre found at s = 150.
        let c = tab6();
        let r = 235.65;
        let f0 = c.frame(150.0).unwrap();
        let centre = f0.position + r * Vector3::new(-f0.heading_rad.sin(), f0.heading_rad.cos(), 0.0);
        for s in [150.0, 222.2, 377.7, 599.9, 600.0] {
            let p = c.frame(s).unwrap().position;
            let d = ((p - centre).xy().norm() - r).abs();
            assert!(d < 1e-10, "s = {s}: {d:e}");
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = tab6();
        let hstep = 1e-3;
        for s in [50.0, 120.3, 149.0, 400.0, 612.5, 800.0] {
            let (m, f, p) = (
                c.frame(s - hstep).unwrap(),
                c.frame(s).unwrap(),
                c.frame(s + hstep).unwrap(),
            );
            let dr = (p.position - m.position) / (2.0 * hstep);
            assert!(
                (dr - f.position_derivative()).norm() < 1e-9,
                "s = {s}: dR/ds {dr:?} vs {:?}",
                f.position_derivative()
            );
            // Level track: the frame's x axis is the tangent.
            assert!((f.tangent() - f.position_derivative()).norm() < 1e-15);
            let dpsi = (p.heading_rad - m.heading_rad) / (2.0 * hstep);
            assert!((dpsi - f.rho_h).abs() < 1e-10, "s = {s}: dψ/ds");
            let dphi = (p.cant_rad - m.cant_rad) / (2.0 * hstep);
            assert!((dphi - f.rho_tw).abs() < 1e-10, "s = {s}: dφ/ds");
            let dk = (p.rho_h - m.rho_h) / (2.0 * hstep);
            assert!((dk - f.drho_h).abs() < 1e-10, "s = {s}: dρ_h/ds");
        }
    }

    #[test]
    fn out_of_range_and_nan_are_errors() {
        let c = tab6();
        assert!(c.frame(-0.1).is_err());
        assert!(c.frame(1000.1).is_err());
        assert!(c.frame(f64::NAN).is_err());
    }

    #[test]
    fn vertical_transition_is_a_parabola() {
        let h = [H::straight(0.0, 300.0)];
        let v = [
            VerticalSection::straight(0.0, 100.0, 0.0),
            VerticalSection::transition(100.0, 200.0, 0.0, 0.02),
            VerticalSection::straight(200.0, 300.0, 0.02),
        ];
        let c = Centreline::new(Start::default(), &h, &v).unwrap();
        let f = c.frame(300.0).unwrap();
        // Z = −(∫θ ds) = −(100·0.01 + 100·0.02) = −3 m; ρ_v = 2e-4 1/m in the transition.
        assert!((f.position.z + 3.0).abs() < 1e-12, "{}", f.position.z);
        assert!((c.frame(150.0).unwrap().rho_v - 2e-4).abs() < 1e-15);
        assert!((c.frame(150.0).unwrap().position.z + 0.25).abs() < 1e-12);
    }

    #[test]
    fn gravity_points_to_the_curve_centre_with_the_papers_cant() {
        let f = tab6().frame(300.0).unwrap();
        let g = f.gravity(9.81);
        // [g sin θ, −g cos θ sin φ, −g cos θ cos φ] with φ = −0.07599: towards +Y, the centre.
        assert!(
            (g.y - 0.07599f64.sin() * 9.81).abs() < 1e-12 && g.y > 0.0,
            "{g:?}"
        );
        assert!((g.z + 0.07599f64.cos() * 9.81).abs() < 1e-12, "{g:?}");
        // Eq. (2): [θ g, −φ g, −g].
        let gp = f.gravity_of(FrameModel::Paper, 9.81);
        assert!(
            (gp - Vector3::new(0.0, 0.07599 * 9.81, -9.81)).norm() < 1e-12,
            "{gp:?}"
        );
    }

    /// A track whose every curvature term is non-zero somewhere: a left curve with cant entered by
    /// a clothoid with a cant ramp (twist), on a vertical curve from a 2 % rise to a 1.5 % fall
    /// that spans the clothoid, then a level stretch of the curve.
    fn twisted() -> Centreline {
        let k = 1.0 / 300.0;
        let c = -0.1;
        Centreline::new(
            Start {
                heading_rad: 0.3,
                ..Start::default()
            },
            &[
                H::straight(0.0, 50.0),
                H::transition(50.0, 130.0, (0.0, 0.0), (k, c)),
                H::curve(130.0, 400.0, 300.0, c),
            ],
            &[
                VerticalSection::straight(0.0, 40.0, -0.02),
                VerticalSection::transition(40.0, 160.0, -0.02, 0.015),
                VerticalSection::straight(160.0, 400.0, 0.015),
            ],
        )
        .unwrap()
    }

    /// The skew part of M as a vector: vee(M) = [M₃₂ − M₂₃, M₁₃ − M₃₁, M₂₁ − M₁₂] / 2.
    fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
        0.5 * Vector3::new(
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        )
    }

    /// Issue 46: the whole motion against the numerical derivatives of the frame's rotation and
    /// position along a canted curve, a clothoid with a cant ramp and a vertical curve (both
    /// tracks, speed 19 m/s, accelerating at 0.7 m/s²): ω against vee(Aᵀ dA/dt), α against
    /// dω/dt, the acceleration against Aᵀ R̈ (R(s(t)) differenced twice); the rotation is
    /// orthonormal. Central differences in s (h = 1e-3 m: truncation ~1e-12 relative).
    #[test]
    fn the_whole_motion_is_the_derivative_of_the_rotation() {
        let (v, v_dot, h) = (19.0, 0.7, 1e-3);
        for (name, c, points) in [
            ("tab6", tab6(), &[120.3, 149.0, 400.0, 612.5][..]),
            (
                "twisted",
                twisted(),
                &[45.0, 60.0, 100.0, 129.0, 145.0, 200.0][..],
            ),
        ] {
            for &s in points {
                let (m, f, p) = (
                    c.frame(s - h).unwrap(),
                    c.frame(s).unwrap(),
                    c.frame(s + h).unwrap(),
                );
                let a = f.rotation;
                assert!(
                    (a.transpose() * a - Matrix3::identity()).norm() < 1e-14,
                    "{name} {s}"
                );
                let motion = f.motion(v, v_dot);
                // ω: Aᵀ Ȧ = [ω]×, Ȧ = V dA/ds.
                let omega = v * vee(&(a.transpose() * (p.rotation - m.rotation) / (2.0 * h)));
                let err = (omega - motion.angular_velocity).norm();
                assert!(
                    err < 1e-9 * omega.norm() + 1e-11,
                    "{name} s = {s}: ω {omega:?} vs {:?}",
                    motion.angular_velocity
                );
                // α = dω/dt = V̇ w + V² dw/ds, w = ω / V.
                let w = |fr: &TrackFrame| fr.motion(1.0, 0.0).angular_velocity;
                let alpha = v_dot * w(&f) + v * v * (w(&p) - w(&m)) / (2.0 * h);
                let err = (alpha - motion.angular_acceleration).norm();
                assert!(
                    err < 1e-8 * alpha.norm() + 1e-9,
                    "{name} s = {s}: α {alpha:?} vs {:?}",
                    motion.angular_acceleration
                );
                // Acceleration: Aᵀ (V̇ R' + V² R'') with R', R'' by differences of the position
                // (R'' over 1 cm: the round-off of metres over h² stays below 1e-7 m/s²).
                let d1 = (p.position - m.position) / (2.0 * h);
                let (m2, p2) = (c.frame(s - 10.0 * h).unwrap(), c.frame(s + 10.0 * h).unwrap());
                let d2 = (p2.position - 2.0 * f.position + m2.position) / (100.0 * h * h);
                let acc = a.transpose() * (v_dot * d1 + v * v * d2);
                let err = (acc - motion.acceleration).norm();
                assert!(
                    err < 1e-5,
                    "{name} s = {s}: a {acc:?} vs {:?}",
                    motion.acceleration
                );
                let vel = a.transpose() * (v * d1);
                assert!((vel - motion.velocity).norm() < 1e-8, "{name} s = {s}");
            }
        }
    }

    /// Issue 46: in the Tab. 6 curve at 19 m/s the whole motion differs from Eq. (3)–(4) by the
    /// first-order terms the paper drops — the pitch rate ω_y = κ φ V (−6.1 mrad/s) and the
    /// acceleration normal to the canted plane −κ φ V² (+0.116 m/s², 1.2 % of g) — and by the
    /// cosines of the cant (κV² cos φ laterally); the paper model is Eq. (3)–(4) as printed.
    #[test]
    fn the_whole_motion_adds_the_terms_eq3_4_drop() {
        let f = tab6().frame(400.0).unwrap();
        let (v, k, phi) = (19.0, 1.0 / 235.65, -0.07599f64);
        let whole = f.motion_of(FrameModel::Whole, v, 0.0);
        let paper = f.motion_of(FrameModel::Paper, v, 0.0);
        assert_eq!(paper.angular_velocity, Vector3::new(0.0, 0.0, k * v));
        assert_eq!(paper.acceleration, Vector3::new(0.0, k * v * v, 0.0));
        let wy = k * phi.sin() * v;
        assert!(
            (whole.angular_velocity.y - wy).abs() < 1e-15 && (wy + 6.13e-3).abs() < 1e-5,
            "{wy}"
        );
        let az = -k * phi.sin() * v * v;
        assert!(
            (whole.acceleration.z - az).abs() < 1e-12 && (az - 0.1163).abs() < 1e-4,
            "{az}"
        );
        assert!((whole.acceleration.y - k * v * v * phi.cos()).abs() < 1e-12);
        // The quasi-static balance in the track plane: lateral κV² cos φ − g sin φ and normal
        // g cos φ + κV² sin φ (with φ < 0: the inside of the curve lower), the closed forms.
        let g = f.gravity(9.81);
        let lateral = whole.acceleration.y - g.y;
        let normal = whole.acceleration.z - g.z;
        assert!((lateral - (k * v * v * phi.abs().cos() - 9.81 * phi.abs().sin())).abs() < 1e-12);
        assert!((normal - (9.81 * phi.cos() + k * v * v * phi.abs().sin())).abs() < 1e-12);
    }
}
