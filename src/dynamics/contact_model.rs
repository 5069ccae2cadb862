//! The contact model of a wheelset, as the equations of motion see it (paper §5, coordinate
//! partitioning): given the independent lateral displacement y and the rail irregularities
//! q_r = [y_lir, z_lir, y_rir, z_rir] (METHOD.md §2), the dependent coordinates z and φ, their
//! first and second time derivatives along the motion, and the real contact points where the
//! normal forces (Eq. 53) and the creep forces act.
//!
//! Three interchangeable models, chosen per scene:
//! - `kec` — the KEC constraints (Eq. 49–51) solved online on the knife-edge-equivalent profiles;
//!   derivatives analytic (first and second, from [`KecSolution`]);
//! - `lookup` — the 1-entry contact lookup table (Eq. 44–46 for the irregularities; the gauge
//!   variation is not in it);
//! - `lookup2` — the 2-entry table over (y, gv), gauge variation ±10 mm by 1 mm;
//! - `online` — the approximate contact constraints (Eq. 35–42) solved at every evaluation.
//!
//! For the tables and `online`, ż and the velocity-dependent part c_z of z̈ = Z_y ÿ + c_z come from
//! the directional difference of z along the motion: with g(ε) = Z(y + ε ẏ, q_r(t + ε)) (the rails
//! advanced to second order), ż = g'(0) and c_z = g''(0), by central differences (three evaluations,
//! each moving the wheelset ~10 µm). The stencil depends on the state only, never on an earlier
//! evaluation, so that the right-hand side is a function the integrator's error control can trust.
//! A departure from the paper (which differentiates its tables), chosen so that the three models
//! share one interface; `kec` uses its exact derivatives. The `online` model keeps its warm start on
//! the true contact with [`ContactGeometry::solve_tracked`] (past a contact-point jump the old branch
//! survives as a local tangency with the profiles interpenetrating).

use thiserror::Error;

use crate::contact::geometry::{ContactError, ContactGeometry, ContactSolution};
use crate::contact::kec::{KecError, KecModel, KecSolution};
use crate::contact::lookup::{LookupTable1, LookupTable2, TableError, TableRow};
use crate::contact::RailOffsets;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;

/// Which contact model a scene uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactKind {
    Kec,
    /// 1-entry table over y (the irregularities' gauge variation is not in it).
    Lookup,
    /// 2-entry table over (y, gv): gauge variation included.
    Lookup2,
    Online,
}

impl ContactKind {
    pub fn name(self) -> &'static str {
        match self {
            ContactKind::Kec => "kec",
            ContactKind::Lookup => "lookup",
            ContactKind::Lookup2 => "lookup2",
            ContactKind::Online => "online",
        }
    }

    pub fn parse(s: &str) -> Option<ContactKind> {
        match s {
            "kec" => Some(ContactKind::Kec),
            "lookup" => Some(ContactKind::Lookup),
            "lookup2" => Some(ContactKind::Lookup2),
            "online" => Some(ContactKind::Online),
            _ => None,
        }
    }
}

/// A contact-model failure during the dynamics.
#[derive(Debug, Error)]
pub enum ContactModelError {
    #[error("KEC: {0}")]
    Kec(#[from] KecError),
    #[error("lookup table: {0}")]
    Table(#[from] TableError),
    #[error("online contact: {0}")]
    Online(#[from] ContactError),
}

/// One real contact point, in the wheelset-track frame (Y left, Z up).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RealContact {
    /// Position (Y, Z), m.
    pub position: (f64, f64),
    /// Unit normal of the rail surface (n_Y, n_Z), pointing into the wheel.
    pub normal: (f64, f64),
    pub contact_angle: f64,
    pub rolling_radius: f64,
    pub wheel_curvature: f64,
    pub rail_curvature: f64,
    /// Surface parameters of the contact on the real wheel and rail (paper convention), m.
    pub s_wheel: f64,
    pub s_rail: f64,
}

/// z, φ and their motion for one evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetKinematics {
    /// Centre height z and roll φ.
    pub z: f64,
    pub phi: f64,
    /// ∂z/∂y, ∂φ/∂y.
    pub z_y: f64,
    pub phi_y: f64,
    /// ż, φ̇ along the motion.
    pub z_dot: f64,
    pub phi_dot: f64,
    /// Velocity-dependent parts: z̈ = z_y ÿ + c_z, φ̈ = φ_y ÿ + c_φ.
    pub c_z: f64,
    pub c_phi: f64,
    /// Left, right.
    pub contacts: [RealContact; 2],
    /// KEC only: the knife-edge contact parameters s^lk, s^rk on the equivalent profiles, m.
    pub s_knife: Option<[f64; 2]>,
}

/// The rail irregularities at the wheelset and their first two time derivatives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailMotion {
    /// [y_lir, z_lir, y_rir, z_rir], m.
    pub q: [f64; 4],
    pub q_dot: [f64; 4],
    pub q_ddot: [f64; 4],
}

/// The contact model of one wheelset (shared by all wheelsets with the same profiles).
#[derive(Debug, Clone)]
pub enum WheelsetContact {
    Kec {
        model: Box<KecModel>,
        pair: Box<WheelRailPair>,
    },
    Lookup {
        table: Box<LookupTable1>,
    },
    Lookup2 {
        table: Box<LookupTable2>,
    },
    Online {
        geometry: Box<ContactGeometry>,
    },
}

fn offsets(q: &[f64; 4]) -> RailOffsets {
    RailOffsets {
        y_left: q[0],
        z_left: q[1],
        y_right: q[2],
        z_right: q[3],
    }
}

fn from_row(row: &TableRow) -> [RealContact; 2] {
    let c = |i: usize, side: Side| {
        let (s, co) = row.contact_angle[i].sin_cos();
        RealContact {
            position: (row.position[2 * i], row.position[2 * i + 1]),
            normal: (-side.sign() * s, co),
            contact_angle: row.contact_angle[i],
            rolling_radius: row.rolling_radius[i],
            wheel_curvature: row.curvature[2 * i],
            rail_curvature: row.curvature[2 * i + 1],
            s_wheel: row.x[2 + 2 * i],
            s_rail: row.x[3 + 2 * i],
        }
    };
    [c(0, Side::Left), c(1, Side::Right)]
}

fn from_online(sol: &ContactSolution) -> [RealContact; 2] {
    let c = |p: &crate::contact::geometry::ContactPoint| RealContact {
        position: p.position,
        normal: p.normal,
        contact_angle: p.contact_angle,
        rolling_radius: p.rolling_radius,
        wheel_curvature: p.wheel_curvature,
        rail_curvature: p.rail_curvature,
        s_wheel: p.s_wheel,
        s_rail: p.s_rail,
    };
    [c(&sol.left), c(&sol.right)]
}

fn from_kec(sol: &KecSolution, pair: &WheelRailPair) -> [RealContact; 2] {
    let c = |i: usize, side: Side| {
        let p = &sol.real[i];
        RealContact {
            position: pair
                .wheelset
                .wheel_point(&pair.wheel, side, p.s_wheel, sol.y, sol.z, sol.phi),
            normal: p.normal(side),
            contact_angle: p.contact_angle,
            rolling_radius: p.rolling_radius,
            wheel_curvature: p.wheel_curvature,
            rail_curvature: p.rail_curvature,
            s_wheel: p.s_wheel,
            s_rail: p.s_rail,
        }
    };
    [c(0, Side::Left), c(1, Side::Right)]
}

/// Warm-start memory of one wheelset's contact solve.
#[derive(Debug, Clone, Default)]
pub struct ContactWarmStart {
    kec: Option<[f64; 4]>,
    online: Option<ContactSolution>,
}

impl WheelsetContact {
    pub fn kind(&self) -> ContactKind {
        match self {
            WheelsetContact::Kec { .. } => ContactKind::Kec,
            WheelsetContact::Lookup { .. } => ContactKind::Lookup,
            WheelsetContact::Lookup2 { .. } => ContactKind::Lookup2,
            WheelsetContact::Online { .. } => ContactKind::Online,
        }
    }

    /// (z, φ, z_y, φ_y, contacts) at one configuration.
    fn at(
        &self,
        y: f64,
        q: &[f64; 4],
        warm: &mut ContactWarmStart,
    ) -> Result<(f64, f64, f64, f64, [RealContact; 2]), ContactModelError> {
        match self {
            WheelsetContact::Kec { model, pair } => {
                let s = model.solve(y, *q, warm.kec)?;
                warm.kec = Some(s.x(model.r0));
                Ok((s.z, s.phi, s.dx_dq[0][0], s.dx_dq[1][0], from_kec(&s, pair)))
            }
            WheelsetContact::Lookup { table } => {
                let row = table.contact(y, &offsets(q))?;
                Ok((row.z(), row.phi(), row.dx_dy[0], row.dx_dy[1], from_row(&row)))
            }
            WheelsetContact::Lookup2 { table } => {
                let row = table.contact(y, &offsets(q))?;
                Ok((row.z(), row.phi(), row.dx_dy[0], row.dx_dy[1], from_row(&row)))
            }
            WheelsetContact::Online { geometry } => {
                let off = offsets(q);
                let sol = match &warm.online {
                    Some(prev) => geometry.solve_tracked(y, &off, prev)?,
                    None => geometry.solve(y, &off)?,
                };
                let out = (sol.z, sol.phi, sol.dx_dy[0], sol.dx_dy[1], from_online(&sol));
                warm.online = Some(sol);
                Ok(out)
            }
        }
    }

    /// The kinematics at lateral displacement y with velocity ẏ, rails moving as `rails`.
    pub fn kinematics(
        &self,
        y: f64,
        y_dot: f64,
        rails: &RailMotion,
        warm: &mut ContactWarmStart,
    ) -> Result<WheelsetKinematics, ContactModelError> {
        match self {
            WheelsetContact::Kec { model, pair } => {
                let s = model.solve(y, rails.q, warm.kec)?;
                warm.kec = Some(s.x(model.r0));
                // q = [y, y_lir, z_lir, y_rir, z_rir].
                let qd = [
                    y_dot,
                    rails.q_dot[0],
                    rails.q_dot[1],
                    rails.q_dot[2],
                    rails.q_dot[3],
                ];
                let qdd_r = [
                    0.0,
                    rails.q_ddot[0],
                    rails.q_ddot[1],
                    rails.q_ddot[2],
                    rails.q_ddot[3],
                ];
                let (mut z_dot, mut phi_dot, mut c_z, mut c_phi) = (0.0, 0.0, 0.0, 0.0);
                for i in 0..5 {
                    z_dot += s.dx_dq[0][i] * qd[i];
                    phi_dot += s.dx_dq[1][i] * qd[i];
                    c_z += s.dx_dq[0][i] * qdd_r[i];
                    c_phi += s.dx_dq[1][i] * qdd_r[i];
                    for j in 0..5 {
                        c_z += s.d2z_dq2[i][j] * qd[i] * qd[j];
                        c_phi += s.d2phi_dq2[i][j] * qd[i] * qd[j];
                    }
                }
                Ok(WheelsetKinematics {
                    z: s.z,
                    phi: s.phi,
                    z_y: s.dx_dq[0][0],
                    phi_y: s.dx_dq[1][0],
                    z_dot,
                    phi_dot,
                    c_z,
                    c_phi,
                    contacts: from_kec(&s, pair),
                    s_knife: Some(s.s_k),
                })
            }
            _ => {
                let (z, phi, z_y, phi_y, contacts) = self.at(y, &rails.q, warm)?;
                // Directional differences along the motion over a time step ε chosen so that the
                // wheelset moves ~10 µm (bounded to [1e-6, 1e-2] s).
                let speed = y_dot.abs() + rails.q_dot.iter().map(|v| v.abs()).sum::<f64>();
                let eps = (1e-5 / speed.max(1e-9)).clamp(1e-6, 1e-2);
                let shift = |e: f64| {
                    let mut q = rails.q;
                    for ((qk, vk), ak) in q.iter_mut().zip(rails.q_dot).zip(rails.q_ddot) {
                        *qk += vk * e + 0.5 * ak * e * e;
                    }
                    (y + y_dot * e, q)
                };
                let mut w = warm.clone();
                let (yp, qp) = shift(eps);
                let (zp, php, ..) = self.at(yp, &qp, &mut w)?;
                let (ym, qm) = shift(-eps);
                let (zm, phm, ..) = self.at(ym, &qm, &mut w)?;
                let z_dot = (zp - zm) / (2.0 * eps);
                let phi_dot = (php - phm) / (2.0 * eps);
                let c_z = (zp - 2.0 * z + zm) / (eps * eps);
                let c_phi = (php - 2.0 * phi + phm) / (eps * eps);
                Ok(WheelsetKinematics {
                    z,
                    phi,
                    z_y,
                    phi_y,
                    z_dot,
                    phi_dot,
                    c_z,
                    c_phi,
                    contacts,
                    s_knife: None,
                })
            }
        }
    }
}
