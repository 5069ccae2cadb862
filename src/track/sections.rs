//! Sections of the horizontal and vertical profiles (paper §2.2, Tab. 1 and 2), and the checks a
//! list of them must pass before a centreline is built from it.
//!
//! Horizontal (Tab. 1): straight (ρ_h = 0), circular curve (ρ_h = 1/R_h), clothoid transition
//! (ρ_h linear in s, ρ'_h = Δρ_h / L_t). The cant φ^t is constant on straights and curves and
//! linear in transitions (ρ_tw = Δφ / L_t). Signs (METHOD.md §0–1): ρ_h > 0 turns left; a positive
//! cant raises the left rail (φ^t is a rotation about the track X axis, Eq. 2), so the Tab. 6 left
//! curve has a negative cant.
//!
//! Vertical (Tab. 2): straight (θ_v constant, ρ_v = 0) and transition (θ_v linear, ρ_v =
//! (θ_v2 − θ_v1)/L_vt). θ_v is the paper's slope: **positive when the track goes down** in the
//! direction of increasing s.
//!
//! Departure from the paper's Tab. 1, stated: the paper's transitions join a straight to a curve;
//! here a transition joins any two curvatures and cants (a compound curve), with the paper's
//! case as the special one. A transition is defined by its end values, which must equal those of
//! its neighbours; a curvature step between two non-transition sections (a straight running into
//! a curve, as on some tramways) is accepted, a step in cant or in slope never is.

/// Relative tolerance of the continuity checks (curvature, cant, slope) and absolute one, m, of
/// the section ends.
pub const JOIN_TOL: f64 = 1e-9;

/// The kind of a horizontal section (Tab. 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HorizontalKind {
    Straight,
    Curve,
    Transition,
}

impl HorizontalKind {
    pub fn name(self) -> &'static str {
        match self {
            HorizontalKind::Straight => "straight",
            HorizontalKind::Curve => "curve",
            HorizontalKind::Transition => "transition",
        }
    }
}

/// The kind of a vertical section (Tab. 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VerticalKind {
    Straight,
    Transition,
}

impl VerticalKind {
    pub fn name(self) -> &'static str {
        match self {
            VerticalKind::Straight => "straight",
            VerticalKind::Transition => "transition",
        }
    }
}

/// One horizontal section over `[from_m, to_m]`: curvature and cant at its start and end (equal on
/// straights and curves).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizontalSection {
    pub kind: HorizontalKind,
    pub from_m: f64,
    pub to_m: f64,
    /// ρ_h at the start and the end, 1/m (> 0: left curve).
    pub curvature_1pm: [f64; 2],
    /// φ^t at the start and the end, rad (> 0: left rail higher).
    pub cant_rad: [f64; 2],
}

impl HorizontalSection {
    pub fn straight(from_m: f64, to_m: f64) -> Self {
        HorizontalSection {
            kind: HorizontalKind::Straight,
            from_m,
            to_m,
            curvature_1pm: [0.0; 2],
            cant_rad: [0.0; 2],
        }
    }

    /// A circular curve of signed radius (> 0: left) and constant cant.
    pub fn curve(from_m: f64, to_m: f64, radius_m: f64, cant_rad: f64) -> Self {
        HorizontalSection {
            kind: HorizontalKind::Curve,
            from_m,
            to_m,
            curvature_1pm: [1.0 / radius_m; 2],
            cant_rad: [cant_rad; 2],
        }
    }

    /// A clothoid from (curvature, cant) `start` to `end`.
    pub fn transition(from_m: f64, to_m: f64, start: (f64, f64), end: (f64, f64)) -> Self {
        HorizontalSection {
            kind: HorizontalKind::Transition,
            from_m,
            to_m,
            curvature_1pm: [start.0, end.0],
            cant_rad: [start.1, end.1],
        }
    }

    pub fn length_m(&self) -> f64 {
        self.to_m - self.from_m
    }

    /// ρ'_h, 1/m² (Tab. 1: 1/(R_h L_t) entering a curve from a straight).
    pub fn curvature_rate(&self) -> f64 {
        (self.curvature_1pm[1] - self.curvature_1pm[0]) / self.length_m()
    }

    /// ρ_tw = dφ^t/ds, rad/m (Tab. 1: φ_c / L_t entering a curve from a straight).
    pub fn twist(&self) -> f64 {
        (self.cant_rad[1] - self.cant_rad[0]) / self.length_m()
    }
}

/// One vertical section over `[from_m, to_m]`: slope θ_v at its start and end (equal on a straight).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerticalSection {
    pub kind: VerticalKind,
    pub from_m: f64,
    pub to_m: f64,
    /// θ_v at the start and the end, rad (> 0: going down).
    pub slope_rad: [f64; 2],
}

impl VerticalSection {
    pub fn straight(from_m: f64, to_m: f64, slope_rad: f64) -> Self {
        VerticalSection {
            kind: VerticalKind::Straight,
            from_m,
            to_m,
            slope_rad: [slope_rad; 2],
        }
    }

    pub fn transition(from_m: f64, to_m: f64, slope_start: f64, slope_end: f64) -> Self {
        VerticalSection {
            kind: VerticalKind::Transition,
            from_m,
            to_m,
            slope_rad: [slope_start, slope_end],
        }
    }

    pub fn length_m(&self) -> f64 {
        self.to_m - self.from_m
    }

    /// ρ_v = dθ_v/ds, 1/m (Tab. 2).
    pub fn curvature(&self) -> f64 {
        (self.slope_rad[1] - self.slope_rad[0]) / self.length_m()
    }
}

fn differ(a: f64, b: f64) -> bool {
    (a - b).abs() > JOIN_TOL * a.abs().max(b.abs()).max(1e-6)
}

/// The largest cant accepted, rad (225 mm on standard gauge; service cants stay within 180–200
/// mm).
pub const MAX_CANT_RAD: f64 = 0.15;
/// The largest service cant, rad (200 mm on standard gauge, 1500 mm between the rails' centres):
/// a cant beyond it, up to [`MAX_CANT_RAD`], is accepted with a warning.
pub const SERVICE_CANT_RAD: f64 = 0.134;
/// The largest cant gradient (twist) of a section accepted, rad/m (15 mm per metre on standard
/// gauge; EN 13803 limits the cant gradient to a few mm/m).
pub const MAX_TWIST_RAD_PER_M: f64 = 0.01;

/// The ends of consecutive sections: gaps, overlaps, lengths. Returns (section index, problem).
fn check_ranges(ranges: &[(f64, f64)], what: &str, problems: &mut Vec<(usize, String)>) {
    if ranges.is_empty() {
        problems.push((0, format!("the {what} profile has no sections")));
    }
    for (i, &(from, to)) in ranges.iter().enumerate() {
        if !(from.is_finite() && to.is_finite()) {
            problems.push((
                i,
                format!("from_m = {from}, to_m = {to}: expected finite numbers"),
            ));
            continue;
        }
        if let Err(e) = crate::limits::check(
            &format!("a track section ending at s = {to} m"),
            to.abs().max(from.abs()),
            crate::limits::MAX_TRACK_LENGTH_M,
            "a track of that length is beyond what a run covers; shorten it",
        ) {
            problems.push((i, e));
        }
        if to < from {
            problems.push((i, format!("negative length: from_m = {from} > to_m = {to}")));
        } else if to - from < 1e-6 {
            problems.push((i, format!("zero length: from_m = to_m = {from}")));
        }
        if i > 0 {
            let prev_to = ranges[i - 1].1;
            if (from - prev_to).abs() > JOIN_TOL * prev_to.abs().max(1.0) {
                let kind = if from > prev_to { "gap" } else { "overlap" };
                problems.push((
                    i,
                    format!(
                        "{kind}: this section starts at s = {from} m, the previous one ends at s = {prev_to} m"
                    ),
                ));
            }
        }
    }
}

/// Checks a horizontal profile: ranges, finite values, what each kind allows, and the joins.
/// Returns every problem found as (section index, problem).
pub fn check_horizontal(sections: &[HorizontalSection]) -> Vec<(usize, String)> {
    let mut problems = Vec::new();
    let ranges: Vec<(f64, f64)> = sections.iter().map(|s| (s.from_m, s.to_m)).collect();
    check_ranges(&ranges, "horizontal", &mut problems);
    for (i, s) in sections.iter().enumerate() {
        let values = [
            s.curvature_1pm[0],
            s.curvature_1pm[1],
            s.cant_rad[0],
            s.cant_rad[1],
        ];
        if values.iter().any(|v| !v.is_finite()) {
            problems.push((
                i,
                format!(
                    "curvature {:?} 1/m, cant {:?} rad: expected finite numbers",
                    s.curvature_1pm, s.cant_rad
                ),
            ));
            continue;
        }
        if s.cant_rad.iter().any(|c| c.abs() > MAX_CANT_RAD) {
            problems.push((
                i,
                format!(
                    "cant {:?} rad: beyond ±{MAX_CANT_RAD} rad (225 mm on standard gauge; service cants stay within 180–200 mm, 0.12–0.13 rad)",
                    s.cant_rad
                ),
            ));
        }
        let length = s.to_m - s.from_m;
        let twist = (s.cant_rad[1] - s.cant_rad[0]).abs() / length;
        if length > 0.0 && twist > MAX_TWIST_RAD_PER_M {
            problems.push((
                i,
                format!(
                    "cant from {} to {} rad over {length:.4} m: a twist of {twist:.3e} rad/m, beyond {MAX_TWIST_RAD_PER_M} rad/m (15 mm per metre on standard gauge; track standards allow about 2–3 mm/m): a transition too short, or its length in km?",
                    s.cant_rad[0], s.cant_rad[1]
                ),
            ));
        }
        match s.kind {
            HorizontalKind::Straight if s.curvature_1pm != [0.0; 2] => {
                problems.push((i, "a straight has zero curvature".into()))
            }
            HorizontalKind::Curve if s.curvature_1pm[0] == 0.0 => {
                problems.push((i, "a curve needs a finite, non-zero radius".into()))
            }
            _ => {}
        }
        if s.kind != HorizontalKind::Transition && differ(s.cant_rad[0], s.cant_rad[1]) {
            problems.push((
                i,
                format!(
                    "the cant of a {} is constant (only transitions twist)",
                    s.kind.name()
                ),
            ));
        }
        if i == 0 {
            continue;
        }
        let p = &sections[i - 1];
        let transition_join = s.kind == HorizontalKind::Transition || p.kind == HorizontalKind::Transition;
        if transition_join && differ(p.curvature_1pm[1], s.curvature_1pm[0]) {
            problems.push((
                i,
                format!(
                    "mismatched curvature at s = {} m: the previous {} ends at {:.9e} 1/m, this {} starts at {:.9e} 1/m (a transition must join the curvatures of its neighbours)",
                    s.from_m,
                    p.kind.name(),
                    p.curvature_1pm[1],
                    s.kind.name(),
                    s.curvature_1pm[0]
                ),
            ));
        }
        if differ(p.cant_rad[1], s.cant_rad[0]) {
            problems.push((
                i,
                format!(
                    "cant step at s = {} m: the previous {} ends at {} rad, this {} starts at {} rad",
                    s.from_m,
                    p.kind.name(),
                    p.cant_rad[1],
                    s.kind.name(),
                    s.cant_rad[0]
                ),
            ));
        }
    }
    problems
}

/// Checks a vertical profile: ranges, finite values, constant slope on straights, continuous slope.
pub fn check_vertical(sections: &[VerticalSection]) -> Vec<(usize, String)> {
    let mut problems = Vec::new();
    let ranges: Vec<(f64, f64)> = sections.iter().map(|s| (s.from_m, s.to_m)).collect();
    check_ranges(&ranges, "vertical", &mut problems);
    for (i, s) in sections.iter().enumerate() {
        if s.slope_rad.iter().any(|v| !v.is_finite()) {
            problems.push((i, format!("slope {:?} rad: expected finite numbers", s.slope_rad)));
            continue;
        }
        if s.slope_rad.iter().any(|v| v.abs() > 0.1) {
            problems.push((
                i,
                format!(
                    "slope {:?} rad: beyond ±0.1 rad (the small-angle Eq. 2 does not hold)",
                    s.slope_rad
                ),
            ));
        }
        if s.kind == VerticalKind::Straight && differ(s.slope_rad[0], s.slope_rad[1]) {
            problems.push((i, "the slope of a straight is constant".into()));
        }
        if i > 0 && differ(sections[i - 1].slope_rad[1], s.slope_rad[0]) {
            problems.push((
                i,
                format!(
                    "slope step at s = {} m: the previous section ends at {} rad, this one starts at {} rad",
                    s.from_m,
                    sections[i - 1].slope_rad[1],
                    s.slope_rad[0]
                ),
            ));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tab6() -> Vec<HorizontalSection> {
        let k = 1.0 / 235.65;
        let c = -0.07599;
        vec![
            HorizontalSection::straight(0.0, 100.0),
            HorizontalSection::transition(100.0, 150.0, (0.0, 0.0), (k, c)),
            HorizontalSection::curve(150.0, 600.0, 235.65, c),
            HorizontalSection::transition(600.0, 650.0, (k, c), (0.0, 0.0)),
            HorizontalSection::straight(650.0, 1000.0),
        ]
    }

    #[test]
    fn tab6_passes_with_the_papers_rates() {
        let s = tab6();
        assert!(check_horizontal(&s).is_empty());
        // Tab. 6: ρ'_h = 8.48716e-5 1/m², ρ_tw = −1.5198e-3 rad/m in the entry transition.
        assert!((s[1].curvature_rate() - 8.48716e-5).abs() < 1e-10);
        assert!((s[1].twist() + 1.5198e-3).abs() < 1e-12);
        assert!((s[3].curvature_rate() + 8.48716e-5).abs() < 1e-10);
    }

    #[test]
    fn every_bad_join_is_reported() {
        let mut s = tab6();
        s[2].from_m = 155.0; // gap after the first transition
        s[3].curvature_1pm[0] = 1.0 / 300.0; // mismatched curvature
        s[4].from_m = 640.0; // overlap
        s[4].to_m = 630.0; // negative length
        let p = check_horizontal(&s);
        let text: Vec<String> = p.iter().map(|(i, m)| format!("{i}: {m}")).collect();
        let all = text.join("\n");
        for needle in [
            "2: gap",
            "3: mismatched curvature",
            "4: overlap",
            "4: negative length",
        ] {
            assert!(all.contains(needle), "missing {needle}:\n{all}");
        }
    }

    #[test]
    fn cant_and_slope_steps_are_errors() {
        let mut s = tab6();
        s[2].cant_rad = [-0.05; 2];
        let p = check_horizontal(&s);
        assert!(p.iter().any(|(i, m)| *i == 2 && m.contains("cant step")), "{p:?}");
        let v = [
            VerticalSection::straight(0.0, 10.0, 0.0),
            VerticalSection::straight(10.0, 20.0, 0.01),
        ];
        let p = check_vertical(&v);
        assert!(
            p.iter().any(|(i, m)| *i == 1 && m.contains("slope step")),
            "{p:?}"
        );
        assert!(
            check_vertical(&[VerticalSection::straight(0.0, 10.0, f64::NAN)])[0]
                .1
                .contains("finite")
        );
    }
}
