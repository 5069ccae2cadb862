//! `kecsim bench rhs`: the cost of one right-hand side (RHS) of each vehicle of the size series
//! ([`super::scaling::vehicle_series`]: a bogie, the Manchester vehicle 1, the MS vehicle, two MS
//! vehicles coupled), and where it goes.
//!
//! Each vehicle runs its scene with KEC over the first `window_s` seconds (the MS vehicle is in
//! the curve from ~8 s), its states kept every millisecond (about its step size, so that each
//! evaluation's warm starts are as close as in a run). The RHS is then evaluated over those states
//! in order, in `batches` passes on one thread and as many on the run's own threads (two on the
//! 2-core VM), interleaved: µs per RHS as the median of the passes, with the smallest and largest beside it (the
//! spread is the figure's error on a shared machine). One more pass on one thread records the wall
//! time of each part of the evaluation ([`PartTimes`]: the clock read between parts costs
//! ~0.1 µs per RHS, included in the total). Beside it, the integration's own µs per RHS over the
//! window (its wall time over its RHS: the integrator's linear algebra and the output sampling
//! included).
//!
//! Instructions per RHS need hardware counters, which this machine's VM does not expose (`perf
//! stat -e instructions`: not supported); docs/performance.md gives the callgrind command that
//! counts them.

use std::fmt::Write as _;
use std::time::Instant;

use crate::dynamics::integrator::{integrate, Flow};
use crate::dynamics::run::{RunPool, Threads};
use crate::dynamics::system::{Evaluator, InitialDisturbance, PartTimes, VehicleModel};
use crate::scenario::RunOptions;

use super::scaling::{compile, vehicle_series, ScalingError};

/// What the benchmark measures.
#[derive(Debug, Clone, PartialEq)]
pub struct RhsSettings {
    /// Simulated window whose states are evaluated, s.
    pub window_s: f64,
    /// Passes over the states per thread setting.
    pub batches: usize,
}

impl Default for RhsSettings {
    fn default() -> Self {
        RhsSettings {
            window_s: 10.0,
            batches: 5,
        }
    }
}

/// A figure measured in several passes: median, smallest, largest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    fn of(mut v: Vec<f64>) -> Spread {
        v.sort_by(f64::total_cmp);
        Spread {
            median: v[v.len() / 2],
            min: v[0],
            max: v[v.len() - 1],
        }
    }
}

/// One vehicle's right-hand side.
#[derive(Debug, Clone, PartialEq)]
pub struct RhsRow {
    pub label: String,
    pub states: usize,
    pub wheelsets: usize,
    pub bodies: usize,
    /// States evaluated per pass.
    pub samples: usize,
    /// µs per RHS on one thread.
    pub one_thread_us: Spread,
    /// µs per RHS on the run's threads.
    pub threads_us: Spread,
    pub threads: usize,
    /// The integration's wall time per RHS over the window, µs (integrator and output included).
    pub in_run_us: f64,
    /// Where one thread's pass went.
    pub parts: PartTimes,
}

/// Every vehicle's row.
#[derive(Debug, Clone, PartialEq)]
pub struct RhsBench {
    pub rows: Vec<RhsRow>,
    pub settings: RhsSettings,
}

/// Measures every vehicle of the size series.
pub fn rhs(settings: &RhsSettings) -> Result<RhsBench, ScalingError> {
    if !(settings.window_s.is_finite() && settings.window_s > 0.0 && settings.window_s <= 40.0) {
        return Err(ScalingError::Window {
            window_s: settings.window_s,
        });
    }
    let batches = settings.batches.max(1);
    let mut rows = Vec::new();
    for (label, text) in vehicle_series()? {
        let scene = compile(&text, &label)?;
        let built = scene
            .build_run(&RunOptions {
                contact: Some("kec".to_string()),
                ..Default::default()
            })
            .map_err(|source| ScalingError::Build {
                label: label.clone(),
                source: Box::new(source),
            })?;
        let model = built.vehicle.as_ref();
        let pool = built.settings.pool.clone();
        let integrator = built.settings.integrator.clone();
        let window = settings.window_s.min(built.settings.duration_s);
        // The states, every millisecond of the window.
        let (states, in_run_us) = pool.install(|| {
            let mut states: Vec<(f64, Vec<f64>)> = Vec::new();
            let x0 = model.initial_state(&InitialDisturbance::default());
            let start = Instant::now();
            let stats = integrate(
                &mut Evaluator::new(model),
                0.0,
                &x0,
                window,
                1e-3,
                &integrator,
                &mut |t, x| {
                    states.push((t, x.to_vec()));
                    Ok(Flow::Continue)
                },
            );
            let wall = start.elapsed().as_secs_f64();
            let us = stats
                .map(|s| 1e6 * wall / s.rhs_evaluations.max(1) as f64)
                .unwrap_or(f64::NAN);
            (states, us)
        });
        let one = RunPool::new(Threads::Count(1));
        // The two settings' passes interleaved, so that a machine slowing down or speeding up
        // weighs on both alike.
        let (mut one_us, mut pool_us) = (Vec::new(), Vec::new());
        for _ in 0..batches {
            one_us.push(one.install(|| pass(model, &states, false).0));
            pool_us.push(pool.install(|| pass(model, &states, false).0));
        }
        let (one_thread_us, threads_us) = (Spread::of(one_us), Spread::of(pool_us));
        let parts = one.install(|| pass(model, &states, true).1);
        rows.push(RhsRow {
            label,
            states: model.dim(),
            wheelsets: model.wheelset_names().len(),
            bodies: model.body_names().len(),
            samples: states.len(),
            one_thread_us,
            threads_us,
            threads: pool.threads(),
            in_run_us,
            parts,
        });
    }
    Ok(RhsBench {
        rows,
        settings: settings.clone(),
    })
}

/// One pass of RHS over `states` in order with one run state (warm starts carried as in a run):
/// µs per RHS, and the part times when `timed`. A state whose evaluation fails (none in these
/// scenes' windows) still counts its time.
fn pass(model: &dyn VehicleModel, states: &[(f64, Vec<f64>)], timed: bool) -> (f64, PartTimes) {
    let mut data = model.new_data();
    if timed {
        data.part_times = Some(PartTimes::default());
    }
    let mut dxdt = vec![0.0; model.dim()];
    let start = Instant::now();
    for (t, x) in states {
        let _ = model.rhs(&mut data, *t, x, &mut dxdt);
    }
    let us = 1e6 * start.elapsed().as_secs_f64() / states.len().max(1) as f64;
    (us, data.part_times.unwrap_or_default())
}

impl RhsBench {
    /// The table, the parts' shares and how to read them.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# kecsim bench rhs: one right-hand side (RHS) of each vehicle, KEC, states of its scene's first {} s every 1 ms",
            self.settings.window_s
        );
        let _ = writeln!(
            s,
            "µs per RHS: median of {} passes over the states (smallest–largest); \"in the run\": the integration's wall time over its RHS (integrator and output included)\n",
            self.settings.batches.max(1)
        );
        let _ = writeln!(
            s,
            "| vehicle | states | wheelsets | bodies | RHS per pass | µs per RHS, 1 thread | µs per RHS, {} threads | speed-up | µs per RHS in the run |",
            self.rows.first().map_or(1, |r| r.threads)
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {:.1} ({:.1}–{:.1}) | {:.1} ({:.1}–{:.1}) | {:.2} | {:.1} |",
                r.label,
                r.states,
                r.wheelsets,
                r.bodies,
                r.samples,
                r.one_thread_us.median,
                r.one_thread_us.min,
                r.one_thread_us.max,
                r.threads_us.median,
                r.threads_us.min,
                r.threads_us.max,
                r.one_thread_us.median / r.threads_us.median,
                r.in_run_us,
            );
        }
        let _ = writeln!(
            s,
            "\nWhere one thread's RHS goes (share of its wall time; µs per RHS in brackets):\n"
        );
        let _ = writeln!(
            s,
            "| vehicle | body frames | contact kinematics (KEC solves, wheelset frames) | force elements | bodies and joints | wheelset dynamics (creep, normal forces, Eq. 53) |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for r in &self.rows {
            let p = &r.parts;
            let n = p.evaluations.max(1) as f64;
            let cell = |v: f64| format!("{:.0} % ({:.1})", 100.0 * v / p.total_s.max(1e-300), 1e6 * v / n);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                r.label,
                cell(p.body_frames_s),
                cell(p.contact_kinematics_s),
                cell(p.elements_s),
                cell(p.bodies_s),
                cell(p.wheelset_dynamics_s),
            );
        }
        let _ = writeln!(
            s,
            "\nInstructions per RHS: this machine exposes no hardware counters; count them with `valgrind --tool=callgrind` (docs/performance.md)."
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_is_median_smallest_largest() {
        let s = Spread::of(vec![3.0, 1.0, 2.0, 10.0, 2.5]);
        assert_eq!((s.median, s.min, s.max), (2.5, 1.0, 10.0));
    }
}
