//! Contact stress against the rail steel's shakedown limit, per wheel, as engineers read rolling
//! contact fatigue off a run.
//!
//! Each sample's contact gives its maximum pressure p0 — Hertz's 3N/(2π a b) (Johnson, *Contact
//! Mechanics*, Eq. 4.29) where Hertz holds, the strip model's pmax where the gap deviates from
//! Hertz's quadratic ([`Sample::contact_pressure`], [`super::patches`]) — and the traction coefficient μ = √(Fx² +
//! Fy²)/N (the friction the patch uses). On **Johnson's shakedown map** (Johnson K.L., "The
//! strength of surfaces in rolling contact", *Proc. IMechE C* 203 (1989) 151–163; kinematically
//! hardening material) a contact at (μ, p0/k), k the steel's yield stress in shear, shakes down
//! to elastic behaviour below
//!
//!   L(μ) = min(4, 1/μ)
//!
//! (the subsurface limit 4 of a line contact for μ ≤ 0.25, the surface limit 1/μ above — the two
//! meet at μ = 0.25; a point contact's subsurface limit is higher, 4.7 for a circle: 4 is on the
//! safe side). Beyond the surface limit the surface layer **ratchets** — the plastic strain grows
//! with every pass, the onset of surface-initiated rolling contact fatigue; that is Ekberg's
//! surface fatigue index FI_surf = μ − k/p0 > 0 (Ekberg A., Kabo E., Andersson H., "An
//! engineering model for prediction of rolling contact fatigue of railway wheels", *Fatigue Fract.
//! Eng. Mater. Struct.* 25 (2002) 899–909). Beyond the subsurface limit (μ ≤ 0.25, p0/k > 4) the
//! material below the surface yields cyclically.
//!
//! **The rail steel**: grade R260 (EN 13674-1), k = 300 MPa — the shear yield the works above
//! use for pearlitic rail and wheel steels (a 0.2 % proof stress of some 520 MPa over √3, with
//! the cyclic hardening of the running surface). The run reports per wheel the largest p0 and
//! p0/k, the point of the map farthest beyond L, and the share of the distance rolled beyond the
//! shakedown limit and in ratchetting.

use serde::Serialize;

use super::sample::Sample;

/// The rail steel the figures are read against.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RailSteel {
    /// Its grade (EN 13674-1).
    pub grade: &'static str,
    /// Yield stress in shear k, MPa.
    pub shear_yield_mpa: f64,
}

/// R260, the usual grade of plain track (see the module's documentation for k).
pub const R260: RailSteel = RailSteel {
    grade: "R260",
    shear_yield_mpa: 300.0,
};

/// The subsurface shakedown limit p0/k (line contact, kinematic hardening).
pub const SUBSURFACE_LIMIT: f64 = 4.0;

/// Johnson's elastic shakedown limit of p0/k at the traction coefficient μ: min(4, 1/μ).
pub fn shakedown_limit(mu: f64) -> f64 {
    if mu > 0.0 {
        SUBSURFACE_LIMIT.min(1.0 / mu)
    } else {
        SUBSURFACE_LIMIT
    }
}

/// Ekberg's surface fatigue index FI_surf = μ − k/p0 (> 0: ratchetting); −∞ without pressure.
pub fn surface_fatigue_index(mu: f64, p0_over_k: f64) -> f64 {
    if p0_over_k > 0.0 {
        mu - 1.0 / p0_over_k
    } else {
        f64::NEG_INFINITY
    }
}

/// One wheel's contact in a sample on the shakedown map: (μ, p0/k), or None off the rail.
pub fn map_point(sample: &Sample, wheel: usize, steel: RailSteel) -> Option<(f64, f64)> {
    let n = sample.normal[wheel];
    // The pressure of the model valid at the contact (Hertz, or the strip model beyond it).
    let p0 = sample.contact_pressure()[wheel];
    if n <= 0.0 || p0 <= 0.0 {
        return None;
    }
    let mu = sample.creep_x[wheel].hypot(sample.creep_y[wheel]) / n;
    Some((mu, p0 * 1e-6 / steel.shear_yield_mpa))
}

/// One wheel's contact stress over the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelStress {
    pub wheelset: String,
    /// `left` or `right`.
    pub wheel: &'static str,
    /// Largest maximum Hertz pressure p0, MPa, and largest p0/k.
    pub max_p0_mpa: f64,
    pub max_p0_over_k: f64,
    /// Largest traction coefficient μ = √(Fx² + Fy²)/N.
    pub max_traction: f64,
    /// The map's point farthest beyond (or closest to) the shakedown limit: its μ, p0/k and
    /// (p0/k)/L(μ) (> 1 beyond).
    pub worst_traction: f64,
    pub worst_p0_over_k: f64,
    pub worst_load_factor: f64,
    /// Largest surface fatigue index FI_surf (> 0: ratchetting).
    pub max_fi_surf: f64,
    /// Shares of the distance rolled on the rail beyond the shakedown limit and in ratchetting.
    pub share_beyond_shakedown: f64,
    pub share_ratchetting: f64,
    /// Share of the distance rolled on the rail where Hertz does not hold (its gap deviation D
    /// beyond [`crate::contact::nonhertz::HERTZ_VALIDITY_LIMIT`]): p0, the map and the wear there
    /// come from the strip model.
    pub share_non_hertzian: f64,
    /// The largest p0 Hertz alone would have given, MPa.
    pub max_p0_hertz_mpa: f64,
}

/// A run's contact stress.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactStress {
    pub rail_steel: RailSteel,
    /// The largest p0 of any wheel, MPa, and which.
    pub max_p0_mpa: f64,
    pub max_wheel: String,
    /// The largest share of any wheel's distance in ratchetting.
    pub max_share_ratchetting: f64,
    /// The largest share of any wheel's distance where Hertz does not hold.
    pub max_share_non_hertzian: f64,
    /// The largest p0 Hertz alone would have given (any wheel), MPa.
    pub max_p0_hertz_mpa: f64,
    /// Contacts outside Hertz's validity where the strip model found no patch (the overlap wider
    /// than its window): Hertz's p0 and area kept there.
    pub patches_unresolved: usize,
    /// Whether the p0 outside Hertz's validity came from the strip model (false:
    /// `[contact_forces] patches = "hertz"`, Hertz's everywhere).
    pub non_hertzian_recomputed: bool,
    pub wheels: Vec<WheelStress>,
}

/// One wheel's contact stress over its samples (in order of arc length).
pub fn wheel_stress(wheelset: &str, wheel: usize, samples: &[Sample], steel: RailSteel) -> WheelStress {
    let mut w = WheelStress {
        wheelset: wheelset.to_string(),
        wheel: super::sample::WHEELS[wheel],
        max_p0_mpa: 0.0,
        max_p0_over_k: 0.0,
        max_traction: 0.0,
        worst_traction: 0.0,
        worst_p0_over_k: 0.0,
        worst_load_factor: 0.0,
        max_fi_surf: f64::NEG_INFINITY,
        share_beyond_shakedown: 0.0,
        share_ratchetting: 0.0,
        share_non_hertzian: 0.0,
        max_p0_hertz_mpa: 0.0,
    };
    for s in samples {
        if s.normal[wheel] > 0.0 {
            w.max_p0_hertz_mpa = w.max_p0_hertz_mpa.max(s.max_pressure()[wheel] * 1e-6);
        }
    }
    let points: Vec<Option<(f64, f64)>> = samples.iter().map(|s| map_point(s, wheel, steel)).collect();
    for &(mu, pk) in points.iter().flatten() {
        w.max_p0_over_k = w.max_p0_over_k.max(pk);
        w.max_p0_mpa = w.max_p0_mpa.max(pk * steel.shear_yield_mpa);
        w.max_traction = w.max_traction.max(mu);
        w.max_fi_surf = w.max_fi_surf.max(surface_fatigue_index(mu, pk));
        let factor = pk / shakedown_limit(mu);
        if factor > w.worst_load_factor {
            (w.worst_traction, w.worst_p0_over_k, w.worst_load_factor) = (mu, pk, factor);
        }
    }
    let (mut on_rail, mut beyond, mut ratchet, mut non_hertz) = (0.0, 0.0, 0.0, 0.0);
    for (pair, pts) in samples.windows(2).zip(points.windows(2)) {
        let ds = (pair[1].s - pair[0].s).abs();
        for (k, (mu, pk)) in pts.iter().enumerate().filter_map(|(k, p)| p.map(|p| (k, p))) {
            on_rail += 0.5 * ds;
            if pair[k].hertz_deviation[wheel] > crate::contact::nonhertz::HERTZ_VALIDITY_LIMIT {
                non_hertz += 0.5 * ds;
            }
            if pk > shakedown_limit(mu) {
                beyond += 0.5 * ds;
            }
            if surface_fatigue_index(mu, pk) > 0.0 {
                ratchet += 0.5 * ds;
            }
        }
    }
    if on_rail > 0.0 {
        w.share_beyond_shakedown = beyond / on_rail;
        w.share_ratchetting = ratchet / on_rail;
        w.share_non_hertzian = non_hertz / on_rail;
    }
    if !w.max_fi_surf.is_finite() {
        w.max_fi_surf = 0.0;
    }
    w
}

/// The contact stress of every wheel of a run against `steel`.
pub fn assess(wheelsets: &[(String, Vec<Sample>)], steel: RailSteel) -> ContactStress {
    let wheels: Vec<WheelStress> = wheelsets
        .iter()
        .flat_map(|(name, samples)| [0, 1].map(|w| wheel_stress(name, w, samples, steel)))
        .collect();
    let worst = wheels.iter().max_by(|a, b| a.max_p0_mpa.total_cmp(&b.max_p0_mpa));
    ContactStress {
        rail_steel: steel,
        max_p0_mpa: worst.map_or(0.0, |w| w.max_p0_mpa),
        max_wheel: worst.map_or(String::new(), |w| format!("{} {}", w.wheelset, w.wheel)),
        max_share_ratchetting: wheels.iter().map(|w| w.share_ratchetting).fold(0.0, f64::max),
        max_share_non_hertzian: wheels.iter().map(|w| w.share_non_hertzian).fold(0.0, f64::max),
        max_p0_hertz_mpa: wheels.iter().map(|w| w.max_p0_hertz_mpa).fold(0.0, f64::max),
        patches_unresolved: 0,
        non_hertzian_recomputed: true,
        wheels,
    }
}

impl std::fmt::Display for ContactStress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let worst = self
            .wheels
            .iter()
            .max_by(|a, b| a.worst_load_factor.total_cmp(&b.worst_load_factor));
        write!(
            f,
            "contact stress ({}, k {:.0} MPa): p0 up to {:.0} MPa on {} (p0/k {:.2})",
            self.rail_steel.grade,
            self.rail_steel.shear_yield_mpa,
            self.max_p0_mpa,
            self.max_wheel,
            self.max_p0_mpa / self.rail_steel.shear_yield_mpa
        )?;
        if let Some(w) = worst {
            write!(
                f,
                "; shakedown map: worst {} {} at μ {:.3}, p0/k {:.2} = {:.2} × the limit min(4, 1/μ)",
                w.wheelset, w.wheel, w.worst_traction, w.worst_p0_over_k, w.worst_load_factor
            )?;
        }
        write!(
            f,
            "; ratchetting (FI_surf = μ − k/p0 > 0) on up to {:.1} % of a wheel's distance",
            100.0 * self.max_share_ratchetting
        )?;
        if self.non_hertzian_recomputed {
            writeln!(
                f,
                "; Hertz outside its validity on up to {:.1} % of a wheel's distance (p0 there from the strip model; Hertz alone: up to {:.0} MPa)",
                100.0 * self.max_share_non_hertzian,
                self.max_p0_hertz_mpa
            )?;
        } else {
            writeln!(
                f,
                "; Hertz outside its validity on up to {:.1} % of a wheel's distance (patches = \"hertz\": its p0 kept there)",
                100.0 * self.max_share_non_hertzian
            )?;
        }
        if self.patches_unresolved > 0 {
            writeln!(
                f,
                "  warning: {} contacts outside Hertz's validity had no strip solution (Hertz's p0 kept there)",
                self.patches_unresolved
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Johnson's map by hand: the subsurface limit 4 up to μ = 0.25, then 1/μ (2 at 0.5, 1.25 at
    /// 0.8); continuous where they meet.
    #[test]
    fn the_shakedown_limit_is_johnsons() {
        for (mu, l) in [(0.0, 4.0), (0.1, 4.0), (0.25, 4.0), (0.5, 2.0), (0.8, 1.25)] {
            assert!(
                (shakedown_limit(mu) - l).abs() < 1e-12,
                "{mu}: {}",
                shakedown_limit(mu)
            );
        }
        assert!((shakedown_limit(0.25 + 1e-9) - 4.0).abs() < 1e-6);
        // FI_surf: μ 0.4 at p0/k 3 → 0.4 − 1/3 > 0 (ratchetting); at p0/k 2 → −0.1.
        assert!((surface_fatigue_index(0.4, 3.0) - (0.4 - 1.0 / 3.0)).abs() < 1e-12);
        assert!(surface_fatigue_index(0.4, 2.0) < 0.0);
    }

    /// A wheel at p0/k = 3 (900 MPa on R260) with μ 0.2 for the first half of its distance (below
    /// the limit 4) and μ 0.45 for the second (beyond 1/0.45 = 2.22, ratchetting): p0 from the
    /// sample's own N, a, b by Hertz (3N/(2π a b)); shares 1/2 by distance.
    #[test]
    fn shares_are_by_distance_beyond_the_limits() {
        let (a, b) = (6e-3, 4e-3);
        let n = 900e6 * 2.0 * std::f64::consts::PI * a * b / 3.0;
        let samples: Vec<Sample> = (0..=200)
            .map(|i| {
                let mut s = Sample::at(i as f64 * 0.01, i as f64 * 0.5, 50.0);
                s.normal = [n, 0.0];
                s.semi_axes = [[a, b], [0.0; 2]];
                let mu = if i < 100 { 0.2 } else { 0.45 };
                s.creep_x = [0.6 * mu * n, 0.0];
                s.creep_y = [-0.8 * mu * n, 0.0];
                s
            })
            .collect();
        let w = wheel_stress("w1", 0, &samples, R260);
        assert!((w.max_p0_mpa - 900.0).abs() < 1e-6, "{}", w.max_p0_mpa);
        assert!((w.max_p0_over_k - 3.0).abs() < 1e-9);
        assert!((w.max_traction - 0.45).abs() < 1e-12);
        assert!(
            (w.share_ratchetting - 0.5).abs() < 0.006,
            "{}",
            w.share_ratchetting
        );
        assert!((w.share_beyond_shakedown - 0.5).abs() < 0.006);
        assert!((w.worst_load_factor - 3.0 * 0.45).abs() < 1e-9);
        assert!((w.max_fi_surf - (0.45 - 1.0 / 3.0)).abs() < 1e-9);
        // The unloaded wheel is nowhere on the map.
        let r = wheel_stress("w1", 1, &samples, R260);
        assert_eq!(
            (r.max_p0_mpa, r.share_ratchetting, r.max_fi_surf),
            (0.0, 0.0, 0.0)
        );
    }
}
