//! The `[vehicle]` table of a scenario, as written: `kind = "wheelset-on-frame"` (one wheelset
//! tied to a frame moving along the track) or `kind = "multibody"` — bodies, wheelsets and force
//! elements (nominal vehicle coordinates, SI units), validated into [`super::Element`]s:
//!
//! ```toml
//! [vehicle]
//! kind = "multibody"
//! [[vehicle.bodies]]
//! name = "bogie"
//! mass_kg = 2615.0
//! inertia_kg_m2 = [1722.0, 1476.0, 3067.0]   # about x (roll), y (pitch), z (yaw)
//! position_m = [0.0, 0.0, 0.6]               # x along the vehicle, y = 0, CG height above rail
//! # floor_height_m = 0.35                     # a carbody's floor above the rail (ride comfort)
//! [[vehicle.wheelsets]]
//! name = "wheelset_1"
//! x_m = 1.28
//! mass_kg = 1813.0
//! inertia_kg_m2 = [1120.0, 112.0, 1120.0]
//! [[vehicle.elements]]
//! type = "bushing"                           # or "axial", "rotational", "carried_mass"
//! name = "primary_1_left"
//! bodies = ["bogie", "wheelset_1"]           # "track": the ideal track-following reference
//! at_m = [1.28, 1.0, 0.46]
//! stiffness = [31.391e6, 3.884e6, 1.22e6, 0.0, 0.0, 0.0]
//! damping = [15e3, 2e3, 4e3, 0.0, 0.0, 0.0]
//! [[vehicle.joints]]                         # spherical joint between two rigid bodies
//! name = "articulation"
//! bodies = ["carbody_1", "carbody_2"]
//! at_m = [6.0, 0.0, 1.8]
//! ```

use nalgebra::Vector3;
use serde::Deserialize;

use super::elements::{BodyRef, Element};

/// `[vehicle]`: the model of the scene. Each kind models only what the scene needs.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum VehicleSpec {
    /// One solid-axle wheelset tied by spring–dampers at its axle boxes to a frame moving at the
    /// reference speed, which also carries the axle load.
    WheelsetOnFrame(WheelsetOnFrameSpec),
    /// Rigid bodies, solid-axle wheelsets and force elements ([`crate::vehicle::spec`]): a bogie,
    /// a whole vehicle.
    Multibody(MultibodySpec),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetOnFrameSpec {
    /// Vertical load of the frame on the wheelset (both boxes), N.
    pub axle_load_n: f64,
    pub wheelset: WheelsetMassSpec,
    pub tie: TieSpec,
}

/// Wheelset mass and principal inertias (roll, spin, yaw).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetMassSpec {
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
}

/// Axle-box tie (per box).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TieSpec {
    pub longitudinal_stiffness_n_per_m: f64,
    pub lateral_stiffness_n_per_m: f64,
    #[serde(default)]
    pub longitudinal_damping_n_s_per_m: f64,
    #[serde(default)]
    pub lateral_damping_n_s_per_m: f64,
    pub half_spacing_m: f64,
}

/// The name of the one wheelset of a [`VehicleSpec::WheelsetOnFrame`] (its CSV: `NAME.csv`).
pub const SINGLE_WHEELSET_NAME: &str = "wheelset_1";

impl VehicleSpec {
    /// The wheelsets' names in output order (one CSV each in `kecsim run --csv DIR`), known
    /// before the model is built.
    pub fn wheelset_names(&self) -> Vec<String> {
        match self {
            VehicleSpec::WheelsetOnFrame(_) => vec![SINGLE_WHEELSET_NAME.to_string()],
            VehicleSpec::Multibody(m) => m.wheelsets.iter().map(|w| w.name.clone()).collect(),
        }
    }

    /// The carbodies' names ([`MultibodySpec::carbodies`]; the single wheelset has none): each
    /// gets a CSV of its floor accelerations in `kecsim run --csv DIR`, known before the model is
    /// built so that the output guard covers those files too.
    pub fn carbody_names(&self) -> Vec<String> {
        match self {
            VehicleSpec::WheelsetOnFrame(_) => Vec::new(),
            VehicleSpec::Multibody(m) => m
                .carbodies()
                .into_iter()
                .filter_map(|(i, _)| m.bodies.get(i).map(|b| b.name.clone()))
                .collect(),
        }
    }

    /// Every file `--csv DIR` writes, in `dir`: `NAME.csv` per wheelset
    /// ([`Self::wheelset_names`]), then per carbody ([`Self::carbody_names`]).
    pub fn csv_files(&self, dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        self.wheelset_names()
            .iter()
            .chain(&self.carbody_names())
            .map(|n| dir.join(format!("{n}.csv")))
            .collect()
    }

    /// The rearmost body's nominal position along the vehicle (≤ 0; the single wheelset: 0), m.
    pub fn rear_offset_m(&self) -> f64 {
        self.extent_m().0
    }

    /// The frontmost body's or wheelset's nominal position along the vehicle (≥ 0; the single
    /// wheelset: 0), m.
    pub fn front_offset_m(&self) -> f64 {
        self.extent_m().1
    }

    /// The rearmost and frontmost nominal positions of the bodies and wheelsets along the vehicle
    /// (the reference point, 0, included), m.
    fn extent_m(&self) -> (f64, f64) {
        match self {
            VehicleSpec::WheelsetOnFrame(_) => (0.0, 0.0),
            VehicleSpec::Multibody(m) => m
                .bodies
                .iter()
                .map(|b| b.position_m[0])
                .chain(m.wheelsets.iter().map(|w| w.x_m))
                .fold((0.0_f64, 0.0_f64), |(lo, hi), x| (lo.min(x), hi.max(x))),
        }
    }

    /// Number of wheelsets.
    pub fn wheelset_count(&self) -> usize {
        match self {
            VehicleSpec::WheelsetOnFrame(_) => 1,
            VehicleSpec::Multibody(m) => m.wheelsets.len(),
        }
    }

    /// The tables' entry counts read from the file: `bodies`, `wheelsets`, `elements`, `joints`
    /// (held to the limits by the scenario, [`crate::scenario`]).
    pub fn table_counts(&self) -> [(&'static str, usize); 4] {
        match self {
            VehicleSpec::WheelsetOnFrame(_) => {
                [("bodies", 0), ("wheelsets", 1), ("elements", 0), ("joints", 0)]
            }
            VehicleSpec::Multibody(m) => [
                ("bodies", m.bodies.len()),
                ("wheelsets", m.wheelsets.len()),
                ("elements", m.elements.len()),
                ("joints", m.joints.len()),
            ],
        }
    }

    /// Attachment points (elements' and joints') farther from a body they attach to than the
    /// vehicle is long, plus [`ATTACHMENT_MARGIN_M`] (its width and height): a position in mm
    /// typed as m, or a point meant for another body. Refused: such an element makes a lever
    /// hundreds of times the vehicle's size, and the run grinds at collapsed steps.
    pub fn far_attachments(&self, r0: f64) -> Vec<String> {
        let VehicleSpec::Multibody(m) = self else {
            return Vec::new();
        };
        let (rear, front) = self.extent_m();
        let reach = front - rear + ATTACHMENT_MARGIN_M;
        // A wheelset's elements hold it at its axle boxes, within a gauge of its centre.
        let centre = |name: &str| -> Option<(Vector3<f64>, bool)> {
            match m.lookup(name)? {
                BodyRef::Track => None,
                BodyRef::Body(i) => Some((nominal_centre(m, r0, i), i >= m.bodies.len())),
            }
        };
        let mut p = Vec::new();
        let mut check = |key: String, point: &[f64; 3], body: &str| {
            let Some((c, wheelset)) = centre(body) else { return };
            let d = (Vector3::from(*point) - c).norm();
            if d.is_finite() && wheelset && d > WHEELSET_REACH_M {
                p.push(format!(
                    "{key} = {point:?}: {d:.1} m from the centre of wheelset \"{body}\" (x_m = {}), which its elements hold at its axle boxes, within {WHEELSET_REACH_M} m — is the wheelset outside its bogie, or the point a position in mm given as m?",
                    c.x
                ));
            } else if d.is_finite() && d > reach {
                p.push(format!(
                    "{key} = {point:?}: {d:.1} m from the centre of \"{body}\", farther than the vehicle is long ({:.1} m) — a position in mm given as m, or a point of another body?",
                    front - rear
                ));
            }
        };
        for e in &m.elements {
            match e {
                ElementSpec::Bushing {
                    name, bodies, at_m, ..
                }
                | ElementSpec::Rotational {
                    name, bodies, at_m, ..
                } => {
                    for b in bodies {
                        check(format!("vehicle.elements[{name}].at_m"), at_m, b);
                    }
                }
                ElementSpec::Axial {
                    name,
                    bodies,
                    from_m,
                    to_m,
                    ..
                } => {
                    check(format!("vehicle.elements[{name}].from_m"), from_m, &bodies[0]);
                    check(format!("vehicle.elements[{name}].to_m"), to_m, &bodies[1]);
                }
                ElementSpec::CarriedMass { name, body, at_m, .. } => {
                    check(format!("vehicle.elements[{name}].at_m"), at_m, body);
                }
            }
        }
        for j in &m.joints {
            for b in &j.bodies {
                check(format!("vehicle.joints[{}].at_m", j.name), &j.at_m, b);
            }
        }
        p
    }

    /// Wheelsets closer to each other than their wheels' diameter (2 r0): two wheelsets at one
    /// position, or wheels that would overlap.
    pub fn spacing_problems(&self, r0: f64) -> Vec<String> {
        let VehicleSpec::Multibody(m) = self else {
            return Vec::new();
        };
        let mut p = Vec::new();
        for (i, a) in m.wheelsets.iter().enumerate() {
            for b in &m.wheelsets[i + 1..] {
                let gap = (a.x_m - b.x_m).abs();
                if gap < 2.0 * r0 {
                    p.push(format!(
                        "vehicle.wheelsets[{}]: x_m = {} is {gap:.3} m from wheelset {} (x_m = {}): their wheels (diameter {:.0} mm) would overlap",
                        b.name,
                        b.x_m,
                        a.name,
                        a.x_m,
                        2e3 * r0
                    ));
                }
            }
        }
        p
    }

    /// Physically doubtful but possible values (warnings, each naming its key): masses and radii
    /// of gyration outside what rail vehicles have.
    pub fn doubtful(&self) -> Vec<String> {
        let mut w = Vec::new();
        let mut light = Vec::new();
        // Radius of gyration sqrt(I/m) of a body of mass m about axis k.
        let mut gyration = |what: String, mass: f64, inertia: &[f64], lo: f64, hi: f64| {
            for (k, i) in inertia.iter().enumerate() {
                let r = (i / mass).sqrt();
                if r.is_finite() && !(lo..=hi).contains(&r) {
                    w.push(format!(
                        "vehicle.{what}.inertia_kg_m2[{k}] = {i}: radius of gyration {r:.3} m for {mass} kg, outside the {lo}..{hi} m of rail vehicles' bodies — check the value and its unit"
                    ));
                }
            }
        };
        match self {
            VehicleSpec::WheelsetOnFrame(f) => {
                gyration(
                    "wheelset".into(),
                    f.wheelset.mass_kg,
                    &f.wheelset.inertia_kg_m2,
                    0.1,
                    2.0,
                );
            }
            VehicleSpec::Multibody(m) => {
                for b in &m.bodies {
                    if b.mass_kg < DOUBTFUL_BODY_MASS_KG {
                        light.push(format!(
                            "vehicle.bodies[{}].mass_kg = {}: lighter than any rail vehicle body (bogie frames weigh 1–3 t, carbodies 10–40 t; g typed as kg?)",
                            b.name, b.mass_kg
                        ));
                    }
                    gyration(
                        format!("bodies[{}]", b.name),
                        b.mass_kg,
                        &b.inertia_kg_m2,
                        0.1,
                        30.0,
                    );
                }
                for ws in &m.wheelsets {
                    gyration(
                        format!("wheelsets[{}]", ws.name),
                        ws.mass_kg,
                        &ws.inertia_kg_m2,
                        0.1,
                        2.0,
                    );
                }
            }
        }
        w.extend(light);
        if let VehicleSpec::Multibody(m) = self {
            for e in &m.elements {
                w.extend(element_doubts(e));
            }
        }
        w
    }

    /// Problems with the values (empty when valid), each naming its key.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        match self {
            VehicleSpec::Multibody(m) => p.extend(m.problems()),
            VehicleSpec::WheelsetOnFrame(w) => {
                p.extend(inertia_problem("wheelset", &w.wheelset.inertia_kg_m2));
                let mut check = |name: &str, v: f64, lo: f64, hi: f64| {
                    if !(v.is_finite() && v >= lo && v <= hi) {
                        p.push(format!("vehicle.{name} = {v}: expected a value in [{lo}, {hi}]"));
                    }
                };
                check("axle_load_n", w.axle_load_n, 0.0, 1e7);
                check("wheelset.mass_kg", w.wheelset.mass_kg, 1.0, 1e5);
                for (i, v) in w.wheelset.inertia_kg_m2.iter().enumerate() {
                    check(&format!("wheelset.inertia_kg_m2[{i}]"), *v, 1e-3, 1e6);
                }
                check(
                    "tie.longitudinal_stiffness_n_per_m",
                    w.tie.longitudinal_stiffness_n_per_m,
                    0.0,
                    1e10,
                );
                check(
                    "tie.lateral_stiffness_n_per_m",
                    w.tie.lateral_stiffness_n_per_m,
                    0.0,
                    1e10,
                );
                check(
                    "tie.longitudinal_damping_n_s_per_m",
                    w.tie.longitudinal_damping_n_s_per_m,
                    0.0,
                    1e8,
                );
                check(
                    "tie.lateral_damping_n_s_per_m",
                    w.tie.lateral_damping_n_s_per_m,
                    0.0,
                    1e8,
                );
                check("tie.half_spacing_m", w.tie.half_spacing_m, 0.1, 3.0);
            }
        }
        p
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MultibodySpec {
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    pub wheelsets: Vec<WheelsetBodySpec>,
    #[serde(default)]
    pub elements: Vec<ElementSpec>,
    /// Spherical joints between rigid bodies (constraints with reactions).
    #[serde(default)]
    pub joints: Vec<JointSpec>,
}

/// `[[vehicle.joints]]`: a spherical joint at one point between two rigid bodies.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    pub name: String,
    pub bodies: [String; 2],
    pub at_m: [f64; 3],
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
    /// Nominal centre: [x along the vehicle, 0, height above the rail top], m.
    pub position_m: [f64; 3],
    /// A carbody's floor height above the rail top, m: where ride comfort is read (EN 12299's
    /// floor points). Absent: the centre's height.
    #[serde(default)]
    pub floor_height_m: Option<f64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetBodySpec {
    pub name: String,
    /// Nominal position along the vehicle, m.
    pub x_m: f64,
    pub mass_kg: f64,
    /// About x (roll), y (axle), z (yaw); an IRW-wheelset: of the whole (y unused).
    pub inertia_kg_m2: [f64; 3],
    /// Present: an IRW-wheelset, two independently rotating wheels on a non-rotating bridge.
    #[serde(default)]
    pub independent_wheels: Option<IrwSpec>,
    /// Its wheels are motored: the drive that holds the speed ([`crate::dynamics::traction`])
    /// acts through the wheelsets marked `true`; where none is, through every wheelset not
    /// marked `false` (none marked at all: every one). Every wheelset `false` drives none, which
    /// a scene with a drive refuses.
    #[serde(default)]
    pub motored: Option<bool>,
}

/// `independent_wheels = { wheel_spin_inertia_kg_m2 = … }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrwSpec {
    /// Each wheel about its axle, kg m².
    pub wheel_spin_inertia_kg_m2: f64,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BumpStopSpec {
    pub axis: Axis,
    pub clearance_m: f64,
    pub stiffness_n_per_m: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ElementSpec {
    /// 6-component bushing at one point (stiffness/damping in the first body's track axes:
    /// x, y, z in N/m and N s/m, then φ, θ, ψ in N m/rad and N m s/rad).
    Bushing {
        name: String,
        bodies: [String; 2],
        at_m: [f64; 3],
        #[serde(default)]
        stiffness: [f64; 6],
        #[serde(default)]
        damping: [f64; 6],
        #[serde(default)]
        bump_stops: Vec<BumpStopSpec>,
    },
    /// Spring–damper along the line between two points (traction rod, damper).
    Axial {
        name: String,
        bodies: [String; 2],
        from_m: [f64; 3],
        to_m: [f64; 3],
        #[serde(default)]
        stiffness_n_per_m: f64,
        #[serde(default)]
        damping_n_s_per_m: f64,
    },
    /// Rotational spring–damper about one axis (anti-roll bar: x; secondary bending: y, z).
    Rotational {
        name: String,
        bodies: [String; 2],
        at_m: [f64; 3],
        axis: Axis,
        stiffness_n_m_per_rad: f64,
        #[serde(default)]
        damping_n_m_s_per_rad: f64,
    },
    /// A mass carried along the track by a body at a point: its weight and the track frame's
    /// inertial forces load the body (e.g. half a carbody on a bogie scene).
    CarriedMass {
        name: String,
        body: String,
        at_m: [f64; 3],
        mass_kg: f64,
    },
}

/// Stiffness above which an element is doubtful, N/m or N m/rad (a wheel–rail contact is ~1e9 N/m;
/// rail vehicles' suspensions stay below 1e8).
const DOUBTFUL_STIFFNESS: f64 = 1e10;
/// Stiffness below which a non-zero element stiffness is doubtful, N/m or N m/rad (a unit
/// mistake: 31 N/m for 31 kN/mm).
const DOUBTFUL_SOFT_STIFFNESS: f64 = 1e3;
/// Body mass below which it is doubtful, kg (the lightest bodies a vehicle model carries — a
/// motor, a bolster — weigh hundreds of kg).
const DOUBTFUL_BODY_MASS_KG: f64 = 50.0;
/// Damping above which an element is doubtful, N s/m or N m s/rad.
const DOUBTFUL_DAMPING: f64 = 1e8;
/// Carried mass above which it is doubtful, kg.
const DOUBTFUL_CARRIED_MASS_KG: f64 = 1e5;

/// An element's doubtful values (warnings): stiffness, damping or a carried mass beyond what rail
/// vehicles have — usually a unit mistake (kN/m given in mN/m, kg in g).
fn element_doubts(e: &ElementSpec) -> Vec<String> {
    let mut w = Vec::new();
    let (name, k, c): (&String, Vec<f64>, Vec<f64>) = match e {
        ElementSpec::Bushing {
            name,
            stiffness,
            damping,
            ..
        } => (name, stiffness.to_vec(), damping.to_vec()),
        ElementSpec::Axial {
            name,
            stiffness_n_per_m,
            damping_n_s_per_m,
            ..
        } => (name, vec![*stiffness_n_per_m], vec![*damping_n_s_per_m]),
        ElementSpec::Rotational {
            name,
            stiffness_n_m_per_rad,
            damping_n_m_s_per_rad,
            ..
        } => (name, vec![*stiffness_n_m_per_rad], vec![*damping_n_m_s_per_rad]),
        ElementSpec::CarriedMass { name, mass_kg, .. } => {
            if *mass_kg > DOUBTFUL_CARRIED_MASS_KG {
                w.push(format!(
                    "vehicle.elements[{name}].mass_kg = {mass_kg}: above {DOUBTFUL_CARRIED_MASS_KG:e} kg, more than a whole rail vehicle"
                ));
            }
            return w;
        }
    };
    if let Some(v) = k.iter().copied().find(|v| *v > DOUBTFUL_STIFFNESS) {
        w.push(format!(
            "vehicle.elements[{name}]: stiffness {v:e} above {DOUBTFUL_STIFFNESS:e} (stiffer than the wheel–rail contact; a unit mistake?)"
        ));
    }
    if let Some(v) = k
        .iter()
        .copied()
        .find(|v| *v > 0.0 && *v < DOUBTFUL_SOFT_STIFFNESS)
    {
        w.push(format!(
            "vehicle.elements[{name}]: stiffness {v:e} below {DOUBTFUL_SOFT_STIFFNESS:e} (softer than any rail vehicle's suspension, whose springs are 1e4–1e8; kN/m or kN/mm typed as N/m?)"
        ));
    }
    if let Some(v) = c.iter().copied().find(|v| *v > DOUBTFUL_DAMPING) {
        w.push(format!(
            "vehicle.elements[{name}]: damping {v:e} above {DOUBTFUL_DAMPING:e} (a unit mistake?)"
        ));
    }
    w
}

/// Principal inertias no rigid body has: one larger than the sum of the other two (the triangle
/// inequality I_a + I_b ≥ I_c of every mass distribution). `key` names the entry.
fn inertia_problem(key: &str, i: &[f64; 3]) -> Option<String> {
    let violated = i.iter().all(|v| v.is_finite())
        && (0..3).any(|k| i[(k + 1) % 3] + i[(k + 2) % 3] < i[k] * (1.0 - 1e-9));
    violated.then(|| {
        format!(
            "vehicle.{key}.inertia_kg_m2 = {i:?}: no rigid body has these principal inertias (each must be at most the sum of the other two)"
        )
    })
}

/// How far beyond the vehicle's length an attachment point may lie from its body's centre, m
/// ([`VehicleSpec::far_attachments`]): a body's half-width and height, and a coupler's reach.
pub const ATTACHMENT_MARGIN_M: f64 = 5.0;

/// How far from a wheelset's centre its elements may attach, m: its axle boxes lie about a gauge
/// apart ([`VehicleSpec::far_attachments`]).
pub const WHEELSET_REACH_M: f64 = 3.0;

/// A problem found in the vehicle table.
pub type VehicleProblem = String;

/// Nominal centre of a system body (index over bodies, then wheelsets), vehicle coordinates.
pub fn nominal_centre(spec: &MultibodySpec, r0: f64, i: usize) -> Vector3<f64> {
    if i < spec.bodies.len() {
        Vector3::from(spec.bodies[i].position_m)
    } else {
        Vector3::new(spec.wheelsets[i - spec.bodies.len()].x_m, 0.0, r0)
    }
}

impl MultibodySpec {
    /// Index of a body by name (bodies first, then wheelsets), or the track reference.
    fn lookup(&self, name: &str) -> Option<BodyRef> {
        if name == "track" {
            return Some(BodyRef::Track);
        }
        self.bodies
            .iter()
            .map(|b| &b.name)
            .chain(self.wheelsets.iter().map(|w| &w.name))
            .position(|n| n == name)
            .map(BodyRef::Body)
    }

    /// The carbodies (indices into the bodies), each with the bogies joined to it by an element:
    /// where ride comfort is read (EN 12299's floor points). A bogie is a body that carries a
    /// wheelset (an element to one) and is joined by an element to a body that carries none; a
    /// carbody is a body that is neither a bogie nor carries a mass (a bogie scene's half
    /// carbody) — a two-axle vehicle's body on its wheelsets is one.
    pub fn carbodies(&self) -> Vec<(usize, Vec<usize>)> {
        let nb = self.bodies.len();
        let index = |name: &str| match self.lookup(name) {
            Some(BodyRef::Body(i)) => Some(i),
            _ => None,
        };
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        let mut carries_mass = vec![false; nb];
        for e in &self.elements {
            match e {
                ElementSpec::Bushing { bodies, .. }
                | ElementSpec::Axial { bodies, .. }
                | ElementSpec::Rotational { bodies, .. } => {
                    if let (Some(a), Some(b)) = (index(&bodies[0]), index(&bodies[1])) {
                        pairs.push((a, b));
                    }
                }
                ElementSpec::CarriedMass { body, .. } => {
                    if let Some(i) = index(body).filter(|&i| i < nb) {
                        carries_mass[i] = true;
                    }
                }
            }
        }
        let joined = |i: usize, k: usize| pairs.iter().any(|&p| p == (i, k) || p == (k, i));
        let carries_wheelset = |i: usize| (nb..nb + self.wheelsets.len()).any(|k| joined(i, k));
        let bogie =
            |i: usize| carries_wheelset(i) && (0..nb).any(|k| k != i && joined(i, k) && !carries_wheelset(k));
        (0..nb)
            .filter(|&i| !bogie(i) && !carries_mass[i])
            .map(|i| {
                (
                    i,
                    (0..nb).filter(|&k| k != i && bogie(k) && joined(i, k)).collect(),
                )
            })
            .collect()
    }

    /// The two rigid bodies of a validated joint (indices into the bodies).
    pub fn joint_bodies(&self, j: &JointSpec) -> (usize, usize) {
        let find = |n: &String| self.bodies.iter().position(|b| &b.name == n).expect("validated");
        (find(&j.bodies[0]), find(&j.bodies[1]))
    }

    /// Names of the system bodies in order (bodies, then wheelsets).
    pub fn body_names(&self) -> Vec<String> {
        self.bodies
            .iter()
            .map(|b| b.name.clone())
            .chain(self.wheelsets.iter().map(|w| w.name.clone()))
            .collect()
    }

    /// An over-constrained joint set: the spherical joints' constraint rows at the nominal
    /// geometry (3 per joint on the bodies' 6 coordinates each) not independent — two joints
    /// between the same bodies, a closed loop — which leaves their reactions undetermined.
    fn redundant_joints(&self) -> Option<String> {
        let nj = self.joints.len();
        let index = |n: &str| self.bodies.iter().position(|b| b.name == n);
        let pairs: Vec<(usize, usize, &JointSpec)> = self
            .joints
            .iter()
            .filter_map(|j| Some((index(&j.bodies[0])?, index(&j.bodies[1])?, j)))
            .collect();
        if nj == 0 || pairs.len() != nj {
            return None; // unknown bodies are reported on their own
        }
        let nb = self.bodies.len();
        let mut jac = nalgebra::DMatrix::<f64>::zeros(3 * nj, 6 * nb);
        for (r, &(a, b, j)) in pairs.iter().enumerate() {
            let at = Vector3::from(j.at_m);
            for (body, sign) in [(a, -1.0), (b, 1.0)] {
                let arm = at - Vector3::from(self.bodies[body].position_m);
                jac.view_mut((3 * r, 6 * body), (3, 3))
                    .copy_from(&(sign * nalgebra::Matrix3::identity()));
                jac.view_mut((3 * r, 6 * body + 3), (3, 3))
                    .copy_from(&(-sign * arm.cross_matrix()));
            }
        }
        // Non-finite or absurd positions are reported on their own; an SVD of them may not
        // converge (nalgebra's loops forever on NaN), so it gets an iteration limit.
        if !jac.iter().all(|v| v.is_finite()) {
            return None;
        }
        let eps = 1e-9 * jac.amax().max(1.0);
        let svd = nalgebra::linalg::SVD::try_new(jac, false, false, f64::EPSILON, 1000)?;
        let rank = svd.singular_values.iter().filter(|&&v| v > eps).count();
        (rank < 3 * nj).then(|| {
            format!(
                "vehicle.joints: over-constrained — {nj} spherical joints give {} independent constraints of {} (two joints between the same bodies, or a closed loop): their reactions are undetermined",
                rank,
                3 * nj
            )
        })
    }

    /// Problems with values and names, each naming the entry.
    pub fn problems(&self) -> Vec<VehicleProblem> {
        let mut p = Vec::new();
        let mut check = |what: String, v: f64, lo: f64, hi: f64| {
            if !(v.is_finite() && v >= lo && v <= hi) {
                p.push(format!("vehicle.{what} = {v}: expected a value in [{lo}, {hi}]"));
            }
        };
        if self.wheelsets.is_empty() {
            check("wheelsets (count)".into(), 0.0, 1.0, 64.0);
        }
        for b in &self.bodies {
            check(format!("bodies[{}].mass_kg", b.name), b.mass_kg, 1.0, 1e6);
            for (i, v) in b.inertia_kg_m2.iter().enumerate() {
                check(format!("bodies[{}].inertia_kg_m2[{i}]", b.name), *v, 1e-3, 1e8);
            }
            check(
                format!("bodies[{}].position_m[1]", b.name),
                b.position_m[1],
                0.0,
                0.0,
            );
            check(
                format!("bodies[{}].position_m[2]", b.name),
                b.position_m[2],
                0.0,
                10.0,
            );
            check(
                format!("bodies[{}].position_m[0]", b.name),
                b.position_m[0],
                -200.0,
                200.0,
            );
            if let Some(h) = b.floor_height_m {
                check(format!("bodies[{}].floor_height_m", b.name), h, 0.0, 10.0);
            }
        }
        for w in &self.wheelsets {
            check(format!("wheelsets[{}].mass_kg", w.name), w.mass_kg, 1.0, 1e5);
            check(format!("wheelsets[{}].x_m", w.name), w.x_m, -200.0, 200.0);
            for (i, v) in w.inertia_kg_m2.iter().enumerate() {
                check(format!("wheelsets[{}].inertia_kg_m2[{i}]", w.name), *v, 1e-3, 1e6);
            }
            if let Some(irw) = &w.independent_wheels {
                check(
                    format!(
                        "wheelsets[{}].independent_wheels.wheel_spin_inertia_kg_m2",
                        w.name
                    ),
                    irw.wheel_spin_inertia_kg_m2,
                    1e-3,
                    1e5,
                );
            }
        }
        let names = self.body_names();
        for (i, n) in names.iter().enumerate() {
            if n == "track" || names[..i].contains(n) {
                p.push(format!("vehicle: body name \"{n}\" is reserved or used twice"));
            }
            // Names become file names (`--csv DIR/NAME.csv`) and entity paths.
            if n.is_empty()
                || n.starts_with('.')
                || !n
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
            {
                p.push(format!(
                    "vehicle: body name \"{n}\": expected letters, digits, '_', '-' or '.' (not first): names become file names"
                ));
            }
        }
        let mut seen: Vec<&str> = Vec::new();
        for name in self
            .elements
            .iter()
            .map(|e| match e {
                ElementSpec::Bushing { name, .. }
                | ElementSpec::Axial { name, .. }
                | ElementSpec::Rotational { name, .. }
                | ElementSpec::CarriedMass { name, .. } => name.as_str(),
            })
            .chain(self.joints.iter().map(|j| j.name.as_str()))
        {
            if seen.contains(&name) {
                p.push(format!(
                    "vehicle.elements[{name}]: the name \"{name}\" is used by two elements or joints"
                ));
            }
            seen.push(name);
        }
        for (name, inertia, what) in self
            .bodies
            .iter()
            .map(|b| (&b.name, &b.inertia_kg_m2, "bodies"))
            .chain(
                self.wheelsets
                    .iter()
                    .map(|w| (&w.name, &w.inertia_kg_m2, "wheelsets")),
            )
        {
            p.extend(inertia_problem(&format!("{what}[{name}]"), inertia));
        }
        for e in &self.elements {
            if let ElementSpec::CarriedMass { name, body, .. } = e {
                if body == "track" {
                    p.push(format!(
                        "vehicle.elements[{name}]: a carried mass rides on a body of the vehicle, not on \"track\""
                    ));
                }
            }
        }
        // Every wheelset hangs in something: a wheelset no element holds would run away.
        for w in &self.wheelsets {
            let held = self.elements.iter().any(|e| match e {
                ElementSpec::Bushing { bodies, .. }
                | ElementSpec::Axial { bodies, .. }
                | ElementSpec::Rotational { bodies, .. } => bodies.contains(&w.name),
                ElementSpec::CarriedMass { body, .. } => body == &w.name,
            });
            if !held {
                p.push(format!(
                    "vehicle.wheelsets[{}]: no element holds it (a wheelset hangs in a bogie or frame by its primary suspension)",
                    w.name
                ));
            }
        }
        if let Some(problem) = self.redundant_joints() {
            p.push(problem);
        }
        for j in &self.joints {
            for b in &j.bodies {
                if !self.bodies.iter().any(|x| &x.name == b) {
                    p.push(format!(
                        "vehicle.joints[{}]: \"{b}\" is not a rigid body of [[vehicle.bodies]] (joints join carbodies and frames)",
                        j.name
                    ));
                }
            }
            if j.bodies[0] == j.bodies[1] {
                p.push(format!(
                    "vehicle.joints[{}]: both ends on \"{}\"",
                    j.name, j.bodies[0]
                ));
            }
            if j.at_m.iter().any(|v| !v.is_finite()) {
                p.push(format!("vehicle.joints[{}].at_m: not finite", j.name));
            }
        }
        for e in &self.elements {
            let (name, ends): (&String, Vec<&String>) = match e {
                ElementSpec::Bushing { name, bodies, .. }
                | ElementSpec::Axial { name, bodies, .. }
                | ElementSpec::Rotational { name, bodies, .. } => (name, bodies.iter().collect()),
                ElementSpec::CarriedMass { name, body, .. } => (name, vec![body]),
            };
            for b in &ends {
                if self.lookup(b).is_none() {
                    p.push(format!(
                        "vehicle.elements[{name}]: unknown body \"{b}\" (known: track, {})",
                        names.join(", ")
                    ));
                }
            }
            if ends.len() == 2 && ends[0] == ends[1] {
                p.push(format!("vehicle.elements[{name}]: both ends on \"{}\"", ends[0]));
            }
            let mut nonneg = |what: &str, v: f64| {
                if !(v.is_finite() && v >= 0.0) {
                    p.push(format!(
                        "vehicle.elements[{name}].{what} = {v}: expected a value ≥ 0"
                    ));
                }
            };
            match e {
                ElementSpec::Bushing {
                    stiffness,
                    damping,
                    bump_stops,
                    ..
                } => {
                    for k in 0..6 {
                        nonneg(&format!("stiffness[{k}]"), stiffness[k]);
                        nonneg(&format!("damping[{k}]"), damping[k]);
                    }
                    for b in bump_stops {
                        nonneg("bump_stops.clearance_m", b.clearance_m);
                        nonneg("bump_stops.stiffness_n_per_m", b.stiffness_n_per_m);
                    }
                }
                ElementSpec::Axial {
                    from_m,
                    to_m,
                    stiffness_n_per_m,
                    damping_n_s_per_m,
                    ..
                } => {
                    nonneg("stiffness_n_per_m", *stiffness_n_per_m);
                    nonneg("damping_n_s_per_m", *damping_n_s_per_m);
                    let l = (Vector3::from(*to_m) - Vector3::from(*from_m)).norm();
                    if l.is_nan() || l <= 1e-3 {
                        p.push(format!(
                            "vehicle.elements[{name}]: from_m and to_m are {l} m apart (an axial element needs a length)"
                        ));
                    }
                }
                ElementSpec::Rotational {
                    stiffness_n_m_per_rad,
                    damping_n_m_s_per_rad,
                    ..
                } => {
                    nonneg("stiffness_n_m_per_rad", *stiffness_n_m_per_rad);
                    nonneg("damping_n_m_s_per_rad", *damping_n_m_s_per_rad);
                }
                ElementSpec::CarriedMass { mass_kg, .. } => nonneg("mass_kg", *mass_kg),
            }
        }
        p
    }

    /// The elements, with arms from the bodies' nominal centres (call after [`Self::problems`]
    /// found none). `r0` is the wheelsets' nominal rolling radius (their centre height).
    pub fn elements(&self, r0: f64) -> Vec<Element> {
        let centre = |r: BodyRef| match r {
            BodyRef::Track => Vector3::zeros(),
            BodyRef::Body(i) => nominal_centre(self, r0, i),
        };
        let body = |n: &String| self.lookup(n).expect("validated");
        // On the track reference the arm is the point's nominal position itself; the system places
        // that point in the track frame at its own arc length (s_ref + x).
        let arm = |r: BodyRef, at: Vector3<f64>| at - centre(r);
        self.elements
            .iter()
            .map(|e| match e {
                ElementSpec::Bushing {
                    name,
                    bodies,
                    at_m,
                    stiffness,
                    damping,
                    bump_stops,
                } => {
                    let (a, b) = (body(&bodies[0]), body(&bodies[1]));
                    let at = Vector3::from(*at_m);
                    let mut stops = [None; 3];
                    for s in bump_stops {
                        stops[s.axis.index()] = Some((s.clearance_m, s.stiffness_n_per_m));
                    }
                    Element::Bushing {
                        name: name.clone(),
                        a,
                        b,
                        arm_a: arm(a, at),
                        arm_b: arm(b, at),
                        stiffness: *stiffness,
                        damping: *damping,
                        bump_stops: stops,
                        preload: [0.0; 6],
                    }
                }
                ElementSpec::Axial {
                    name,
                    bodies,
                    from_m,
                    to_m,
                    stiffness_n_per_m,
                    damping_n_s_per_m,
                } => {
                    let (a, b) = (body(&bodies[0]), body(&bodies[1]));
                    let (from, to) = (Vector3::from(*from_m), Vector3::from(*to_m));
                    Element::Axial {
                        name: name.clone(),
                        a,
                        b,
                        arm_a: arm(a, from),
                        arm_b: arm(b, to),
                        length_m: (to - from).norm(),
                        stiffness: *stiffness_n_per_m,
                        damping: *damping_n_s_per_m,
                        preload: 0.0,
                    }
                }
                ElementSpec::Rotational {
                    name,
                    bodies,
                    at_m,
                    axis,
                    stiffness_n_m_per_rad,
                    damping_n_m_s_per_rad,
                } => {
                    let (a, b) = (body(&bodies[0]), body(&bodies[1]));
                    let at = Vector3::from(*at_m);
                    let (mut k, mut c) = ([0.0; 6], [0.0; 6]);
                    k[3 + axis.index()] = *stiffness_n_m_per_rad;
                    c[3 + axis.index()] = *damping_n_m_s_per_rad;
                    Element::Bushing {
                        name: name.clone(),
                        a,
                        b,
                        arm_a: arm(a, at),
                        arm_b: arm(b, at),
                        stiffness: k,
                        damping: c,
                        bump_stops: [None; 3],
                        preload: [0.0; 6],
                    }
                }
                ElementSpec::CarriedMass {
                    name,
                    body: on,
                    at_m,
                    mass_kg,
                } => {
                    let b = body(on);
                    Element::CarriedMass {
                        name: name.clone(),
                        body: b,
                        arm: arm(b, Vector3::from(*at_m)),
                        mass_kg: *mass_kg,
                    }
                }
            })
            .collect()
    }
}
