//! The flange measures of a wheel profile, as EN 13715 defines them for the wheel's datum system
//! (the taping line, 70 mm from the flange back on standard-gauge wheels):
//!
//! * **flange height** S_h: from the taping line to the flange tip, radially;
//! * **flange thickness** S_d: from the flange back to the flange's flank, laterally, measured
//!   [`SD_HEIGHT_M`] (10 mm) above the taping line (radially outwards);
//! * **qR** (flange slope measure): the lateral distance between the S_d point and the point of
//!   the flank [`QR_TIP_OFFSET_M`] (2 mm) inside the flange tip — the smaller it is, the steeper
//!   and sharper the flange (EN 15313's in-service limit: qR ≥ 6.5 mm);
//! * the **steepest flange angle**: the largest slope angle of the flank, the angle Nadal's limit
//!   reads (S1002: 70°).
//!
//! In the profile's frame (see [`super`]) the flange hangs below the taping line at negative s, so
//! "10 mm above the taping line" is z = −10 mm on the flank (s between the tip and the tread).
//! S1002 (h28 e32.5) gives S_h = 28 mm, S_d = 32.5 mm, qR ≈ 10.8 mm, 70°.

use super::curve::Profile;

/// Height above the taping line at which the flange thickness is measured, m.
pub const SD_HEIGHT_M: f64 = 0.010;
/// Radial distance from the flange tip of qR's second point, m.
pub const QR_TIP_OFFSET_M: f64 = 0.002;
/// EN 15313's smallest qR in service, m (a sharper flange risks climbing).
pub const QR_MIN_M: f64 = 0.0065;
/// The flange thicknesses of EN 13715's e-variants (e28 to e32.5; S1002 nominal 32.5), m.
pub const SD_RANGE_M: (f64, f64) = (0.028, 0.0325);
/// The flange heights EN 13715 defines (h28 to h32), m.
pub const SH_RANGE_M: (f64, f64) = (0.028, 0.032);
/// The steepest flange angle below which Nadal's limit loses its meaning (EN 14363 uses 70°), rad.
pub const FLANGE_ANGLE_MIN_RAD: f64 = 70.0 * std::f64::consts::PI / 180.0;

/// The flange measures of a wheel profile (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlangeMeasures {
    /// S_h, m.
    pub height_m: f64,
    /// S_d, m.
    pub thickness_m: f64,
    /// qR, m.
    pub qr_m: f64,
    /// The largest flank angle, rad.
    pub steepest_angle_rad: f64,
    /// Surface parameter s of the flange tip (lowest point), m.
    pub tip_s: f64,
}

impl FlangeMeasures {
    /// Each measure outside its EN 13715 / EN 15313 range, in words (empty: all within).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        let mm = |v: f64| v * 1e3;
        if !(SH_RANGE_M.0 - 1e-6..=SH_RANGE_M.1 + 1e-6).contains(&self.height_m) {
            p.push(format!(
                "flange height {:.2} mm outside EN 13715's {:.0}..{:.0} mm",
                mm(self.height_m),
                mm(SH_RANGE_M.0),
                mm(SH_RANGE_M.1)
            ));
        }
        if !(SD_RANGE_M.0 - 1e-6..=SD_RANGE_M.1 + 1e-6).contains(&self.thickness_m) {
            p.push(format!(
                "flange thickness {:.2} mm outside EN 13715's {:.1}..{:.1} mm",
                mm(self.thickness_m),
                mm(SD_RANGE_M.0),
                mm(SD_RANGE_M.1)
            ));
        }
        if self.qr_m < QR_MIN_M {
            p.push(format!(
                "qR {:.2} mm below EN 15313's {:.1} mm (a sharp flange)",
                mm(self.qr_m),
                mm(QR_MIN_M)
            ));
        }
        if self.steepest_angle_rad < FLANGE_ANGLE_MIN_RAD - 1e-6 {
            p.push(format!(
                "steepest flange angle {:.2}° below {:.0}° (Nadal's limit would not mean what it says)",
                self.steepest_angle_rad.to_degrees(),
                FLANGE_ANGLE_MIN_RAD.to_degrees()
            ));
        }
        p
    }
}

/// The flank's s where the profile height is `z` (between the tip and the taping line), by
/// bisection on the monotone flank.
fn flank_at(wheel: &Profile, tip_s: f64, z: f64) -> Option<f64> {
    let (mut lo, mut hi) = (tip_s, 0.0);
    if !(wheel.eval(lo).z <= z && wheel.eval(hi).z >= z) {
        return None;
    }
    for _ in 0..80 {
        let m = 0.5 * (lo + hi);
        if wheel.eval(m).z < z {
            lo = m
        } else {
            hi = m
        }
    }
    Some(0.5 * (lo + hi))
}

/// Measures the flange of `wheel`, whose flange back lies `back_from_taping_m` (70 mm on
/// standard wheels) inside the taping line. Errors say what the profile lacks.
pub fn flange_measures(wheel: &Profile, back_from_taping_m: f64) -> Result<FlangeMeasures, String> {
    let (a, _) = wheel.domain();
    if a >= 0.0 {
        return Err("the profile has no flange side (no points at negative s)".into());
    }
    // The tip: the lowest point on the flange side (dense scan, then golden refinement).
    let n = ((-a) / 2e-5).ceil() as usize;
    let s_at = |k: usize| a + (-a) * k as f64 / n as f64;
    let k_tip = (0..=n)
        .min_by(|&i, &j| wheel.eval(s_at(i)).z.total_cmp(&wheel.eval(s_at(j)).z))
        .unwrap_or(0);
    let tip_s = s_at(k_tip);
    let height_m = -wheel.eval(tip_s).z;
    if height_m < SD_HEIGHT_M + QR_TIP_OFFSET_M {
        return Err(format!(
            "flange height {:.2} mm: a flange must reach at least {:.0} mm below the taping line to be measured",
            height_m * 1e3,
            (SD_HEIGHT_M + QR_TIP_OFFSET_M) * 1e3
        ));
    }
    let sd_s = flank_at(wheel, tip_s, -SD_HEIGHT_M).ok_or("no flank point 10 mm above the taping line")?;
    let qr_s =
        flank_at(wheel, tip_s, -(height_m - QR_TIP_OFFSET_M)).ok_or("no flank point 2 mm inside the tip")?;
    // Steepest flank angle between the tip and the taping line.
    let m = ((-tip_s) / 1e-5).ceil() as usize;
    let steepest = (0..=m)
        .map(|k| wheel.eval(tip_s + (-tip_s) * k as f64 / m as f64).dz.atan())
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(FlangeMeasures {
        height_m,
        thickness_m: sd_s + back_from_taping_m,
        qr_m: sd_s - qr_s,
        steepest_angle_rad: steepest,
        tip_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::StandardProfile;

    #[test]
    fn s1002_has_its_published_flange_measures() {
        // EN 13715's S1002 h28 e32.5: S_h 28 mm, S_d 32.5 mm, a 70° flank; qR of the new profile
        // 10.8 mm (the figure wheel-gauge manuals quote for a new S1002).
        let m = flange_measures(&StandardProfile::S1002.profile(), 0.070).unwrap();
        assert!((m.height_m - 0.028).abs() < 2e-5, "{m:?}");
        assert!((m.thickness_m - 0.0325).abs() < 5e-5, "{m:?}");
        assert!((m.qr_m - 0.0108).abs() < 2e-4, "{m:?}");
        assert!((m.steepest_angle_rad.to_degrees() - 70.0).abs() < 0.1, "{m:?}");
        assert!(m.problems().is_empty(), "{:?}", m.problems());
    }

    #[test]
    fn a_thin_or_low_flange_is_named() {
        let m = FlangeMeasures {
            height_m: 0.020,
            thickness_m: 0.022,
            qr_m: 0.005,
            steepest_angle_rad: 1.1,
            tip_s: -0.05,
        };
        let p = m.problems().join("; ");
        assert!(p.contains("flange height 20.00 mm"), "{p}");
        assert!(p.contains("flange thickness 22.00 mm"), "{p}");
        assert!(p.contains("qR 5.00 mm"), "{p}");
        assert!(p.contains("63.03°"), "{p}");
    }
}
