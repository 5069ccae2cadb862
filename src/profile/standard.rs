//! Standard profiles generated from their published sectionwise geometry (paper §3 uses the
//! S1002 wheel; the MS vehicle runs on UIC54).
//!
//! * **S1002** wheel (EN 13715, h28 e32.5): the DLR/Netter analytic definition, eight sections
//!   (polynomials, circles, straight flank). Coordinates as published: S \[mm\] lateral from the
//!   taping line, positive towards the field side (flange at negative S); F(S) \[mm\] radial offset,
//!   positive = larger radius. Flange back at S = −70 mm (nominal rolling circle 70 mm from it).
//! * **60E1 (UIC60)** and **54E1 (UIC54)** rail heads (EN 13674-1): arcs R300, R80, R13 joined
//!   tangentially, then the 1:20 flank; y \[mm\] from the rail centreline, depth d \[mm\] below the top.
//!
//! The published geometry is in mm and is kept so here (the boundary); [`StandardProfile::profile`]
//! converts to SI once when it builds the runtime [`Profile`] (a C² spline through points sampled
//! every 0.1 mm of arc length and at every section joint).

use super::curve::{Profile, ProfileKind};

/// One analytic section `g(x)` on `[x0, x1]` (mm), value positive *down* (F for the wheel, depth
/// for a rail).
#[derive(Debug, Clone, Copy)]
pub enum Section {
    /// g = Σ c_k x^k (up to degree 8).
    Poly { x0: f64, x1: f64, c: [f64; 9] },
    /// g = gc + sign·sqrt(r² − (x − xc)²).
    Circle {
        x0: f64,
        x1: f64,
        xc: f64,
        gc: f64,
        r: f64,
        sign: f64,
    },
}

impl Section {
    /// Lateral range `(x0, x1)`, `x0 < x1`.
    pub fn range(&self) -> (f64, f64) {
        match *self {
            Section::Poly { x0, x1, .. } | Section::Circle { x0, x1, .. } => (x0, x1),
        }
    }

    /// `(g, g', g'')` at `x` (mm, mm/mm, 1/mm).
    pub fn eval(&self, x: f64) -> (f64, f64, f64) {
        match *self {
            Section::Poly { c, .. } => {
                let (mut g, mut d1, mut d2) = (0.0, 0.0, 0.0);
                for k in (0..9).rev() {
                    d2 = d2 * x + d1;
                    d1 = d1 * x + g;
                    g = g * x + c[k];
                }
                (g, d1, 2.0 * d2)
            }
            Section::Circle { xc, gc, r, sign, .. } => {
                let u = x - xc;
                let w = (r * r - u * u).max(0.0).sqrt();
                let g = gc + sign * w;
                let d1 = -sign * u / w;
                let d2 = -sign * r * r / (w * w * w);
                (g, d1, d2)
            }
        }
    }
}

/// A profile defined sectionwise; sections sorted by lateral position and contiguous.
#[derive(Debug, Clone)]
pub struct SectionCurve {
    pub sections: Vec<Section>,
}

impl SectionCurve {
    /// Lateral range covered.
    pub fn range(&self) -> (f64, f64) {
        (
            self.sections[0].range().0,
            self.sections[self.sections.len() - 1].range().1,
        )
    }

    /// Section joints (interior breakpoints), mm.
    pub fn joints(&self) -> Vec<f64> {
        self.sections[1..].iter().map(|s| s.range().0).collect()
    }

    /// The section that holds `x` (the left one at a joint), clamped to the ends.
    pub fn section_at(&self, x: f64) -> &Section {
        self.sections
            .iter()
            .find(|s| x <= s.range().1)
            .unwrap_or(&self.sections[self.sections.len() - 1])
    }

    /// `(g, g', g'')` at `x`.
    pub fn eval(&self, x: f64) -> (f64, f64, f64) {
        self.section_at(x).eval(x)
    }

    /// Points sampled every `ds` mm of arc length inside each section, plus every joint (where a
    /// published definition has a tiny value jump, the joint takes the mean of both sides).
    pub fn sample(&self, ds: f64) -> Vec<(f64, f64)> {
        let mut pts = Vec::new();
        for (k, sec) in self.sections.iter().enumerate() {
            let (x0, x1) = sec.range();
            let g0 = if k == 0 {
                sec.eval(x0).0
            } else {
                0.5 * (sec.eval(x0).0 + self.sections[k - 1].eval(x0).0)
            };
            pts.push((x0, g0));
            let mut x = x0;
            loop {
                let slope = sec.eval(x).1;
                let step = ds / (1.0 + slope * slope).sqrt();
                x += step;
                if x >= x1 - 0.25 * step {
                    break;
                }
                pts.push((x, sec.eval(x).0));
            }
        }
        let last = self.sections[self.sections.len() - 1];
        let x1 = last.range().1;
        pts.push((x1, last.eval(x1).0));
        pts
    }
}

/// The standard profiles kecsim generates itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StandardProfile {
    /// S1002 wheel, EN 13715 h28 e32.5.
    S1002,
    /// 60E1 (UIC60) rail head, upright.
    Rail60E1,
    /// 54E1 (UIC54) rail head, upright.
    Rail54E1,
}

/// Arc length step of the sampling behind the runtime spline, mm.
pub const SAMPLE_STEP_MM: f64 = 0.1;

/// Steepest slope kept at the S1002 flange back: the section-H circle has a vertical tangent at
/// S = −70 mm, which no function z(y) can represent; the generated profile starts where
/// |dF/dS| = 10 (84.3°), 0.10 mm from the flange back. No wheel–rail contact exists there.
pub const S1002_MAX_FLANGE_BACK_SLOPE: f64 = 10.0;

/// Depth below the top of rail down to which the 1:20 head flank is generated, mm.
pub const RAIL_FLANK_DEPTH_MM: f64 = 30.0;

impl StandardProfile {
    /// All standard profiles.
    pub const ALL: [StandardProfile; 3] = [Self::S1002, Self::Rail60E1, Self::Rail54E1];

    /// The name used on the command line and in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            Self::S1002 => "s1002",
            Self::Rail60E1 => "60e1",
            Self::Rail54E1 => "54e1",
        }
    }

    /// Looks a standard profile up by name (case-insensitive; `uic60`/`uic54` are aliases).
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "s1002" => Some(Self::S1002),
            "60e1" | "uic60" => Some(Self::Rail60E1),
            "54e1" | "uic54" => Some(Self::Rail54E1),
            _ => None,
        }
    }

    /// Wheel or rail.
    pub fn kind(self) -> ProfileKind {
        match self {
            Self::S1002 => ProfileKind::Wheel,
            _ => ProfileKind::Rail,
        }
    }

    /// Where the published definition comes from.
    pub fn source(self) -> &'static str {
        match self {
            Self::S1002 => "S1002 (EN 13715 h28 e32.5), DLR/Netter sectionwise analytic definition",
            Self::Rail60E1 => "60E1/UIC60 head (EN 13674-1): R300, R80 (to |y|=26.0265), R13, 1:20 flank",
            Self::Rail54E1 => "54E1/UIC54 head (EN 13674-1): R300, R80 (to |y|=24.8635), R13, 1:20 flank",
        }
    }

    /// The published sectionwise definition, mm, value positive down (F or depth).
    pub fn sections(self) -> SectionCurve {
        match self {
            Self::S1002 => s1002_sections(),
            Self::Rail60E1 => rail_head_sections(20.456 / 2.0, 52.053 / 2.0),
            Self::Rail54E1 => rail_head_sections(20.024 / 2.0, 49.727 / 2.0),
        }
    }

    /// The rail head's published arcs (`blend::RailHead`); `None` for the wheel.
    pub(crate) fn rail_head(self) -> Option<super::blend::RailHead> {
        let arc_ends_mm = match self {
            Self::S1002 => return None,
            Self::Rail60E1 => [20.456 / 2.0, 52.053 / 2.0],
            Self::Rail54E1 => [20.024 / 2.0, 49.727 / 2.0],
        };
        Some(super::blend::RailHead {
            radii_mm: [300.0, 80.0, 13.0],
            arc_ends_mm,
            flank_slope: 20.0,
            flank_depth_mm: RAIL_FLANK_DEPTH_MM,
        })
    }

    /// The rail head with the curvature at its arc–arc joints (R300/R80, R80/R13) blended over
    /// ± `blend_mm` of arc length (`profile::blend`; a model change: the arcs keep their radii
    /// and move by micrometres). Named `<name>:blend=<blend_mm>`, the name
    /// [`Profile::resolve`](crate::profile::Profile::resolve) reads. `None` for the wheel or a
    /// half-width outside (0, 3] mm (`blend::MAX_BLEND_MM`).
    pub fn blended(self, blend_mm: f64) -> Option<Profile> {
        let head = self.rail_head()?;
        if !(blend_mm > 0.0 && blend_mm <= super::blend::MAX_BLEND_MM) {
            return None;
        }
        let pts = head.points(blend_mm, SAMPLE_STEP_MM);
        let s: Vec<f64> = pts.iter().map(|p| p.0 * 1e-3).collect();
        let z: Vec<f64> = pts.iter().map(|p| -p.1 * 1e-3).collect();
        let sections = self.sections();
        let moved = super::blend::max_shape_change_mm(&head, &|x| sections.eval(x).0, blend_mm);
        let source = format!(
            "{}; the curvature at the R300/R80 and R80/R13 joints blended over ±{blend_mm} mm of arc length, the head moved by at most {:.1} µm normal to it (kecsim, issue 52: a model change)",
            self.source(),
            moved * 1e3
        );
        Some(
            Profile::from_points(
                &format!("{}:blend={blend_mm}", self.name()),
                self.kind(),
                &source,
                s,
                z,
            )
            .expect("blended rail head sampling yields a valid spline"),
        )
    }

    /// The runtime profile (SI, z up).
    pub fn profile(self) -> Profile {
        let pts = self.sections().sample(SAMPLE_STEP_MM);
        let s: Vec<f64> = pts.iter().map(|p| p.0 * 1e-3).collect();
        let z: Vec<f64> = pts.iter().map(|p| -p.1 * 1e-3).collect();
        Profile::from_points(self.name(), self.kind(), self.source(), s, z)
            .expect("standard profile sampling yields a valid spline")
    }
}

/// S1002 sections A–H (flange back → field side order), coefficients from
/// `shared/design/facts/s1002-wheel.txt`.
fn s1002_sections() -> SectionCurve {
    let (aa, ba) = (1.364323640, 0.066666667);
    let b = [
        0.0,
        -3.358537058e-02,
        1.565681624e-03,
        -2.810427944e-05,
        5.844240864e-08,
        -1.562379023e-08,
        5.309217349e-15,
        -5.957839843e-12,
        2.646656573e-13,
    ];
    let c = [
        -4.320221063e+03,
        -1.038384026e+03,
        -1.065501873e+02,
        -6.051367875,
        -2.054332446e-01,
        -4.169739389e-03,
        -4.687195829e-05,
        -2.252755540e-07,
        0.0,
    ];
    let (ad, bd, cd) = (16.446, 13.0, 26.210665);
    let (ae, be) = (93.576667419, 2.747477419);
    let (af, bf, cf) = (8.834924130, 20.0, 58.558326413);
    let (ag, bg, cg) = (16.0, 12.0, 55.0);
    let (ah, bh, ch) = (9.519259302, 20.5, 49.5);
    // Start of section H where |dF/dS| = S1002_MAX_FLANGE_BACK_SLOPE.
    let m = S1002_MAX_FLANGE_BACK_SLOPE;
    let x_start = -ch - bh * m / (1.0 + m * m).sqrt();
    let mut line = [0.0; 9];
    line[0] = -ae;
    line[1] = -be;
    let mut cham = [0.0; 9];
    cham[0] = aa;
    cham[1] = -ba;
    let sections = vec![
        Section::Circle {
            x0: x_start,
            x1: -62.764705882,
            xc: -ch,
            gc: ah,
            r: bh,
            sign: 1.0,
        },
        Section::Circle {
            x0: -62.764705882,
            x1: -49.662510381,
            xc: -cg,
            gc: ag,
            r: bg,
            sign: 1.0,
        },
        Section::Circle {
            x0: -49.662510381,
            x1: -39.764473993,
            xc: -cf,
            gc: af,
            r: bf,
            sign: 1.0,
        },
        Section::Poly {
            x0: -39.764473993,
            x1: -38.426669071,
            c: line,
        },
        Section::Circle {
            x0: -38.426669071,
            x1: -35.0,
            xc: -cd,
            gc: ad,
            r: bd,
            sign: -1.0,
        },
        Section::Poly {
            x0: -35.0,
            x1: -26.0,
            c,
        },
        Section::Poly {
            x0: -26.0,
            x1: 32.15796,
            c: b,
        },
        Section::Poly {
            x0: 32.15796,
            x1: 60.0,
            c: cham,
        },
    ];
    SectionCurve { sections }
}

/// Rail head of EN 13674-1 construction: R300 from the top to |y| = x1, tangent R80 to |y| = x2,
/// tangent R13 until its tangent reaches the 1:20 flank, then the flank down to
/// [`RAIL_FLANK_DEPTH_MM`]. Symmetric about the rail centreline; depth positive down.
fn rail_head_sections(x1: f64, x2: f64) -> SectionCurve {
    let (r1, r2, r3) = (300.0, 80.0, 13.0);
    let phi1 = (x1 / r1).asin();
    let (x20, z20) = ((r1 - r2) * phi1.sin(), r1 - (r1 - r2) * phi1.cos());
    let phi2 = ((x2 - x20) / r2).asin();
    let (x30, z30) = (x20 + (r2 - r3) * phi2.sin(), z20 - (r2 - r3) * phi2.cos());
    // R13 ends where the tangent slope |dd/dy| = 20 (the 1:20 flank).
    let flank = 20.0_f64;
    let x3 = x30 + r3 * flank / (1.0 + flank * flank).sqrt();
    let d3 = z30 - (r3 * r3 - (x3 - x30).powi(2)).sqrt();
    let x4 = x3 + (RAIL_FLANK_DEPTH_MM - d3) / flank;
    let line_right = {
        let mut c = [0.0; 9];
        c[0] = d3 - flank * x3;
        c[1] = flank;
        c
    };
    let line_left = {
        let mut c = [0.0; 9];
        c[0] = d3 - flank * x3;
        c[1] = -flank;
        c
    };
    let sections = vec![
        Section::Poly {
            x0: -x4,
            x1: -x3,
            c: line_left,
        },
        Section::Circle {
            x0: -x3,
            x1: -x2,
            xc: -x30,
            gc: z30,
            r: r3,
            sign: -1.0,
        },
        Section::Circle {
            x0: -x2,
            x1: -x1,
            xc: -x20,
            gc: z20,
            r: r2,
            sign: -1.0,
        },
        Section::Circle {
            x0: -x1,
            x1,
            xc: 0.0,
            gc: r1,
            r: r1,
            sign: -1.0,
        },
        Section::Circle {
            x0: x1,
            x1: x2,
            xc: x20,
            gc: z20,
            r: r2,
            sign: -1.0,
        },
        Section::Circle {
            x0: x2,
            x1: x3,
            xc: x30,
            gc: z30,
            r: r3,
            sign: -1.0,
        },
        Section::Poly {
            x0: x3,
            x1: x4,
            c: line_right,
        },
    ];
    SectionCurve { sections }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Value and slope agree on both sides of every joint.
    fn assert_joints_continuous(p: StandardProfile, value_tol_mm: f64, slope_tol: f64) {
        let sc = p.sections();
        for w in sc.sections.windows(2) {
            let x = w[0].range().1;
            assert_eq!(x, w[1].range().0, "{p:?}: sections not contiguous");
            let (ga, da, _) = w[0].eval(x);
            let (gb, db, _) = w[1].eval(x);
            assert!(
                (ga - gb).abs() < value_tol_mm,
                "{p:?} value jump {} at {x}",
                ga - gb
            );
            assert!(
                (da - db).abs() < slope_tol * (1.0 + da.abs()),
                "{p:?} slope {da} vs {db} at {x}"
            );
        }
    }

    #[test]
    fn s1002_joints_continuous() {
        // The published definition jumps by ≤1.2e-4 mm at S = −26 and −35; slopes agree to 4 digits.
        assert_joints_continuous(StandardProfile::S1002, 1.5e-4, 1e-3);
    }

    #[test]
    fn rail_joints_continuous() {
        assert_joints_continuous(StandardProfile::Rail60E1, 1e-9, 1e-9);
        assert_joints_continuous(StandardProfile::Rail54E1, 1e-9, 1e-9);
    }

    #[test]
    fn s1002_flange_height_angle_thickness() {
        let sc = StandardProfile::S1002.sections();
        // Flange height: max F (flange tip), dense search.
        let (mut fmax, mut xmax) = (f64::MIN, 0.0);
        for k in 0..=200_000 {
            let x = -69.8 + 129.8 * k as f64 / 200_000.0;
            let f = sc.eval(x).0;
            if f > fmax {
                (fmax, xmax) = (f, x);
            }
        }
        assert!((fmax - 28.0).abs() < 1e-3, "flange height {fmax}");
        assert!((xmax + 55.0).abs() < 1e-2, "flange tip at {xmax}");
        // Flange angle: steepest slope on the flank is tan 70°.
        let steepest = (0..=10_000)
            .map(|k| -45.0 + 10.0 * k as f64 / 10_000.0)
            .map(|x| sc.eval(x).1.abs())
            .fold(0.0, f64::max);
        assert!((steepest.atan().to_degrees() - 70.0).abs() < 1e-3, "flange angle");
        // Flange thickness: from the flange back (−70) to where F = 10 on the flank.
        let (mut a, mut b) = (-45.0, -30.0);
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if sc.eval(m).0 > 10.0 {
                a = m
            } else {
                b = m
            }
        }
        assert!((70.0 + a - 32.5).abs() < 1e-3, "flange thickness {}", 70.0 + a);
        // Taping line: F(0) = 0.
        assert!(sc.eval(0.0).0.abs() < 1e-12);
    }

    #[test]
    fn rail_head_widths_and_published_depths() {
        // 60E1 head width 72 mm (R13 ends at the 1:20 tangent, |y| ≈ 36.0).
        let r60 = StandardProfile::Rail60E1.sections();
        let x3 = r60.sections[5].range().1;
        assert!((x3 - 36.0).abs() < 0.01, "60E1 R13 end {x3}");
        // Depths computed from the GENSYS recipe (facts/rails.txt).
        for (y, d) in [
            (5.0, 0.0417),
            (15.0, 0.4802),
            (25.0, 2.0653),
            (30.0, 3.9845),
            (34.0, 7.9956),
        ] {
            let g = r60.eval(y).0;
            assert!((g - d).abs() < 2e-3, "60E1 depth at {y}: {g} vs {d}");
        }
        let r54 = StandardProfile::Rail54E1.sections();
        let x3 = r54.sections[5].range().1;
        assert!((x3 - 35.0).abs() < 0.1, "54E1 head width {}", 2.0 * x3);
    }

    #[test]
    fn names_round_trip() {
        for p in StandardProfile::ALL {
            assert_eq!(StandardProfile::from_name(p.name()), Some(p));
        }
        assert_eq!(
            StandardProfile::from_name("UIC60"),
            Some(StandardProfile::Rail60E1)
        );
        assert_eq!(StandardProfile::from_name("s1003"), None);
    }
}

/// The blended rail head (`super::blend`) against the published one.
#[cfg(test)]
mod blend_tests {
    use super::super::blend::{max_shape_change_mm, RailHead};
    use super::StandardProfile;

    fn head54() -> (RailHead, impl Fn(f64) -> f64) {
        let sc = StandardProfile::Rail54E1.sections();
        (StandardProfile::Rail54E1.rail_head().unwrap(), move |x: f64| {
            sc.eval(x).0
        })
    }

    /// Radius of the circle through three points, mm.
    fn circumradius(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
        let d = |p: (f64, f64), q: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
        let area2 = ((b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)).abs();
        d(a, b) * d(b, c) * d(c, a) / (2.0 * area2)
    }

    /// Unblended, the integrated head is the published sectionwise one (an independent form:
    /// the circles' closed forms of `standard`), to the quadrature's accuracy.
    #[test]
    fn unblended_head_is_the_published_one() {
        let (head, published) = head54();
        // Normal to the head (the flank is steep): Simpson across the published jumps, a few pm.
        let exact = max_shape_change_mm(&head, &published, 0.0);
        assert!(exact < 1e-8, "{exact} mm");
        for w in [0.25, 1.0] {
            let change = max_shape_change_mm(&head, &published, w);
            println!("54E1 blended over ±{w} mm: shape change {:.2} µm", change * 1e3);
        }
    }

    /// Blended over ±1 mm: the curvature is continuous and monotone from the crown to the flank
    /// joint; away from the blends each arc has its published radius (circles through three of
    /// the points); the shape moves by at most 7 µm; the R13 meets the flank at the published
    /// slope 20.
    #[test]
    fn blended_head_keeps_the_radii_and_moves_by_micrometres() {
        let (head, published) = head54();
        let w = 1.0;
        let ([s1, s2, s3], _) = head.joints();
        let mut last = head.curvature(0.0, w);
        let n = 200_000;
        for k in 1..n {
            let s = s3 * k as f64 / n as f64;
            let kk = head.curvature(s, w);
            assert!(kk >= last - 1e-15, "curvature falls at s = {s}");
            assert!(kk - last < 1e-4, "curvature jumps by {} at s = {s}", kk - last);
            last = kk;
        }
        let pts = head.half_points(w, 0.01);
        // Arc length of point k ≈ 0.01 k (the points every 10 µm of arc).
        for (s_mid, r) in [
            (0.5 * s1, 300.0),
            (0.5 * (s1 + s2), 80.0),
            (0.5 * (s2 + s3) + 1.0, 13.0),
        ] {
            let k = (s_mid / 0.01).round() as usize;
            let rr = circumradius(pts[k - 50], pts[k], pts[k + 50]);
            assert!((rr - r).abs() < 1e-3 * r, "radius {rr} where R{r}");
        }
        // Inside a blend the radius lies between its two arcs'.
        let k = (s2 / 0.01).round() as usize;
        let rr = circumradius(pts[k - 5], pts[k], pts[k + 5]);
        assert!(rr > 13.0 && rr < 80.0, "{rr}");
        let change = max_shape_change_mm(&head, &published, w);
        assert!(change < 7e-3 && change > 1e-4, "shape change {change} mm");
        // The flank: the last points lie on a line of slope 20, as published.
        let m = pts.len();
        let slope = (pts[m - 1].1 - pts[m - 2].1) / (pts[m - 1].0 - pts[m - 2].0);
        assert!((slope - 20.0).abs() < 1e-9, "{slope}");
    }

    /// The name `54e1:blend=1` resolves to the blended head; nonsense is refused, naming it.
    #[test]
    fn blended_rail_resolves_by_name() {
        use crate::profile::{Profile, ProfileKind};
        let p = Profile::resolve("54e1:blend=1", ProfileKind::Rail).unwrap();
        assert_eq!(p.name, "54e1:blend=1");
        assert!(p.source.contains("moved by at most 5.2 µm"), "{}", p.source);
        let exact = Profile::resolve("54e1", ProfileKind::Rail).unwrap();
        // At the crown both agree; the blend region's curvature differs.
        assert!((p.eval(0.0).z - exact.eval(0.0).z).abs() < 1e-9);
        for (spec, want) in [
            ("s1002:blend=1", "standard rail head"),
            ("54e1:blend=x", "half-width in mm"),
            ("54e1:blend=9", "at most 3"),
            ("54e1:blend=0", "above 0"),
        ] {
            let e = Profile::resolve(spec, ProfileKind::Rail).unwrap_err().to_string();
            assert!(
                e.contains(want) && e.contains(spec.split(':').next().unwrap()),
                "{spec}: {e}"
            );
        }
    }
}
