//! Power spectral densities of the four track irregularities (paper §2.3: generated "using
//! analytical expressions of the PSD"; which ones is not stated). Formulas and parameters from
//! `../shared/design/facts/track-irregularity-psd.txt`, restated here with their status.
//!
//! Convention: Ω spatial angular frequency, rad/m (= 2π / wavelength); S(Ω) **one-sided**, in
//! m²/(rad/m), so that the variance over a band is ∫ S dΩ over that band. Cross level is the
//! height difference of the two rails (m), gauge variation the gauge difference (m).
//!
//! **FRA classes 1–6** (Hamid et al. 1983, in the form of Garg & Dukkipati 1984; A in cm²·rad/m,
//! k = 0.25, converted to m² by 1e-4):
//! ```text
//! vertical profile  S_v(Ω)  = k A_v Ω_c² / (Ω² (Ω² + Ω_c²))
//! alignment         S_a(Ω)  = k A_a Ω_c² / (Ω² (Ω² + Ω_c²))
//! cross level       S_cl(Ω) = 4 k A_v Ω_c² / ((Ω² + Ω_c²)(Ω² + Ω_s²))
//! gauge variation   S_gv(Ω) = 4 k A_v Ω_c² / ((Ω² + Ω_c²)(Ω² + Ω_s²))
//! ```
//! Verified (two independent public sources): k = 0.25, Ω_c = 0.8245 rad/m, the six A_v values, the
//! vertical form. **Not verified**: the A_a and Ω_s columns, the cross-level and gauge forms, and
//! the use of A_v for gauge (most tables give no A_g) — treat FRA alignment, cross level and gauge
//! as plausible, not authoritative.
//!
//! **German (DB/ORE) low and high disturbance** (Ω_c = 0.8246, Ω_r = 0.0206, Ω_s = 0.4380 rad/m,
//! b = 0.75 m; A in m·rad):
//! ```text
//! vertical profile  S_v(Ω)  = A_v Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
//! alignment         S_a(Ω)  = A_a Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
//! cross level       S_cl(Ω) = (2b)² (A_v / b²) Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))
//! gauge variation   S_gv(Ω) = A_g Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))
//! ```
//! (the published cross-level density is of the angle, rad²/(rad/m); × (2b)² gives the height
//! difference). Forms and parameters agree across three public codes (one citing Guo et al.,
//! Comput. Struct. 2012); **not verified** against the original ORE/DB document, nor whether that
//! document means a one- or two-sided density (here: one-sided, as the codes use it).

use std::fmt;
use std::str::FromStr;

/// The four irregularities, in the order used everywhere in this module.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Alignment al = (y_lir + y_rir)/2.
    Alignment,
    /// Vertical profile vp = (z_lir + z_rir)/2.
    VerticalProfile,
    /// Gauge variation gv = y_lir − y_rir.
    GaugeVariation,
    /// Cross level cl = z_lir − z_rir.
    CrossLevel,
}

impl Channel {
    pub const ALL: [Channel; 4] = [
        Channel::Alignment,
        Channel::VerticalProfile,
        Channel::GaugeVariation,
        Channel::CrossLevel,
    ];

    /// Short name: al, vp, gv, cl.
    pub fn short(self) -> &'static str {
        ["al", "vp", "gv", "cl"][self as usize]
    }
}

/// A PSD family and level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Psd {
    /// FRA track class 1 (worst) … 6 (best).
    Fra(u8),
    GermanLow,
    GermanHigh,
}

/// FRA parameters per class: A_v, A_a (cm²·rad/m), Ω_s (rad/m).
const FRA: [(f64, f64, f64); 6] = [
    (1.2107, 3.3634, 0.6046),
    (1.0181, 1.2107, 0.9308),
    (0.6816, 0.4128, 0.8520),
    (0.5376, 0.3027, 1.1312),
    (0.2095, 0.0762, 0.8209),
    (0.0339, 0.0339, 0.4380),
];
const FRA_K: f64 = 0.25;
const FRA_WC: f64 = 0.8245;
const CM2: f64 = 1e-4;

const DE_WC: f64 = 0.8246;
const DE_WR: f64 = 0.0206;
const DE_WS: f64 = 0.4380;
const DE_B: f64 = 0.75;

impl Psd {
    /// Every supported spectrum.
    pub const ALL: [Psd; 8] = [
        Psd::Fra(1),
        Psd::Fra(2),
        Psd::Fra(3),
        Psd::Fra(4),
        Psd::Fra(5),
        Psd::Fra(6),
        Psd::GermanLow,
        Psd::GermanHigh,
    ];

    /// One-sided density of `channel` at Ω (rad/m), m²/(rad/m).
    pub fn density(self, channel: Channel, omega: f64) -> f64 {
        let w2 = omega * omega;
        match self {
            Psd::Fra(class) => {
                let (av, aa, ws) = FRA[(class.clamp(1, 6) - 1) as usize];
                let wc2 = FRA_WC * FRA_WC;
                match channel {
                    Channel::VerticalProfile => CM2 * FRA_K * av * wc2 / (w2 * (w2 + wc2)),
                    Channel::Alignment => CM2 * FRA_K * aa * wc2 / (w2 * (w2 + wc2)),
                    Channel::CrossLevel | Channel::GaugeVariation => {
                        CM2 * 4.0 * FRA_K * av * wc2 / ((w2 + wc2) * (w2 + ws * ws))
                    }
                }
            }
            Psd::GermanLow | Psd::GermanHigh => {
                let (aa, av, ag) = if self == Psd::GermanLow {
                    (2.119e-7, 4.032e-7, 5.32e-8)
                } else {
                    (6.125e-7, 1.080e-6, 1.032e-7)
                };
                let (wc2, wr2, ws2) = (DE_WC * DE_WC, DE_WR * DE_WR, DE_WS * DE_WS);
                let base = wc2 / ((w2 + wr2) * (w2 + wc2));
                match channel {
                    Channel::VerticalProfile => av * base,
                    Channel::Alignment => aa * base,
                    // Angle density (A_v/b²)…, times (2b)² for the height difference.
                    Channel::CrossLevel => {
                        (2.0 * DE_B).powi(2) * (av / (DE_B * DE_B)) * base * w2 / (w2 + ws2)
                    }
                    Channel::GaugeVariation => ag * base * w2 / (w2 + ws2),
                }
            }
        }
    }

    /// ∫ S dΩ over [Ω1, Ω2], m² (composite 8-point Gauss–Legendre on 64 log-spaced panels: the
    /// densities are smooth rational functions; relative error < 1e-12 over any band of practical
    /// wavelengths).
    pub fn band_variance(self, channel: Channel, omega1: f64, omega2: f64) -> f64 {
        const X: [f64; 4] = [
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_2,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        let (la, lb) = (omega1.ln(), omega2.ln());
        let panels = 64;
        let mut sum = 0.0;
        for p in 0..panels {
            let a = la + (lb - la) * p as f64 / panels as f64;
            let b = la + (lb - la) * (p + 1) as f64 / panels as f64;
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for j in 0..4 {
                for sign in [-1.0, 1.0] {
                    // Substitution Ω = e^t, dΩ = Ω dt.
                    let w = (mid + sign * half * X[j]).exp();
                    sum += W[j] * half * self.density(channel, w) * w;
                }
            }
        }
        sum
    }

    /// The wavelength band used when the file names none, m: FRA 1.524–304.8 m (5–1000 ft, the
    /// band of the FRA fits), German 0.5–80 m (the band the public codes use).
    pub fn default_band_m(self) -> (f64, f64) {
        match self {
            Psd::Fra(_) => (1.524, 304.8),
            Psd::GermanLow | Psd::GermanHigh => (0.5, 80.0),
        }
    }

    /// Which parameters are verified, in one line for summaries.
    pub fn provenance(self) -> &'static str {
        match self {
            Psd::Fra(_) => "FRA (Hamid 1983 / Garg & Dukkipati 1984): vertical form, k, Ωc, Av verified; Aa, Ωs, cross-level and gauge forms NOT verified",
            _ => "German low/high (ORE/DB, as in Guo et al. 2012 and public codes): forms and A values consistent across codes, NOT verified against the original; one-sided assumed",
        }
    }
}

impl fmt::Display for Psd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Psd::Fra(c) => write!(f, "fra{c}"),
            Psd::GermanLow => write!(f, "german-low"),
            Psd::GermanHigh => write!(f, "german-high"),
        }
    }
}

impl FromStr for Psd {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim().to_ascii_lowercase();
        let found = Psd::ALL.iter().find(|p| p.to_string() == t);
        found.copied().ok_or_else(|| {
            let names: Vec<String> = Psd::ALL.iter().map(|p| p.to_string()).collect();
            format!("unknown PSD '{s}': expected one of {}", names.join(", "))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for p in Psd::ALL {
            assert_eq!(p.to_string().parse::<Psd>().unwrap(), p);
        }
        assert!("fra7".parse::<Psd>().unwrap_err().contains("german-high"));
    }

    #[test]
    fn fra_vertical_band_variance_has_a_closed_form() {
        // ∫ k A Ωc² / (Ω²(Ω² + Ωc²)) dΩ = k A [−1/Ω − atan(Ω/Ωc)/Ωc].
        let (a, b) = (
            2.0 * std::f64::consts::PI / 300.0,
            2.0 * std::f64::consts::PI / 1.5,
        );
        let prim = |w: f64| -1.0 / w - (w / FRA_WC).atan() / FRA_WC;
        let exact = CM2 * FRA_K * 0.5376 * (prim(b) - prim(a));
        let num = Psd::Fra(4).band_variance(Channel::VerticalProfile, a, b);
        assert!(((num - exact) / exact).abs() < 1e-12, "{num} vs {exact}");
    }

    #[test]
    fn german_vertical_band_variance_has_a_closed_form() {
        // A Ωc²/((Ω²+r²)(Ω²+c²)) = A Ωc²/(c²−r²) (1/(Ω²+r²) − 1/(Ω²+c²)).
        let (a, b) = (
            2.0 * std::f64::consts::PI / 80.0,
            2.0 * std::f64::consts::PI / 0.5,
        );
        let (r, c) = (DE_WR, DE_WC);
        let prim = |w: f64| c * c / (c * c - r * r) * ((w / r).atan() / r - (w / c).atan() / c);
        let exact = 1.080e-6 * (prim(b) - prim(a));
        let num = Psd::GermanHigh.band_variance(Channel::VerticalProfile, a, b);
        assert!(((num - exact) / exact).abs() < 1e-12, "{num} vs {exact}");
    }

    #[test]
    fn levels_are_ordered() {
        let w = 0.5;
        for ch in Channel::ALL {
            assert!(Psd::GermanHigh.density(ch, w) > Psd::GermanLow.density(ch, w));
        }
        for c in 1..6 {
            assert!(
                Psd::Fra(c).density(Channel::VerticalProfile, w)
                    > Psd::Fra(c + 1).density(Channel::VerticalProfile, w)
            );
        }
    }
}
