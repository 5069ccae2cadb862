//! A vehicle of rigid bodies and solid-axle wheelsets joined by force elements, moving along the
//! track (paper §2.4–2.5, §5, §7; DYNAMICS.md §1–4): the system the bogie and Manchester scenes
//! integrate.
//!
//! **Bodies** (carbodies, bogie frames): 6 coordinates each, q = (x, y, z, φ, θ, ψ) relative to the
//! body-track frame at s_i = s₀ + d_i + x_i (see [`crate::vehicle`]). Linearised Newton–Euler in
//! the moving frame (DYNAMICS.md §2), with r = (0, y, h + z) and ṙ = (ẋ, ẏ, ż):
//!
//! ```text
//! m (r̈ + a_t + 2 ω_t × ṙ + α_t × r + ω_t × (ω_t × r)) = F + m g_t
//! I (Θ̈ + α_t) + ω × (I ω) = M,    ω = ω_t + Θ̇
//! ```
//!
//! with a_t, ω_t, α_t the track frame's motion at V (whole, or Eq. 3–4: [`crate::track::FrameModel`]) and g_t gravity in track components
//! (Eq. 2); the mass matrix is diagonal, so each body's accelerations are explicit.
//!
//! **Wheelsets**: [`super::wheelset::evaluate`] (the 10×10 Newton–Euler + normal-force solve of
//! Eq. 53, creep forces at the real contact points), each with its own track frame, rail
//! irregularities and contact model kinematics; they couple to the bodies through the elements'
//! forces only, so each is solved on its own (DYNAMICS.md §3).
//!
//! **Static preloads.** Scenario files give the loaded vehicle's geometry, as the railway world
//! writes it; the elements' static forces are then computed: the bodies are settled under gravity
//! on level tangent track with the wheelsets held at their centred contact position (Newton on the
//! bodies' 6 n static equations, finite-difference stiffness), and each element is preloaded with
//! the force it carries there. At the nominal configuration the vehicle is then in equilibrium
//! (checked by a test) and the wheel loads are the static ones.
//!
//! State: per body [q, q̇] (12), then per wheelset [x, y, ψ, ẋ, ẏ, ψ̇, Ω, θ_l, θ_r, θ̇_l, θ̇_r] (11)
//! or, per IRW-wheelset, [x, y, ψ, ẋ, ẏ, ψ̇, Ω_l, Ω_r, θ_l, θ_r, θ̇_l, θ̇_r] (12: each wheel's spin;
//! the bridge does not pitch); θ a lifted wheel's roll about the other wheel's contact
//! ([`super::wheelset::Lift`]).

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix3x6, Matrix6, Vector3, Vector6};

use super::kinematics::{initial_pose, Kind, Kinematics, KinematicsMemo};
use super::reference::{FrameAt, Reference, G};
use super::system::{
    BodySample, DynamicsError, FloorPoint, InitialDisturbance, PartTimes, Settling, VehicleData,
    VehicleModel, VehicleSample, WheelsetSample,
};
use super::traction::{
    DriveInfo, SpeedLoop, TractionLaw, TractionState, DEFAULT_BANDWIDTH_HZ, LOST_SPEED_FRACTION,
};
use super::wheelset::{
    FrameMotion, IrwInertia, Landing, Load, WheelsetDynamics, WheelsetInertia, WheelsetState,
};
use crate::contact::forces::ContactForceSettings;
use crate::contact::{ContactModel, WarmStart};
use crate::track::{RailMotion, RailOffsets};
use crate::vehicle::elements::{BodyRef, Element, ElementLoad, FrameLoads, Pose};
use crate::vehicle::spec::MultibodySpec;

/// A rigid body of the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    pub name: String,
    pub mass_kg: f64,
    /// Principal moments (roll, pitch, yaw), kg m².
    pub inertia: Vector3<f64>,
    /// Nominal position along the vehicle d_i, m.
    pub d: f64,
    /// Nominal centre height above the rail top h_i, m.
    pub h: f64,
}

/// A solid-axle wheelset of the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetBody {
    pub name: String,
    pub d: f64,
    pub inertia: WheelsetInertia,
}

/// Adds the time since `lap` to the part `field` picks (when part times are asked for) and
/// restarts the lap.
fn lap_into(
    times: &mut Option<PartTimes>,
    lap: &mut Option<Instant>,
    field: impl Fn(&mut PartTimes) -> &mut f64,
) {
    if let (Some(p), Some(l)) = (times.as_mut(), lap.as_mut()) {
        let now = Instant::now();
        *field(p) += (now - *l).as_secs_f64();
        *l = now;
    }
}

/// The parts of an evaluation a caller reads ([`Multibody::evaluate_parts`]).
#[derive(Debug, Clone, Copy)]
struct Parts {
    /// The bodies' accelerations (and the joints).
    bodies: bool,
    /// The wheelsets' dynamics.
    wheelsets: bool,
    /// Keep each wheelset's solved kinematics in its memo (a full evaluation).
    keep: bool,
    /// Bit j: wheelset j's dynamics are skipped, its rows left as they are (a Newton iteration
    /// carries them forward, [`VehicleModel::rhs_reusing`]).
    quiet: u64,
}

impl Parts {
    const ALL: Parts = Parts {
        bodies: true,
        wheelsets: true,
        keep: true,
        quiet: 0,
    };
}

/// A spherical joint between two rigid bodies at one point (arms from their centres).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub a: usize,
    pub b: usize,
    pub arm_a: Vector3<f64>,
    pub arm_b: Vector3<f64>,
}

/// Static residual, element loads and joint penalty forces of one configuration.
type StaticState = (DVector<f64>, Vec<ElementLoad>, Vec<Vector3<f64>>);

/// Baumgarte's stabilisation of the joints, ω_c (rad/s): the violation obeys ë + 2ω_c ė + ω_c² e = 0.
pub const JOINT_STABILISATION_RAD_S: f64 = 20.0;
/// Penalty stiffness standing for the joints in the static settling, N/m.
const JOINT_PENALTY_N_PER_M: f64 = 1e10;

/// Wheelsets per parallel task of a right-hand side: the MS vehicle's six in two tasks of three
/// (one per core of a 2-core machine); smaller tasks cost more in scheduling than they save.
const WHEELSETS_PER_TASK: usize = 3;

/// The multibody vehicle system (the model, with its elements preloaded by the static settling;
/// its run state is a [`VehicleData`]).
pub struct Multibody {
    pub bodies: Vec<RigidBody>,
    pub wheelsets: Vec<WheelsetBody>,
    pub elements: Vec<Element>,
    pub joints: Vec<Joint>,
    pub contact: Arc<dyn ContactModel>,
    pub forces: ContactForceSettings,
    pub r0: f64,
    pub reference: Reference,
    /// The static settling behind the elements' preloads.
    pub settling: Settling,
    /// The carbodies' floor points where ride comfort is read (EN 12299: above each bogie and at the middle of each module).
    pub floor_points: Vec<FloorPoint>,
    /// What drives the vehicle along the track ([`super::traction`]).
    pub drive: Drive,
}

/// The vehicle's drive: its law and the wheels it acts through ([`super::traction`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    pub law: TractionLaw,
    /// The driven wheelsets (the motored ones, every one where none is marked), each with the
    /// body that carries its motors and takes their reaction (the body its suspension joins it
    /// to; none: the reaction is not modelled).
    pub driven: Vec<(usize, Option<usize>)>,
    /// What the speed loop reads (bodies first, then wheelsets, as [`BodyRef::Body`]): the driven
    /// wheelsets and their carriers, each once.
    pub sensed: Vec<usize>,
    /// The elements tying the vehicle to the track frame ([`Multibody::ties`]).
    pub ties: Vec<usize>,
    /// M_e ([`Multibody::effective_mass_kg`]), kg.
    pub effective_mass_kg: f64,
}

/// Why a traction law does not fit a vehicle (the scene's key is named by the caller).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriveError {
    #[error("the vehicle is tied to the track frame by {elements}, which holds its speed: it cannot {what}")]
    Tied { elements: String, what: &'static str },
}

/// The part of a body point's absolute acceleration (components in the body's track frame) without
/// the body's own accelerations r̈, Θ̈: k = a_t + α_t × ρ + ω_t × (ω_t × ρ) + 2 ω_t × ρ̇ +
/// Θ̇ × (Θ̇ × p), ρ the point in the body-track frame, p its arm (the joints' k,
/// [`Multibody::apply_joints`], and the floor points').
fn point_acceleration_part(pose: &Pose, m: &FrameMotion, p: &Vector3<f64>) -> Vector3<f64> {
    let rho = pose.local_point(p);
    let rho_dot = pose.centre_velocity + pose.theta_dot.cross(p);
    let (w, al) = (v3(m.omega), v3(m.alpha));
    v3(m.accel)
        + al.cross(&rho)
        + w.cross(&w.cross(&rho))
        + 2.0 * w.cross(&rho_dot)
        + pose.theta_dot.cross(&pose.theta_dot.cross(p))
}

/// A bogie closer than this to a carbody's middle (along the vehicle) is under the middle floor
/// point, m.
const FLOOR_POINT_MERGE_M: f64 = 0.5;

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// What a carried mass feels of a frame's motion.
fn frame_loads(m: &FrameMotion) -> FrameLoads {
    FrameLoads {
        accel: v3(m.accel),
        alpha: v3(m.alpha),
        gravity: v3(m.gravity),
    }
}

impl Multibody {
    /// Builds the system from a validated `[vehicle]` table and settles it (the elements' static
    /// preloads; see the module doc).
    pub fn new(
        spec: &MultibodySpec,
        contact: Arc<dyn ContactModel>,
        forces: ContactForceSettings,
        r0: f64,
        reference: Reference,
    ) -> Result<Multibody, DynamicsError> {
        let bodies: Vec<RigidBody> = spec
            .bodies
            .iter()
            .map(|b| RigidBody {
                name: b.name.clone(),
                mass_kg: b.mass_kg,
                inertia: Vector3::from(b.inertia_kg_m2),
                d: b.position_m[0],
                h: b.position_m[2],
            })
            .collect();
        let wheelsets: Vec<WheelsetBody> = spec
            .wheelsets
            .iter()
            .map(|w| WheelsetBody {
                name: w.name.clone(),
                d: w.x_m,
                inertia: WheelsetInertia {
                    mass_kg: w.mass_kg,
                    inertia_kg_m2: w.inertia_kg_m2,
                    irw: w.independent_wheels.map(|i| IrwInertia {
                        wheel_spin_kg_m2: i.wheel_spin_inertia_kg_m2,
                    }),
                },
            })
            .collect();
        let mut sys = Multibody {
            bodies,
            wheelsets,
            elements: spec.elements(r0),
            joints: spec
                .joints
                .iter()
                .map(|j| {
                    let (a, b) = spec.joint_bodies(j);
                    let at = Vector3::from(j.at_m);
                    Joint {
                        name: j.name.clone(),
                        a,
                        b,
                        arm_a: at - crate::vehicle::spec::nominal_centre(spec, r0, a),
                        arm_b: at - crate::vehicle::spec::nominal_centre(spec, r0, b),
                    }
                })
                .collect(),
            contact,
            forces,
            r0,
            reference,
            settling: Settling {
                sag: Vec::new(),
                residual: 0.0,
                axle_loads: Vec::new(),
            },
            floor_points: Vec::new(),
            drive: Drive {
                law: TractionLaw::Coast,
                driven: Vec::new(),
                sensed: Vec::new(),
                ties: Vec::new(),
                effective_mass_kg: 0.0,
            },
        };
        sys.drive.ties = sys.ties();
        sys.drive.effective_mass_kg = sys.effective_mass_kg();
        sys.drive.driven = sys.driven_wheelsets(spec);
        let nb = sys.bodies.len();
        for &(j, carrier) in &sys.drive.driven {
            for k in carrier.into_iter().chain([nb + j]) {
                if !sys.drive.sensed.contains(&k) {
                    sys.drive.sensed.push(k);
                }
            }
        }
        sys.drive.law = if sys.drive.ties.is_empty() {
            TractionLaw::HoldSpeed(sys.speed_loop(DEFAULT_BANDWIDTH_HZ, None))
        } else {
            TractionLaw::Tied
        };
        let floor_heights: Vec<f64> = spec
            .bodies
            .iter()
            .map(|b| b.floor_height_m.unwrap_or(b.position_m[2]))
            .collect();
        sys.floor_points = sys.find_floor_points(&spec.carbodies(), &floor_heights);
        sys.settling = sys.settle()?;
        Ok(sys)
    }

    fn body_offset(&self, i: usize) -> usize {
        12 * i
    }

    /// The driven wheelsets ([`Drive::driven`]): those marked `motored = true`, else every one
    /// not marked `motored = false` (`motored = false` on one wheelset made every wheelset
    /// motored); each with the first body an element joins it to.
    fn driven_wheelsets(&self, spec: &MultibodySpec) -> Vec<(usize, Option<usize>)> {
        let nb = self.bodies.len();
        let marked: Vec<usize> = (0..self.wheelsets.len())
            .filter(|&j| spec.wheelsets.get(j).is_some_and(|w| w.motored == Some(true)))
            .collect();
        let driven = if marked.is_empty() {
            (0..self.wheelsets.len())
                .filter(|&j| spec.wheelsets.get(j).is_none_or(|w| w.motored != Some(false)))
                .collect()
        } else {
            marked
        };
        driven
            .into_iter()
            .map(|j| {
                let carrier = self.elements.iter().find_map(|e| match e.ends() {
                    (BodyRef::Body(a), BodyRef::Body(b)) if b == nb + j && a < nb => Some(a),
                    (BodyRef::Body(a), BodyRef::Body(b)) if a == nb + j && b < nb => Some(b),
                    _ => None,
                });
                (j, carrier)
            })
            .collect()
    }

    /// The elements that tie the vehicle to the track frame (an end on `track`), by index.
    pub fn ties(&self) -> Vec<usize> {
        self.elements
            .iter()
            .enumerate()
            .filter(|(_, e)| {
                let (a, b) = e.ends();
                !matches!(e, Element::CarriedMass { .. }) && (a == BodyRef::Track || b == BodyRef::Track)
            })
            .map(|(k, _)| k)
            .collect()
    }

    /// The translating masses: bodies', then wheelsets', kg.
    fn translating_masses(&self) -> impl Iterator<Item = f64> + '_ {
        self.bodies
            .iter()
            .map(|b| b.mass_kg)
            .chain(self.wheelsets.iter().map(|w| w.inertia.mass_kg))
    }

    /// The mass-weighted offset along the track and its rate of the masses `k` (bodies first,
    /// then wheelsets, as [`BodyRef::Body`]) at state `x`: (Σ m, Σ m x / Σ m, Σ m ẋ / Σ m).
    fn longitudinal(&self, x: &[f64], masses: impl Iterator<Item = usize>) -> (f64, f64, f64) {
        let nb = self.bodies.len();
        let (mut m_sum, mut mx, mut mxd) = (0.0, 0.0, 0.0);
        for k in masses {
            let (m, o, rate) = if k < nb {
                (self.bodies[k].mass_kg, self.body_offset(k), 6)
            } else {
                (
                    self.wheelsets[k - nb].inertia.mass_kg,
                    self.wheelset_offset(k - nb),
                    3,
                )
            };
            m_sum += m;
            mx += m * x[o];
            mxd += m * x[o + rate];
        }
        if m_sum > 0.0 {
            (m_sum, mx / m_sum, mxd / m_sum)
        } else {
            (0.0, 0.0, 0.0)
        }
    }

    /// M_e of the speed loop: the translating masses plus each wheel's spin inertia over r₀²
    /// (a solid axle's I_y for its two wheels), kg.
    pub fn effective_mass_kg(&self) -> f64 {
        let rotating: f64 = self
            .wheelsets
            .iter()
            .map(|w| match w.inertia.irw {
                Some(irw) => 2.0 * irw.wheel_spin_kg_m2,
                None => w.inertia.inertia_kg_m2[1],
            })
            .sum();
        self.translating_masses().sum::<f64>() + rotating / (self.r0 * self.r0)
    }

    /// The speed loop of this vehicle at bandwidth `bandwidth_hz` with the drive's limit.
    pub fn speed_loop(&self, bandwidth_hz: f64, max_force_n: Option<f64>) -> SpeedLoop {
        SpeedLoop {
            bandwidth_hz,
            effective_mass_kg: self.drive.effective_mass_kg,
            max_force_n,
        }
    }

    /// Sets the traction law. A vehicle tied to the track frame ([`Self::ties`]) keeps its tie's
    /// speed: it takes [`TractionLaw::Tied`] for a held speed and refuses coasting or a given
    /// force; a free vehicle cannot be [`TractionLaw::Tied`].
    /// The settled load on the driven wheelsets, N, and their names: μ times it is the most
    /// their wheels can transmit along the rails (adhesion).
    pub fn driven_load(&self) -> (f64, Vec<String>) {
        let load = self
            .drive
            .driven
            .iter()
            .filter_map(|&(j, _)| self.settling.axle_loads.get(j))
            .sum();
        let names = self
            .drive
            .driven
            .iter()
            .map(|&(j, _)| self.wheelsets[j].name.clone())
            .collect();
        (load, names)
    }

    pub fn set_traction(&mut self, law: TractionLaw) -> Result<(), DriveError> {
        let ties = &self.drive.ties;
        let names = || {
            ties.iter()
                .map(|&k| format!("'{}'", self.elements[k].name()))
                .collect::<Vec<_>>()
                .join(", ")
        };
        self.drive.law = match (law, ties.is_empty()) {
            (TractionLaw::HoldSpeed(_) | TractionLaw::Tied, false) => TractionLaw::Tied,
            (TractionLaw::Coast, false) => {
                return Err(DriveError::Tied {
                    elements: names(),
                    what: "coast",
                })
            }
            (TractionLaw::Force { .. }, false) => {
                return Err(DriveError::Tied {
                    elements: names(),
                    what: "be driven by a given force",
                })
            }
            (TractionLaw::Tied, true) => TractionLaw::HoldSpeed(self.speed_loop(DEFAULT_BANDWIDTH_HZ, None)),
            (law, true) => law,
        };
        Ok(())
    }

    /// The drive at (t, x): the law's force, each driven wheel's torque T = F r₀ / n, the
    /// reaction −2T on each carrier about its y axis (the axle's direction to first order), the
    /// ties' longitudinal force from the element loads `loads` at the poses `poses`, and the
    /// power. Returns the state, the motors' torques per wheelset (left, right) and the ramp's
    /// prescribed acceleration V̇ (0 but for a held speed's ramp).
    fn drive_at(
        &self,
        t: f64,
        x: &[f64],
        loads: &[ElementLoad],
        poses: &[Pose],
    ) -> (TractionState, Vec<[f64; 2]>, f64) {
        let (v, v_dot) = self.reference.speed_at(t);
        // The centre of mass's offset and speed error along the track.
        let (_, x_g, x_g_dot) = self.longitudinal(x, 0..self.bodies.len() + self.wheelsets.len());
        // The loop reads the position and speed of the driven wheelsets and the bodies carrying
        // their motors (collocated with the drive; see the traction module).
        let (m_d, x_d, x_d_dot) = self.longitudinal(x, self.drive.sensed.iter().copied());
        let demand = match self.drive.law {
            TractionLaw::Coast | TractionLaw::Tied => 0.0,
            TractionLaw::Force { force_n } => force_n,
            TractionLaw::HoldSpeed(l) if m_d > 0.0 => l.demand(x_d, x_d_dot),
            TractionLaw::HoldSpeed(_) => 0.0,
        };
        let drive = match self.drive.law {
            TractionLaw::HoldSpeed(SpeedLoop {
                max_force_n: Some(limit),
                ..
            }) => demand.clamp(-limit, limit),
            _ => demand,
        };
        let mut torques = vec![[0.0; 2]; self.wheelsets.len()];
        let mut power = 0.0;
        if drive != 0.0 && !self.drive.driven.is_empty() {
            let per_wheel = drive * self.r0 / (2 * self.drive.driven.len()) as f64;
            for &(j, _) in &self.drive.driven {
                torques[j] = [per_wheel; 2];
                let o = self.wheelset_offset(j);
                let st = WheelsetState::read(&x[o..], self.is_irw(j));
                power += per_wheel * (st.omega + st.omega_right);
            }
        }
        // The ties' longitudinal force on the vehicle, in the tied body's axes.
        let mut tie = 0.0;
        for &k in &self.drive.ties {
            let (a, b) = self.elements[k].ends();
            let l = &loads[k];
            let (body, sign) = match (a, b) {
                (BodyRef::Track, BodyRef::Body(i)) => (i, 1.0),
                (BodyRef::Body(i), _) => (i, -1.0),
                _ => continue,
            };
            if let Some(p) = poses.get(body) {
                tie += (p.rotation.transpose() * (sign * l.force)).x;
            }
        }
        power += tie * v;
        // A held speed's ramp: its inertia prescribed to every mass and wheel.
        let ramp = match self.drive.law {
            TractionLaw::HoldSpeed(_) => v_dot,
            _ => 0.0,
        };
        let ramp_n = self.drive.effective_mass_kg * ramp;
        power += ramp_n * v;
        let state = TractionState {
            demand_n: demand,
            drive_n: drive,
            ramp_n,
            tie_n: tie,
            power_w: power,
            offset_m: x_g,
            speed_m_s: v + x_g_dot,
        };
        (state, torques, ramp)
    }

    /// A held speed that cannot be held: the drive's limit passed, or the speed lost.
    fn check_drive(&self, t: f64, traction: &TractionState) -> Result<(), DynamicsError> {
        let TractionLaw::HoldSpeed(l) = self.drive.law else {
            return Ok(());
        };
        let (v, _) = self.reference.speed_at(t);
        if let Some(limit) = l.max_force_n {
            if traction.demand_n.abs() > limit {
                return Err(DynamicsError::TractionLimit {
                    demand_n: traction.demand_n,
                    limit_n: limit,
                    speed_m_s: v,
                });
            }
        }
        if (traction.speed_m_s - v).abs() > LOST_SPEED_FRACTION * v.max(1.0) {
            return Err(DynamicsError::SpeedLost {
                speed_m_s: traction.speed_m_s,
                reference_m_s: v,
                bandwidth_hz: l.bandwidth_hz,
            });
        }
        Ok(())
    }

    /// EN 12299's floor points: on each carbody ([`MultibodySpec::carbodies`]), at its middle
    /// (its centre's x) and above each bogie joined to it (the bogie's x; a bogie within 0.5 m of
    /// the middle makes the middle point "over" it), at the floor height `floor_heights[i]` above
    /// the rail top.
    fn find_floor_points(&self, carbodies: &[(usize, Vec<usize>)], floor_heights: &[f64]) -> Vec<FloorPoint> {
        let mut points = Vec::new();
        for (i, bogies) in carbodies {
            let Some(c) = self.bodies.get(*i) else { continue };
            let height = floor_heights.get(*i).copied().unwrap_or(c.h);
            let mut point = |name: String, over: Option<&RigidBody>, x: f64| {
                points.push(FloorPoint {
                    carbody: c.name.clone(),
                    point: name,
                    over_bogie: over.map(|b| b.name.clone()),
                    x_m: x,
                    height_m: height,
                    body: *i,
                    arm: [x - c.d, 0.0, height - c.h],
                })
            };
            let bogies: Vec<&RigidBody> = bogies.iter().filter_map(|&k| self.bodies.get(k)).collect();
            let middle = bogies.iter().find(|b| (b.d - c.d).abs() < FLOOR_POINT_MERGE_M);
            point("middle".to_string(), middle.copied(), c.d);
            for b in bogies.iter().filter(|b| (b.d - c.d).abs() >= FLOOR_POINT_MERGE_M) {
                point(format!("over_{}", b.name), Some(b), b.d);
            }
        }
        points
    }

    /// What an accelerometer at each floor point reads, in its carbody's axes, less the static
    /// 1 g on z, m/s²: the specific force f = a − g of the point, its absolute acceleration (in
    /// the body's track frame, p its arm) a = k + r̈ + Θ̈ × p with k the part without the body's
    /// accelerations ([`point_acceleration_part`], as the joints'), turned into the body's axes
    /// to first order in its rotation Θ, f_b = f − Θ × f.
    fn floor_accelerations(
        &self,
        poses: &[Pose],
        motions: &[FrameMotion],
        qdd: &[[Vector3<f64>; 2]],
    ) -> Vec<[f64; 3]> {
        self.floor_points
            .iter()
            .filter_map(|fp| {
                let (pose, m, q) = (poses.get(fp.body)?, motions.get(fp.body)?, qdd.get(fp.body)?);
                let p = v3(fp.arm);
                let g = v3(m.gravity);
                let f = point_acceleration_part(pose, m, &p) + q[0] + q[1].cross(&p) - g;
                let fb = f - pose.theta.cross(&f);
                Some([fb.x, fb.y, fb.z - g.norm()])
            })
            .collect()
    }

    /// The bodies that carry wheelsets (bogie frames), whose modes against the wheelsets' primary
    /// suspensions are the stiffest of the bodies': their [q, q̇] blocks, in groups of bodies
    /// that share no element and no joint chain (greedy colouring), so that each group's
    /// blocks are differenced together.
    fn stiff_body_groups(&self) -> Vec<Vec<(usize, usize)>> {
        let nb = self.bodies.len();
        let body = |r: BodyRef| match r {
            BodyRef::Body(i) if i < nb => Some(i),
            _ => None,
        };
        let carries_wheelset = |i: usize| {
            self.elements.iter().any(|e| {
                let (a, b) = e.ends();
                (body(a) == Some(i) && matches!(b, BodyRef::Body(k) if k >= nb))
                    || (body(b) == Some(i) && matches!(a, BodyRef::Body(k) if k >= nb))
            })
        };
        // Adjacency: an element between two bodies, or both in one chain of joints (the joint
        // forces couple every body of a chain).
        let mut chain: Vec<usize> = (0..nb).collect();
        fn root(chain: &mut [usize], mut i: usize) -> usize {
            while chain[i] != i {
                chain[i] = chain[chain[i]];
                i = chain[i];
            }
            i
        }
        for j in &self.joints {
            let (ra, rb) = (root(&mut chain, j.a), root(&mut chain, j.b));
            chain[ra] = rb;
        }
        let mut adjacent = vec![vec![false; nb]; nb];
        for e in &self.elements {
            let (a, b) = e.ends();
            if let (Some(a), Some(b)) = (body(a), body(b)) {
                adjacent[a][b] = true;
                adjacent[b][a] = true;
            }
        }
        // Two bodies share a root only if joints link them.
        let roots: Vec<usize> = (0..nb).map(|i| root(&mut chain, i)).collect();
        for (a, row) in adjacent.iter_mut().enumerate() {
            for (b, cell) in row.iter_mut().enumerate() {
                if a != b && roots[a] == roots[b] {
                    *cell = true;
                }
            }
        }
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in (0..nb).filter(|&i| carries_wheelset(i)) {
            match groups.iter_mut().find(|g| g.iter().all(|&k| !adjacent[i][k])) {
                Some(g) => g.push(i),
                None => groups.push(vec![i]),
            }
        }
        groups
            .into_iter()
            .map(|g| g.into_iter().map(|i| (self.body_offset(i), 12)).collect())
            .collect()
    }

    /// State size of wheelset j ([`WheelsetState::slot_size`]): solid axle [x, y, ψ, ẋ, ẏ, ψ̇, Ω,
    /// θ_l, θ_r, θ̇_l, θ̇_r] (11); IRW-wheelset [x, y, ψ, ẋ, ẏ, ψ̇, Ω_l, Ω_r, θ_l, θ_r, θ̇_l, θ̇_r]
    /// (12: each wheel's spin; the bridge does not pitch).
    fn wheelset_size(&self, j: usize) -> usize {
        WheelsetState::slot_size(self.is_irw(j))
    }

    fn is_irw(&self, j: usize) -> bool {
        self.wheelsets[j].inertia.irw.is_some()
    }

    /// Wheelset j's contact-model kinematics (two-point) and its frame at state `st`.
    fn wheelset_kinematics(
        &self,
        warm: &mut WarmStart,
        j: usize,
        st: &WheelsetState,
        s_ref: f64,
        v: f64,
        v_dot: f64,
    ) -> Result<(Kinematics, FrameAt, f64), DynamicsError> {
        let s = s_ref + self.wheelsets[j].d + st.x;
        let f = self.frame_at(s, v, v_dot)?;
        let kin = Kinematics::of(self.contact.as_ref(), st, &st.shifted_rails(&f.rails), warm)
            .map_err(DynamicsError::contact(&self.wheelsets[j].name, st.y, s))?;
        Ok((kin, f, s))
    }

    fn wheelset_offset(&self, j: usize) -> usize {
        12 * self.bodies.len() + (0..j).map(|k| self.wheelset_size(k)).sum::<usize>()
    }

    /// Initial state: every wheelset at lateral offset y₀ and yaw ψ₀, rolling without
    /// longitudinal creep, Ω = V₀ / r̄ with r̄ the mean rolling radius of its two contacts there
    /// (ideal rails); bodies at their nominal positions.
    fn initial(&self, y0: f64, psi0: f64) -> Vec<f64> {
        let mut x = vec![0.0; self.dim()];
        let mut warm = WarmStart::default();
        let rigid = self
            .contact
            .kinematics(y0, 0.0, &RailMotion::default(), &mut warm)
            .ok();
        let r_mean = rigid
            .as_ref()
            .map(|k| 0.5 * (k.contacts[0].rolling_radius + k.contacts[1].rolling_radius))
            .unwrap_or(self.r0);
        let mut sink = 0.0;
        for j in 0..self.wheelsets.len() {
            let o = self.wheelset_offset(j);
            let omega = self.reference.speed.at(0.0) / r_mean;
            // The elastic model: the free z, φ in the lift slots, sunk by the static approach
            // (where the rigid solve fails at y₀, the run's first evaluation reports it).
            let q = 0.5 * self.settling.axle_loads[j];
            let v0 = self.reference.speed.at(0.0);
            let rails = self
                .frame_at(self.reference.s_ref(0.0) + self.wheelsets[j].d, v0, 0.0)
                .map(|f| RailOffsets::from_array(f.rails.q))
                .unwrap_or_default();
            let free = initial_pose(self.contact.as_ref(), y0, &rails, [q, q], &self.forces)
                .ok()
                .flatten();
            if let (Some((z, _)), Some(k)) = (free, &rigid) {
                sink += (k.z - z) / self.wheelsets.len() as f64;
            }
            WheelsetState {
                y: y0,
                psi: psi0,
                omega,
                omega_right: omega,
                lift: free.map_or([0.0; 2], |(z, phi)| [z, phi]),
                ..WheelsetState::default()
            }
            .write(&mut x[o..], self.is_irw(j));
        }
        // The bodies sink with the wheelsets (their preloads were settled on rigid contacts).
        for i in 0..self.bodies.len() {
            x[self.body_offset(i) + 2] -= sink;
        }
        x
    }

    fn frame_at(&self, s: f64, v: f64, v_dot: f64) -> Result<FrameAt, DynamicsError> {
        self.reference
            .frame(s, v, v_dot)
            .map_err(|source| DynamicsError::Track { s, source })
    }

    /// Pose of the track reference at its point with nominal x (arms include x: centre −x e_x).
    fn track_pose(&self, s_ref: f64, x: f64, v: f64, v_dot: f64) -> Result<(Pose, FrameAt), DynamicsError> {
        let s = s_ref + x;
        let f = self
            .reference
            .frame_of_body(s, v, v_dot)
            .map_err(|source| DynamicsError::Track { s, source })?;
        Ok((
            Pose {
                origin: f.origin,
                rotation: f.rotation,
                centre: Vector3::new(-x, 0.0, 0.0),
                theta: Vector3::zeros(),
                centre_velocity: Vector3::zeros(),
                theta_dot: Vector3::zeros(),
                speed: v,
                omega_t: v3(f.motion.omega),
            },
            f,
        ))
    }

    /// The elements' loads at the given poses (bodies, then wheelsets).
    fn element_loads(
        &self,
        poses: &[Pose],
        frames: &[FrameLoads],
        s_ref: f64,
        v: f64,
        v_dot: f64,
    ) -> Result<Vec<ElementLoad>, DynamicsError> {
        let mut out = Vec::with_capacity(self.elements.len());
        for e in &self.elements {
            let (a, b) = e.ends();
            let end = |r: BodyRef, arm_x: f64| -> Result<(Pose, FrameLoads), DynamicsError> {
                match r {
                    BodyRef::Body(i) => Ok((poses[i], frames[i])),
                    BodyRef::Track => {
                        let (p, f) = self.track_pose(s_ref, arm_x, v, v_dot)?;
                        Ok((p, frame_loads(&f.motion)))
                    }
                }
            };
            let (xa, xb) = match e {
                Element::Bushing { arm_a, arm_b, .. } | Element::Axial { arm_a, arm_b, .. } => {
                    (arm_a.x, arm_b.x)
                }
                Element::CarriedMass { arm, .. } => (arm.x, arm.x),
            };
            let (pa, _) = end(a, xa)?;
            let (pb, fb) = end(b, xb)?;
            out.push(e.load(&pa, &pb, &fb));
        }
        Ok(out)
    }

    /// Adds element loads to the bodies' (force, moment about the centre) in their track axes.
    fn accumulate(&self, poses: &[Pose], loads: &[ElementLoad], acc: &mut [(Vector3<f64>, Vector3<f64>)]) {
        for (e, l) in self.elements.iter().zip(loads) {
            let (a, b) = e.ends();
            let mut apply = |r: BodyRef, sign: f64, point: &Vector3<f64>| {
                if let BodyRef::Body(i) = r {
                    let p = &poses[i];
                    let at = p.rotation.transpose();
                    let f = at * (sign * l.force);
                    let arm = at * (point - p.origin) - p.centre;
                    acc[i].0 += f;
                    acc[i].1 += arm.cross(&f) + at * (sign * l.moment);
                }
            };
            if !matches!(e, Element::CarriedMass { .. }) {
                apply(a, -1.0, &l.point_a);
            }
            apply(b, 1.0, &l.point_b);
        }
    }

    /// Evaluates the system at (t, x): accelerations into `dxdt` (when given; the sample is then
    /// left empty, the right-hand side needing none) or the sample (without `dxdt`).
    pub fn evaluate(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: Option<&mut [f64]>,
    ) -> Result<VehicleSample, DynamicsError> {
        self.evaluate_parts(data, t, x, dxdt, Parts::ALL)
    }

    /// Which parts of the right-hand side the rows `rows` (blocks (offset, size)) need.
    fn parts_for(&self, rows: &[(usize, usize)]) -> Parts {
        let split = self.wheelset_offset(0);
        Parts {
            bodies: rows.iter().any(|&(o, _)| o < split),
            wheelsets: rows.iter().any(|&(o, m)| o + m > split),
            keep: false,
            quiet: 0,
        }
    }

    /// [`Self::evaluate`] with only the `parts` a caller reads: the bodies' rows, the wheelsets'
    /// rows. Every wheelset's kinematics is solved either way (its pose loads the elements), or
    /// taken from its [`KinematicsMemo`] where the time and its slot are the memo's to the bit.
    fn evaluate_parts(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: Option<&mut [f64]>,
        parts: Parts,
    ) -> Result<VehicleSample, DynamicsError> {
        let clock = data.part_times.is_some().then(Instant::now);
        let mut lap = clock;
        let (v, v_dot) = self.reference.speed_at(t);
        let s_ref = self.reference.s_ref(t);
        let nb = self.bodies.len();
        let nw = self.wheelsets.len();
        let mut poses = Vec::with_capacity(nb + nw);
        let mut frames = Vec::with_capacity(nb + nw);
        let mut motions = Vec::with_capacity(nb + nw);
        // A right-hand side (dxdt given) builds no sample: only the output asks for one.
        let sampling = dxdt.is_none();
        let mut body_samples = Vec::with_capacity(if sampling { nb } else { 0 });
        for (i, b) in self.bodies.iter().enumerate() {
            let o = self.body_offset(i);
            let q = &x[o..o + 6];
            let qd = &x[o + 6..o + 12];
            let s = s_ref + b.d + q[0];
            let f = self
                .reference
                .frame_of_body(s, v, v_dot)
                .map_err(|source| DynamicsError::Track { s, source })?;
            poses.push(Pose {
                origin: f.origin,
                rotation: f.rotation,
                centre: Vector3::new(0.0, q[1], b.h + q[2]),
                theta: Vector3::new(q[3], q[4], q[5]),
                centre_velocity: Vector3::new(qd[0], qd[1], qd[2]),
                theta_dot: Vector3::new(qd[3], qd[4], qd[5]),
                speed: v,
                omega_t: v3(f.motion.omega),
            });
            frames.push(frame_loads(&f.motion));
            motions.push(f.motion);
            if sampling {
                body_samples.push(BodySample {
                    s,
                    q: [q[0], q[1], q[2], q[3], q[4], q[5]],
                    q_dot: [qd[0], qd[1], qd[2], qd[3], qd[4], qd[5]],
                });
            }
        }
        lap_into(&mut data.part_times, &mut lap, |p| &mut p.body_frames_s);
        // Each wheelset's contact kinematics depends only on its own state and warm start: the
        // wheelsets are evaluated in parallel (the results, errors included, in wheelset order).
        let kinematics: Vec<Result<_, DynamicsError>> = data
            .warm
            .par_iter_mut()
            .zip(data.kinematics_memo.par_iter_mut())
            .enumerate()
            .with_min_len(WHEELSETS_PER_TASK)
            .map(|(j, (warm, memo))| {
                let o = self.wheelset_offset(j);
                let slot = &x[o..o + self.wheelset_size(j)];
                let st = WheelsetState::read(slot, self.is_irw(j));
                if let Some(m) = memo.as_ref().filter(|m| m.matches(t, slot)) {
                    let s = s_ref + self.wheelsets[j].d + st.x;
                    return Ok((st, m.kin.clone(), m.frame, s, m.pose.clone()));
                }
                let (kin, f, s) = self.wheelset_kinematics(warm, j, &st, s_ref, v, v_dot)?;
                // The pose: the two-point configuration moved by a lifted wheel's θ.
                let pose = kin
                    .pose(&st)
                    .map_err(DynamicsError::wheelset(&self.wheelsets[j].name, st.y))?;
                if parts.keep {
                    KinematicsMemo::keep(memo, t, slot, &kin, &pose, f);
                }
                Ok((st, kin, f, s, pose))
            })
            .collect();
        data.contact_evaluations += nw;
        let mut ws_states = Vec::with_capacity(nw);
        let mut kins = Vec::with_capacity(nw);
        let mut ws_s = Vec::with_capacity(nw);
        let mut ws_rails = Vec::with_capacity(nw);
        for r in kinematics {
            let (st, kin, f, s, pose) = r?;
            poses.push(Pose {
                origin: f.origin,
                rotation: f.rotation,
                centre: Vector3::new(0.0, st.y, pose.z),
                theta: Vector3::new(pose.phi, 0.0, st.psi),
                centre_velocity: Vector3::new(st.x_dot, st.y_dot, pose.z_dot),
                theta_dot: Vector3::new(pose.phi_dot, 0.0, st.psi_dot),
                speed: v,
                omega_t: v3(f.motion.omega),
            });
            frames.push(frame_loads(&f.motion));
            motions.push(f.motion);
            ws_states.push(st);
            kins.push((kin, pose));
            ws_s.push(s);
            ws_rails.push(f.rails.q);
        }
        lap_into(&mut data.part_times, &mut lap, |p| &mut p.contact_kinematics_s);
        let loads = self.element_loads(&poses, &frames, s_ref, v, v_dot)?;
        let mut acc = vec![(Vector3::zeros(), Vector3::zeros()); nb + nw];
        self.accumulate(&poses, &loads, &mut acc);
        let (traction, mut torques, ramp) = self.drive_at(t, x, &loads, &poses);
        if sampling {
            self.check_drive(t, &traction)?;
        }
        for &(j, carrier) in &self.drive.driven {
            if let Some(i) = carrier {
                acc[i].1.y -= torques[j][0] + torques[j][1];
            }
        }
        if ramp != 0.0 {
            // The ramp's inertia, prescribed: m V̇ on every mass, I V̇ / r₀ on every wheel.
            for (i, b) in self.bodies.iter().enumerate() {
                acc[i].0.x += b.mass_kg * ramp;
            }
            for (j, w) in self.wheelsets.iter().enumerate() {
                acc[nb + j].0.x += w.inertia.mass_kg * ramp;
                let per_wheel = match w.inertia.irw {
                    Some(irw) => irw.wheel_spin_kg_m2,
                    None => 0.5 * w.inertia.inertia_kg_m2[1],
                } * ramp
                    / self.r0;
                torques[j][0] += per_wheel;
                torques[j][1] += per_wheel;
            }
        }
        lap_into(&mut data.part_times, &mut lap, |p| &mut p.elements_s);
        let mut dxdt = dxdt;
        let mut qdd: Vec<[Vector3<f64>; 2]> = Vec::with_capacity(nb);
        // The bodies' rows (skipped where only the wheelsets' are read).
        for (i, b) in self
            .bodies
            .iter()
            .enumerate()
            .take(if parts.bodies { nb } else { 0 })
        {
            let m = &motions[i];
            let p = &poses[i];
            let (f, mo) = acc[i];
            let (w_t, a_t, al_t, g_t) = (v3(m.omega), v3(m.accel), v3(m.alpha), v3(m.gravity));
            let r = p.centre;
            let r_dot = p.centre_velocity;
            let acc_lin = f / b.mass_kg + g_t
                - a_t
                - 2.0 * w_t.cross(&r_dot)
                - al_t.cross(&r)
                - w_t.cross(&w_t.cross(&r));
            let w = w_t + p.theta_dot;
            let iw = b.inertia.component_mul(&w);
            let acc_rot = (mo - w.cross(&iw)).component_div(&b.inertia) - al_t;
            qdd.push([acc_lin, acc_rot]);
        }
        let joint_error = if parts.bodies {
            self.apply_joints(&poses, &motions, &mut qdd)?
        } else {
            Vec::new()
        };
        if let Some(d) = dxdt.as_deref_mut() {
            for (i, q) in qdd.iter().enumerate() {
                let o = self.body_offset(i);
                for k in 0..6 {
                    d[o + k] = x[o + 6 + k];
                }
                for k in 0..3 {
                    d[o + 6 + k] = q[0][k];
                    d[o + 9 + k] = q[1][k];
                }
            }
        }
        // Each wheelset's dynamics depends only on its own state, loads and normal-force start:
        // in parallel, as the kinematics.
        lap_into(&mut data.part_times, &mut lap, |p| &mut p.bodies_s);
        if !parts.wheelsets {
            return Ok(VehicleSample::default());
        }
        let dynamics: Vec<Result<Option<WheelsetDynamics>, DynamicsError>> = data
            .normal_start
            .par_iter_mut()
            .enumerate()
            .with_min_len(WHEELSETS_PER_TASK)
            .map(|(j, start)| {
                if parts.quiet >> j & 1 == 1 {
                    return Ok(None);
                }
                let (f, mo) = acc[nb + j];
                let load = Load {
                    force: f.into(),
                    moment: mo.into(),
                    drive_torque: torques[j],
                };
                kins[j]
                    .0
                    .evaluate(
                        &self.wheelsets[j].inertia,
                        &ws_states[j],
                        &motions[nb + j],
                        &load,
                        &self.forces,
                        start,
                        self.reference.lateral_flexibility().as_ref(),
                    )
                    .map(Some)
                    .map_err(DynamicsError::wheelset(&self.wheelsets[j].name, ws_states[j].y))
            })
            .collect();
        lap_into(&mut data.part_times, &mut lap, |p| &mut p.wheelset_dynamics_s);
        if let (Some(p), Some(c)) = (data.part_times.as_mut(), clock) {
            p.total_s += c.elapsed().as_secs_f64();
            p.evaluations += 1;
        }
        let mut ws_samples = Vec::with_capacity(if sampling { nw } else { 0 });
        for (j, (dynamics, (_, pose))) in dynamics.into_iter().zip(kins).enumerate() {
            let Some(dynamics) = dynamics? else {
                continue;
            };
            if let Some(d) = dxdt.as_deref_mut() {
                let o = self.wheelset_offset(j);
                WheelsetState::write_rates(&x[o..], &mut d[o..], &dynamics, self.is_irw(j));
                continue;
            }
            ws_samples.push(WheelsetSample {
                state: ws_states[j],
                kin: pose,
                dynamics,
                speed: v + ws_states[j].x_dot,
                reference_speed: v,
                drive_torque: torques[j],
                s: ws_s[j],
                rails: ws_rails[j],
            });
        }
        let floor = if sampling && parts.bodies {
            self.floor_accelerations(&poses, &motions, &qdd)
        } else {
            Vec::new()
        };
        Ok(VehicleSample {
            floor,
            bodies: body_samples,
            wheelsets: ws_samples,
            elements: if sampling {
                loads.iter().map(|l| (l.deflection, l.local_force)).collect()
            } else {
                Vec::new()
            },
            joint_error,
            traction,
        })
    }

    /// Spherical joints (DYNAMICS.md §5): corrects the bodies' unconstrained accelerations q̈₀ by
    /// the joint reactions, q̈ = q̈₀ + M⁻¹ Jᵀ μ with (J M⁻¹ Jᵀ) μ = γ − J q̈₀. Per joint, in the
    /// first body's track axes (R = A_aᵀ A_b): the absolute accelerations of the joint point on both
    /// bodies agree, R (k_b + r̈_b − [p_b]× Θ̈_b) − (k_a + r̈_a − [p_a]× Θ̈_a) = −2ω_c ė − ω_c² e,
    /// with k = a_t + α_t × ρ + ω_t × (ω_t × ρ) + 2 ω_t × ρ̇ + Θ̇ × (Θ̇ × p) the part without
    /// the body's accelerations (ρ the point in the body-track frame) and e, ė the violation
    /// (Baumgarte). Returns |e| per joint.
    fn apply_joints(
        &self,
        poses: &[Pose],
        motions: &[FrameMotion],
        qdd: &mut [[Vector3<f64>; 2]],
    ) -> Result<Vec<f64>, DynamicsError> {
        let nj = self.joints.len();
        if nj == 0 {
            return Ok(Vec::new());
        }
        let skew = |p: &Vector3<f64>| p.cross_matrix();
        let k_of = |i: usize, p: &Vector3<f64>| point_acceleration_part(&poses[i], &motions[i], p);
        // J (3 nj × 6 nb) is sparse: joint r's rows hold a 3×6 block [lin | ang] for each of its
        // two bodies. So S = J M⁻¹ Jᵀ is built block by block (joints r, s couple through a
        // shared body), with the same result as the dense products at a fraction of their cost.
        let mut blocks: Vec<[(usize, Matrix3x6<f64>); 2]> = Vec::with_capacity(nj);
        let mut gamma = DVector::<f64>::zeros(3 * nj);
        let mut errors = Vec::with_capacity(nj);
        let wc = JOINT_STABILISATION_RAD_S;
        let block = |lin: Matrix3<f64>, ang: Matrix3<f64>| {
            let mut b = Matrix3x6::zeros();
            b.fixed_view_mut::<3, 3>(0, 0).copy_from(&lin);
            b.fixed_view_mut::<3, 3>(0, 3).copy_from(&ang);
            b
        };
        for (r, jt) in self.joints.iter().enumerate() {
            let (pa, pb) = (&poses[jt.a], &poses[jt.b]);
            let at = pa.rotation.transpose();
            let rot = at * pb.rotation;
            let e = at * (pb.point(&jt.arm_b) - pa.point(&jt.arm_a));
            let e_dot = at * (pb.point_velocity(&jt.arm_b) - pa.point_velocity(&jt.arm_a));
            errors.push(e.norm());
            let g = -2.0 * wc * e_dot - wc * wc * e - (rot * k_of(jt.b, &jt.arm_b) - k_of(jt.a, &jt.arm_a));
            blocks.push([
                (jt.a, block(-Matrix3::identity(), skew(&jt.arm_a))),
                (jt.b, block(rot, -rot * skew(&jt.arm_b))),
            ]);
            gamma.rows_mut(3 * r, 3).copy_from(&g);
        }
        let minv = |i: usize| {
            let b = &self.bodies[i];
            Vector6::new(
                1.0 / b.mass_kg,
                1.0 / b.mass_kg,
                1.0 / b.mass_kg,
                1.0 / b.inertia[0],
                1.0 / b.inertia[1],
                1.0 / b.inertia[2],
            )
        };
        let q0 = |i: usize| {
            let q = &qdd[i];
            Vector6::new(q[0][0], q[0][1], q[0][2], q[1][0], q[1][1], q[1][2])
        };
        // S and γ − J q̈₀.
        let mut schur = DMatrix::<f64>::zeros(3 * nj, 3 * nj);
        for (r, bl) in blocks.iter().enumerate() {
            for &(body, b) in bl {
                let rhs = b * q0(body);
                let mut g = gamma.fixed_rows_mut::<3>(3 * r);
                g -= rhs;
                let bm = b * Matrix6::from_diagonal(&minv(body));
                for (s, bl_s) in blocks.iter().enumerate() {
                    for &(body_s, bs) in bl_s {
                        if body_s == body {
                            let mut v = schur.fixed_view_mut::<3, 3>(3 * r, 3 * s);
                            v += bm * bs.transpose();
                        }
                    }
                }
            }
        }
        let mu = schur.lu().solve(&gamma).ok_or(DynamicsError::JointsSingular)?;
        // q̈ += M⁻¹ Jᵀ μ.
        for (r, bl) in blocks.iter().enumerate() {
            let m = mu.fixed_rows::<3>(3 * r);
            for &(body, b) in bl {
                let dq = (b.transpose() * m).component_mul(&minv(body));
                let q = &mut qdd[body];
                for k in 0..3 {
                    q[0][k] += dq[k];
                    q[1][k] += dq[3 + k];
                }
            }
        }
        Ok(errors)
    }

    /// Static residual of the bodies (6 per body: force, moment in track axes) with body
    /// displacements `u`, wheelsets centred (z, φ from the contact model at y = 0), on level
    /// tangent track at rest.
    ///
    /// The joints act as stiff penalty springs plus `joint_static` (global force on each joint's
    /// second body, the reactions found by the settling); returns the residual, the element loads
    /// and the joints' penalty forces.
    fn static_residual(
        &self,
        u: &[f64],
        wheelset_poses: &[Pose],
        joint_static: &[Vector3<f64>],
    ) -> Result<StaticState, DynamicsError> {
        let nb = self.bodies.len();
        let mut poses = Vec::with_capacity(nb + wheelset_poses.len());
        for (i, b) in self.bodies.iter().enumerate() {
            let q = &u[6 * i..6 * i + 6];
            poses.push(Pose {
                origin: Vector3::new(b.d + q[0], 0.0, 0.0),
                rotation: Matrix3::identity(),
                centre: Vector3::new(0.0, q[1], b.h + q[2]),
                theta: Vector3::new(q[3], q[4], q[5]),
                centre_velocity: Vector3::zeros(),
                theta_dot: Vector3::zeros(),
                speed: 0.0,
                omega_t: Vector3::zeros(),
            });
        }
        poses.extend_from_slice(wheelset_poses);
        let level = FrameLoads {
            accel: Vector3::zeros(),
            alpha: Vector3::zeros(),
            gravity: Vector3::new(0.0, 0.0, -G),
        };
        let frames = vec![level; poses.len()];
        let mut loads = Vec::with_capacity(self.elements.len());
        for e in &self.elements {
            let (a, b) = e.ends();
            let end = |r: BodyRef, arm_x: f64| match r {
                BodyRef::Body(i) => poses[i],
                BodyRef::Track => Pose {
                    origin: Vector3::new(arm_x, 0.0, 0.0),
                    rotation: Matrix3::identity(),
                    centre: Vector3::new(-arm_x, 0.0, 0.0),
                    theta: Vector3::zeros(),
                    centre_velocity: Vector3::zeros(),
                    theta_dot: Vector3::zeros(),
                    speed: 0.0,
                    omega_t: Vector3::zeros(),
                },
            };
            let (xa, xb) = match e {
                Element::Bushing { arm_a, arm_b, .. } | Element::Axial { arm_a, arm_b, .. } => {
                    (arm_a.x, arm_b.x)
                }
                Element::CarriedMass { arm, .. } => (arm.x, arm.x),
            };
            loads.push(e.load(&end(a, xa), &end(b, xb), &level));
        }
        let mut acc = vec![(Vector3::zeros(), Vector3::zeros()); poses.len()];
        self.accumulate(&poses, &loads, &mut acc);
        // The joints, as stiff penalty springs (statics only).
        let mut penalty = Vec::with_capacity(self.joints.len());
        for (k, jt) in self.joints.iter().enumerate() {
            let (pa, pb) = (&poses[jt.a], &poses[jt.b]);
            let (ga, gb) = (pa.point(&jt.arm_a), pb.point(&jt.arm_b));
            let f_pen = -JOINT_PENALTY_N_PER_M * (gb - ga);
            penalty.push(f_pen);
            let f = f_pen + joint_static.get(k).copied().unwrap_or_else(Vector3::zeros);
            for (i, sign, g) in [(jt.b, 1.0, gb), (jt.a, -1.0, ga)] {
                let arm = g - poses[i].origin - poses[i].centre;
                acc[i].0 += sign * f;
                acc[i].1 += arm.cross(&(sign * f));
            }
        }
        let mut r = DVector::zeros(6 * nb);
        for (i, b) in self.bodies.iter().enumerate() {
            let f = acc[i].0 + b.mass_kg * frames[i].gravity;
            for k in 0..3 {
                r[6 * i + k] = f[k];
                r[6 * i + 3 + k] = acc[i].1[k];
            }
        }
        Ok((r, loads, penalty))
    }

    /// Settles the bodies under gravity and preloads the elements with their static forces (see
    /// the module doc). Returns the static sag the preloads replace, the residual and the static
    /// wheel loads.
    fn settle(&mut self) -> Result<Settling, DynamicsError> {
        let nb = self.bodies.len();
        let mut warm = WarmStart::default();
        let kin = self
            .contact
            .kinematics(0.0, 0.0, &RailMotion::default(), &mut warm)
            .map_err(DynamicsError::CentredContact)?;
        let ws_poses: Vec<Pose> = self
            .wheelsets
            .iter()
            .map(|w| Pose {
                origin: Vector3::new(w.d, 0.0, 0.0),
                rotation: Matrix3::identity(),
                centre: Vector3::new(0.0, 0.0, kin.z),
                theta: Vector3::new(kin.phi, 0.0, 0.0),
                centre_velocity: Vector3::zeros(),
                theta_dot: Vector3::zeros(),
                speed: 0.0,
                omega_t: Vector3::zeros(),
            })
            .collect();
        let n = 6 * nb;
        let mut u = vec![0.0; n];
        let weight: f64 = self.bodies.iter().map(|b| b.mass_kg * G).sum::<f64>().max(1.0);
        // One step of Newton from the nominal geometry: the linear statics, with which the
        // linearised preloads below are consistent. (Iterating to the nonlinear settled state and
        // then linearising left the nominal state out of balance by the elements' second-order
        // forces: on the MS vehicle 5.9 kN from the traction rods, horizontal 1 m rods whose length
        // changes by 0.8 mm when the secondary sags 40 mm.)
        let (r, nominal, _) = self.static_residual(&u, &ws_poses, &[])?;
        if n > 0 && r.amax() >= 1e-9 * weight {
            let mut jac = DMatrix::zeros(n, n);
            let h = 1e-7;
            for k in 0..n {
                let mut up = u.clone();
                up[k] += h;
                let (rp, _, _) = self.static_residual(&up, &ws_poses, &[])?;
                jac.set_column(k, &((rp - &r) / h));
            }
            let names = || {
                self.bodies
                    .iter()
                    .map(|b| b.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let du = jac
                .lu()
                .solve(&(-&r))
                .ok_or_else(|| DynamicsError::StaticsSingular { bodies: names() })?;
            u.copy_from_slice(du.as_slice());
        }
        // The static forces by the linearisation at the nominal geometry (the settled state is
        // centimetres away; its rotated lever arms must not enter the preloads): loads at ε u,
        // extrapolated to u.
        let eps = 1e-6;
        let small: Vec<f64> = u.iter().map(|v| v * eps).collect();
        let (_, settled, penalty) = self.static_residual(&small, &ws_poses, &[])?;
        for ((e, ls), ln) in self.elements.iter_mut().zip(&settled).zip(&nominal) {
            let extrapolated = ElementLoad {
                force: ln.force + (ls.force - ln.force) / eps,
                moment: ln.moment + (ls.moment - ln.moment) / eps,
                local_force: ln.local_force + (ls.local_force - ln.local_force) / eps,
                ..*ln
            };
            e.set_preload(&extrapolated, ln);
            e.set_moment_preload(&extrapolated.moment, &ln.moment);
        }
        // The joints' static reactions (at run time the joint constraints supply them).
        let joint_static: Vec<Vector3<f64>> = penalty.iter().map(|f| f / eps).collect();
        // Check: at the nominal configuration the preloaded elements and the joints' reactions
        // balance gravity (the settling's residual is this one: the linear step's own is only
        // the elements' nonlinearity over the sag).
        let (r, loads, _) = self.static_residual(&vec![0.0; n], &ws_poses, &joint_static)?;
        let residual = r.amax();
        let mut all_poses: Vec<Pose> = self
            .bodies
            .iter()
            .map(|b| Pose {
                origin: Vector3::new(b.d, 0.0, 0.0),
                rotation: Matrix3::identity(),
                centre: Vector3::new(0.0, 0.0, b.h),
                theta: Vector3::zeros(),
                centre_velocity: Vector3::zeros(),
                theta_dot: Vector3::zeros(),
                speed: 0.0,
                omega_t: Vector3::zeros(),
            })
            .collect();
        all_poses.extend_from_slice(&ws_poses);
        let mut acc = vec![(Vector3::zeros(), Vector3::zeros()); all_poses.len()];
        self.accumulate(&all_poses, &loads, &mut acc);
        let axle_loads: Vec<f64> = self
            .wheelsets
            .iter()
            .enumerate()
            .map(|(j, w)| -acc[nb + j].0.z + w.inertia.mass_kg * G)
            .collect();
        Ok(Settling {
            sag: (0..nb)
                .map(|i| {
                    [
                        u[6 * i],
                        u[6 * i + 1],
                        u[6 * i + 2],
                        u[6 * i + 3],
                        u[6 * i + 4],
                        u[6 * i + 5],
                    ]
                })
                .collect(),
            residual,
            axle_loads,
        })
    }
}

impl VehicleModel for Multibody {
    fn dim(&self) -> usize {
        12 * self.bodies.len()
            + (0..self.wheelsets.len())
                .map(|j| self.wheelset_size(j))
                .sum::<usize>()
    }

    fn wheelset_names(&self) -> Vec<String> {
        self.wheelsets.iter().map(|w| w.name.clone()).collect()
    }

    fn body_names(&self) -> Vec<String> {
        self.bodies.iter().map(|b| b.name.clone()).collect()
    }

    fn initial_state(&self, initial: &InitialDisturbance) -> Vec<f64> {
        let mut x = self.initial(initial.lateral_m, initial.yaw_rad);
        for j in 0..self.wheelsets.len() {
            x[self.wheelset_offset(j) + 4] = initial.lateral_velocity_m_s;
        }
        for i in 0..self.bodies.len() {
            x[self.body_offset(i) + 7] = initial.lateral_velocity_m_s;
        }
        x
    }

    /// Fresh warm starts; each wheel's normal force starts from half its static axle load.
    fn new_data(&self) -> VehicleData {
        VehicleData::new(
            self.settling
                .axle_loads
                .iter()
                .map(|q| [0.5 * q, 0.5 * q])
                .collect(),
        )
    }

    fn rhs(&self, data: &mut VehicleData, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), DynamicsError> {
        self.evaluate(data, t, x, Some(dxdt)).map(|_| ())
    }

    /// The rows of a finite-difference pass: the bogie frames' pass skips the wheelsets'
    /// dynamics (and takes their kinematics from the memo: their states are f(t, x)'s), the
    /// wheelsets' pass the bodies' accelerations and the joints.
    fn rhs_rows(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        rows: &[(usize, usize)],
    ) -> Result<(), DynamicsError> {
        self.evaluate_parts(data, t, x, Some(dxdt), self.parts_for(rows))
            .map(|_| ())
    }

    /// A Newton iteration's right-hand side without the quiet wheelsets' dynamics (their
    /// kinematics solved all the same: their poses load the elements).
    fn rhs_reusing(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        quiet: &[bool],
    ) -> Result<(), DynamicsError> {
        let mask = quiet
            .iter()
            .enumerate()
            .filter(|(_, &q)| q)
            .fold(0u64, |m, (j, _)| m | 1 << j);
        self.evaluate_parts(
            data,
            t,
            x,
            Some(dxdt),
            Parts {
                quiet: mask,
                ..Parts::ALL
            },
        )
        .map(|_| ())
    }

    /// Up to 64 wheelsets (the quiet ones a bit mask).
    fn reuses_wheelsets(&self) -> bool {
        self.wheelsets.len() <= 64
    }

    fn sample(&self, data: &mut VehicleData, t: f64, x: &[f64]) -> Result<VehicleSample, DynamicsError> {
        self.evaluate(data, t, x, None)
    }

    fn wheelset_slots(&self) -> Vec<(usize, usize)> {
        (0..self.wheelsets.len())
            .map(|j| (self.wheelset_offset(j), self.wheelset_size(j)))
            .collect()
    }

    fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
        (0..self.bodies.len())
            .map(|i| (self.body_offset(i), 12))
            .collect()
    }

    fn newton_groups(&self) -> Vec<Vec<(usize, usize)>> {
        let mut groups = vec![self.wheelset_slots()];
        groups.extend(self.stiff_body_groups());
        groups
    }

    /// None with the elastic model (its slots hold the free pose; no landing events).
    fn lift_offsets(&self) -> Vec<usize> {
        if !Kind::of(self.contact.as_ref()).lands() {
            return Vec::new();
        }
        (0..self.wheelsets.len())
            .map(|j| self.wheelset_offset(j) + WheelsetState::lift_index(self.is_irw(j)))
            .collect()
    }

    fn land(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &mut [f64],
        wheelset: usize,
        side: usize,
    ) -> Result<Option<Landing>, DynamicsError> {
        let j = wheelset;
        let (o, irw) = (self.wheelset_offset(j), self.is_irw(j));
        let mut st = WheelsetState::read(&x[o..], irw);
        let (v, v_dot) = self.reference.speed_at(t);
        let (kin, _, _) =
            self.wheelset_kinematics(&mut data.warm[j], j, &st, self.reference.s_ref(t), v, v_dot)?;
        let landing = kin
            .land(
                &self.wheelsets[j].inertia,
                &mut st,
                self.reference.lateral_flexibility().as_ref(),
                side,
            )
            .map_err(DynamicsError::wheelset(&self.wheelsets[j].name, st.y))?;
        st.write(&mut x[o..], irw);
        Ok(landing)
    }

    fn contact(&self) -> &dyn ContactModel {
        self.contact.as_ref()
    }

    fn reference(&self) -> &Reference {
        &self.reference
    }

    fn nominal_radius(&self) -> f64 {
        self.r0
    }

    fn settling(&self) -> Option<&Settling> {
        Some(&self.settling)
    }

    fn drive_info(&self) -> DriveInfo {
        let (mode, controller_hz) = match self.drive.law {
            TractionLaw::Coast => ("coast", None),
            TractionLaw::Force { .. } => ("force", None),
            TractionLaw::HoldSpeed(l) => ("hold_speed", Some(l.bandwidth_hz)),
            TractionLaw::Tied => ("tied", None),
        };
        let driven = match self.drive.law {
            TractionLaw::Tied => Vec::new(),
            _ => self
                .drive
                .driven
                .iter()
                .map(|&(j, _)| self.wheelsets[j].name.clone())
                .collect(),
        };
        DriveInfo {
            mode,
            controller_hz,
            driven_wheelsets: driven,
            weight_n: self.settling.axle_loads.iter().sum(),
            effective_mass_kg: self.drive.effective_mass_kg,
        }
    }

    fn floor_points(&self) -> Vec<FloorPoint> {
        self.floor_points.clone()
    }
}
