//! Spectral estimates of sampled signals, to check generated irregularities against their PSD:
//! Welch's method (Hann window, 50 % overlap) and the variance in a wavelength band.
//!
//! Conventions as in `super::psd`: Ω in rad/m, one-sided densities in m²/(rad/m). For N samples
//! at spacing h with window w, the one-sided estimate at Ω_j = 2π j/(N h) is
//! Ŝ(Ω_j) = h |Σ w_n x_n e^{−iΩ_j n h}|² / (π Σ w_n²) — Parseval then gives Σ Ŝ ΔΩ = variance.

/// In-place radix-2 FFT (forward, e^{−i...}); `re.len()` must be a power of two.
pub fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    debug_assert!(n.is_power_of_two() && im.len() == n);
    let mut j = 0usize;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -std::f64::consts::TAU / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (ws, wc) = (ang * k as f64).sin_cos();
                let (a, b) = (start + k, start + k + len / 2);
                let tr = re[b] * wc - im[b] * ws;
                let ti = re[b] * ws + im[b] * wc;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
            }
        }
        len <<= 1;
    }
}

/// Welch estimate of the one-sided PSD of `x` sampled at spacing `h` (m), segments of `seg`
/// samples (a power of two), Hann window, 50 % overlap, the segment mean removed. Returns
/// (Ω_j, Ŝ_j) for j = 1 … seg/2 − 1.
pub fn welch(x: &[f64], h: f64, seg: usize) -> Vec<(f64, f64)> {
    let hann: Vec<f64> = (0..seg)
        .map(|n| 0.5 - 0.5 * (std::f64::consts::TAU * n as f64 / seg as f64).cos())
        .collect();
    let w2: f64 = hann.iter().map(|w| w * w).sum();
    let mut acc = vec![0.0; seg / 2];
    let mut count = 0usize;
    let mut start = 0usize;
    while start + seg <= x.len() {
        let part = &x[start..start + seg];
        let mean = part.iter().sum::<f64>() / seg as f64;
        let mut re: Vec<f64> = part.iter().zip(&hann).map(|(v, w)| (v - mean) * w).collect();
        let mut im = vec![0.0; seg];
        fft(&mut re, &mut im);
        for j in 1..seg / 2 {
            acc[j] += h * (re[j] * re[j] + im[j] * im[j]) / (std::f64::consts::PI * w2);
        }
        count += 1;
        start += seg / 2;
    }
    let d_omega = std::f64::consts::TAU / (seg as f64 * h);
    (1..seg / 2)
        .map(|j| (j as f64 * d_omega, acc[j] / count.max(1) as f64))
        .collect()
}

/// Variance of `x` (spacing `h`) in the wavelength band [λ_a, λ_b] m: the periodogram of the whole
/// record (rectangular window, mean removed, zero-padded to a power of two) summed over the band.
pub fn band_variance(x: &[f64], h: f64, lambda_a: f64, lambda_b: f64) -> f64 {
    let n = x.len().next_power_of_two();
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let mut re = vec![0.0; n];
    for (r, v) in re.iter_mut().zip(x) {
        *r = v - mean;
    }
    let mut im = vec![0.0; n];
    fft(&mut re, &mut im);
    let d_omega = std::f64::consts::TAU / (n as f64 * h);
    let (wa, wb) = (std::f64::consts::TAU / lambda_b, std::f64::consts::TAU / lambda_a);
    let mut sum = 0.0;
    for j in 1..n / 2 {
        let w = j as f64 * d_omega;
        if w >= wa && w < wb {
            sum += 2.0 * (re[j] * re[j] + im[j] * im[j]);
        }
    }
    // Parseval: Σ_all |X|² = n Σ x² (zero padding included), variance = Σ x² / len.
    sum / (n as f64 * x.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_matches_a_direct_dft() {
        let x: Vec<f64> = (0..16)
            .map(|k| ((k * 7 % 5) as f64 - 2.0) * 0.3 + k as f64 * 0.01)
            .collect();
        let (mut re, mut im) = (x.clone(), vec![0.0; 16]);
        fft(&mut re, &mut im);
        for j in 0..16 {
            let (mut a, mut b) = (0.0, 0.0);
            for (n, v) in x.iter().enumerate() {
                let ang = -std::f64::consts::TAU * (j * n) as f64 / 16.0;
                a += v * ang.cos();
                b += v * ang.sin();
            }
            assert!((re[j] - a).abs() < 1e-12 && (im[j] - b).abs() < 1e-12);
        }
    }

    #[test]
    fn a_cosine_puts_its_variance_in_its_band() {
        // a cos(Ω s) with λ = 8 m: variance a²/2, all of it in the band 6..10 m.
        let h = 0.1;
        let x: Vec<f64> = (0..20_000)
            .map(|k| 3.0 * (std::f64::consts::TAU * k as f64 * h / 8.0).cos())
            .collect();
        let v = band_variance(&x, h, 6.0, 10.0);
        assert!((v - 4.5).abs() < 0.05, "{v}");
        assert!(band_variance(&x, h, 20.0, 40.0) < 1e-3);
        let est = welch(&x, h, 4096);
        let total: f64 = est.iter().map(|(_, s)| s).sum::<f64>() * (est[1].0 - est[0].0);
        assert!((total - 4.5).abs() < 0.05, "{total}");
    }
}
