//! The run's 3D view: the vehicle on its track, from the scene itself (no per-vehicle code).
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/world/track/rails`, `run/world/track/sleepers` | LineStrips3D, every [`STRETCH_INTERVAL_S`] | the stretch of track under and ahead of the vehicle: both rails with cant, gauge and irregularities, a sleeper every 0.6 m |
//! | `run/world/vehicle/NAME` | Transform3D | the track frame at the body's or wheelset's arc length (Eq. 1–2) |
//! | `run/world/vehicle/NAME/pose` | Transform3D | its displacement in that frame: (0, e y, z), e the exaggeration, z from the nominal height |
//! | `run/world/vehicle/NAME/pose/body` | Transform3D | its nominal height (h, or r0 for a wheelset) and its rotation (φ, θ, e ψ) about its centre |
//! | `run/world/vehicle/NAME/pose/body/shape` | Boxes3D / LineStrips3D, static | a body as a box; a wheelset's axle and wheels |
//! | `run/world/vehicle/WHEELSET/contact` | Points3D | the real contact points (lifted wheels grey) |
//! | `run/world/vehicle/WHEELSET/forces` | Arrows3D | the rail's force on each wheel: creep Fx, Y and Q ([`FORCE_SCALE_M_PER_N`]) |
//! | `run/world/follow` | Transform3D | the front wheelset's track frame: the 3D view's origin, so the camera follows it |
//! | `run/world/elements/bushings`, `run/world/elements/axial` | Points3D / LineStrips3D | the force elements between bodies: a bushing as a point at its attachment (the middle of its two bodies' points), an axial element (rod, damper) as the line between its two attachment points; coloured by the force's magnitude ([`super::bands::force_color`], 0–100 kN) |
//!
//! **Coordinates**: the track's global frame (X, Y left, Z up; Eq. 1) shifted to the track's start,
//! so that the f32 of the recording keeps ~0.1 mm over a kilometre. Each body and wheelset is
//! logged at three levels: its track frame (global, f32), its displacement in that frame (small
//! numbers: f32 keeps ~1e-9 m of them) and its rotation about its centre, so that a reader can
//! recover the simulated states from the recording (the test
//! `recording::the_3d_view_follows_the_simulated_states`).
//!
//! **Scale**: true scale by default — the vehicle is drawn where it is. `--exaggerate F` (F > 1)
//! magnifies only the wheelsets' lateral and yaw motion relative to the track, and the rails'
//! lateral irregularities with them, so that the wheelsets' millimetres show; the bodies (carbodies,
//! bogie frames) stay at true scale, where a magnified lateral offset of 30–50 mm in a curve drew
//! the carbodies metres off the track and their yaw tens of degrees across it. (A wheelset's
//! magnified yaw can still draw its wheels across the rails: the title says the factor.) Vertical
//! motion, roll and pitch are true scale, as are the cross-sections.

use std::sync::Arc;

use nalgebra::{Matrix3, Rotation3, Vector3};
use rerun::{
    Arrows3D, Boxes3D, Color, LineStrips3D, Points3D, Radius, RecordingStream, TimeColumn, Transform3D,
};

use super::bands::force_color;
use super::{log_static, InspectError};
use crate::dynamics::sample::Sample;
use crate::dynamics::system::BodySample;
use crate::scenario::Scene;
use crate::track::{RailOffsets, Track};
use crate::vehicle::elements::{BodyRef, Element};
use crate::vehicle::spec::VehicleSpec;

/// The default exaggeration of the wheelsets' lateral and yaw motion relative to the track: none
/// (true scale; see the module doc).
pub const DEFAULT_EXAGGERATION: f64 = 1.0;

/// Length of a force arrow per newton, m/N (1 m per 50 kN).
pub const FORCE_SCALE_M_PER_N: f64 = 1.0 / 50e3;

/// Simulated time between two 3D frames (≤ 50 Hz), s.
pub const FRAME_INTERVAL_S: f64 = 0.02;

/// Simulated time between two stretches of track drawn around the vehicle, s: each reaches from
/// behind the last wheelset to where the first one will be at the next stretch, so that the
/// vehicle is always on the latest one; the whole line is the track plan's. (The whole kilometre
/// in 3D would make the view's camera frame a kilometre.)
pub const STRETCH_INTERVAL_S: f64 = 0.5;
/// Track drawn behind the last wheelset and ahead of where the first will be, m.
const STRETCH_MARGIN_M: f64 = 6.0;

/// Sleeper spacing, m.
const SLEEPER_SPACING_M: f64 = 0.6;
/// Rail drawing resolution along the track, m.
const RAIL_STEP_M: f64 = 1.0;

/// What the 3D view draws beyond the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct World3dSettings {
    /// The factor on the wheelsets' lateral and yaw motion relative to the track (1: true scale).
    pub exaggerate: f64,
}

impl Default for World3dSettings {
    fn default() -> Self {
        World3dSettings {
            exaggerate: DEFAULT_EXAGGERATION,
        }
    }
}

/// Where a vehicle's 3D drawing goes and how it looks: `run/world` for a run; `compare/world/MODEL`
/// for each model of a comparison, the first with the track, the others ghosted in a colour of
/// their own.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldStyle {
    /// The entity path everything goes under.
    pub root: String,
    /// Draw the stretch of track (one vehicle of several draws it).
    pub track: bool,
    /// The bodies' and wheels' colour (None: the run's grey bodies and blue wheels).
    pub tint: Option<Color>,
    /// The drawing's lateral offset from the track, m (to the left): vehicles of several models
    /// side by side, each on its own track.
    pub offset_m: f64,
}

impl Default for WorldStyle {
    fn default() -> Self {
        WorldStyle {
            root: "run/world".to_string(),
            track: true,
            tint: None,
            offset_m: 0.0,
        }
    }
}

/// A rigid body's drawing: its box.
#[derive(Debug, Clone)]
struct BodyShape {
    name: String,
    /// Nominal centre height above the rail top, m.
    h: f64,
    /// Half sizes (x, y, z), m.
    half: [f32; 3],
}

/// A wheelset's drawing.
#[derive(Debug, Clone)]
struct WheelsetShape {
    name: String,
    r0: f64,
    /// Lateral position of each wheel's running circle, m.
    half_track: f64,
}

/// A force element between two bodies (indices into the bodies, then the wheelsets) and its
/// attachment arms from their nominal centres.
#[derive(Debug, Clone)]
struct ElementShape {
    a: usize,
    arm_a: Vector3<f64>,
    b: usize,
    arm_b: Vector3<f64>,
    /// An axial element (drawn as a line); else a bushing (a point).
    axial: bool,
    /// Its index among the vehicle's elements (the order of the run's element forces).
    index: usize,
}

/// The drawable force elements of `scene`'s vehicle: bushings and axial elements between two
/// bodies (not those on the track reference, nor carried masses).
fn element_shapes(scene: &Scene) -> Vec<ElementShape> {
    let r0 = scene.pair.wheelset.nominal_radius_m;
    let Some((_, VehicleSpec::Multibody(m))) = scene.simulation.as_ref() else {
        return Vec::new();
    };
    m.elements(r0)
        .into_iter()
        .enumerate()
        .filter_map(|(index, e)| {
            let (a, b, arm_a, arm_b, axial) = match e {
                Element::Bushing {
                    a, b, arm_a, arm_b, ..
                } => (a, b, arm_a, arm_b, false),
                Element::Axial {
                    a, b, arm_a, arm_b, ..
                } => (a, b, arm_a, arm_b, true),
                Element::CarriedMass { .. } => return None,
            };
            match (a, b) {
                (BodyRef::Body(a), BodyRef::Body(b)) => Some(ElementShape {
                    a,
                    arm_a,
                    b,
                    arm_b,
                    axial,
                    index,
                }),
                _ => None,
            }
        })
        .collect()
}

/// A body's pose in the drawing: its track frame's position and rotation, its centre in that
/// frame, its rotation about the centre.
type DrawnPose = (Vector3<f64>, Matrix3<f64>, Vector3<f64>, Matrix3<f64>);

/// One body's or wheelset's transforms at one frame: the track frame, the displacement in it, and
/// the rotation about the centre at its nominal height.
#[derive(Debug, Clone, Copy)]
struct Placed {
    frame_t: [f32; 3],
    frame_m: [f32; 9],
    pose_t: [f32; 3],
    body_t: [f32; 3],
    body_m: [f32; 9],
}

/// One 3D frame, waiting for its batch.
#[derive(Debug, Clone)]
struct FrameRow {
    t: f64,
    distance_mm: i64,
    bodies: Vec<Placed>,
    wheelsets: Vec<Placed>,
    /// Per wheelset: the two contact points and forces in its track frame, and whether each wheel
    /// is lifted.
    contact: Vec<[[f32; 3]; 2]>,
    forces: Vec<[[f32; 3]; 2]>,
    lifted: Vec<[bool; 2]>,
    /// The bushings' points and the axial elements' lines (drawing coordinates), with their
    /// forces' magnitudes, N.
    bushings: Vec<([f32; 3], f64)>,
    axial: Vec<([[f32; 3]; 2], f64)>,
}

/// The box of a uniform solid with the body's mass and principal inertias (roll, pitch, yaw):
/// I_x = m (b² + c²)/12 etc., so a² = 6 (I_y + I_z − I_x)/m for the full length a along x. A set
/// of inertias no box has (one larger than the other two together) gives the nearest: sizes ≥ 0.1 m.
pub fn equivalent_box(mass_kg: f64, inertia: [f64; 3]) -> [f64; 3] {
    let [ix, iy, iz] = inertia;
    let side = |a: f64, b: f64, c: f64| (6.0 * (a + b - c) / mass_kg).max(0.01).sqrt();
    [side(iy, iz, ix), side(ix, iz, iy), side(ix, iy, iz)]
}

/// The vehicle's drawings from the scene.
fn shapes(scene: &Scene) -> (Vec<BodyShape>, Vec<WheelsetShape>) {
    let r0 = scene.pair.wheelset.nominal_radius_m;
    let half_track = scene.pair.wheelset.l_w();
    let wheelset = |name: String| WheelsetShape { name, r0, half_track };
    match scene.simulation.as_ref().map(|(_, v)| v) {
        Some(VehicleSpec::Multibody(m)) => (
            m.bodies
                .iter()
                .map(|b| {
                    let [a, w, c] = equivalent_box(b.mass_kg, b.inertia_kg_m2);
                    BodyShape {
                        name: b.name.clone(),
                        h: b.position_m[2],
                        half: [(a / 2.0) as f32, (w / 2.0) as f32, (c / 2.0) as f32],
                    }
                })
                .collect(),
            m.wheelsets.iter().map(|w| wheelset(w.name.clone())).collect(),
        ),
        Some(spec) => (
            Vec::new(),
            spec.wheelset_names().into_iter().map(wheelset).collect(),
        ),
        None => (Vec::new(), Vec::new()),
    }
}

fn mat(m: &Matrix3<f64>) -> [f32; 9] {
    // Column-major, as Rerun's Mat3x3.
    let mut out = [0.0f32; 9];
    for c in 0..3 {
        for r in 0..3 {
            out[3 * c + r] = m[(r, c)] as f32;
        }
    }
    out
}

fn v32(v: &Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The run's 3D world: statics at the start, a frame every [`FRAME_INTERVAL_S`], sent as columns
/// with the recorder's batches.
pub struct World3d {
    /// The entity path everything goes under ([`WorldStyle::root`]).
    root: String,
    draw_track: bool,
    tint: Option<Color>,
    track: Option<Arc<Track>>,
    /// The global position the drawing is relative to (the track's start), m.
    origin: Vector3<f64>,
    /// The drawing's lateral offset from the track ([`WorldStyle::offset_m`]).
    offset_m: f64,
    settings: World3dSettings,
    bodies: Vec<BodyShape>,
    wheelsets: Vec<WheelsetShape>,
    elements: Vec<ElementShape>,
    rows: Vec<FrameRow>,
    next_t: f64,
    /// The pending stretches of track: time, distance (mm), rails, sleepers.
    stretches: Vec<Stretch>,
    next_stretch_t: f64,
    /// The rails' lateral positions (the wheels' running circles), m.
    half_gauge: f64,
}

/// Both rails as polylines (left, right) and the sleepers as segments.
type TrackLines = ([Vec<[f32; 3]>; 2], Vec<[[f32; 3]; 2]>);

/// A stretch of track around the vehicle, waiting for its batch.
struct Stretch {
    t: f64,
    distance_mm: i64,
    rails: [Vec<[f32; 3]>; 2],
    sleepers: Vec<[[f32; 3]; 2]>,
}

impl World3d {
    pub fn new(scene: &Scene, settings: World3dSettings) -> World3d {
        Self::styled(scene, settings, WorldStyle::default())
    }

    /// [`Self::new`] under another root, with or without the track, tinted.
    pub fn styled(scene: &Scene, settings: World3dSettings, style: WorldStyle) -> World3d {
        let (bodies, wheelsets) = shapes(scene);
        let track = scene.track.clone();
        let origin = track
            .as_ref()
            .and_then(|t| t.centreline.frame(t.centreline.range().0).ok())
            .map_or_else(Vector3::zeros, |f| f.position);
        World3d {
            root: style.root,
            draw_track: style.track,
            tint: style.tint,
            track,
            origin,
            offset_m: style.offset_m,
            settings,
            bodies,
            wheelsets,
            elements: element_shapes(scene),
            rows: Vec::new(),
            next_t: f64::NEG_INFINITY,
            stretches: Vec::new(),
            next_stretch_t: f64::NEG_INFINITY,
            half_gauge: scene.pair.wheelset.l_w(),
        }
    }

    /// The 3D view's title (with the exaggeration).
    pub fn title(settings: &World3dSettings) -> String {
        let forces = (1.0 / FORCE_SCALE_M_PER_N / 1e3).round();
        // The colour key: the contact points and their forces.
        let key = format!("contacts red (lifted grey), their forces orange, 1 m per {forces} kN");
        if settings.exaggerate == 1.0 {
            format!("true scale; {key}")
        } else {
            format!(
                "wheelsets' lateral and yaw × {}, bodies true scale; {key}",
                settings.exaggerate
            )
        }
    }

    /// The track frame at `s` relative to [`Self::origin`]: position and rotation (a straight
    /// level line along X where the scene has no track).
    fn frame(&self, s: f64) -> (Vector3<f64>, Matrix3<f64>) {
        match self.track.as_ref().and_then(|t| t.centreline.frame(s).ok()) {
            Some(f) => (
                f.position - self.origin + f.rotation * Vector3::new(0.0, self.offset_m, 0.0),
                f.rotation,
            ),
            None => (Vector3::new(s, self.offset_m, 0.0), Matrix3::identity()),
        }
    }

    /// The rails' offsets at `s` (zero without irregularities).
    fn rails(&self, s: f64) -> RailOffsets {
        match self.track.as_ref().and_then(|t| t.eval(s).ok()) {
            Some((_, irr)) => {
                let [al, vp, gv, cl] = irr.value;
                RailOffsets::from_irregularities(al, vp, gv, cl)
            }
            None => RailOffsets::default(),
        }
    }

    /// The track from `s0` to `s1`: both rails (lateral irregularities × the exaggeration) and
    /// the sleepers.
    fn stretch(&self, s0: f64, s1: f64) -> TrackLines {
        let e = self.settings.exaggerate;
        let (lo, hi) = self
            .track
            .as_ref()
            .map_or((f64::NEG_INFINITY, f64::INFINITY), |t| t.centreline.range());
        let (s0, s1) = (s0.max(lo), s1.min(hi));
        let n = ((s1 - s0) / RAIL_STEP_M).ceil().max(1.0) as usize;
        let mut rails = [Vec::with_capacity(n + 1), Vec::with_capacity(n + 1)];
        for i in 0..=n {
            let s = (s0 + i as f64 * RAIL_STEP_M).min(s1);
            let (p, a) = self.frame(s);
            let r = self.rails(s);
            rails[0].push(v32(&(p + a * Vector3::new(
                0.0,
                self.half_gauge + e * r.y_left,
                r.z_left,
            ))));
            rails[1].push(v32(&(p + a * Vector3::new(
                0.0,
                -self.half_gauge + e * r.y_right,
                r.z_right,
            ))));
        }
        let first = (s0 / SLEEPER_SPACING_M).ceil() as i64;
        let last = (s1 / SLEEPER_SPACING_M).floor() as i64;
        let sleepers = (first..=last)
            .map(|i| {
                let (p, a) = self.frame(i as f64 * SLEEPER_SPACING_M);
                let end = |y: f64| v32(&(p + a * Vector3::new(0.0, y, -0.17)));
                [end(1.3), end(-1.3)]
            })
            .collect();
        (rails, sleepers)
    }

    /// The vehicle's shapes (static).
    pub fn log_statics(&self, rec: &RecordingStream) -> Result<(), InspectError> {
        for b in &self.bodies {
            log_static(
                rec,
                &format!("{}/vehicle/{}/pose/body/shape", self.root, b.name),
                &Boxes3D::from_half_sizes([b.half])
                    .with_fill_mode(rerun::components::FillMode::Solid)
                    .with_colors([self
                        .tint
                        .unwrap_or(Color::from_unmultiplied_rgba(200, 200, 215, 90))]),
            )?;
        }
        for w in &self.wheelsets {
            let (r0, l) = (w.r0 as f32, w.half_track as f32);
            let circle = |y: f32| -> Vec<[f32; 3]> {
                (0..=48)
                    .map(|i| {
                        let a = i as f32 / 48.0 * std::f32::consts::TAU;
                        [r0 * a.cos(), y, r0 * a.sin()]
                    })
                    .collect()
            };
            log_static(
                rec,
                &format!("{}/vehicle/{}/pose/body/shape", self.root, w.name),
                &LineStrips3D::new([
                    vec![[0.0, -l - 0.1, 0.0], [0.0, l + 0.1, 0.0]],
                    circle(l),
                    circle(-l),
                ])
                .with_colors([
                    Color::from_rgb(90, 90, 100),
                    self.tint.unwrap_or(Color::from_rgb(70, 140, 230)),
                    self.tint.unwrap_or(Color::from_rgb(70, 140, 230)),
                ])
                .with_radii([
                    Radius::new_scene_units(0.06),
                    Radius::new_scene_units(0.03),
                    Radius::new_scene_units(0.03),
                ]),
            )?;
        }
        Ok(())
    }

    /// Keeps a frame of `wheelsets`, `bodies` and the force `elements`' (deflection, force) (in
    /// the order of the scene's; `elements` may be empty: no elements drawn) if one is due, and a
    /// stretch of track if one is due.
    pub fn sample(
        &mut self,
        t: f64,
        wheelsets: &[Sample],
        bodies: &[BodySample],
        elements: &[(Vector3<f64>, Vector3<f64>)],
    ) {
        // A run whose vehicle is not the scene's (another count of wheelsets or bodies) is not
        // drawn: nothing here would place it.
        if t < self.next_t - 1e-9
            || wheelsets.len() != self.wheelsets.len()
            || bodies.len() != self.bodies.len()
            || wheelsets.is_empty()
        {
            return;
        }
        if self.draw_track && t >= self.next_stretch_t - 1e-9 {
            self.next_stretch_t = t + STRETCH_INTERVAL_S;
            let (lo, hi) = wheelsets
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
                    (lo.min(w.s), hi.max(w.s))
                });
            let ahead = wheelsets[0].speed.max(0.0) * STRETCH_INTERVAL_S;
            let (rails, sleepers) = self.stretch(lo - STRETCH_MARGIN_M, hi + ahead + STRETCH_MARGIN_M);
            self.stretches.push(Stretch {
                t,
                distance_mm: (wheelsets[0].s * 1e3).round() as i64,
                rails,
                sleepers,
            });
        }
        self.next_t = t + FRAME_INTERVAL_S;
        let e = self.settings.exaggerate;
        // Each body's and wheelset's pose in the drawing (f64, for the elements' points) and
        // its transforms.
        let mut poses: Vec<DrawnPose> = Vec::new();
        let mut placed = |s: f64, pose_t: Vector3<f64>, height: f64, angles: [f64; 3]| {
            let (p, a) = self.frame(s);
            let r = Rotation3::from_euler_angles(angles[0], angles[1], angles[2]);
            poses.push((p, a, pose_t + Vector3::new(0.0, 0.0, height), *r.matrix()));
            Placed {
                frame_t: v32(&p),
                frame_m: mat(&a),
                pose_t: v32(&pose_t),
                body_t: [0.0, 0.0, height as f32],
                body_m: mat(r.matrix()),
            }
        };
        let body_rows: Vec<Placed> = self
            .bodies
            .iter()
            .zip(bodies)
            .map(|(b, q)| {
                // The bodies at true scale (see the module doc).
                placed(
                    q.s,
                    Vector3::new(0.0, q.q[1], q.q[2]),
                    b.h,
                    [q.q[3], q.q[4], q.q[5]],
                )
            })
            .collect();
        let mut ws_rows = Vec::with_capacity(wheelsets.len());
        let (mut contact, mut forces, mut lifted) = (Vec::new(), Vec::new(), Vec::new());
        for (w, s) in self.wheelsets.iter().zip(wheelsets) {
            ws_rows.push(placed(
                s.s,
                Vector3::new(0.0, e * s.y, s.z),
                w.r0,
                [s.roll, 0.0, e * s.yaw],
            ));
            // The contact points relative to the exaggerated wheelset centre, true scale.
            let shift = (e - 1.0) * s.y;
            contact.push([0, 1].map(|i| [0.0, (s.position[i].0 + shift) as f32, s.position[i].1 as f32]));
            forces.push([0, 1].map(|i| {
                v32(&(Vector3::new(s.creep_x[i], s.y_force[i], s.q_force[i]) * FORCE_SCALE_M_PER_N))
            }));
            lifted.push([s.lift[0] > 0.0, s.lift[1] > 0.0]);
        }
        // The force elements, where the run gives their forces and every body is drawn.
        let (mut bushings, mut axial) = (Vec::new(), Vec::new());
        if !elements.is_empty() && poses.len() == self.bodies.len() + self.wheelsets.len() {
            let point = |i: usize, arm: &Vector3<f64>| {
                let (p, a, c, r) = &poses[i];
                p + a * (c + r * arm)
            };
            for el in &self.elements {
                let Some((_, force)) = elements.get(el.index) else {
                    continue;
                };
                let (pa, pb) = (point(el.a, &el.arm_a), point(el.b, &el.arm_b));
                if el.axial {
                    axial.push(([v32(&pa), v32(&pb)], force.norm()));
                } else {
                    bushings.push((v32(&(0.5 * (pa + pb))), force.norm()));
                }
            }
        }
        self.rows.push(FrameRow {
            t,
            distance_mm: (wheelsets.first().map_or(0.0, |s| s.s) * 1e3).round() as i64,
            bodies: body_rows,
            wheelsets: ws_rows,
            contact,
            forces,
            lifted,
            bushings,
            axial,
        });
    }

    /// Sends the pending frames as columns on `time` and `distance_mm`.
    pub fn send(
        &mut self,
        rec: &RecordingStream,
        time: &'static str,
        distance: &'static str,
    ) -> Result<(), InspectError> {
        self.send_stretches(rec, time, distance)?;
        let rows = std::mem::take(&mut self.rows);
        let n = rows.len();
        if n == 0 {
            return Ok(());
        }
        let timelines = || {
            [
                TimeColumn::new_duration_secs(time, rows.iter().map(|r| r.t)),
                TimeColumn::new_sequence(distance, rows.iter().map(|r| r.distance_mm)),
            ]
        };
        let send = |entity: String,
                    columns: Result<
            Box<dyn Iterator<Item = rerun::SerializedComponentColumn>>,
            rerun::SerializationError,
        >|
         -> Result<(), InspectError> {
            let columns = columns.map_err(|e| InspectError::Log {
                entity: entity.clone(),
                source: e.into(),
            })?;
            rec.send_columns(entity.as_str(), timelines(), columns)
                .map_err(|source| InspectError::Log { entity, source })
        };
        let transforms = |t: Vec<[f32; 3]>, m: Vec<[f32; 9]>| {
            Transform3D::update_fields()
                .with_many_translation(t)
                .with_many_mat3x3(m)
                .columns_of_unit_batches()
                .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>)
        };
        let names: Vec<&String> = self
            .bodies
            .iter()
            .map(|b| &b.name)
            .chain(self.wheelsets.iter().map(|w| &w.name))
            .collect();
        let nb = self.bodies.len();
        for (k, name) in names.iter().enumerate() {
            let at = |r: &FrameRow| {
                if k < nb {
                    r.bodies[k]
                } else {
                    r.wheelsets[k - nb]
                }
            };
            send(
                format!("{}/vehicle/{name}", self.root),
                transforms(
                    rows.iter().map(|r| at(r).frame_t).collect(),
                    rows.iter().map(|r| at(r).frame_m).collect(),
                ),
            )?;
            send(
                format!("{}/vehicle/{name}/pose", self.root),
                Transform3D::update_fields()
                    .with_many_translation(rows.iter().map(|r| at(r).pose_t))
                    .columns_of_unit_batches()
                    .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>),
            )?;
            send(
                format!("{}/vehicle/{name}/pose/body", self.root),
                transforms(
                    rows.iter().map(|r| at(r).body_t).collect(),
                    rows.iter().map(|r| at(r).body_m).collect(),
                ),
            )?;
        }
        for (k, w) in self.wheelsets.iter().enumerate() {
            let colors = |r: &FrameRow| {
                r.lifted[k].map(|l| {
                    if l {
                        Color::from_rgb(150, 150, 150)
                    } else {
                        Color::from_rgb(230, 50, 50)
                    }
                })
            };
            send(
                format!("{}/vehicle/{}/contact", self.root, w.name),
                Points3D::new(rows.iter().flat_map(|r| r.contact[k]))
                    .with_colors(rows.iter().flat_map(colors))
                    // A fixed size on screen (4 cm showed as ~3 px in the whole-vehicle view).
                    .with_radii(std::iter::repeat_n(Radius::new_ui_points(5.0), 2 * n))
                    .columns(std::iter::repeat_n(2, n))
                    .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>),
            )?;
            send(
                format!("{}/vehicle/{}/forces", self.root, w.name),
                Arrows3D::from_vectors(rows.iter().flat_map(|r| r.forces[k]))
                    .with_origins(rows.iter().flat_map(|r| r.contact[k]))
                    .with_colors(std::iter::repeat_n(Color::from_rgb(230, 160, 40), 2 * n))
                    .columns(std::iter::repeat_n(2, n))
                    .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>),
            )?;
        }
        let bushings: Vec<&([f32; 3], f64)> = rows.iter().flat_map(|r| &r.bushings).collect();
        if !bushings.is_empty() {
            send(
                format!("{}/elements/bushings", self.root),
                Points3D::new(bushings.iter().map(|b| b.0))
                    .with_colors(bushings.iter().map(|b| force_color(b.1)))
                    .with_radii(std::iter::repeat_n(Radius::new_scene_units(0.07), bushings.len()))
                    .columns(rows.iter().map(|r| r.bushings.len()))
                    .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>),
            )?;
        }
        let axial: Vec<&([[f32; 3]; 2], f64)> = rows.iter().flat_map(|r| &r.axial).collect();
        if !axial.is_empty() {
            send(
                format!("{}/elements/axial", self.root),
                LineStrips3D::new(axial.iter().map(|a| a.0))
                    .with_colors(axial.iter().map(|a| force_color(a.1)))
                    .with_radii(std::iter::repeat_n(Radius::new_scene_units(0.04), axial.len()))
                    .columns(rows.iter().map(|r| r.axial.len()))
                    .map(|c| Box::new(c) as Box<dyn Iterator<Item = _>>),
            )?;
        }
        if !self.wheelsets.is_empty() {
            send(
                format!("{}/follow", self.root),
                transforms(
                    rows.iter().map(|r| r.wheelsets[0].frame_t).collect(),
                    rows.iter().map(|r| r.wheelsets[0].frame_m).collect(),
                ),
            )?;
        }
        Ok(())
    }
}

impl World3d {
    /// Sends the pending stretches of track, one row each.
    fn send_stretches(
        &mut self,
        rec: &RecordingStream,
        time: &'static str,
        distance: &'static str,
    ) -> Result<(), InspectError> {
        for st in std::mem::take(&mut self.stretches) {
            let timelines = [
                TimeColumn::new_duration_secs(time, [st.t]),
                TimeColumn::new_sequence(distance, [st.distance_mm]),
            ];
            let grey = Color::from_rgb(150, 150, 160);
            let rails = LineStrips3D::new(st.rails)
                .with_colors([grey, grey])
                .with_radii([Radius::new_scene_units(0.03); 2])
                .columns([2]);
            let k = st.sleepers.len();
            let sleepers = LineStrips3D::new(st.sleepers)
                .with_colors(std::iter::repeat_n(Color::from_rgb(120, 95, 70), k))
                .with_radii(std::iter::repeat_n(Radius::new_scene_units(0.06), k))
                .columns([k]);
            for (entity, columns) in [
                (format!("{}/track/rails", self.root), rails),
                (format!("{}/track/sleepers", self.root), sleepers),
            ] {
                let columns = columns.map_err(|e| InspectError::Log {
                    entity: entity.clone(),
                    source: e.into(),
                })?;
                rec.send_columns(entity.as_str(), timelines.clone(), columns)
                    .map_err(|source| InspectError::Log { entity, source })?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 47: the exaggeration (`--exaggerate`) magnifies the wheelsets' lateral and yaw motion
    /// relative to the track only; a body (carbody, bogie frame) is drawn where it is — at ×50 a
    /// carbody 40 mm off the centreline in a curve was drawn 2 m off, its 10 mrad yaw as 27°.
    #[test]
    fn the_bodies_are_drawn_at_true_scale() {
        let text = crate::scenario::DEFAULT_SCENARIO;
        let scene = crate::scenario::Scenario::parse(text, "<default>")
            .unwrap()
            .compile("<default>", std::path::Path::new("."))
            .unwrap();
        let e = 50.0;
        let mut world = World3d::new(&scene, World3dSettings { exaggerate: e });
        let (y_body, yaw_body, y_ws, yaw_ws) = (0.04, 0.01, 0.005, 0.007);
        let bodies: Vec<BodySample> = (0..world.bodies.len())
            .map(|_| BodySample {
                s: 100.0,
                q: [0.0, y_body, 0.01, 0.002, 0.0, yaw_body],
                q_dot: [0.0; 6],
            })
            .collect();
        let mut ws = Sample::at(0.0, 100.0, 19.0);
        ws.y = y_ws;
        ws.yaw = yaw_ws;
        let wheelsets = vec![ws; world.wheelsets.len()];
        assert!(!bodies.is_empty() && !wheelsets.is_empty());
        world.sample(0.0, &wheelsets, &bodies, &[]);
        let row = &world.rows[0];
        // The yaw of a drawn rotation matrix (column-major): atan2(m[1], m[0]).
        let yaw = |m: &[f32; 9]| (m[1] as f64).atan2(m[0] as f64);
        for b in &row.bodies {
            assert!((b.pose_t[1] as f64 - y_body).abs() < 1e-7, "{:?}", b.pose_t);
            assert!((yaw(&b.body_m) - yaw_body).abs() < 1e-6);
        }
        for w in &row.wheelsets {
            assert!((w.pose_t[1] as f64 - e * y_ws).abs() < 1e-7, "{:?}", w.pose_t);
            assert!((yaw(&w.body_m) - e * yaw_ws).abs() < 1e-6);
        }
        // At true scale (the default) the wheelsets too.
        assert_eq!(World3dSettings::default().exaggerate, 1.0);
    }

    /// A uniform box's inertias give back its sides.
    #[test]
    fn the_equivalent_box_of_a_box_is_the_box() {
        let (m, a, b, c) = (1000.0, 10.0, 2.6, 3.0);
        let i = [
            m * (b * b + c * c) / 12.0,
            m * (a * a + c * c) / 12.0,
            m * (a * a + b * b) / 12.0,
        ];
        let got = equivalent_box(m, i);
        for (g, w) in got.iter().zip([a, b, c]) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }
}
