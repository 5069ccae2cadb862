//! Wheel wear from the wear number (the energy dissipated in each contact patch per metre rolled),
//! as engineers read it off a run: per wheel, the wear rate of a published wear function
//! integrated over the distance rolled, and **where on the profiles** it goes.
//!
//! **The wear number** Tγ = |Fx ξx + Fy ξy| (N; [`Sample::wear_number`]) — the creep forces'
//! work per distance rolled. The spin term |Mz φ| is written apart (`tgamma_spin_*_n`) and left
//! out of the wear here, as the USFD function was fitted to Tγ without it (Lewis & Dwyer-Joyce
//! 2004; Braghin et al. 2006 use Fx ξx + Fy ξy).
//!
//! **The USFD (University of Sheffield) wear function** (Lewis R., Dwyer-Joyce R.S., "Wear
//! mechanisms and transitions in railway wheel steels", *Proc. IMechE J* 218 (2004) 467–478, twin
//! disc tests of R8T wheel against UIC60 900A rail steel; as used by Braghin F., Lewis R.,
//! Dwyer-Joyce R.S., Bruni S., "A mathematical model to predict railway wheel profile evolution
//! due to wear", *Wear* 261 (2006) 1253–1264, Table 1): the wheel's wear rate K, µg of steel per
//! metre rolled per mm² of contact area, against the wear index Tγ/A (N/mm², A = π a b the Hertz
//! patch's area), in three regimes:
//!
//! | regime       | Tγ/A (N/mm²)       | K (µg/(m·mm²))       |
//! |--------------|--------------------|----------------------|
//! | mild         | Tγ/A < 10.4        | 5.3 · Tγ/A           |
//! | severe       | 10.4 ≤ Tγ/A ≤ 77.2 | 55.0                 |
//! | catastrophic | Tγ/A > 77.2        | 61.9 · Tγ/A − 4723   |
//!
//! A wheel's mass lost per metre rolled is then K · A (µg/m, which is mg/km), its volume that
//! over the steel's density 7850 kg/m³. Integrated over the wheelset's arc length (trapezoids
//! between output samples; a lifted wheel wears nothing) into the run's wear per wheel, and
//! divided by the distance into the wear per kilometre. The function is the wheel's: the rail's
//! wear needs its own (the rail passes under every wheel), so for the rail the run reports only
//! where the wheels' wear goes on it — the wear-weighted running band over s^r.
//!
//! **Where the wear goes**: the mass lost binned over the contact's position on the wheel s^w and
//! on the rail s^r ([`BIN_MM`] wide bins), a histogram of the wear along each profile.

use serde::Serialize;

use super::safety::{sliding_mean, WINDOW_M};
use super::sample::Sample;

/// The USFD function's mild–severe transition, Tγ/A in N/mm².
pub const MILD_LIMIT_N_MM2: f64 = 10.4;
/// The USFD function's severe–catastrophic transition, Tγ/A in N/mm².
pub const SEVERE_LIMIT_N_MM2: f64 = 77.2;
/// Wheel steel's density, kg/m³ (volume from mass).
pub const STEEL_DENSITY_KG_M3: f64 = 7850.0;
/// Width of the wear histogram's bins over s^w and s^r, mm.
pub const BIN_MM: f64 = 2.0;

/// The USFD function's regimes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WearRegime {
    Mild,
    Severe,
    Catastrophic,
}

impl WearRegime {
    /// The regime of a wear index Tγ/A (N/mm²).
    pub fn of(index_n_mm2: f64) -> WearRegime {
        if index_n_mm2 < MILD_LIMIT_N_MM2 {
            WearRegime::Mild
        } else if index_n_mm2 <= SEVERE_LIMIT_N_MM2 {
            WearRegime::Severe
        } else {
            WearRegime::Catastrophic
        }
    }
}

/// The USFD wear rate K (µg per metre rolled per mm² of contact) at the wear index Tγ/A (N/mm²;
/// see the module's table). 0 for a non-positive index.
pub fn usfd_wear_rate(index_n_mm2: f64) -> f64 {
    if index_n_mm2.is_nan() || index_n_mm2 <= 0.0 {
        return 0.0;
    }
    match WearRegime::of(index_n_mm2) {
        WearRegime::Mild => 5.3 * index_n_mm2,
        WearRegime::Severe => 55.0,
        WearRegime::Catastrophic => 61.9 * index_n_mm2 - 4723.0,
    }
}

/// One wheel's contact in a sample as the wear function reads it: its wear index Tγ/A (N/mm²) and
/// the mass it loses per metre rolled K·A (µg/m = mg/km); (0, 0) for a wheel off its rail or
/// without a patch.
pub fn wear_of(sample: &Sample, wheel: usize) -> (f64, f64) {
    // The patch's real area where Hertz does not hold (the strip model's), else Hertz's πab.
    let area_mm2 = sample.patch_area()[wheel] * 1e6;
    if sample.normal[wheel] <= 0.0 || area_mm2.is_nan() || area_mm2 <= 0.0 {
        return (0.0, 0.0);
    }
    let index = sample.wear_number()[wheel] / area_mm2;
    (index, usfd_wear_rate(index) * area_mm2)
}

/// The wear histogram of one profile: the mass lost in each [`BIN_MM`] bin that holds any.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WearBin {
    /// The bin's centre on the profile (s^w or s^r, paper convention), mm.
    pub s_mm: f64,
    /// The mass lost with the contact in this bin, mg.
    pub mass_mg: f64,
}

/// One wheel's wear over the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelWear {
    pub wheelset: String,
    /// `left` or `right`.
    pub wheel: &'static str,
    /// Mass lost over the run, mg, and per kilometre rolled, mg/km.
    pub mass_mg: f64,
    pub mass_mg_per_km: f64,
    /// The same as a volume, mm³/km.
    pub volume_mm3_per_km: f64,
    /// Largest wear number Tγ, N, and largest 2 m sliding mean of Tγ along the track, N (EN
    /// 14363's window, as the Y/Q figures'; only full windows).
    pub max_tgamma_n: f64,
    pub max_tgamma_2m_n: f64,
    /// Largest wear index Tγ/A, N/mm², and its regime.
    pub max_wear_index_n_mm2: f64,
    pub worst_regime: WearRegime,
    /// Share of the distance rolled in each regime (mild, severe, catastrophic; off the rail
    /// counts in none).
    pub distance_share: [f64; 3],
    /// Where the wear goes on the wheel (s^w) and on the rail (s^r).
    pub wheel_histogram: Vec<WearBin>,
    pub rail_histogram: Vec<WearBin>,
}

/// A run's wear: every wheel, and what the figures rest on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Wear {
    /// The wear function (`usfd`: Lewis & Dwyer-Joyce 2004, R8T wheel on UIC60 900A rail).
    pub function: &'static str,
    /// The distance rolled by the first wheelset, m.
    pub distance_m: f64,
    /// The largest wear per km of a wheel, mg/km, and which.
    pub max_mass_mg_per_km: f64,
    pub max_wheel: String,
    pub wheels: Vec<WheelWear>,
}

/// A histogram's bins from (position, mass) pairs, m and µg.
fn histogram(parts: &[(f64, f64)]) -> Vec<WearBin> {
    let mut bins: std::collections::BTreeMap<i64, f64> = std::collections::BTreeMap::new();
    for &(s, m) in parts {
        if m > 0.0 && s.is_finite() {
            *bins.entry((s * 1e3 / BIN_MM).round() as i64).or_insert(0.0) += m;
        }
    }
    bins.into_iter()
        .map(|(k, m)| WearBin {
            s_mm: k as f64 * BIN_MM,
            mass_mg: m * 1e-3,
        })
        .collect()
}

/// One wheel's wear over its samples (in order of arc length).
pub fn wheel_wear(wheelset: &str, wheel: usize, samples: &[Sample]) -> WheelWear {
    // Each sample's wear index and mass rate, once.
    let rates: Vec<(f64, f64)> = samples.iter().map(|s| wear_of(s, wheel)).collect();
    let mut mass_ug = 0.0;
    let mut share = [0.0; 3];
    let (mut on_wheel, mut on_rail) = (Vec::new(), Vec::new());
    for (pair, r) in samples.windows(2).zip(rates.windows(2)) {
        let ds = (pair[1].s - pair[0].s).abs();
        // The interval's mass goes half to each end's contact position.
        for (p, &(index, rate)) in pair.iter().zip(r) {
            let part = 0.5 * rate * ds;
            mass_ug += part;
            on_wheel.push((p.s_wheel[wheel], part));
            on_rail.push((p.s_rail[wheel], part));
            if index > 0.0 {
                let k = match WearRegime::of(index) {
                    WearRegime::Mild => 0,
                    WearRegime::Severe => 1,
                    WearRegime::Catastrophic => 2,
                };
                share[k] += 0.5 * ds;
            }
        }
    }
    let max_index = rates.iter().map(|r| r.0).fold(0.0, f64::max);
    let distance = match (samples.first(), samples.last()) {
        (Some(a), Some(b)) => (b.s - a.s).abs(),
        _ => 0.0,
    };
    let s: Vec<f64> = samples.iter().map(|p| p.s).collect();
    let tg: Vec<f64> = samples.iter().map(|p| p.wear_number()[wheel]).collect();
    let max_tg = tg.iter().copied().fold(0.0, f64::max);
    let first = s.first().copied().unwrap_or(0.0);
    let max_tgamma_2m_n = sliding_mean(&s, &tg, WINDOW_M)
        .iter()
        .zip(&s)
        .filter(|(_, &si)| si - first >= WINDOW_M)
        .map(|(m, _)| *m)
        .fold(0.0, f64::max);
    let per_km = if distance > 0.0 { mass_ug / distance } else { 0.0 };
    WheelWear {
        wheelset: wheelset.to_string(),
        wheel: super::sample::WHEELS[wheel],
        mass_mg: mass_ug * 1e-3,
        mass_mg_per_km: per_km,
        volume_mm3_per_km: per_km * 1e-6 / STEEL_DENSITY_KG_M3 * 1e9,
        max_tgamma_n: max_tg,
        max_tgamma_2m_n,
        max_wear_index_n_mm2: max_index,
        worst_regime: WearRegime::of(max_index),
        distance_share: share.map(|d| if distance > 0.0 { d / distance } else { 0.0 }),
        wheel_histogram: histogram(&on_wheel),
        rail_histogram: histogram(&on_rail),
    }
}

/// The wear of every wheel of a run.
pub fn assess(wheelsets: &[(String, Vec<Sample>)]) -> Wear {
    let wheels: Vec<WheelWear> = wheelsets
        .iter()
        .flat_map(|(name, samples)| [0, 1].map(|w| wheel_wear(name, w, samples)))
        .collect();
    let worst = wheels
        .iter()
        .max_by(|a, b| a.mass_mg_per_km.total_cmp(&b.mass_mg_per_km));
    Wear {
        function: "usfd",
        distance_m: wheelsets
            .first()
            .and_then(|w| Some((w.1.last()?.s - w.1.first()?.s).abs()))
            .unwrap_or(0.0),
        max_mass_mg_per_km: worst.map_or(0.0, |w| w.mass_mg_per_km),
        max_wheel: worst.map_or(String::new(), |w| format!("{} {}", w.wheelset, w.wheel)),
        wheels,
    }
}

impl std::fmt::Display for Wear {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let total: f64 = self.wheels.iter().map(|w| w.mass_mg).sum();
        let worst_index = self
            .wheels
            .iter()
            .map(|w| w.max_wear_index_n_mm2)
            .fold(0.0, f64::max);
        writeln!(
            f,
            "wear (USFD function, wheel steel): up to {:.2} mg/km on {} ({:.1} mg over {:.0} m for all wheels); largest Tγ/A {:.2} N/mm² ({:?}; mild < {MILD_LIMIT_N_MM2} ≤ severe ≤ {SEVERE_LIMIT_N_MM2} < catastrophic)",
            self.max_mass_mg_per_km,
            self.max_wheel,
            total,
            self.distance_m,
            worst_index,
            WearRegime::of(worst_index),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published curve (Lewis & Dwyer-Joyce 2004; Braghin et al. 2006, Table 1) at points of
    /// each regime, by hand: 5.3 × 5 = 26.5; 55 in the severe plateau; 61.9 × 100 − 4723 = 1467.
    /// The regimes nearly join at the published transitions (5.3 × 10.4 = 55.12; 61.9 × 77.2 −
    /// 4723 = 55.68: within 1.3 % of 55).
    #[test]
    fn the_usfd_function_follows_its_published_curve() {
        for (index, k) in [
            (5.0, 26.5),
            (1.0, 5.3),
            (10.0, 53.0),
            (30.0, 55.0),
            (77.0, 55.0),
            (100.0, 1467.0),
        ] {
            assert!(
                (usfd_wear_rate(index) - k).abs() < 1e-9,
                "{index}: {}",
                usfd_wear_rate(index)
            );
        }
        for limit in [MILD_LIMIT_N_MM2, SEVERE_LIMIT_N_MM2] {
            let (below, above) = (usfd_wear_rate(limit - 1e-9), usfd_wear_rate(limit + 1e-9));
            assert!(
                (below - above).abs() / 55.0 < 0.013,
                "{limit}: {below} vs {above}"
            );
        }
        assert_eq!(usfd_wear_rate(0.0), 0.0);
        assert_eq!(usfd_wear_rate(f64::NAN), 0.0);
        assert_eq!(WearRegime::of(50.0), WearRegime::Severe);
    }

    /// A wheel rolling at constant Tγ and patch over 100 m loses K·A·100 m, all in the bin of its
    /// contact position, and its wear per km is K·A (mg/km): by hand, a = 6 mm, b = 4 mm, A =
    /// 75.398 mm², Tγ = 200 N, Tγ/A = 2.6526 N/mm² (mild), K = 14.059 µg/(m mm²), K·A =
    /// 1060.0 µg/m.
    #[test]
    fn constant_contact_wears_at_the_functions_rate() {
        let mut samples = Vec::new();
        for i in 0..=100 {
            let mut s = Sample::at(i as f64 * 0.05, i as f64, 20.0);
            s.normal = [50e3, 50e3];
            s.semi_axes = [[6e-3, 4e-3]; 2];
            s.creep_x = [-2e3, 0.0];
            s.creepage = [[0.1, 0.0, 0.0], [0.0; 3]];
            s.s_wheel = [3.1e-3, 0.0];
            s.s_rail = [-12.9e-3, 0.0];
            samples.push(s);
        }
        let w = wheel_wear("w1", 0, &samples);
        let area = std::f64::consts::PI * 6.0 * 4.0;
        let k = 5.3 * 200.0 / area;
        assert!(
            (w.mass_mg_per_km - k * area).abs() < 1e-9 * k * area,
            "{}",
            w.mass_mg_per_km
        );
        assert!(
            (w.mass_mg - k * area * 100.0 * 1e-3).abs() < 1e-9,
            "{}",
            w.mass_mg
        );
        assert_eq!(w.wheel_histogram.len(), 1);
        assert!((w.wheel_histogram[0].s_mm - 4.0).abs() < 1e-9);
        assert!((w.rail_histogram[0].s_mm + 12.0).abs() < 1e-9);
        assert!((w.wheel_histogram[0].mass_mg - w.mass_mg).abs() < 1e-9);
        assert_eq!(w.worst_regime, WearRegime::Mild);
        assert!((w.distance_share[0] - 1.0).abs() < 1e-12);
        assert!((w.max_tgamma_2m_n - 200.0).abs() < 1e-9);
        // The other wheel has no creep: no wear.
        assert_eq!(wheel_wear("w1", 1, &samples).mass_mg, 0.0);
    }
}
