//! Ride comfort of a run at the carbodies' floor points ([`FloorPoint`]: above each bogie and at
//! the middle of each module), from the floor accelerations every sample carries
//! ([`super::system::VehicleSample::floor`]: what an accelerometer on the floor reads in the
//! carbody's axes, the quasi-static lateral acceleration of a curve included, less 1 g on z).
//!
//! Per floor point (`super::comfort` for the weightings and spectra):
//! - **EN 12299's mean comfort N_MV** (standard method) = 6 √((a_XP95^Wd)² + (a_YP95^Wd)² +
//!   (a_ZP95^Wb)²), the 95th percentiles of the 5 s r.m.s. of the weighted accelerations. The
//!   standard evaluates 5 min (60 blocks); a run gives the blocks it has (a 51 s kilometre, 10),
//!   which the figure states. Its scale: < 1 very comfortable, 1–2 comfortable, 2–4 medium, 4–5
//!   uncomfortable, ≥ 5 very uncomfortable.
//! - **EN 12299's continuous comfort** Cc_y(t), Cc_z(t): the 5 s running r.m.s. of the lateral
//!   acceleration weighted Wd and the vertical weighted Wb; its largest value once a window is
//!   full (none for a run shorter than 5 s).
//! - **Sperling's ride index** Wz, lateral and vertical, over 0.5–30 Hz (< 2.5 reads "more
//!   pronounced but not unpleasant", 3 "strong, irregular but still tolerable", ≥ 4 "extremely
//!   unpleasant").
//! - the unweighted largest |a| and r.m.s. (about the mean), for what the weightings take out.

use serde::Serialize;

use super::comfort::{self, SperlingDirection, Weighting, CC_WINDOW_S};
use super::system::FloorPoint;

/// Ride comfort at one floor point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloorComfort {
    #[serde(flatten)]
    pub point: FloorPoint,
    /// EN 12299's N_MV and its class (None: shorter than one 5 s block).
    pub n_mv: Option<f64>,
    pub n_mv_class: Option<&'static str>,
    /// The largest continuous comfort Cc_y (Wd) and Cc_z (Wb), m/s² (None: shorter than 5 s).
    pub cc_y_max_m_s2: Option<f64>,
    pub cc_z_max_m_s2: Option<f64>,
    /// Sperling's Wz lateral and vertical, and their classes.
    pub wz_y: f64,
    pub wz_z: f64,
    pub wz_y_class: &'static str,
    pub wz_z_class: &'static str,
    /// Unweighted: largest |a_y|, |a_z| and r.m.s. about the mean, m/s².
    pub max_abs_y_m_s2: f64,
    pub max_abs_z_m_s2: f64,
    pub rms_y_m_s2: f64,
    pub rms_z_m_s2: f64,
}

/// A run's ride comfort.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comfort {
    /// The sampling rate of the accelerations, Hz, and the time they cover, s.
    pub sample_rate_hz: f64,
    pub duration_s: f64,
    /// EN 12299's 5 s blocks the run holds (the standard's N_MV takes 60).
    pub blocks: usize,
    /// The largest N_MV of a floor point and where (`CARBODY POINT`).
    pub max_n_mv: Option<f64>,
    pub max_n_mv_at: String,
    /// The largest Wz lateral and vertical of a floor point.
    pub max_wz_y: f64,
    pub max_wz_z: f64,
    pub points: Vec<FloorComfort>,
}

/// The continuous comfort Cc_y(t) (Wd) and Cc_z(t) (Wb) of one floor point's accelerations
/// (x, y, z), m/s², at each sample.
pub fn continuous_comfort(acc: &[[f64; 3]], fs_hz: f64) -> [Vec<f64>; 2] {
    let y: Vec<f64> = acc.iter().map(|a| a[1]).collect();
    let z: Vec<f64> = acc.iter().map(|a| a[2]).collect();
    continuous_comfort_yz(&y, &z, fs_hz)
}

/// [`continuous_comfort`] of the lateral and vertical accelerations apart.
fn continuous_comfort_yz(y: &[f64], z: &[f64], fs_hz: f64) -> [Vec<f64>; 2] {
    [
        comfort::running_rms(&Weighting::Wd.apply(y, fs_hz), fs_hz, CC_WINDOW_S),
        comfort::running_rms(&Weighting::Wb.apply(z, fs_hz), fs_hz, CC_WINDOW_S),
    ]
}

/// r.m.s. about the mean.
fn rms_about_mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

/// Ride comfort at one floor point from its accelerations (x, y, z), m/s², sampled at `fs_hz`.
pub fn floor_comfort(point: &FloorPoint, acc: &[[f64; 3]], fs_hz: f64) -> FloorComfort {
    let axis = |k: usize| acc.iter().map(|a| a[k]).collect::<Vec<f64>>();
    let (x, y, z) = (axis(0), axis(1), axis(2));
    let n_mv = comfort::n_mv(&x, &y, &z, fs_hz);
    // Cc once its window is full.
    let full = (CC_WINDOW_S * fs_hz).ceil() as usize;
    let [cy, cz] = continuous_comfort_yz(&y, &z, fs_hz);
    let max_full =
        |c: &[f64]| (c.len() >= full && full > 0).then(|| c[full - 1..].iter().copied().fold(0.0, f64::max));
    let wz_y = comfort::sperling_wz(&y, fs_hz, SperlingDirection::Lateral);
    let wz_z = comfort::sperling_wz(&z, fs_hz, SperlingDirection::Vertical);
    let max_abs = |v: &[f64]| v.iter().map(|a| a.abs()).fold(0.0, f64::max);
    FloorComfort {
        point: point.clone(),
        n_mv,
        n_mv_class: n_mv.map(comfort::n_mv_class),
        cc_y_max_m_s2: max_full(&cy),
        cc_z_max_m_s2: max_full(&cz),
        wz_y,
        wz_z,
        wz_y_class: comfort::sperling_class(wz_y),
        wz_z_class: comfort::sperling_class(wz_z),
        max_abs_y_m_s2: max_abs(&y),
        max_abs_z_m_s2: max_abs(&z),
        rms_y_m_s2: rms_about_mean(&y),
        rms_z_m_s2: rms_about_mean(&z),
    }
}

/// The ride comfort of a run: every floor point's accelerations (in sample order), sampled at
/// `fs_hz`. None without floor points or samples.
pub fn assess(floor: &[(FloorPoint, Vec<[f64; 3]>)], fs_hz: f64) -> Option<Comfort> {
    let n = floor.first()?.1.len();
    if n == 0 || fs_hz.is_nan() || fs_hz <= 0.0 {
        return None;
    }
    let points: Vec<FloorComfort> = floor.iter().map(|(p, a)| floor_comfort(p, a, fs_hz)).collect();
    let worst = points
        .iter()
        .filter(|p| p.n_mv.is_some())
        .max_by(|a, b| a.n_mv.unwrap_or(0.0).total_cmp(&b.n_mv.unwrap_or(0.0)));
    Some(Comfort {
        sample_rate_hz: fs_hz,
        duration_s: n as f64 / fs_hz,
        blocks: (n as f64 / (CC_WINDOW_S * fs_hz)).floor() as usize,
        max_n_mv: worst.and_then(|p| p.n_mv),
        max_n_mv_at: worst.map_or(String::new(), |p| {
            format!("{} {}", p.point.carbody, p.point.point)
        }),
        max_wz_y: points.iter().map(|p| p.wz_y).fold(0.0, f64::max),
        max_wz_z: points.iter().map(|p| p.wz_z).fold(0.0, f64::max),
        points,
    })
}

impl std::fmt::Display for Comfort {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.max_n_mv {
            Some(n) => write!(
                f,
                "ride comfort (EN 12299, {} blocks of 5 s; the standard takes 60): N_MV up to {n:.2} ({}) at {}",
                self.blocks,
                comfort::n_mv_class(n),
                self.max_n_mv_at
            )?,
            None => write!(f, "ride comfort: no N_MV (the run is shorter than one 5 s block)")?,
        }
        writeln!(
            f,
            "; Sperling Wz up to {:.2} lateral, {:.2} vertical ({} floor points)",
            self.max_wz_y,
            self.max_wz_z,
            self.points.len()
        )
    }
}
