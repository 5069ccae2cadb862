//! Ride comfort from carbody floor accelerations (m/s², sampled at a constant rate fs, Hz).
//!
//! **Frequency weightings** (EN 12299:2009, with the weighting structure of ISO 2631-1:1997,
//! annex A), ω_i = 2π f_i, s = jω, H = H_h H_l H_t H_s:
//!
//! - band limiting, Q1 = 1/√2, f1 = 0.4 Hz, f2 = 100 Hz:
//!   H_h = s²/(s² + ω1 s/Q1 + ω1²), H_l = ω2²/(s² + ω2 s/Q1 + ω2²);
//! - acceleration–velocity transition H_t = (1 + s/ω3)/(1 + s/(Q4 ω4) + s²/ω4²);
//! - upward step H_s = K (1 + s/(Q5 ω5) + s²/ω5²)/(1 + s/(Q6 ω6) + s²/ω6²);
//! - [`Weighting::Wb`] (vertical): f3 = f4 = 16 Hz, Q4 = 0.63, f5 = 2.5 Hz, f6 = 4 Hz,
//!   Q5 = Q6 = 0.8, K = 0.4 (the step rises from 0.4 to 0.4 (4/2.5)² = 1.024). These are
//!   EN 12299's values; ISO 2631-4 / ISO 8041 give Wb with Q4 = 0.55, Q5 = 0.9, Q6 = 0.95 and a
//!   step normalised to 1.024 at high frequency — not used here;
//! - [`Weighting::Wd`] (horizontal): f3 = f4 = 2 Hz, Q4 = 0.63, no step (H_s = 1).
//!
//! **Filtering is done in the frequency domain** ([`Weighting::apply`]): the N samples are
//! zero-padded to M, the smallest power of two ≥ 2N, transformed (rustfft), bin k is multiplied by
//! H(j2πf_k), f_k = k fs/M for k < M/2 and (k − M) fs/M above (so H(−f) = conj H(f)); the
//! bin at fs/2, its own mirror, takes Re H(j π fs) so that the result stays real. The inverse
//! transform, scaled by 1/M, gives the first N samples. This realises the analog transfer
//! function exactly at every frequency below fs/2 — no bilinear warping. Content above fs/2 is
//! absent from the samples, so a band limit above fs/2 (Wb's and Wd's 100 Hz low-pass at
//! 100 Hz sampling) acts only through its tail below fs/2 (0.97 at 50 Hz). The product is a
//! circular convolution; the zero padding makes it the linear convolution of a filter starting
//! at rest (zeros before the first sample, no wrap-around of the end onto the start) as long as
//! the impulse response has decayed within M − N ≥ N samples (the 0.4 Hz high-pass's envelope is
//! e^(−1.78 t/s): 1e-4 after 5 s). It is non-causal only through this padding and the band limit
//! at fs/2 that sampling imposes: the sampled H is the analog one cut at fs/2, whose impulse
//! response rings before t = 0 like 1/t. For a full-band impulse at 100 Hz that is 12 % (Wb) /
//! 7 % (Wd) of the peak one sample before, 1.4 % / 0.7 % 0.1 s before (test
//! `apply_starts_at_rest`); for band-limited content (anything measured through an
//! anti-aliasing filter, a smooth simulated signal) it is negligible.
//!
//! **EN 12299 comfort**: the continuous comfort Cc(t) is the [`running_rms`] over
//! [`CC_WINDOW_S`] = 5 s of a weighted signal; the mean comfort standard method [`n_mv`] is
//! N_MV = 6 √((a_XP95^Wd)² + (a_YP95^Wd)² + (a_ZP95^Wb)²), a_P95 the 95th [`percentile`] of the
//! 5 s [`block_rms`] values; the scale is [`n_mv_class`].
//!
//! **Sperling's ride index** (Sperling 1941; as in Garg & Dukkipati, *Dynamics of Railway
//! Vehicle Systems*, 1984): for one harmonic of peak a (cm/s²) at f (Hz),
//! Wz = 0.896 (a³ F(f)/f)^(1/10) ([`sperling_wz_harmonic`]). For a random signal the spectral
//! form ([`sperling_wz`]) with the fitted weighting B(f) ([`sperling_weight`]):
//! Wz = (Σ_{k: 0.5 ≤ f_k ≤ 30 Hz} a_k² B(f_k)²)^0.15, a_k = 2|X_k|/N the peak amplitude of bin k
//! of the FFT of the N samples (cm/s², no padding); Parseval-consistent, so independent of the
//! record length for a stationary signal, and (a B)^0.3 for one harmonic. B is a fit of
//! (F/f)^(1/3): the two forms differ by up to ~2 % below 10 Hz, ~4 % at 15 Hz (tests).

use std::f64::consts::{FRAC_1_SQRT_2, PI};

use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use serde::Serialize;

/// EN 12299's window of the continuous comfort Cc(t) and block of the mean comfort N_MV, s.
pub const CC_WINDOW_S: f64 = 5.0;
/// The band over which Sperling's index sums, Hz.
pub const SPERLING_BAND_HZ: (f64, f64) = (0.5, 30.0);

/// EN 12299's band-limiting corner frequencies (Hz) and quality factor.
const F1_HZ: f64 = 0.4;
const F2_HZ: f64 = 100.0;
const Q1: f64 = FRAC_1_SQRT_2;

/// EN 12299's frequency weightings (the standard's analog transfer functions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Weighting {
    /// Vertical.
    Wb,
    /// Horizontal (longitudinal and lateral).
    Wd,
}

/// 1 + s/(q ω) + s²/ω², the normalised second-order polynomial of the weightings.
fn quad(s: Complex64, w: f64, q: f64) -> Complex64 {
    1.0 + s / (q * w) + (s / w) * (s / w)
}

impl Weighting {
    /// H(j2πf), complex (f may be negative: H(−f) = conj H(f)).
    pub fn response(self, f_hz: f64) -> Complex64 {
        let s = Complex64::new(0.0, 2.0 * PI * f_hz);
        let w = |f: f64| 2.0 * PI * f;
        let (w1, w2) = (w(F1_HZ), w(F2_HZ));
        let high_pass = (s / w1) * (s / w1) / quad(s, w1, Q1);
        let low_pass = 1.0 / quad(s, w2, Q1);
        let (f3, f4, q4) = match self {
            Weighting::Wb => (16.0, 16.0, 0.63),
            Weighting::Wd => (2.0, 2.0, 0.63),
        };
        let transition = (1.0 + s / w(f3)) / quad(s, w(f4), q4);
        let step = match self {
            Weighting::Wb => 0.4 * quad(s, w(2.5), 0.8) / quad(s, w(4.0), 0.8),
            Weighting::Wd => Complex64::new(1.0, 0.0),
        };
        high_pass * low_pass * transition * step
    }

    /// |H(j2πf)| (the tests' check of the weightings against EN 12299's tables).
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn gain(self, f_hz: f64) -> f64 {
        self.response(f_hz).norm()
    }

    /// The weighted signal (same length), filtered in the frequency domain (module doc).
    /// Empty in, or fs not finite and > 0 → empty out.
    pub fn apply(self, signal: &[f64], fs_hz: f64) -> Vec<f64> {
        let n = signal.len();
        if n == 0 || !valid_rate(fs_hz) {
            return Vec::new();
        }
        let m = (2 * n).next_power_of_two();
        let mut buf: Vec<Complex64> = signal.iter().map(|&x| Complex64::new(x, 0.0)).collect();
        buf.resize(m, Complex64::new(0.0, 0.0));
        let mut planner = FftPlanner::<f64>::new();
        planner.plan_fft_forward(m).process(&mut buf);
        let df = fs_hz / m as f64;
        for (k, x) in buf.iter_mut().enumerate() {
            let h = if 2 * k < m {
                self.response(k as f64 * df)
            } else if 2 * k == m {
                Complex64::new(self.response(0.5 * fs_hz).re, 0.0)
            } else {
                self.response((m - k) as f64 * df).conj()
            };
            *x *= h;
        }
        planner.plan_fft_inverse(m).process(&mut buf);
        buf.iter().take(n).map(|c| c.re / m as f64).collect()
    }
}

fn valid_rate(fs_hz: f64) -> bool {
    fs_hz.is_finite() && fs_hz > 0.0
}

/// A duration in samples (fs·duration), snapped to the nearest integer when within 1e-9 of it
/// (5 s · 100 Hz is 500 samples, whatever the rounding); None unless finite and > 0.
fn samples_in(duration_s: f64, fs_hz: f64) -> Option<f64> {
    let w = duration_s * fs_hz;
    if !valid_rate(fs_hz) || !w.is_finite() || w <= 0.0 {
        return None;
    }
    let r = w.round();
    Some(if (w - r).abs() <= 1e-9 * r.max(1.0) { r } else { w })
}

/// Sperling's direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SperlingDirection {
    Vertical,
    Lateral,
}

/// Sperling's weighting B(f) (magnitude), the fit used by comfort codes:
/// B_v(f) = 0.588 √((1.911 f² + (0.25 f²)²)/((1 − 0.277 f²)² + (1.563 f − 0.0368 f³)²)),
/// B_l = 1.25 B_v; 0 at f = 0.
pub fn sperling_weight(f_hz: f64, dir: SperlingDirection) -> f64 {
    let f = f_hz.abs();
    let f2 = f * f;
    let num = 1.911 * f2 + (0.25 * f2).powi(2);
    let den = (1.0 - 0.277 * f2).powi(2) + (1.563 * f - 0.0368 * f * f2).powi(2);
    let bv = 0.588 * (num / den).sqrt();
    match dir {
        SperlingDirection::Vertical => bv,
        SperlingDirection::Lateral => 1.25 * bv,
    }
}

/// Sperling's ride index Wz of an acceleration signal in m/s² (converted to cm/s² inside), over
/// [`SPERLING_BAND_HZ`]: (Σ a_k² B(f_k)²)^0.15 with a_k = 2|X_k|/N (|X_k|/N at fs/2) from the
/// FFT of the N samples as they are. 0 for fewer than 2 samples, fs not finite and > 0, or a
/// signal without content in the band (zeros give 0, not NaN).
pub fn sperling_wz(signal: &[f64], fs_hz: f64, dir: SperlingDirection) -> f64 {
    let n = signal.len();
    if n < 2 || !valid_rate(fs_hz) {
        return 0.0;
    }
    let mut buf: Vec<Complex64> = signal.iter().map(|&x| Complex64::new(100.0 * x, 0.0)).collect();
    FftPlanner::<f64>::new().plan_fft_forward(n).process(&mut buf);
    let df = fs_hz / n as f64;
    let (lo, hi) = SPERLING_BAND_HZ;
    let sum: f64 = buf
        .iter()
        .enumerate()
        .take(n / 2 + 1)
        .skip(1)
        .filter(|(k, _)| (lo..=hi).contains(&(*k as f64 * df)))
        .map(|(k, x)| {
            let scale = if 2 * k == n { 1.0 } else { 2.0 };
            let a = scale * x.norm() / n as f64;
            (a * sperling_weight(k as f64 * df, dir)).powi(2)
        })
        .sum();
    sum.powf(0.15)
}

/// Sperling's F(f): vertical 0.325 f² (f < 5.9), 400/f² (5.9 ≤ f < 20), 1 (f ≥ 20); lateral
/// 0.8 f² (f < 5.4), 650/f² (5.4 ≤ f < 26), 1 (f ≥ 26).
#[cfg_attr(not(test), allow(dead_code))]
fn sperling_f(f: f64, dir: SperlingDirection) -> f64 {
    let (c_low, f_a, c_high, f_b) = match dir {
        SperlingDirection::Vertical => (0.325, 5.9, 400.0, 20.0),
        SperlingDirection::Lateral => (0.8, 5.4, 650.0, 26.0),
    };
    if f < f_a {
        c_low * f * f
    } else if f < f_b {
        c_high / (f * f)
    } else {
        1.0
    }
}

/// The classic single-harmonic form Wz = 0.896 (a³ F(f)/f)^(1/10), a = 100·|peak| the peak
/// acceleration in cm/s². 0 below 0.5 Hz (where F is not defined) or for f not a number; F = 1
/// above 20 Hz (vertical) / 26 Hz (lateral), no upper cut.
#[cfg_attr(not(test), allow(dead_code))] // the closed form the spectral Wz is tested against
pub fn sperling_wz_harmonic(peak_m_s2: f64, f_hz: f64, dir: SperlingDirection) -> f64 {
    if f_hz.is_nan() || f_hz < SPERLING_BAND_HZ.0 {
        return 0.0;
    }
    let a = 100.0 * peak_m_s2.abs();
    0.896 * (a.powi(3) * sperling_f(f_hz, dir) / f_hz).powf(0.1)
}

/// r.m.s. over a sliding window of `window_s` ending at each sample (EN 12299's continuous
/// comfort Cc(t) with [`CC_WINDOW_S`] on a weighted signal): out\[i\] = √(mean of x_j² over the
/// samples j with t_i − window < t_j ≤ t_i), t = j/fs; the first samples' windows hold what there
/// is. Same length as input; empty if fs or fs·window is not finite and > 0. From prefix sums: a
/// non-finite sample makes every later value non-finite.
pub fn running_rms(signal: &[f64], fs_hz: f64, window_s: f64) -> Vec<f64> {
    let Some(w) = samples_in(window_s, fs_hz) else {
        return Vec::new();
    };
    let mut prefix = Vec::with_capacity(signal.len() + 1);
    prefix.push(0.0);
    let mut acc = 0.0;
    for x in signal {
        acc += x * x;
        prefix.push(acc);
    }
    (0..signal.len())
        .map(|i| {
            // j > i − w ⇔ j ≥ ⌊i − w⌋ + 1; w > 0 so lo ≤ i.
            let lo = ((i as f64 - w).floor() + 1.0).max(0.0) as usize;
            let sum = prefix[i + 1] - prefix[lo];
            (sum / (i + 1 - lo) as f64).max(0.0).sqrt()
        })
        .collect()
}

/// The r.m.s. of each consecutive, non-overlapping block of `block_s` (⌊fs·block⌋ samples;
/// EN 12299: 5 s); a last partial block is dropped. Empty if the signal is shorter than one
/// block or fs·block is not finite and ≥ 1.
pub fn block_rms(signal: &[f64], fs_hz: f64, block_s: f64) -> Vec<f64> {
    let Some(w) = samples_in(block_s, fs_hz) else {
        return Vec::new();
    };
    let len = w.floor() as usize;
    if len == 0 {
        return Vec::new();
    }
    signal
        .chunks_exact(len)
        .map(|c| (c.iter().map(|x| x * x).sum::<f64>() / len as f64).sqrt())
        .collect()
}

/// The p-th percentile (0..=100) of values, linear interpolation between order statistics (the
/// "type 7" definition: rank = p/100·(n−1), numpy's default); None if empty or p is outside
/// 0..=100. Sorted by `total_cmp` (NaN last).
pub fn percentile(values: &[f64], p: f64) -> Option<f64> {
    if values.is_empty() || !(0.0..=100.0).contains(&p) {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = p / 100.0 * (v.len() - 1) as f64;
    let lo = (rank.floor() as usize).min(v.len() - 1);
    let frac = rank - lo as f64;
    let (a, b) = (v[lo], v[(lo + 1).min(v.len() - 1)]);
    Some(if frac == 0.0 { a } else { a + frac * (b - a) })
}

/// EN 12299's mean comfort, standard (simplified) method:
/// N_MV = 6 √((a_XP95^Wd)² + (a_YP95^Wd)² + (a_ZP95^Wb)²), each a_P95 the 95th percentile of the
/// 5 s block r.m.s. of the weighted floor acceleration (x longitudinal and y lateral weighted
/// Wd, z vertical Wb). Inputs in m/s², same length and rate. The standard evaluates 5 min (60
/// blocks); a shorter run gives the percentile of the blocks it has (with one block, its r.m.s.).
/// None if shorter than one 5 s block, the lengths differ, or fs is not finite and > 0.
pub fn n_mv(ax: &[f64], ay: &[f64], az: &[f64], fs_hz: f64) -> Option<f64> {
    if ax.len() != az.len() || ay.len() != az.len() {
        return None;
    }
    let p95 = |sig: &[f64], w: Weighting| {
        let blocks = block_rms(&w.apply(sig, fs_hz), fs_hz, CC_WINDOW_S);
        percentile(&blocks, 95.0)
    };
    let x = p95(ax, Weighting::Wd)?;
    let y = p95(ay, Weighting::Wd)?;
    let z = p95(az, Weighting::Wb)?;
    Some(6.0 * (x * x + y * y + z * z).sqrt())
}

/// EN 12299's scale for N_MV: "very comfortable" (< 1), "comfortable" (1–2), "medium" (2–4),
/// "uncomfortable" (4–5), "very uncomfortable" (≥ 5); "undefined" for NaN.
pub fn n_mv_class(n_mv: f64) -> &'static str {
    match n_mv {
        x if x.is_nan() => "undefined",
        x if x < 1.0 => "very comfortable",
        x if x < 2.0 => "comfortable",
        x if x < 4.0 => "medium",
        x if x < 5.0 => "uncomfortable",
        _ => "very uncomfortable",
    }
}

/// Sperling's scale for Wz (ride comfort): the text of the largest threshold ≤ Wz
/// ("imperceptible" below 1, "undefined" for NaN).
pub fn sperling_class(wz: f64) -> &'static str {
    const SCALE: [(f64, &str); 8] = [
        (4.5, "harmful"),
        (4.0, "extremely unpleasant"),
        (3.5, "extremely irregular, unpleasant"),
        (3.25, "very irregular"),
        (3.0, "strong, irregular but still tolerable"),
        (2.5, "more pronounced but not unpleasant"),
        (2.0, "clearly noticeable"),
        (1.0, "just noticeable"),
    ];
    if wz.is_nan() {
        return "undefined";
    }
    SCALE
        .iter()
        .find(|(t, _)| wz >= *t)
        .map_or("imperceptible", |(_, s)| s)
}

#[cfg(test)]
mod tests {
    use super::SperlingDirection::{Lateral, Vertical};
    use super::*;

    fn sine(a: f64, f: f64, phase: f64, fs: f64, secs: f64) -> Vec<f64> {
        let n = (secs * fs).round() as usize;
        let x = |i: usize| a * (2.0 * PI * f * i as f64 / fs + phase).sin();
        (0..n).map(x).collect()
    }

    /// By hand from the transfer functions (|H_h| = 1/√(1 + (f1/f)⁴), |H_l| = 1/√(1 + (f/f2)⁴)):
    /// - Wd 1 Hz: H_h 1/√1.0256 = 0.98744; H_t |1 + 0.5j|/|0.75 + 0.79365j| = 1.11803/1.09196
    ///   = 1.02388; H_l ≈ 1 → 1.0110 (ISO 2631-1 table: 1.011).
    /// - Wd 2 Hz: H_h 0.99920; H_t √2/(1/0.63) = 0.89095 → 0.8902 (table 0.890).
    /// - Wd 4 Hz: H_t |1 + 2j|/|−3 + 3.1746j| = 2.23607/4.36783 = 0.51194 → 0.5119 (table 0.512).
    /// - Wd 0.1 Hz: H_h 1/√257 = 0.06238, H_t |1 + 0.05j|/|0.9975 + 0.07937j| = 1.00060 → 0.06242.
    /// - Wb 1 Hz: H_h 0.98744; H_t |1 + j/16|/|0.99609 + 0.09921j| = 1.00195/1.00102 = 1.00093;
    ///   H_s 0.4 |0.84 + 0.5j|/|0.9375 + 0.3125j| = 0.4·0.97755/0.98821 = 0.39568 → 0.3911.
    /// - Wb 8 Hz: H_h 0.999997, H_l 0.99998; H_t = Wd's at 1 Hz = 1.02388;
    ///   H_s 0.4 |−9.24 + 4j|/|−3 + 2.5j| = 0.4·10.0686/3.90512 = 1.03133 → 1.0559.
    #[test]
    fn gains_match_hand_values() {
        let cases = [
            (Weighting::Wd, 1.0, 1.0110, 1.5e-3),
            (Weighting::Wd, 2.0, 0.8902, 1.5e-3),
            (Weighting::Wd, 4.0, 0.5119, 1.5e-3),
            (Weighting::Wd, 0.1, 0.06242, 1.5e-3),
            (Weighting::Wb, 1.0, 0.3911, 2e-3),
            (Weighting::Wb, 8.0, 1.0559, 2e-3),
        ];
        for (w, f, hand, tol) in cases {
            let g = w.gain(f);
            println!("{w:?} {f} Hz: gain {g:.5}, hand {hand}");
            assert!((g - hand).abs() < tol, "{w:?} at {f} Hz: {g} vs {hand}");
        }
        assert!(Weighting::Wd.gain(0.1) < 0.07, "high-pass");
        let r = Weighting::Wb.response(3.0);
        assert!((Weighting::Wb.response(-3.0) - r.conj()).norm() < 1e-15);
    }

    /// A sinusoid through `apply`, 40 s at 100 Hz, on and off the padded grid (100/8192 Hz): in
    /// 5–35 s, a least-squares fit gives amplitude ratio = gain(f) within 1 % and phase shift =
    /// arg H within 0.02 rad; sample by sample the output is a|H| sin(ωt + φ + arg H) within
    /// 1e-3 of a|H| (measured ≤ 1.1e-4: the start's transient, the end's pre-ringing).
    #[test]
    fn apply_gives_gain_and_phase() {
        let (fs, a, phi) = (100.0, 0.7, 0.3);
        for w in [Weighting::Wb, Weighting::Wd] {
            for f in [1.3, 4.0, 328.0 * 100.0 / 8192.0, 7.77, 12.7] {
                let x = sine(a, f, phi, fs, 40.0);
                let y = w.apply(&x, fs);
                assert_eq!(y.len(), x.len());
                let h = w.response(f);
                let amp = a * h.norm();
                // Σs², Σsc, Σc², Σys, Σyc and the largest deviation from a|H| sin(ωt + φ + arg H).
                let mut m = [0.0; 6];
                for (i, yi) in y.iter().enumerate().take(3500).skip(500) {
                    let arg = 2.0 * PI * f * i as f64 / fs;
                    let (s, c) = arg.sin_cos();
                    for (acc, v) in m.iter_mut().zip([s * s, s * c, c * c, yi * s, yi * c]) {
                        *acc += v;
                    }
                    m[5] = f64::max(m[5], (yi - amp * (arg + phi + h.arg()).sin()).abs());
                }
                let [ss, sc, cc, ys, yc, err] = m;
                let det = ss * cc - sc * sc;
                let (p, q) = ((ys * cc - yc * sc) / det, (yc * ss - ys * sc) / det);
                let ratio = p.hypot(q) / a / h.norm();
                let dphase = (q.atan2(p) - phi - h.arg() + PI).rem_euclid(2.0 * PI) - PI;
                let rel = err / amp;
                println!("{w:?} {f:.4} Hz: ratio {ratio:.6}, phase {dphase:.1e}, dev {rel:.1e}");
                assert!((ratio - 1.0).abs() < 0.01 && dphase.abs() < 0.02 && rel < 1e-3);
            }
        }
    }

    /// A Gaussian pulse (σ 0.05 s) at 18 s of 20 s: the response's tail runs past the end; with
    /// the padding nothing wraps onto the start, so the output before 17.5 s stays below 1e-6 of
    /// its peak (measured ~1e-16; without padding, M = N, it is 1e-2 for Wb, 2e-2 for Wd). An
    /// impulse (full band) shows the fs/2 band-limit's pre-ringing, bounded here as measured: Wb
    /// 0.123 of the peak at the sample before, 0.014 at 0.1 s, 0.0016 at 1 s; Wd 0.066, 0.0069,
    /// 0.00075 (decaying like 1/t).
    #[test]
    fn apply_starts_at_rest() {
        let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (w, bounds) in [
            (Weighting::Wb, [0.13, 0.015, 0.002]),
            (Weighting::Wd, [0.07, 0.0075, 0.001]),
        ] {
            let g: Vec<f64> = (0..2000)
                .map(|i| (-0.5 * ((i as f64 / 100.0 - 18.0) / 0.05).powi(2)).exp())
                .collect();
            let y = w.apply(&g, 100.0);
            let wrap = max_abs(&y[..1750]) / max_abs(&y);
            let mut x = vec![0.0; 2000];
            x[1000] = 1.0;
            let y = w.apply(&x, 100.0);
            let peak = max_abs(&y);
            let pre = [1000, 990, 900].map(|k| max_abs(&y[..k]) / peak);
            println!("{w:?}: wrap-around {wrap:.1e}, impulse pre-ringing {pre:.4?}");
            assert!(wrap < 1e-6);
            assert!(pre.iter().zip(bounds).all(|(p, b)| *p < b));
        }
    }

    /// On the FFT grid (20 s at 100 Hz, 0.05 Hz bins) a harmonic of peak a gives exactly
    /// (100 a B(f))^0.3 — to 1e-9; against the classic 0.896 (a³F/f)^0.1 within 2 % at 1–8 Hz and
    /// 4 % at 15 Hz (measured, vertical/lateral: +0.77/−1.53 % at 1 Hz, +0.47/−1.83 % at 2 Hz,
    /// +0.63/−1.67 % at 4 Hz, +0.03/+1.89 % at 8 Hz, −3.85/−2.06 % at 15 Hz: B fits F less well
    /// above 10 Hz). Two harmonics: (Σ (100 a_i B_i)²)^0.15 to 1e-9 (Parseval).
    #[test]
    fn sperling_against_closed_forms() {
        let (fs, a) = (100.0, 0.5);
        for dir in [Vertical, Lateral] {
            for (f, tol) in [(1.0, 0.02), (2.0, 0.02), (4.0, 0.02), (8.0, 0.02), (15.0, 0.04)] {
                let wz = sperling_wz(&sine(a, f, 0.4, fs, 20.0), fs, dir);
                let exact = (100.0 * a * sperling_weight(f, dir)).powf(0.3);
                let classic = sperling_wz_harmonic(a, f, dir);
                println!(
                    "{dir:?} {f} Hz: Wz {wz:.6}, classic {classic:.6}, diff {:+.2} %",
                    100.0 * (wz / classic - 1.0)
                );
                assert!((wz - exact).abs() < 1e-9, "{wz} vs {exact}");
                assert!((wz / classic - 1.0).abs() < tol);
            }
            let (a1, f1, a2, f2) = (0.3, 1.5, 0.2, 7.0);
            let x: Vec<f64> = sine(a1, f1, 0.1, fs, 20.0)
                .iter()
                .zip(sine(a2, f2, 1.2, fs, 20.0))
                .map(|(p, q)| p + q)
                .collect();
            let b = |a: f64, f: f64| (100.0 * a * sperling_weight(f, dir)).powi(2);
            let expect = (b(a1, f1) + b(a2, f2)).powf(0.15);
            assert!((sperling_wz(&x, fs, dir) - expect).abs() < 1e-9);
        }
    }

    /// Constant c → |c|; a 2 Hz sinusoid with a 5 s (10-period) window → a/√2 within 1e-3 once
    /// full; the window bounds (t_i − w, t_i] by hand at fs = 1 Hz, w = 2 s.
    #[test]
    fn running_and_block_rms() {
        let c = running_rms(&[-0.7; 300], 100.0, 5.0);
        assert!(c.len() == 300 && c.iter().all(|v| (v - 0.7).abs() < 1e-12));
        let a = 0.8;
        let r = running_rms(&sine(a, 2.0, 0.2, 100.0, 20.0), 100.0, CC_WINDOW_S);
        assert!(r[499..].iter().all(|v| (v - a / 2f64.sqrt()).abs() < 1e-3));
        let h = running_rms(&[3.0, 4.0, 0.0, 2.0], 1.0, 2.0);
        let hand = [3.0, 12.5f64.sqrt(), 8.0f64.sqrt(), 2.0f64.sqrt()];
        assert!(h.iter().zip(hand).all(|(v, e)| (v - e).abs() < 1e-12), "{h:?}");

        assert_eq!(block_rms(&[1.0; 1230], 100.0, 5.0).len(), 2);
        assert!(block_rms(&[1.0; 499], 100.0, 5.0).is_empty());
        let b = block_rms(&[3.0, -3.0, 1.0, 1.0, 9.0], 1.0, 2.0);
        assert_eq!(b, vec![3.0, 1.0]);
    }

    /// Sorted [1, 1.5, 2.6, 3, 4, 9]: p50 rank 2.5 → 2.8; p95 rank 4.75 → 4 + 0.75·5 = 7.75;
    /// p20 rank 1 → 1.5 (numpy.percentile's default gives the same).
    #[test]
    fn percentile_type7() {
        let v = [3.0, 1.0, 4.0, 1.5, 9.0, 2.6];
        for (p, e) in [(0.0, 1.0), (20.0, 1.5), (50.0, 2.8), (95.0, 7.75), (100.0, 9.0)] {
            let got = percentile(&v, p);
            assert!(got.is_some_and(|g| (g - e).abs() < 1e-12), "p{p}: {got:?}");
        }
        assert_eq!(percentile(&[], 50.0), None);
        assert_eq!(percentile(&v, 101.0), None);
        assert_eq!(percentile(&v, f64::NAN), None);
        assert_eq!(percentile(&[2.0], 95.0), Some(2.0));
    }

    /// az = 4 Hz, amplitude a, 60 s, ax = ay = 0: N_MV = 6 gain_Wb(4) a/√2 within 1 %.
    #[test]
    fn n_mv_of_a_sinusoid() {
        let (fs, a) = (100.0, 0.3);
        let az = sine(a, 4.0, 0.0, fs, 60.0);
        let zero = vec![0.0; az.len()];
        let n = n_mv(&zero, &zero, &az, fs);
        let expect = 6.0 * Weighting::Wb.gain(4.0) * a / 2f64.sqrt();
        println!("N_MV {n:?}, expected {expect:.6}");
        assert!(n.is_some_and(|n| (n / expect - 1.0).abs() < 0.01));
        let short = vec![0.1; 300];
        assert_eq!(n_mv(&short, &short, &short, fs), None);
        assert_eq!(n_mv(&zero[1..], &zero, &az, fs), None);
        assert_eq!(n_mv_class(0.5), "very comfortable");
        assert_eq!(n_mv_class(1.0), "comfortable");
        assert_eq!(n_mv_class(3.9), "medium");
        assert_eq!(n_mv_class(4.0), "uncomfortable");
        assert_eq!(n_mv_class(5.0), "very uncomfortable");
        assert_eq!(sperling_class(0.9), "imperceptible");
        assert_eq!(sperling_class(2.5), "more pronounced but not unpleasant");
        assert_eq!(sperling_class(3.3), "very irregular");
        assert_eq!(sperling_class(4.6), "harmful");
    }

    #[test]
    fn edge_cases() {
        for w in [Weighting::Wb, Weighting::Wd] {
            assert!(w.apply(&[], 100.0).is_empty());
            assert!(w.apply(&[1.0, 2.0], 0.0).is_empty());
            assert!(w.apply(&[1.0, 2.0], f64::NAN).is_empty());
            assert_eq!(w.apply(&[1.0], 100.0).len(), 1);
            assert!(w.apply(&[0.0; 10], 100.0).iter().all(|v| *v == 0.0));
        }
        assert_eq!(sperling_wz(&[], 100.0, Vertical), 0.0);
        assert_eq!(sperling_wz(&[0.0; 500], 100.0, Vertical), 0.0);
        assert_eq!(sperling_wz(&[1.0; 500], -1.0, Lateral), 0.0);
        assert_eq!(sperling_wz_harmonic(1.0, 0.2, Vertical), 0.0);
        assert_eq!(sperling_weight(0.0, Vertical), 0.0);
        assert!(running_rms(&[], 100.0, 5.0).is_empty());
        assert!(running_rms(&[1.0], 0.0, 5.0).is_empty());
        assert!(running_rms(&[1.0], 100.0, -5.0).is_empty());
        assert!(block_rms(&[1.0; 100], -100.0, 5.0).is_empty());
        assert!(block_rms(&[1.0; 100], 100.0, 0.001).is_empty());
        assert_eq!(n_mv(&[], &[], &[], 100.0), None);
        assert_eq!(n_mv(&[0.0; 600], &[0.0; 600], &[0.0; 600], 100.0), Some(0.0));
        assert_eq!(n_mv(&[0.0; 600], &[0.0; 600], &[0.0; 600], 0.0), None);
    }
}
