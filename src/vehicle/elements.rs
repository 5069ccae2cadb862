//! Force elements between bodies, evaluated from the bodies' poses (see [`super`] for the
//! kinematics of a body point).
//!
//! Each element gives the force (global components) and pure moment acting on its second body `b`
//! at b's attachment point; the first body `a` receives the opposite at its own attachment point.
//! Deflections d and rotations Δθ are expressed in the track axes of `a`:
//!
//! ```text
//! bushing:      d = A_aᵀ (G_b − G_a),  ḋ = A_aᵀ (Ġ_b − Ġ_a) − ω_a × d,
//!               Δθ = Θ_b − Θ_a + rot(A_aᵀ A_b),  Δθ̇ = Θ̇_b − Θ̇_a + ω_b − ω_a,
//!               F = −(K d + C ḋ) − bump(d) + F₀,   M = −(K_r Δθ + C_r Δθ̇) + M₀
//! axial:        L = |G_b − G_a|, e = (G_b − G_a)/L,  F = −(k (L − L₀) + c L̇ − F₀) e
//! rotational:   a bushing with one rotational component (axis x, y or z)
//! carried mass: F = m (g_t − a_t − α_t × p − ω_t × (ω_t × p)) on its body at p (no reaction)
//! ```
//!
//! K, C are diagonal in those axes; bump stops add k_b (|d_k| − g) beyond the clearance g;
//! F₀, M₀, F₀ (axial) are the static preloads, computed by the system so that the nominal
//! configuration on level tangent track is in equilibrium.

use nalgebra::{Matrix3, Vector3};

/// One end of an element: a body of the system (bodies first, then wheelsets) or the ideal
/// track-following reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRef {
    Track,
    Body(usize),
}

/// Where a body is and how it moves (see [`super`]): everything an element needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// R(s_i), the body-track frame's origin, global, m.
    pub origin: Vector3<f64>,
    /// A(s_i), body-track frame → global.
    pub rotation: Matrix3<f64>,
    /// Centre in the body-track frame, (0, y, h + z), m.
    pub centre: Vector3<f64>,
    /// Small rotations (φ, θ, ψ), rad.
    pub theta: Vector3<f64>,
    /// (ẋ, ẏ, ż), m/s.
    pub centre_velocity: Vector3<f64>,
    /// (φ̇, θ̇, ψ̇), rad/s.
    pub theta_dot: Vector3<f64>,
    /// Forward speed of the frame V, m/s.
    pub speed: f64,
    /// ω_t of the frame (Eq. 4), track components, rad/s.
    pub omega_t: Vector3<f64>,
}

impl Pose {
    /// Track-frame position of a body point with arm `p`, relative to the frame origin.
    #[inline]
    pub fn local_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.centre + p + self.theta.cross(p)
    }

    /// Global position of a body point with arm `p`.
    #[inline]
    pub fn point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.origin + self.rotation * self.local_point(p)
    }

    /// Global velocity of a body point with arm `p`.
    #[inline]
    pub fn point_velocity(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let r = self.local_point(p);
        self.rotation
            * (Vector3::new(self.speed, 0.0, 0.0)
                + self.centre_velocity
                + self.omega_t.cross(&r)
                + self.theta_dot.cross(p))
    }
}

/// A force element (formulas in the module doc). Points are arms from the bodies' centres.
#[derive(Debug, Clone, PartialEq)]
pub enum Element {
    Bushing {
        name: String,
        a: BodyRef,
        b: BodyRef,
        arm_a: Vector3<f64>,
        arm_b: Vector3<f64>,
        /// [k_x, k_y, k_z] N/m, [k_φ, k_θ, k_ψ] N m/rad.
        stiffness: [f64; 6],
        damping: [f64; 6],
        /// Bump stops per translational axis: (clearance m, stiffness N/m).
        bump_stops: [Option<(f64, f64)>; 3],
        /// Static preload (force, moment on b, a's track axes).
        preload: [f64; 6],
    },
    Axial {
        name: String,
        a: BodyRef,
        b: BodyRef,
        arm_a: Vector3<f64>,
        arm_b: Vector3<f64>,
        length_m: f64,
        stiffness: f64,
        damping: f64,
        /// Static tension, N.
        preload: f64,
    },
    CarriedMass {
        name: String,
        body: BodyRef,
        arm: Vector3<f64>,
        mass_kg: f64,
    },
}

/// What an element does to its bodies: force (global) and moment (global) on b at `point_b`, and
/// the opposite on a at `point_a` (both global positions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementLoad {
    pub force: Vector3<f64>,
    pub moment: Vector3<f64>,
    pub point_a: Vector3<f64>,
    pub point_b: Vector3<f64>,
    /// Deflection in a's axes (bushing: d; axial: [L − L₀, 0, 0]), m.
    pub deflection: Vector3<f64>,
    /// Force in a's axes, N.
    pub local_force: Vector3<f64>,
}

/// The frame motion a carried mass feels: a_t, α_t, g_t (track components).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameLoads {
    pub accel: Vector3<f64>,
    pub alpha: Vector3<f64>,
    pub gravity: Vector3<f64>,
}

/// Small rotation vector of a rotation close to identity (its skew part).
fn small_rotation(r: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (r[(2, 1)] - r[(1, 2)]),
        0.5 * (r[(0, 2)] - r[(2, 0)]),
        0.5 * (r[(1, 0)] - r[(0, 1)]),
    )
}

impl Element {
    pub fn name(&self) -> &str {
        match self {
            Element::Bushing { name, .. }
            | Element::Axial { name, .. }
            | Element::CarriedMass { name, .. } => name,
        }
    }

    /// The two ends (a carried mass: its body twice, the first one a no-op reaction).
    pub fn ends(&self) -> (BodyRef, BodyRef) {
        match self {
            Element::Bushing { a, b, .. } | Element::Axial { a, b, .. } => (*a, *b),
            Element::CarriedMass { body, .. } => (BodyRef::Track, *body),
        }
    }

    /// The element's load from the poses of its ends (for a carried mass, `pa` is unused and
    /// `frame` gives its body frame's motion).
    pub fn load(&self, pa: &Pose, pb: &Pose, frame: &FrameLoads) -> ElementLoad {
        match self {
            Element::Bushing {
                arm_a,
                arm_b,
                stiffness: k,
                damping: c,
                bump_stops,
                preload,
                ..
            } => {
                let (ga, gb) = (pa.point(arm_a), pb.point(arm_b));
                let at = pa.rotation.transpose();
                let d = at * (gb - ga);
                let d_dot = at * (pb.point_velocity(arm_b) - pa.point_velocity(arm_a)) - pa.omega_t.cross(&d);
                let rel = at * pb.rotation;
                let dth = pb.theta - pa.theta + small_rotation(&rel);
                let dth_dot = pb.theta_dot - pa.theta_dot + pb.omega_t - pa.omega_t;
                let mut f = Vector3::zeros();
                let mut m = Vector3::zeros();
                for i in 0..3 {
                    f[i] = -k[i] * d[i] - c[i] * d_dot[i] + preload[i];
                    if let Some((gap, kb)) = bump_stops[i] {
                        let excess = d[i].abs() - gap;
                        if excess > 0.0 {
                            f[i] -= kb * excess * d[i].signum();
                        }
                    }
                    m[i] = -k[3 + i] * dth[i] - c[3 + i] * dth_dot[i] + preload[3 + i];
                }
                ElementLoad {
                    force: pa.rotation * f,
                    moment: pa.rotation * m,
                    point_a: ga,
                    point_b: gb,
                    deflection: d,
                    local_force: f,
                }
            }
            Element::Axial {
                arm_a,
                arm_b,
                length_m,
                stiffness,
                damping,
                preload,
                ..
            } => {
                let (ga, gb) = (pa.point(arm_a), pb.point(arm_b));
                let r = gb - ga;
                let l = r.norm();
                let e = r / l;
                let l_dot = e.dot(&(pb.point_velocity(arm_b) - pa.point_velocity(arm_a)));
                let tension = stiffness * (l - length_m) + damping * l_dot - preload;
                let force = -tension * e;
                ElementLoad {
                    force,
                    moment: Vector3::zeros(),
                    point_a: ga,
                    point_b: gb,
                    deflection: Vector3::new(l - length_m, 0.0, 0.0),
                    local_force: pa.rotation.transpose() * force,
                }
            }
            Element::CarriedMass { arm, mass_kg, .. } => {
                let w = pb.omega_t;
                let local = *mass_kg
                    * (frame.gravity - frame.accel - frame.alpha.cross(arm) - w.cross(&w.cross(arm)));
                let gb = pb.point(arm);
                ElementLoad {
                    force: pb.rotation * local,
                    moment: Vector3::zeros(),
                    point_a: gb,
                    point_b: gb,
                    deflection: Vector3::zeros(),
                    local_force: local,
                }
            }
        }
    }

    /// Sets the static preload from the element's load in the settled configuration (that load
    /// minus what the element's law gives at the nominal configuration, which is zero for all but
    /// geometric effects), so that it carries the same force at the nominal configuration.
    pub fn set_preload(&mut self, settled: &ElementLoad, nominal: &ElementLoad) {
        match self {
            Element::Bushing { preload, .. } => {
                for (i, p) in preload.iter_mut().take(3).enumerate() {
                    *p += settled.local_force[i] - nominal.local_force[i];
                }
            }
            Element::Axial { preload, .. } => {
                let e = (nominal.point_b - nominal.point_a).normalize();
                let t_settled = -settled.force.dot(&e);
                let t_nominal = -nominal.force.dot(&e);
                *preload -= t_settled - t_nominal;
            }
            Element::CarriedMass { .. } => {}
        }
    }

    /// Sets the static moment preload of a bushing (see [`Element::set_preload`]).
    pub fn set_moment_preload(&mut self, settled: &Vector3<f64>, nominal: &Vector3<f64>) {
        if let Element::Bushing { preload, .. } = self {
            for i in 0..3 {
                preload[3 + i] += settled[i] - nominal[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose() -> Pose {
        Pose {
            origin: Vector3::new(10.0, 5.0, 0.0),
            rotation: Matrix3::identity(),
            centre: Vector3::new(0.0, 0.0, 0.5),
            theta: Vector3::zeros(),
            centre_velocity: Vector3::zeros(),
            theta_dot: Vector3::zeros(),
            speed: 10.0,
            omega_t: Vector3::zeros(),
        }
    }

    fn bushing(k: [f64; 6], c: [f64; 6]) -> Element {
        Element::Bushing {
            name: "b".into(),
            a: BodyRef::Body(0),
            b: BodyRef::Body(1),
            arm_a: Vector3::new(1.0, 1.0, 0.0),
            arm_b: Vector3::new(0.0, 1.0, 0.0),
            stiffness: k,
            damping: c,
            bump_stops: [None, Some((0.01, 1e7)), None],
            preload: [0.0; 6],
        }
    }

    #[test]
    fn bushing_restores_and_bump_stop_engages() {
        let e = bushing([1e6, 2e6, 3e6, 0.0, 0.0, 4e5], [0.0; 6]);
        let pa = pose();
        let mut pb = pose();
        pb.origin.x += 1.0; // b's frame 1 m further along (tangent track): points coincide
        pb.centre.y = 0.005;
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!((l.deflection - Vector3::new(0.0, 0.005, 0.0)).norm() < 1e-12);
        assert!((l.force - Vector3::new(0.0, -1e4, 0.0)).norm() < 1e-6);
        // Beyond the 10 mm clearance the bump stop adds 1e7 N/m.
        pb.centre.y = 0.012;
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!((l.force.y - (-2e6 * 0.012 - 1e7 * 0.002)).abs() < 1e-6);
        // A yaw of b: the point moves by ψ × arm and the rotational stiffness resists ψ.
        pb.centre.y = 0.0;
        pb.theta.z = 1e-3;
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!((l.deflection.x - (-1e-3)).abs() < 1e-12, "{:?}", l.deflection);
        assert!((l.moment.z + 4e5 * 1e-3).abs() < 1e-9);
    }

    #[test]
    fn damping_sees_relative_velocity_only() {
        let e = bushing([0.0; 6], [1e3, 2e3, 3e3, 0.0, 0.0, 0.0]);
        let pa = pose();
        let mut pb = pose();
        pb.origin.x += 1.0;
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!(
            l.force.norm() < 1e-9,
            "common forward speed is no deflection rate"
        );
        pb.centre_velocity = Vector3::new(0.0, 0.0, 0.1);
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!((l.force.z + 300.0).abs() < 1e-9);
    }

    #[test]
    fn axial_spring_acts_along_its_line() {
        let e = Element::Axial {
            name: "rod".into(),
            a: BodyRef::Body(0),
            b: BodyRef::Body(1),
            arm_a: Vector3::zeros(),
            arm_b: Vector3::zeros(),
            length_m: 5.0_f64.sqrt(),
            stiffness: 1e5,
            damping: 0.0,
            preload: 0.0,
        };
        let pa = pose();
        let mut pb = pose();
        pb.origin += Vector3::new(2.0, 1.0, 0.0);
        pb.centre.x += 0.01 * 2.0 / 5.0_f64.sqrt(); // stretch by 0.01 m along the line
        pb.centre.y += 0.01 / 5.0_f64.sqrt();
        let l = e.load(&pa, &pb, &FrameLoads::default());
        assert!((l.deflection.x - 0.01).abs() < 1e-9);
        let along = l.force.dot(&Vector3::new(2.0, 1.0, 0.0).normalize());
        assert!((along + 1e3).abs() < 1e-6, "{along}");
    }
}
