//! What `kecsim track` prints and writes: the track sampled along s, its CSV, and a summary with
//! the checks a reader wants (end heading against the integral of curvature; irregularity RMS per
//! wavelength band against the PSD integral).

use std::path::Path;

use super::irregularity::Origin;
use super::psd::Channel;
use super::rails::RailOffsets;
use super::sections::HorizontalKind;
use super::{spectrum, Track, TrackError, TrackFrame};

/// The CSV columns, in order (the Interface contract: `s_m`, `x_m`, `y_m`, `z_m`, `heading_rad`,
/// `cant_rad`, `curvature_1pm`, `al_mm`, `vp_mm`, `gv_mm`, `cl_mm` must stay).
pub const CSV_COLUMNS: [&str; 19] = [
    "s_m",
    "x_m",
    "y_m",
    "z_m",
    "heading_rad",
    "slope_rad",
    "cant_rad",
    "curvature_1pm",
    "vertical_curvature_1pm",
    "twist_rad_per_m",
    "curvature_rate_1pm2",
    "al_mm",
    "vp_mm",
    "gv_mm",
    "cl_mm",
    "y_left_mm",
    "z_left_mm",
    "y_right_mm",
    "z_right_mm",
];

/// The track at one s.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    pub frame: TrackFrame,
    /// al, vp, gv, cl, m.
    pub irregularity: [f64; 4],
    pub rails: RailOffsets,
}

/// Samples the track every `step_m` from its start, the end included.
pub fn sample(track: &Track, step_m: f64) -> Result<Vec<Sample>, TrackError> {
    if !(step_m.is_finite() && step_m > 0.0) {
        return Err(TrackError::Limit(format!(
            "--step {step_m}: expected a positive length in m"
        )));
    }
    let (a, b) = track.centreline.range();
    crate::limits::check(
        &format!("sampling the track every {step_m:.3e} m"),
        (b - a) / step_m,
        crate::limits::MAX_GRID_POINTS,
        "use a coarser --step",
    )
    .map_err(TrackError::Limit)?;
    let n = ((b - a) / step_m + 1e-9).floor() as usize;
    let mut s: Vec<f64> = (0..=n).map(|k| a + k as f64 * step_m).collect();
    if b - s[n] > 1e-9 {
        s.push(b);
    }
    s.iter()
        .map(|&x| {
            let (frame, irr) = track.eval(x.min(b))?;
            Ok(Sample {
                frame,
                irregularity: irr.value,
                rails: irr.rail_offsets(),
            })
        })
        .collect()
}

/// Writes the samples as CSV ([`CSV_COLUMNS`]; lengths in m, irregularities in mm).
pub fn write_csv(samples: &[Sample], path: &Path) -> Result<(), TrackError> {
    let io = |source: std::io::Error| TrackError::Write {
        path: path.display().to_string(),
        source,
    };
    let mut w = crate::files::csv_writer(path).map_err(io)?;
    w.write_record(CSV_COLUMNS).map_err(|e| io(e.into()))?;
    for smp in samples {
        let f = &smp.frame;
        let i = smp.irregularity;
        let r = smp.rails;
        let geometry = [
            f.s,
            f.position.x,
            f.position.y,
            f.position.z,
            f.heading_rad,
            f.slope_rad,
            f.cant_rad,
            f.rho_h,
            f.rho_v,
            f.rho_tw,
            f.drho_h,
        ];
        let mm = [i[0], i[1], i[2], i[3], r.y_left, r.z_left, r.y_right, r.z_right];
        let row: Vec<String> = geometry
            .iter()
            .map(|v| format!("{v:.12e}"))
            .chain(mm.iter().map(|v| format!("{:.9}", v * 1e3)))
            .collect();
        w.write_record(&row).map_err(|e| io(e.into()))?;
    }
    crate::files::commit_csv(w).map_err(io)
}

/// ∫ ρ_h ds over the whole track from the sections (exact: ρ_h is linear in each), rad.
pub fn curvature_integral(track: &Track) -> f64 {
    let (h, _) = track.centreline.sections();
    h.iter()
        .map(|s| 0.5 * (s.curvature_1pm[0] + s.curvature_1pm[1]) * s.length_m())
        .sum()
}

/// Wavelength bands for the RMS check: λ_min·3^k up to λ_max (the last one clipped).
pub fn bands(lambda_min: f64, lambda_max: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut a = lambda_min;
    while a < lambda_max * (1.0 - 1e-9) {
        let b = (a * 3.0).min(lambda_max);
        out.push((a, b));
        a = b;
    }
    out
}

/// One row of the band check: measured RMS of a generated irregularity against the PSD integral.
#[derive(Debug, Clone, Copy)]
pub struct BandRms {
    pub channel: Channel,
    pub lambda: (f64, f64),
    /// RMS of the generated signal in the band (periodogram of the track-long record), m.
    pub measured_m: f64,
    /// √∫ S dΩ over the band, m.
    pub target_m: f64,
}

/// RMS per wavelength band of generated irregularities against their PSD (None if measured or
/// absent). The signal is read at its nodes (a uniform grid at λ_min/10).
pub fn band_rms(track: &Track) -> Option<Vec<BandRms>> {
    let irr = track.irregularities.as_ref()?;
    let Origin::Generated(g) = irr.origin else {
        return None;
    };
    let nodes: Vec<(f64, [f64; 4])> = irr.node_values().collect();
    let h = nodes[1].0 - nodes[0].0;
    let mut rows = Vec::new();
    let tau = std::f64::consts::TAU;
    let mut all = vec![(g.wavelength_min_m, g.wavelength_max_m)];
    all.extend(bands(g.wavelength_min_m, g.wavelength_max_m));
    for ch in Channel::ALL {
        let x: Vec<f64> = nodes.iter().map(|(_, v)| v[ch as usize]).collect();
        for &(a, b) in &all {
            rows.push(BandRms {
                channel: ch,
                lambda: (a, b),
                measured_m: spectrum::band_variance(&x, h, a, b).sqrt(),
                target_m: g.psd.band_variance(ch, tau / b, tau / a).sqrt(),
            });
        }
    }
    Some(rows)
}

/// The summary printed by `kecsim track` and stored in the recording (markdown).
pub fn summary_markdown(track: &Track, samples: &[Sample]) -> String {
    let (a, b) = track.centreline.range();
    let (h, v) = track.centreline.sections();
    let mut s = format!("# kecsim track: {}\n\n", track.name);
    s += &format!(
        "s = {a} .. {b} m ({} horizontal, {} vertical sections; {} precomputed nodes); gauge {} mm.\n\n",
        h.len(),
        v.len(),
        track.centreline.node_count(),
        track.gauge.gauge_m * 1e3
    );
    s += "| horizontal | s [m] | radius [m] | cant [rad] | twist ρ_tw [rad/m] | ρ'_h [1/m²] |\n|---|---|---|---|---|---|\n";
    for sec in h {
        let radius = |k: f64| {
            if k == 0.0 {
                "∞".to_string()
            } else {
                format!("{:.2}", 1.0 / k)
            }
        };
        let r = match sec.kind {
            HorizontalKind::Transition => format!(
                "{} → {}",
                radius(sec.curvature_1pm[0]),
                radius(sec.curvature_1pm[1])
            ),
            _ => radius(sec.curvature_1pm[0]),
        };
        s += &format!(
            "| {} | {} – {} | {} | {:+.5} → {:+.5} | {:+.4e} | {:+.5e} |\n",
            sec.kind.name(),
            sec.from_m,
            sec.to_m,
            r,
            sec.cant_rad[0],
            sec.cant_rad[1],
            sec.twist(),
            sec.curvature_rate()
        );
    }
    s += "\n| vertical | s [m] | slope θ_v [rad, + down] |\n|---|---|---|\n";
    for sec in v {
        s += &format!(
            "| {} | {} – {} | {:+.5} → {:+.5} |\n",
            sec.kind.name(),
            sec.from_m,
            sec.to_m,
            sec.slope_rad[0],
            sec.slope_rad[1]
        );
    }
    if let Some(end) = samples.last() {
        let f = &end.frame;
        let integral = curvature_integral(track);
        s += &format!(
            "\nEnd of track: R = ({:.6}, {:.6}, {:.6}) m, heading {:.12} rad; ∫ρ_h ds from the sections {:.12} rad (difference {:.1e} rad).\n",
            f.position.x,
            f.position.y,
            f.position.z,
            f.heading_rad,
            integral,
            (f.heading_rad - integral).abs()
        );
    }
    match &track.irregularities {
        None => s += "\nNo irregularities (al, vp, gv, cl are zero).\n",
        Some(irr) => {
            match &irr.origin {
                Origin::Measured { path } => {
                    s += &format!("\nIrregularities measured: {path} ({} rows).\n", irr.len());
                }
                Origin::Generated(g) => {
                    s += &format!(
                        "\nIrregularities generated: PSD {} (seed {}), wavelengths {} – {} m, sum of cosines, node spacing {:.3} m.\n{}.\n",
                        g.psd,
                        g.seed,
                        g.wavelength_min_m,
                        g.wavelength_max_m,
                        {
                            let n: Vec<_> = irr.node_values().take(2).collect();
                            n[1].0 - n[0].0
                        },
                        g.psd.provenance()
                    );
                }
            }
            let mut rms = [0.0; 4];
            let mut max: [f64; 4] = [0.0; 4];
            for smp in samples {
                for c in 0..4 {
                    rms[c] += smp.irregularity[c] * smp.irregularity[c];
                    max[c] = max[c].max(smp.irregularity[c].abs());
                }
            }
            s += "\n| | al | vp | gv | cl |\n|---|---|---|---|---|\n";
            s += &format!(
                "| RMS (samples) [mm] | {} |\n",
                rms.iter()
                    .map(|r| format!("{:.3}", (r / samples.len() as f64).sqrt() * 1e3))
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
            s += &format!(
                "| max \\|x\\| [mm] | {} |\n",
                max.iter()
                    .map(|m| format!("{:.3}", m * 1e3))
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
            if let Some(rows) = band_rms(track) {
                s += "\nRMS per wavelength band, this realisation (periodogram of the track-long record) against √∫S dΩ of the PSD (one realisation on a finite track scatters by a few %, more in bands whose longest wavelength approaches the track length; averaged over seeds the agreement is within ~1 %, see tests/track.rs):\n\n| band [m] | al [mm] | vp [mm] | gv [mm] | cl [mm] |\n|---|---|---|---|---|\n";
                let per = rows.len() / 4;
                for k in 0..per {
                    let (la, lb) = rows[k].lambda;
                    let cells: Vec<String> = (0..4)
                        .map(|c| {
                            let r = rows[c * per + k];
                            format!("{:.3} / {:.3}", r.measured_m * 1e3, r.target_m * 1e3)
                        })
                        .collect();
                    s += &format!("| {la:.2} – {lb:.2} | {} |\n", cells.join(" | "));
                }
                s += "(generated / PSD)\n";
            }
        }
    }
    s
}
