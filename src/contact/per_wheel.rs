//! The **per-wheel entry** of a contact lookup table: each wheel read from the centred (gv = 0)
//! table at its own lateral offset from its own displaced rail, the wheelset's z and roll from
//! the two wheels together. The default entry of the `lookup2` contact model (issue 48); the
//! paper's literal 2-entry table, gauge columns interpolated in gv, is `lookup2-paper`.
//!
//! **Why.** The paper's 2-entry table (§4.3) tabulates the pair over (y, gv) and interpolates
//! between gauge columns. But a gauge variation moves each rail by ±gv/2: the left wheel then
//! sees its rail exactly as at y − gv/2 on the centred track, the right wheel as at y + gv/2; only
//! the roll, which the two wheels set together, differs from either centred configuration. The
//! interpolation across columns instead mixes contacts of different wheel offsets: across 1 mm
//! columns it misses the contact angle by up to 3.15° near the flange root of the MS stand-in
//! (16.05° against 19.20° at y = 3.22 mm, gv = 0.5 mm), 0.25° across 0.1 mm columns; the per-wheel
//! entry by ≤ 0.19°, from the one centred column (no extra preprocessing). It is what the
//! KEC-method does with its equivalent profiles (paper §5: each knife edge at its own rail), here
//! with the table's own interpolation, so that KEC and the table are compared on the same footing.
//!
//! **The entry.** On the ideal pair at gauge variation gv (the frame of the rail pair's rigid
//! motion, [`enter_rotated`](super::lookup::enter_rotated), takes the cross level out), side σ (+1 left, −1 right) reads the
//! centred row at u_σ: the wheelset's centre C(u_σ) = (u_σ, z(u_σ)), roll φ(u_σ), the contact
//! point P_σ(u_σ). The real wheelset has a roll φ of its own; turned about P_σ by
//! Δ_σ = φ − φ(u_σ) the wheel keeps its contact to first order (a body turned about its contact
//! point), and its rail is moved by σ gv/2:
//!
//! ```text
//! C_σ = P_σ + R(Δ_σ) (C(u_σ) − P_σ) + (σ gv/2, 0)
//! F = [ C_l,y − y′,  C_r,y − y′,  C_l,z − C_r,z ] = 0     in X = [u_l, u_r, φ]
//! ```
//!
//! solved by Newton (the Jacobian from the table's slopes dz/dy, dφ/dy and the PCHIP slopes of
//! the contact positions, so exact for the interpolant); z = C_l,z. The slopes of the result:
//! dX/dy′ = J⁻¹ [1, 1, 0]ᵀ and dX/dgv = −J⁻¹ [½, −½, 0]ᵀ. Each side's contact (surface
//! parameters, contact angle, rolling radius, curvatures) is its row's, the contact point moved
//! with its rail.
//!
//! **What it neglects.** Turning the wheel about P_σ by Δ keeps the gap closed only to first
//! order: the contact point moves along the profiles by ≈ Δ/(κ_r − κ_w) and the wheel sinks by
//! ≈ Δ²/(2 (κ_r − κ_w)) (κ the lateral curvatures: 2 µm at Δ = 1 mrad on a near-conformal
//! contact 2 % from the rail's R80). The read contact stays the row's (the contact angle is the
//! rail's at P_σ, unchanged to first order). On the centred track Δ = 0 and the entry is the
//! table itself. The y′ range ends where either wheel reaches its flange side's end of the
//! centred table (its flange climb, moved with its rail); a wheel on its field side beyond the
//! table (a widened gauge) is continued linearly in wheel-fixed terms (`side_centre`), as the KEC
//! equivalent profiles extrapolate their end cubic.

use nalgebra::{Matrix3, Matrix4, Vector3, Vector4};

use super::lookup::{turned_back, LookupTable1, RailPairMotion, TableError, TableRow};
use crate::track::RailOffsets;

/// Newton iterations of the per-wheel entry at most (it converges in 2–4).
const MAX_ITERATIONS: usize = 30;
/// The longest Newton step in a wheel's entry u, m.
const MAX_STEP_M: f64 = 1e-3;
/// The per-wheel Newton stops when its step is below this (m in u, rad in φ).
const TOLERANCE: f64 = 1e-14;
/// Where Newton cycles across a contact jump of the table, an iterate whose residual (m) is
/// within this is taken (the turned centre's step there: Δ |ΔP| ≲ 5 µm at Δ = 1 mrad).
const JUMP_RESIDUAL_M: f64 = 2e-5;

/// One side's wheelset centre after the turn about its contact point, with its derivatives in
/// its entry u and in the roll φ.
struct SideCentre {
    row: TableRow,
    centre: (f64, f64),
    d_u: (f64, f64),
    d_phi: (f64, f64),
}

/// How far beyond the centred table a wheel on its field side is extrapolated at most, m.
pub const FIELD_EXTRAPOLATION_MAX_M: f64 = 0.015;

/// The field side of side `i` (0 left, 1 right) lies beyond the table's low end (left: the
/// wheelset moved to −y) or its high end (right).
fn field_side_low(i: usize) -> bool {
    i == 0
}

/// Side `i` (0 left, 1 right) read at `u` with the wheelset's roll `phi`, its rail moved by
/// σ gv/2.
///
/// **Beyond the table on the field side** (a widened gauge lets the wheelset run past the centred
/// gauge's flange contact, so the other wheel stands further out on its field side than the
/// centred table reaches) the side's data are continued linearly from the table's end e, in the
/// quantities that belong to one wheel alone: the contact point on the rail P(u) and the wheel-fixed
/// vector from the contact point to the wheelset centre w(u) = R(−φ(u)) (C(u) − P(u)) — with
/// dw/du = R(−φ)[(dC − dP) − φ_u J (C − P)], J the quarter turn — so that
/// C_σ = P + R(φ) w + (σ gv/2, 0) continues C¹ from the table; the surface parameters linearly, the
/// contact angle, rolling radius and curvatures held at the end's. (The pair's own roll, steep at
/// the end where the other wheel climbs its flange, drops out: it is the KEC equivalent profiles'
/// extrapolation of their end cubic, in the same wheel-fixed terms.)
fn side_centre(table: &LookupTable1, i: usize, u: f64, phi: f64, gv: f64) -> Result<SideCentre, TableError> {
    let (lo, hi) = table.range();
    let sigma = if i == 0 { 1.0 } else { -1.0 };
    let beyond_field = if field_side_low(i) { u < lo } else { u > hi };
    let e = if beyond_field { u.clamp(lo, hi) } else { u };
    let (mut row, ps) = table.lookup_with_position_slopes(e)?;
    let p = (row.position[2 * i], row.position[2 * i + 1]);
    let dp = (ps[2 * i], ps[2 * i + 1]);
    let v = (e - p.0, row.x[0] - p.1);
    let dc = (1.0, row.dx_dy[0]);
    let phi_u = row.dx_dy[1];
    let rot = |a: f64, v: (f64, f64)| {
        let (sa, ca) = a.sin_cos();
        (ca * v.0 - sa * v.1, sa * v.0 + ca * v.1)
    };
    if !beyond_field {
        let delta = phi - row.x[1];
        let w = rot(delta, v);
        let wp = (-w.1, w.0);
        let turned = rot(delta, (dc.0 - dp.0, dc.1 - dp.1));
        return Ok(SideCentre {
            row,
            centre: (p.0 + w.0 + 0.5 * sigma * gv, p.1 + w.1),
            d_u: (dp.0 + turned.0 - phi_u * wp.0, dp.1 + turned.1 - phi_u * wp.1),
            d_phi: wp,
        });
    }
    let du = u - e;
    if du.abs() > FIELD_EXTRAPOLATION_MAX_M {
        return Err(TableError::OutOfRange {
            what: "a wheel's offset from its rail (the per-wheel entry, field side)",
            value_mm: u * 1e3,
            min_mm: (lo - FIELD_EXTRAPOLATION_MAX_M) * 1e3,
            max_mm: (hi + FIELD_EXTRAPOLATION_MAX_M) * 1e3,
        });
    }
    // Wheel-fixed w(e) and its slope, then linear in u.
    let we = rot(-row.x[1], v);
    let jv = (-v.1, v.0);
    let dw = rot(
        -row.x[1],
        (dc.0 - dp.0 - phi_u * jv.0, dc.1 - dp.1 - phi_u * jv.1),
    );
    let w0 = (we.0 + dw.0 * du, we.1 + dw.1 * du);
    let pu = (p.0 + dp.0 * du, p.1 + dp.1 * du);
    let w = rot(phi, w0);
    let dwr = rot(phi, dw);
    for k in 2..6 {
        row.x[k] += row.dx_dy[k] * du;
    }
    row.position[2 * i] = pu.0;
    row.position[2 * i + 1] = pu.1;
    Ok(SideCentre {
        row,
        centre: (pu.0 + w.0 + 0.5 * sigma * gv, pu.1 + w.1),
        d_u: (dp.0 + dwr.0, dp.1 + dwr.1),
        d_phi: (-w.1, w.0),
    })
}

/// Where the wheelset stands in the frame of the ideal pair: at a given y′ (a row of the turned
/// frame), or at the y′ that the rail pair's rigid motion gives for the wheelset at y
/// ([`enter_rotated`](super::lookup::enter_rotated)'s G(y′) = c y′ − s (z(y′) − z_r) − (y − al) = 0, solved together with the
/// per-wheel equations).
#[derive(Clone, Copy)]
enum Target {
    Fixed(f64),
    Turned { u0: f64, c: f64, s: f64, z_r: f64 },
}

/// The per-wheel Newton in X = [u_l, u_r, φ, y′] (module docs, with the fourth equation from
/// `target`): the converged row of the ideal pair at gauge variation `gv` and its y′.
fn solve(table: &LookupTable1, gv: f64, target: Target) -> Result<(TableRow, f64), TableError> {
    let (lo, hi) = table.range();
    let mut yp = match target {
        Target::Fixed(yp) => yp,
        Target::Turned { u0, c, s, z_r } => (u0 + s * (table.lookup(u0.clamp(lo, hi))?.x[0] - z_r)) / c,
    };
    let beyond = |yp: f64, high: bool| TableError::BeyondFlangeLimit {
        y_mm: yp * 1e3,
        gv_mm: gv * 1e3,
        limit_mm: if high { hi + 0.5 * gv } else { lo - 0.5 * gv } * 1e3,
    };
    // Each wheel held short of its flange side's end (its field side may go beyond: side_centre).
    let hold = |x: &mut Vector4<f64>| {
        let held = x[0] > hi || x[1] < lo;
        x[0] = x[0].min(hi);
        x[1] = x[1].max(lo);
        held
    };
    let mut x = Vector4::new(yp - 0.5 * gv, yp + 0.5 * gv, 0.0, yp);
    hold(&mut x);
    x[2] = 0.5 * (table.lookup(x[0].clamp(lo, hi))?.x[1] + table.lookup(x[1].clamp(lo, hi))?.x[1]);
    let mut held = 0;
    let mut best: Option<(f64, Vector4<f64>)> = None;
    for _ in 0..MAX_ITERATIONS {
        let l = side_centre(table, 0, x[0], x[2], gv)?;
        let r = side_centre(table, 1, x[1], x[2], gv)?;
        let (f4, j4) = match target {
            Target::Fixed(yp) => (x[3] - yp, [0.0, 0.0, 0.0, 1.0]),
            Target::Turned { u0, c, s, z_r } => (
                c * x[3] - s * (l.centre.1 - z_r) - u0,
                [-s * l.d_u.1, 0.0, -s * l.d_phi.1, c],
            ),
        };
        let f = Vector4::new(l.centre.0 - x[3], r.centre.0 - x[3], l.centre.1 - r.centre.1, f4);
        #[rustfmt::skip]
        let j = Matrix4::new(
            l.d_u.0, 0.0, l.d_phi.0, -1.0,
            0.0, r.d_u.0, r.d_phi.0, -1.0,
            l.d_u.1, -r.d_u.1, l.d_phi.1 - r.d_phi.1, 0.0,
            j4[0], j4[1], j4[2], j4[3],
        );
        let step = j.lu().solve(&f).ok_or_else(|| {
            TableError::Invalid(format!(
                "per-wheel entry at y′ = {:.4} mm, gv = {:.4} mm: singular Jacobian",
                x[3] * 1e3,
                gv * 1e3
            ))
        })?;
        if step.amax() <= TOLERANCE {
            let row = converged(&l, &r, x[2], x[3], gv)?;
            return Ok((row, x[3]));
        }
        if best.as_ref().is_none_or(|(b, _)| f.amax() < *b) {
            best = Some((f.amax(), x));
        }
        // A step in either wheel's entry longer than MAX_STEP_M is shortened (the direction
        // kept): near a contact jump or both flanges the Jacobian of one side can nearly vanish and
        // a full step throw a wheel tens of millimetres off its table.
        let longest = step[0].abs().max(step[1].abs());
        x -= if longest > MAX_STEP_M {
            step * (MAX_STEP_M / longest)
        } else {
            step
        };
        // A wheel held at the table's end: converging there means beyond it.
        held = if hold(&mut x) { held + 1 } else { 0 };
        if held > 2 {
            // Beyond on the side the wheelset moved to.
            return Err(beyond(x[3], x[3] > 0.0));
        }
        yp = x[3];
    }
    // At a contact jump of the table a turned wheel's centre steps by ≈ Δ |ΔP| (a few µm): F may
    // step over zero and Newton cycle across the jump. The iterate with the smallest residual
    // stands for it when that residual is within the step's size.
    if let Some((_, x)) = best.filter(|(f, _)| *f <= JUMP_RESIDUAL_M) {
        let l = side_centre(table, 0, x[0], x[2], gv)?;
        let r = side_centre(table, 1, x[1], x[2], gv)?;
        return Ok((converged(&l, &r, x[2], x[3], gv)?, x[3]));
    }
    Err(TableError::Invalid(format!(
        "per-wheel entry at y′ = {:.4} mm, gv = {:.4} mm: Newton did not converge in {MAX_ITERATIONS} iterations (smallest residual {:.3e} m)",
        yp * 1e3,
        gv * 1e3,
        best.map_or(f64::NAN, |b| b.0)
    )))
}

/// The row at a converged per-wheel solution: z and φ, each side's contact from its own row (its
/// point moved with its rail), and the slopes dX/dy′ = J⁻¹ [1, 1, 0]ᵀ, dX/dgv = −J⁻¹ [½, −½, 0]ᵀ
/// of the three per-wheel equations at fixed y′.
fn converged(l: &SideCentre, r: &SideCentre, phi: f64, yp: f64, gv: f64) -> Result<TableRow, TableError> {
    #[rustfmt::skip]
    let j = Matrix3::new(
        l.d_u.0, 0.0, l.d_phi.0,
        0.0, r.d_u.0, r.d_phi.0,
        l.d_u.1, -r.d_u.1, l.d_phi.1 - r.d_phi.1,
    );
    let lu = j.lu();
    let singular = || {
        TableError::Invalid(format!(
            "per-wheel entry at y′ = {:.4} mm, gv = {:.4} mm: singular Jacobian",
            yp * 1e3,
            gv * 1e3
        ))
    };
    let dy = lu.solve(&Vector3::new(1.0, 1.0, 0.0)).ok_or_else(singular)?;
    let dg = -lu.solve(&Vector3::new(0.5, -0.5, 0.0)).ok_or_else(singular)?;
    let mut out = l.row;
    out.y = yp;
    out.gv = gv;
    out.x[0] = l.centre.1;
    out.x[1] = phi;
    out.dx_dy[0] = l.d_u.1 * dy[0] + l.d_phi.1 * dy[2];
    out.dx_dy[1] = dy[2];
    out.dx_dgv[0] = l.d_u.1 * dg[0] + l.d_phi.1 * dg[2];
    out.dx_dgv[1] = dg[2];
    for (i, s) in [(0, l), (1, r)] {
        for k in [2 + 2 * i, 3 + 2 * i] {
            out.x[k] = s.row.x[k];
            out.dx_dy[k] = s.row.dx_dy[k] * dy[i];
            out.dx_dgv[k] = s.row.dx_dy[k] * dg[i];
        }
        let sigma = if i == 0 { 1.0 } else { -1.0 };
        out.position[2 * i] = s.row.position[2 * i] + 0.5 * sigma * gv;
        out.position[2 * i + 1] = s.row.position[2 * i + 1];
        out.contact_angle[i] = s.row.contact_angle[i];
        out.rolling_radius[i] = s.row.rolling_radius[i];
        out.curvature[2 * i] = s.row.curvature[2 * i];
        out.curvature[2 * i + 1] = s.row.curvature[2 * i + 1];
        out.two_point_gap[i] = s.row.two_point_gap[i];
    }
    Ok(out)
}

/// The configuration of a wheelset at lateral displacement `yp` on the ideal rail pair at gauge
/// variation `gv` (each rail moved outwards by gv/2), from the centred table `table` by the
/// per-wheel entry (module docs). The row's y is `yp`, its gv `gv`.
pub fn per_wheel_row(table: &LookupTable1, yp: f64, gv: f64) -> Result<TableRow, TableError> {
    let (lo, hi) = per_wheel_range(table, gv);
    if !(lo..=hi).contains(&yp) {
        return Err(TableError::BeyondFlangeLimit {
            y_mm: yp * 1e3,
            gv_mm: gv * 1e3,
            limit_mm: if yp > hi { hi } else { lo } * 1e3,
        });
    }
    Ok(solve(table, gv, Target::Fixed(yp))?.0)
}

/// The y′ range of the per-wheel entry at gauge variation `gv`: each wheel short of its flange
/// side's end of the centred table (its rail moved by ±gv/2: the flange contact moves with it),
/// the other wheel's field side continued beyond the table where a widened gauge needs it (up
/// to [`FIELD_EXTRAPOLATION_MAX_M`]).
pub fn per_wheel_range(table: &LookupTable1, gv: f64) -> (f64, f64) {
    let (lo, hi) = table.range();
    (lo - 0.5 * gv, hi + 0.5 * gv)
}

/// The contact of a wheelset at `y` on rails with offsets `off` from the centred table `table`
/// by the per-wheel entry, in the frame of the rail pair's rigid motion ([`enter_rotated`](super::lookup::enter_rotated): the
/// cross level and the rails' common motion taken out exactly, the gauge variation left as ±gv/2):
/// one Newton for the per-wheel equations and enter_rotated's G(y′) = 0 together, then
/// [`turned_back`].
pub fn contact_per_wheel(table: &LookupTable1, y: f64, off: &RailOffsets) -> Result<TableRow, TableError> {
    if table.gv != 0.0 {
        return Err(TableError::Invalid(format!(
            "the per-wheel entry reads the centred table (gv = 0), got gv = {} mm",
            table.gv * 1e3
        )));
    }
    let m = RailPairMotion::new(off, table.l_r);
    let (s, c) = m.theta.sin_cos();
    let target = Target::Turned {
        u0: y - m.al,
        c,
        s,
        z_r: table.z_r,
    };
    let (row, yp) = solve(table, m.gv, target)?;
    let (lo, hi) = per_wheel_range(table, m.gv);
    if !(lo..=hi).contains(&yp) {
        return Err(TableError::BeyondFlangeLimit {
            y_mm: yp * 1e3,
            gv_mm: m.gv * 1e3,
            limit_mm: if yp > hi { hi } else { lo } * 1e3,
        });
    }
    Ok(turned_back(&row, yp, y, &m, table.z_r))
}
