//! `kecsim bench patch-run`: the cost of the samples' contact patches beyond Hertz on a run —
//! the output worker's post-processing (`dynamics::patches`, `patches = "post"`, the
//! default).
//!
//! The embedded default scene (the MS kilometre) runs its first `duration_s` with the patches
//! measured but not recomputed (`patches = "hertz"`: the samples carry Hertz's pmax and area and
//! the semi-axes the strip model starts from). Its samples are then post-processed the way the
//! output worker does it (`PatchPostProcess::apply_warm`, each wheelset's samples in order with its
//! warm start), `passes` times: the median wall time per contact recomputed, with the smallest and
//! largest pass beside it (the spread is the figure's error on a shared machine). What the
//! recomputation gives is printed with it — the contacts recomputed, the largest pmax, the sums of
//! pmax and area over the samples — so that a faster post-processing shows whether it computes the
//! same patches.

use std::fmt::Write as _;
use std::time::Instant;

use crate::dynamics::patches::{PatchPostProcess, PatchWarm};
use crate::dynamics::sample::Sample;
use crate::scenario::{RunOptions, Scenario, DEFAULT_SCENARIO};

/// What the benchmark measures.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchRunSettings {
    /// Simulated time of the default scene whose samples are post-processed, s.
    pub duration_s: f64,
    /// Passes over the samples.
    pub passes: usize,
}

impl Default for PatchRunSettings {
    fn default() -> Self {
        PatchRunSettings {
            duration_s: 51.0,
            passes: 3,
        }
    }
}

/// What one post-processing of the samples gives (the same on every pass).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PatchRunResult {
    /// Wheel contacts with a positive normal force.
    pub contacts: usize,
    /// Contacts recomputed by the strip model (outside Hertz's validity).
    pub recomputed: usize,
    /// Contacts whose strip solution failed (Hertz's kept).
    pub unresolved: usize,
    /// Largest pmax over the samples, Pa.
    pub max_pmax: f64,
    /// Sum of pmax over the contacts, Pa (a fingerprint of the recomputation).
    pub sum_pmax: f64,
    /// Sum of the patch areas over the contacts, m².
    pub sum_area: f64,
}

/// The benchmark's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchRunBench {
    pub settings: PatchRunSettings,
    pub samples: usize,
    /// Wall time of the run that made the samples, s.
    pub run_s: f64,
    /// Wall time of each pass, s.
    pub pass_s: Vec<f64>,
    pub result: PatchRunResult,
}

/// Post-processes `wheelsets`' samples (copies) as the output worker does.
fn pass(pp: &PatchPostProcess, wheelsets: &[(String, Vec<Sample>)]) -> PatchRunResult {
    let mut r = PatchRunResult::default();
    for (_, samples) in wheelsets {
        let mut warm = PatchWarm::default();
        for s in samples {
            let mut s = *s;
            r.unresolved += pp.apply_warm(&mut s, &mut warm);
            for i in 0..2 {
                if s.normal[i] > 0.0 {
                    r.contacts += 1;
                    r.recomputed += usize::from(s.patches[i] > 0);
                    r.max_pmax = r.max_pmax.max(s.pmax[i]);
                    r.sum_pmax += s.pmax[i];
                    r.sum_area += s.contact_area[i];
                }
            }
        }
    }
    r
}

/// Runs the benchmark (see the module's documentation).
pub fn patch_run(settings: &PatchRunSettings) -> Result<PatchRunBench, String> {
    if !(settings.duration_s.is_finite() && settings.duration_s > 0.0) {
        return Err(format!(
            "--duration {}: expected a positive number of seconds",
            settings.duration_s
        ));
    }
    let (pp, wheelsets, run_s) = hertz_samples(settings.duration_s)?;
    let samples = wheelsets.iter().map(|w| w.1.len()).sum();
    let mut pass_s = Vec::new();
    let mut result = PatchRunResult::default();
    for _ in 0..settings.passes.max(1) {
        let t = Instant::now();
        result = pass(&pp, &wheelsets);
        pass_s.push(t.elapsed().as_secs_f64());
    }
    Ok(PatchRunBench {
        settings: settings.clone(),
        samples,
        run_s,
        pass_s,
        result,
    })
}

/// The default scene's samples over its first `duration_s` with Hertz's patches (D measured),
/// the scene's post-processing, and the run's wall time.
#[allow(clippy::type_complexity)]
fn hertz_samples(duration_s: f64) -> Result<(PatchPostProcess, Vec<(String, Vec<Sample>)>, f64), String> {
    let scenario = Scenario::parse(DEFAULT_SCENARIO, "<default>").map_err(|e| e.to_string())?;
    let scene = scenario
        .compile("<default>", std::path::Path::new("."))
        .map_err(|e| e.to_string())?;
    let mut built = scene
        .build_run(&RunOptions::default())
        .map_err(|e| e.to_string())?;
    built.settings.duration_s = duration_s.min(built.settings.duration_s);
    let pp = built
        .settings
        .patches
        .clone()
        .ok_or("the default scene has no patch post-processing")?;
    built.settings.patches = Some(std::sync::Arc::new(PatchPostProcess {
        recompute: false,
        ..(*pp).clone()
    }));
    let start = Instant::now();
    let out = built.run(&mut []);
    let run_s = start.elapsed().as_secs_f64();
    if let Some(e) = &out.summary.error {
        return Err(format!("the default scene's run failed: {e}"));
    }
    Ok(((*pp).clone(), out.wheelsets, run_s))
}

impl PatchRunBench {
    /// The printed report.
    pub fn text(&self) -> String {
        let mut p = self.pass_s.clone();
        p.sort_by(f64::total_cmp);
        let med = p[p.len() / 2];
        let r = &self.result;
        let per = |s: f64| 1e6 * s / r.recomputed.max(1) as f64;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "the samples' patches beyond Hertz (the output worker's post-processing) on the default scene's first {} s",
            self.settings.duration_s
        );
        let _ = writeln!(
            out,
            "run (patches = \"hertz\") {:.2} s; {} wheelset samples, {} wheel contacts, {} recomputed by the strip model ({:.1} %), {} unresolved",
            self.run_s,
            self.samples,
            r.contacts,
            r.recomputed,
            100.0 * r.recomputed as f64 / r.contacts.max(1) as f64,
            r.unresolved
        );
        let _ = writeln!(
            out,
            "post-processing, {} passes: {:.3} s median ({:.3}–{:.3}); {:.1} µs per recomputed contact ({:.1}–{:.1}); {:.2} of the run's wall time",
            p.len(),
            med,
            p[0],
            p[p.len() - 1],
            per(med),
            per(p[0]),
            per(p[p.len() - 1]),
            med / self.run_s
        );
        let _ = writeln!(
            out,
            "what it computes: max pmax {:.3} MPa; sum of pmax {:.9e} Pa; sum of areas {:.9e} m²",
            1e-6 * r.max_pmax,
            r.sum_pmax,
            r.sum_area
        );
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The output worker's window prediction ([`PatchWarm::wide`]) is a saving, not a difference:
    /// the samples' patches are the same, to the last bit, whether each wheel's gap is sampled
    /// narrow first (no prediction: [`PatchPostProcess::apply`]), as predicted, or over both
    /// windows at once every time — over a stretch where both windows are needed.
    #[test]
    fn the_window_prediction_changes_no_patch() {
        let (pp, wheelsets, _) = hertz_samples(3.0).unwrap();
        let fingerprint = |mode: u8| {
            let mut out = Vec::new();
            let (mut narrow_ok, mut wide) = (0, 0);
            for (_, samples) in &wheelsets {
                let mut pw = PatchWarm::default();
                let mut plain = [None; 2];
                for s in samples {
                    let mut s = *s;
                    match mode {
                        0 => {
                            pp.apply(&mut s, &mut plain);
                        }
                        1 => {
                            pp.apply_warm(&mut s, &mut pw);
                        }
                        _ => {
                            pw.wide = [true; 2];
                            pp.apply_warm(&mut s, &mut pw);
                        }
                    }
                    for i in 0..2 {
                        if mode == 1 && s.patches[i] > 0 {
                            if pw.wide[i] {
                                wide += 1;
                            } else {
                                narrow_ok += 1;
                            }
                        }
                        out.extend([
                            s.pmax[i].to_bits(),
                            s.contact_area[i].to_bits(),
                            u64::from(s.patches[i]),
                        ]);
                    }
                }
            }
            (out, narrow_ok, wide)
        };
        let (plain, _, _) = fingerprint(0);
        let (predicted, narrow_ok, wide) = fingerprint(1);
        let (both, _, _) = fingerprint(2);
        assert!(narrow_ok > 100 && wide > 100, "narrow {narrow_ok}, wide {wide}");
        assert_eq!(plain, predicted);
        assert_eq!(plain, both);
    }
}
