//! The non-Hertzian patch model: Kik & Piotrowski's virtual penetration on strips, with the
//! patch's shape corrected so that a quadratic gap gives Hertz's ellipse exactly.
//!
//! **Kik–Piotrowski** (W. Kik, J. Piotrowski, "A fast, approximate method to calculate normal load
//! at contact between wheel and rail and creep forces during rolling", 2nd mini-conference on
//! contact mechanics, Budapest 1996; J. Piotrowski, W. Kik, *Vehicle System Dynamics* 46 (2008)
//! 27–48). The wheel approaches the rail rigidly by δ along u; a patch is a connected region
//! where the profiles, brought together by only the *virtual* approach ε δ, overlap. Cut into
//! strips across the rolling direction, a strip at lateral position y with normal overlap h(y)
//! has the half-length of the overlap of the wheel's circle (longitudinal curvature A(y) =
//! cos γ(y) / 2r(y), Meusnier; rail straight) with the plane,
//!
//! ```text
//! l(y) = c_x √(h(y) / A(y)),        h(y) = (g_c + ε δ_c − g(y)) cos θ(y)
//! ```
//!
//! and the pressure is semi-elliptic along each strip, Hertz's form strip by strip:
//!
//! ```text
//! p(x, y) = (P / L) √(l(y)² − x²),   L = max l,   pmax = P
//! ```
//!
//! P follows from elasticity at the patch's centre (the gap's minimum): the surface displacement
//! there under the whole pressure (Boussinesq, two bodies of contact modulus E*) equals the real
//! approach δ_c = δ − g_c,
//!
//! ```text
//! δ_c cos θ_c = 1/(π E*) Σ_patches ∫∫ p(x, y) / √(x² + (y − y_c)²) dx dy
//! ```
//!
//! (one equation per patch, the patches' pressures acting on each other's centres), and the
//! normal force is N = (P/L) Σ (π/2) l² Δy.
//!
//! **The correction (departure from Kik–Piotrowski).** They take ε = 0.55 and c_x = 1. A
//! quadratic gap g = B y² (Hertz's case) then gives an ellipse of axis ratio √(B/A), where Hertz's
//! is ≈ (B/A)^(2/3), and a pmax off Hertz's by up to ~10 % at the ratios of a flange contact.
//! Here ε and c_x are those that make the model Hertz's on a quadratic gap: with Hertz's
//! semi-axes a (rolling), b (lateral) and approach δ_H for the curvatures (A, B),
//!
//! ```text
//! ε = B b² / δ_H,       c_x = (a / b) √(A / B)
//! ```
//!
//! (ε = ½ and c_x = 1 for a circle), evaluated at the patch's equivalent lateral curvature
//! B_eq = h_c / b_w² (h_c the virtual overlap at the centre, b_w the patch's half-width along the
//! surface) — a fixed point in ε, since b_w depends on ε. This is the aim of Vollebregt &
//! Piotrowski's KPEC ("Kik–Piotrowski with elliptic correction", in CONTACT), not its formulas.
//! On a quadratic gap the strips then carry Hertz's semi-ellipsoid and the elastic condition
//! returns Hertz's p0 and N (to the quadrature: the tests check 0.5 %).
//!
//! **The integrals.** Each strip is a band of constant l and width Δy; its displacement at y_c is
//! integrated across the band in closed form (asinh) and along x = l sin t by Gauss–Legendre in t;
//! in the band that holds y_c the log singularity at x = 0 is taken out and integrated exactly
//! (∫₀^{π/2} cos² t ln sin t dt = −(π/4)(ln 2 + ½)).
//!
//! **What the model neglects**: the elastic interaction along the strips beyond the centre
//! condition (the strips' shape is imposed, not solved: the exact half-space solution is
//! CONTACT's), the curvature of the surface across the patch (a conformal patch on a 13 mm
//! radius is treated as flat, as CONTACT's planar option does), and yaw's effect on the gap.

use super::gap::GapSection;
use crate::contact::forces::hertz::{HertzContact, Material, RelativeCurvature};

/// Settings of the strip model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripSettings {
    /// Strips per patch.
    pub strips: usize,
    /// Gauss–Legendre nodes along each strip.
    pub nodes: usize,
    /// Minima of the gap deeper than this below the approach are candidate patches, m.
    pub candidate_gap_m: f64,
}

impl Default for StripSettings {
    fn default() -> Self {
        StripSettings {
            strips: 24,
            nodes: 8,
            candidate_gap_m: 1e-3,
        }
    }
}

/// One strip of a patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strip {
    /// Across-coordinate of the strip's centre (see [`GapSection::w`]), m.
    pub w: f64,
    /// Rail parameter at the strip's centre (paper convention), m.
    pub s_rail: f64,
    /// Wheel parameter at the strip's centre, m.
    pub s_wheel: f64,
    /// Width along the surface, m.
    pub width: f64,
    /// Half-length l in the rolling direction, m.
    pub half_length: f64,
    /// Pressure on the strip's centre line (x = 0), Pa.
    pub pressure: f64,
}

/// One contact patch of the strip model.
#[derive(Debug, Clone, PartialEq)]
pub struct StripPatch {
    pub strips: Vec<Strip>,
    /// Maximum pressure, Pa.
    pub max_pressure: f64,
    /// Normal force, N.
    pub normal_force: f64,
    /// Area, m².
    pub area: f64,
    /// The load's centre on the rail and wheel (paper convention), m.
    pub s_rail: f64,
    pub s_wheel: f64,
    /// Contact angle at the load's centre, track frame, rad.
    pub contact_angle: f64,
    /// Rolling radius at the load's centre, m.
    pub rolling_radius: f64,
    /// The patch's lateral ends on the rail (paper convention), m.
    pub s_rail_range: (f64, f64),
    /// Width along the surface, m.
    pub width: f64,
    /// Longest strip, 2 max l, m.
    pub length: f64,
    /// cos of the angle between the patch's normal (at its centre) and the approach u.
    pub cos_u: f64,
    /// Normal approach at the centre (the real one, not the virtual), m.
    pub approach: f64,
    /// The virtual penetration factor ε and the length correction c_x used.
    pub virtual_factor: f64,
    pub length_factor: f64,
}

impl StripPatch {
    /// The ellipse of the same area and width (a along the rolling direction), m: what the
    /// creep-force models take (Kalker's coefficients at a/b).
    pub fn equivalent_ellipse(&self) -> (f64, f64) {
        let b = 0.5 * self.width;
        (self.area / (std::f64::consts::PI * b), b)
    }
}

/// Why the strip model found no patches.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StripError {
    #[error("non-Hertzian patch: load {0} N must be positive and finite")]
    Load(f64),
    #[error("non-Hertzian patch: the overlap reaches the end of the sampled gap ({0:.1} mm from the contact): the profiles are conformal over more than the window")]
    Window(f64),
    #[error("non-Hertzian patch: no overlap carries the load (approach {0:.3e} m)")]
    NoPatch(f64),
    #[error(
        "non-Hertzian patch: the approach did not converge in {0} iterations (load {1:.4e} of {2:.4e} N)"
    )]
    NoConvergence(usize, f64, f64),
}

/// Gauss–Legendre nodes and weights on [0, π/2].
fn gauss_legendre_half_pi(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        let h = std::f64::consts::FRAC_PI_4;
        out.push((h * (x + 1.0), h * w));
    }
    out
}

/// ∫∫ √(l² − x²) / √(x² + (y − y_c)²) over the band |x| ≤ l, y ∈ [y_c + d_lo, y_c + d_hi].
///
/// With x = l sin t the integrand is smooth in t except on the scale of the band's nearer edge
/// distance d (the log-like behaviour of the y-integral for x ≲ d): the t-range is cut at
/// sin t = 4ʲ d / l (a graded composite Gauss–Legendre rule) so that each piece is smooth.
fn band_integral(l: f64, d_lo: f64, d_hi: f64, gl: &[(f64, f64)]) -> f64 {
    if l <= 0.0 || d_hi <= d_lo {
        return 0.0;
    }
    // d + √(d² + x²): the antiderivative's argument (its logarithm, asinh(x/d) + ln d).
    let arg = |d: f64, x: f64| d + (d * d + x * x).sqrt();
    let straddles = d_lo < 0.0 && d_hi > 0.0;
    let (near, far) = if straddles {
        ((-d_lo).min(d_hi), (-d_lo).max(d_hi))
    } else if d_lo >= 0.0 {
        (d_lo, d_hi)
    } else {
        (-d_hi, -d_lo)
    };
    // Integrand in t (without the Jacobian-and-weight factor cos² t): F(x) (+ 2 ln x where the
    // band holds y_c: that log is integrated exactly below). The band's two logarithms are taken
    // as one (of their arguments' product or quotient): the same to rounding, half the cost.
    let f = |x: f64| -> f64 {
        if straddles {
            (arg(-d_lo, x) * arg(d_hi, x)).ln()
        } else if near > 0.0 {
            (arg(far, x) / arg(near, x)).ln()
        } else {
            (arg(far, x) / x).ln()
        }
    };
    let scale = if near > 0.0 { near } else { far };
    // The t-range [0, π/2] cut at sin t = 4ʲ scale / l, segment by segment (no list kept).
    let mut sum = 0.0;
    let mut t0 = 0.0;
    let mut r = scale / l;
    loop {
        let last = r >= 1.0 || r.is_nan();
        let t1 = if last {
            std::f64::consts::FRAC_PI_2
        } else {
            r.asin()
        };
        let k = (t1 - t0) / std::f64::consts::FRAC_PI_2;
        for &(t, w) in gl {
            let st = (t0 + k * t).sin();
            sum += k * w * (1.0 - st * st) * f(l * st);
        }
        if last {
            break;
        }
        t0 = t1;
        r *= 4.0;
    }
    if straddles {
        let log_part = std::f64::consts::FRAC_PI_4 * (l.ln() - std::f64::consts::LN_2 - 0.5);
        2.0 * l * l * (sum - 2.0 * log_part)
    } else {
        2.0 * l * l * sum
    }
}

/// The Hertz-matching factors (ε, c_x) for relative curvatures (A, B) (module documentation).
fn hertz_factors(a_curv: f64, b_curv: f64) -> Option<(f64, f64)> {
    let h = HertzContact::solve(
        RelativeCurvature { a: a_curv, b: b_curv },
        1.0,
        &Material::STEEL,
        &Material::STEEL,
    )
    .ok()?;
    let eps = b_curv * h.b * h.b / h.penetration;
    let cx = (h.a / h.b) * (a_curv / b_curv).sqrt();
    (eps.is_finite() && cx.is_finite()).then_some((eps, cx))
}

/// Linear interpolation of a sampled column at across-coordinate `x` (uniform grid).
fn lerp(sec: &GapSection, col: &[f64], x: f64) -> f64 {
    let h = sec.w[1] - sec.w[0];
    let f = ((x - sec.w[0]) / h).clamp(0.0, (sec.w.len() - 1) as f64);
    let i = (f.floor() as usize).min(sec.w.len() - 2);
    let t = f - i as f64;
    col[i] + t * (col[i + 1] - col[i])
}

/// A patch's shape before its pressure is known (P = 1).
struct Shape {
    centre: usize,
    /// Real approach along u at the centre, δ − g_c.
    approach_u: f64,
    eps: f64,
    cx: f64,
    lo: f64,
    hi: f64,
    strips: Vec<Strip>,
    max_l: f64,
}

/// The arc length along the rail surface at each sample (0 at the first).
fn arc_lengths(sec: &GapSection) -> Vec<f64> {
    let mut arc = Vec::with_capacity(sec.w.len());
    let mut acc = 0.0;
    arc.push(0.0);
    for i in 1..sec.w.len() {
        let dw = sec.w[i] - sec.w[i - 1];
        acc += dw * 0.5 * (1.0 / sec.cos_slope[i] + 1.0 / sec.cos_slope[i - 1]);
        arc.push(acc);
    }
    arc
}

/// Where the gap crosses `level` between samples i and i ± 1 (linear), going outwards from
/// `centre`; Err if the overlap reaches the section's end.
fn crossing(sec: &GapSection, centre: usize, level: f64, step: i64) -> Result<f64, StripError> {
    let n = sec.w.len() as i64;
    let mut i = centre as i64;
    loop {
        let j = i + step;
        if j < 0 || j >= n {
            return Err(StripError::Window(1e3 * sec.w[i as usize].abs()));
        }
        let (gi, gj) = (sec.gap[i as usize], sec.gap[j as usize]);
        if gj >= level {
            let t = (level - gi) / (gj - gi);
            return Ok(sec.w[i as usize] + t * (sec.w[j as usize] - sec.w[i as usize]));
        }
        i = j;
    }
}

fn shape(
    sec: &GapSection,
    arc: &[f64],
    centre: usize,
    delta: f64,
    settings: &StripSettings,
) -> Result<Option<Shape>, StripError> {
    let gc = sec.gap[centre];
    let approach_u = delta - gc;
    if approach_u <= 0.0 {
        return Ok(None);
    }
    let a_c = sec.contact_angle[centre].cos().abs() / (2.0 * sec.radius[centre]);
    let mut eps = 0.55;
    let mut cx = 1.0;
    for _ in 0..60 {
        let level = gc + eps * approach_u;
        let lo = crossing(sec, centre, level, -1)?;
        let hi = crossing(sec, centre, level, 1)?;
        let b_w = 0.5 * (lerp(sec, arc, hi) - lerp(sec, arc, lo));
        let h_c = eps * approach_u * sec.cos_slope[centre];
        let b_eq = h_c / (b_w * b_w);
        let Some((e_new, c_new)) = hertz_factors(a_c, b_eq) else {
            break;
        };
        let done = (e_new - eps).abs() < 1e-6;
        eps = e_new;
        cx = c_new;
        if done {
            break;
        }
    }
    let level = gc + eps * approach_u;
    let lo = crossing(sec, centre, level, -1)?;
    let hi = crossing(sec, centre, level, 1)?;
    let n = settings.strips.max(4);
    let dw = (hi - lo) / n as f64;
    let mut strips = Vec::with_capacity(n);
    let mut max_l: f64 = 0.0;
    for k in 0..n {
        let w = lo + (k as f64 + 0.5) * dw;
        let cos_s = lerp(sec, &sec.cos_slope, w);
        let h = ((level - lerp(sec, &sec.gap, w)) * cos_s).max(0.0);
        let a_k = lerp(sec, &sec.contact_angle, w).cos().abs() / (2.0 * lerp(sec, &sec.radius, w));
        let l = cx * (h / a_k).sqrt();
        max_l = max_l.max(l);
        strips.push(Strip {
            w,
            s_rail: lerp(sec, &sec.s_rail, w),
            s_wheel: lerp(sec, &sec.s_wheel, w),
            width: dw / cos_s,
            half_length: l,
            pressure: 0.0,
        });
    }
    if max_l <= 0.0 {
        return Ok(None);
    }
    Ok(Some(Shape {
        centre,
        approach_u,
        eps,
        cx,
        lo,
        hi,
        strips,
        max_l,
    }))
}

/// The patches and their pressures at a rigid approach δ along u: (shapes, P per shape).
fn patches_at(
    sec: &GapSection,
    arc: &[f64],
    candidates: &[usize],
    delta: f64,
    e_star: f64,
    settings: &StripSettings,
    gl: &[(f64, f64)],
) -> Result<(Vec<Shape>, Vec<f64>), StripError> {
    let mut shapes: Vec<Shape> = Vec::new();
    for &c in candidates {
        if shapes.iter().any(|s| sec.w[c] >= s.lo && sec.w[c] <= s.hi) {
            continue;
        }
        if let Some(s) = shape(sec, arc, c, delta, settings)? {
            // A later (shallower) minimum whose region swallows an earlier patch is the same patch.
            if shapes
                .iter()
                .any(|o| sec.w[o.centre] >= s.lo && sec.w[o.centre] <= s.hi)
            {
                continue;
            }
            shapes.push(s);
        }
    }
    loop {
        let k = shapes.len();
        if k == 0 {
            return Ok((shapes, Vec::new()));
        }
        // Displacement at centre i per unit P of patch j.
        let mut m = vec![vec![0.0; k]; k];
        let mut d = vec![0.0; k];
        for i in 0..k {
            let yc = arc[shapes[i].centre];
            d[i] = shapes[i].approach_u * sec.cos_slope[shapes[i].centre];
            for j in 0..k {
                let mut sum = 0.0;
                for s in &shapes[j].strips {
                    let ys = lerp(sec, arc, s.w);
                    sum += band_integral(
                        s.half_length,
                        ys - 0.5 * s.width - yc,
                        ys + 0.5 * s.width - yc,
                        gl,
                    );
                }
                m[i][j] = sum / (std::f64::consts::PI * e_star * shapes[j].max_l);
            }
        }
        let p = solve_small(m, d);
        if let Some(worst) = (0..k)
            .filter(|&j| p[j].is_nan() || p[j] <= 0.0)
            .min_by(|&a, &b| p[a].total_cmp(&p[b]))
        {
            shapes.remove(worst);
            continue;
        }
        return Ok((shapes, p));
    }
}

/// Gaussian elimination with partial pivoting (k ≤ a handful).
fn solve_small(mut m: Vec<Vec<f64>>, mut d: Vec<f64>) -> Vec<f64> {
    let k = d.len();
    for c in 0..k {
        let piv = (c..k)
            .max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))
            .unwrap_or(c);
        m.swap(c, piv);
        d.swap(c, piv);
        for r in c + 1..k {
            let f = m[r][c] / m[c][c];
            let pivot_row = m[c].clone();
            for (x, &pv) in m[r].iter_mut().zip(&pivot_row).skip(c) {
                *x -= f * pv;
            }
            d[r] -= f * d[c];
        }
    }
    let mut x = vec![0.0; k];
    for r in (0..k).rev() {
        let s: f64 = (r + 1..k).map(|c| m[r][c] * x[c]).sum();
        x[r] = (d[r] - s) / m[r][r];
    }
    x
}

/// Normal force of a shape at pressure scale P.
fn force(shape: &Shape, p: f64) -> f64 {
    p / shape.max_l
        * shape
            .strips
            .iter()
            .map(|s| std::f64::consts::FRAC_PI_2 * s.half_length * s.half_length * s.width)
            .sum::<f64>()
}

/// The patches carrying `load` (N) along the approach direction u of `sec` (each patch's normal
/// force times the cosine between its normal and u, summed), for two bodies of contact modulus
/// `e_star` (Pa). Deepest patch first.
pub fn solve(
    sec: &GapSection,
    load: f64,
    e_star: f64,
    settings: &StripSettings,
) -> Result<Vec<StripPatch>, StripError> {
    solve_from(sec, load, e_star, settings, None).map(|(p, _)| p)
}

/// [`solve`] from a guess of the rigid approach δ along u (m; e.g. the previous sample's), and
/// the approach it found. The approach is found by the secant method on ln F(ln δ) (F ∝ δ^{3/2}
/// for Hertz, closer to δ for a conformal patch), safeguarded by bisection once bracketed.
pub fn solve_from(
    sec: &GapSection,
    load: f64,
    e_star: f64,
    settings: &StripSettings,
    guess: Option<f64>,
) -> Result<(Vec<StripPatch>, f64), StripError> {
    if !(load.is_finite() && load > 0.0) {
        return Err(StripError::Load(load));
    }
    let arc = arc_lengths(sec);
    let gl = gauss_legendre_half_pi(settings.nodes.max(4));
    let mut candidates: Vec<usize> = sec
        .minima(sec.gap[sec.contact].max(0.0) + settings.candidate_gap_m)
        .into_iter()
        .filter(|&i| i > 0 && i + 1 < sec.w.len())
        .collect();
    if !candidates.contains(&sec.contact) {
        candidates.insert(0, sec.contact);
    }
    let total = |delta: f64| -> Result<(f64, Vec<Shape>, Vec<f64>), StripError> {
        let (shapes, p) = patches_at(sec, &arc, &candidates, delta, e_star, settings, &gl)?;
        let f = shapes
            .iter()
            .zip(&p)
            .map(|(s, &pj)| force(s, pj) * sec.cos_slope[s.centre])
            .sum();
        Ok((f, shapes, p))
    };
    let gmin = sec.gap[sec.contact].max(0.0);
    // x = ln(δ − g_min), the secant's variable.
    let mut x = guess
        .filter(|g| g.is_finite() && *g > gmin)
        .map_or((2e-5f64).ln(), |g| (g - gmin).ln());
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut prev: Option<(f64, f64)> = None;
    let max_iter = 80;
    let mut last = (0.0, Vec::new(), Vec::new());
    let target = load.ln();
    for _ in 0..max_iter {
        let delta = gmin + x.exp();
        last = total(delta)?;
        let f = last.0;
        if (f / load - 1.0).abs() < 1e-6 {
            return Ok((build(sec, &last.1, &last.2), delta));
        }
        if f < load {
            lo = lo.max(x);
        } else {
            hi = hi.min(x);
        }
        let next = if f > 0.0 {
            let lf = f.ln();
            let slope = match prev {
                Some((px, pf)) if (x - px).abs() > 1e-12 && (lf - pf).abs() > 1e-12 => {
                    ((lf - pf) / (x - px)).clamp(0.3, 3.0)
                }
                _ => 1.5,
            };
            prev = Some((x, lf));
            x + (target - lf) / slope
        } else {
            x + std::f64::consts::LN_2
        };
        x = if next > lo && next < hi {
            next
        } else if lo.is_finite() && hi.is_finite() {
            0.5 * (lo + hi)
        } else if f < load {
            x + 1.0
        } else {
            x - 1.0
        };
    }
    if last.1.is_empty() {
        return Err(StripError::NoPatch(gmin + x.exp()));
    }
    Err(StripError::NoConvergence(max_iter, last.0, load))
}

fn build(sec: &GapSection, shapes: &[Shape], p: &[f64]) -> Vec<StripPatch> {
    shapes
        .iter()
        .zip(p)
        .map(|(s, &pj)| {
            let strips: Vec<Strip> = s
                .strips
                .iter()
                .map(|st| Strip {
                    pressure: pj * st.half_length / s.max_l,
                    ..*st
                })
                .collect();
            let weight = |st: &Strip| st.half_length * st.half_length * st.width;
            let total_w: f64 = strips.iter().map(weight).sum();
            let wbar = strips.iter().map(|st| weight(st) * st.w).sum::<f64>() / total_w;
            StripPatch {
                max_pressure: pj,
                normal_force: force(s, pj),
                area: strips.iter().map(|st| 2.0 * st.half_length * st.width).sum(),
                s_rail: lerp(sec, &sec.s_rail, wbar),
                s_wheel: lerp(sec, &sec.s_wheel, wbar),
                contact_angle: lerp(sec, &sec.contact_angle, wbar),
                rolling_radius: lerp(sec, &sec.radius, wbar),
                s_rail_range: (lerp(sec, &sec.s_rail, s.lo), lerp(sec, &sec.s_rail, s.hi)),
                width: strips.iter().map(|st| st.width).sum(),
                length: 2.0 * s.max_l,
                cos_u: sec.cos_slope[s.centre],
                approach: s.approach_u * sec.cos_slope[s.centre],
                virtual_factor: s.eps,
                length_factor: s.cx,
                strips,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::nonhertz::gap::{GapInput, GapSection};
    use crate::profile::{Profile, ProfileKind};
    use crate::track::Side;

    fn circle(kind: ProfileKind, r: f64) -> Profile {
        let n = 2001;
        let s: Vec<f64> = (0..n)
            .map(|i| 0.8 * r.min(0.05) * (2.0 * i as f64 / (n - 1) as f64 - 1.0))
            .collect();
        let sign = if kind == ProfileKind::Rail { -1.0 } else { 1.0 };
        let z = s.iter().map(|s| sign * (r - (r * r - s * s).sqrt())).collect();
        Profile::from_points("circle", kind, "test", s, z).unwrap()
    }

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        let gl = gauss_legendre_half_pi(12);
        let i: f64 = gl.iter().map(|(t, w)| w * t.powi(5)).sum();
        let exact = std::f64::consts::FRAC_PI_2.powi(6) / 6.0;
        assert!((i - exact).abs() < 1e-12 * exact);
    }

    #[test]
    fn band_integrals_add_up_across_a_split() {
        // One band split in two at y_c (the singular case on both halves' edge) or elsewhere.
        let gl = gauss_legendre_half_pi(16);
        let whole = band_integral(3e-3, -1e-3, 2e-3, &gl);
        let split = band_integral(3e-3, -1e-3, 0.5e-3, &gl) + band_integral(3e-3, 0.5e-3, 2e-3, &gl);
        assert!((whole - split).abs() < 2e-3 * whole, "{whole} vs {split}");
    }

    /// Hertz's closed form on two circles (a quadratic gap): the strip model must reproduce p0,
    /// the semi-axes and the approach, for a circular and two elongated ellipses.
    #[test]
    fn a_quadratic_gap_gives_hertz() {
        for (r_wheel_lat, r_rail) in [(-0.4, 0.3), (1e3, 0.3), (0.05, 0.013), (1e3, 0.08)] {
            let wheel = if r_wheel_lat < 0.0 {
                // Concave wheel (hollow-worn tread): radius 0.4 m, rail 0.3 m.
                let mut w = circle(ProfileKind::Rail, -r_wheel_lat);
                w.kind = ProfileKind::Wheel;
                w
            } else {
                circle(ProfileKind::Wheel, r_wheel_lat)
            };
            let rail = circle(ProfileKind::Rail, r_rail);
            let sec = GapSection::new(
                &wheel,
                &rail,
                &GapInput {
                    side: Side::Left,
                    s_wheel: 0.0,
                    s_rail: 0.0,
                    nominal_radius: 0.46,
                    rail_angle: 0.0,
                    approach_angle: 0.0,
                    half_window: crate::contact::nonhertz::gap::GAP_WINDOW_M,
                },
            )
            .unwrap();
            let e_star = Material::STEEL.contact_modulus(&Material::STEEL);
            let n = 60e3;
            let patches = solve(&sec, n, e_star, &StripSettings::default()).unwrap();
            assert_eq!(patches.len(), 1);
            let p = &patches[0];
            let kw = 1.0 / r_wheel_lat;
            let curv = RelativeCurvature {
                a: 0.5 / 0.46,
                b: 0.5 * (kw + 1.0 / r_rail),
            };
            let h = HertzContact::solve(curv, n, &Material::STEEL, &Material::STEEL).unwrap();
            let rel = |x: f64, y: f64| (x / y - 1.0).abs();
            assert!(
                rel(p.max_pressure, h.max_pressure) < 5e-3,
                "{r_wheel_lat}/{r_rail}: p0 {} vs Hertz {}",
                p.max_pressure,
                h.max_pressure
            );
            assert!(rel(p.normal_force, n) < 1e-6);
            assert!(rel(0.5 * p.width, h.b) < 5e-3, "b {} vs {}", 0.5 * p.width, h.b);
            assert!(rel(0.5 * p.length, h.a) < 5e-3, "a {} vs {}", 0.5 * p.length, h.a);
            assert!(
                rel(p.area, std::f64::consts::PI * h.a * h.b) < 1.5e-2,
                "area {} vs {}",
                p.area,
                std::f64::consts::PI * h.a * h.b
            );
            assert!(
                rel(p.approach, h.penetration) < 5e-3,
                "δ {} vs {}",
                p.approach,
                h.penetration
            );
        }
    }
}

#[cfg(test)]
mod timing {
    use super::*;
    use crate::contact::nonhertz::gap::{GapInput, GapSection, GAP_WINDOW_M};
    use crate::profile::StandardProfile;
    use crate::track::Side;

    #[test]
    #[ignore = "timing probe"]
    fn time_one_solve() {
        let wheel = StandardProfile::S1002.profile();
        let rail = StandardProfile::Rail60E1.profile();
        let e_star = Material::STEEL.contact_modulus(&Material::STEEL);
        for (sw, sr) in [(0.003, -0.003), (-0.03, -0.031)] {
            let input = GapInput {
                side: Side::Left,
                s_wheel: sw,
                s_rail: sr,
                nominal_radius: 0.46,
                rail_angle: 0.025,
                approach_angle: 0.0,
                half_window: GAP_WINDOW_M,
            };
            let t = std::time::Instant::now();
            let n = 200;
            let mut sec = None;
            for _ in 0..n {
                sec = Some(GapSection::new(&wheel, &rail, &input).unwrap());
            }
            let t_gap = t.elapsed().as_secs_f64() / n as f64;
            let sec = sec.unwrap();
            let t = std::time::Instant::now();
            let mut r = Vec::new();
            for _ in 0..n {
                r = solve(&sec, 50e3, e_star, &StripSettings::default()).unwrap_or_default();
            }
            let t_solve = t.elapsed().as_secs_f64() / n as f64;
            println!(
                "gap {:.1} µs, solve {:.1} µs, patches {}, pmax {:.1}",
                t_gap * 1e6,
                t_solve * 1e6,
                r.len(),
                r[0].max_pressure * 1e-6
            );
            for (strips, nodes) in [(24, 8), (32, 8), (24, 6), (16, 6), (80, 16)] {
                let st = StripSettings {
                    strips,
                    nodes,
                    ..StripSettings::default()
                };
                let t = std::time::Instant::now();
                for _ in 0..n {
                    r = solve(&sec, 50e3, e_star, &st).unwrap_or_default();
                }
                println!(
                    "  {strips}/{nodes}: {:.1} µs pmax {:.1} area {:.3}",
                    t.elapsed().as_secs_f64() / n as f64 * 1e6,
                    r[0].max_pressure * 1e-6,
                    r[0].area * 1e6
                );
            }
        }
    }
}
