//! Run observers of the command line: the progress bar (rate and ETA, silent when stderr is not a
//! terminal) and the pacing of `--pace X` (play at X times real time).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use kecsim::dynamics::output::{ObserverError, OutputSample, RunObserver, RunStart};
use kecsim::dynamics::{CancelToken, RunSummary};

/// A progress bar over the simulated time, in ms, with the real-time factor and the ETA; when
/// stderr is not a terminal (a batch job, a log file), a progress line every
/// [`PROGRESS_LINE_EVERY`] of wall time instead, so that a long run shows a sign of life.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    duration_s: f64,
    last_line: Instant,
    every: Duration,
}

/// Interval of the progress lines written when stderr is not a terminal.
pub const PROGRESS_LINE_EVERY: Duration = Duration::from_secs(10);

impl Progress {
    /// Drawn on stderr when it is a terminal, hidden otherwise.
    pub fn new() -> Progress {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr_with_hz(10)
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(0), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{wide_bar} {percent:>3}% · t = {msg} · {elapsed_precise} elapsed, ETA {eta}",
            )
            .expect("a valid template"),
        );
        Progress {
            bar,
            start: Instant::now(),
            duration_s: 0.0,
            last_line: Instant::now(),
            // KECSIM_PROGRESS_S overrides the interval (tests; batch systems with their own taste).
            every: std::env::var("KECSIM_PROGRESS_S")
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite() && *v >= 0.0)
                .map_or(PROGRESS_LINE_EVERY, Duration::from_secs_f64),
        }
    }
}

impl RunObserver for Progress {
    fn start(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.bar.set_length((run.duration_s * 1e3).round() as u64);
        self.start = Instant::now();
        self.last_line = self.start;
        self.duration_s = run.duration_s;
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        self.bar.set_position((sample.t * 1e3).round() as u64);
        if !self.bar.is_hidden() {
            let wall = self.start.elapsed().as_secs_f64();
            self.bar.set_message(format!(
                "{:.2} s simulated, {:.1}× real time",
                sample.t,
                if wall > 0.0 { sample.t / wall } else { 0.0 }
            ));
        } else if sample.t > 0.0 && self.last_line.elapsed() >= self.every {
            self.last_line = Instant::now();
            let wall = self.start.elapsed().as_secs_f64();
            let rate = sample.t / wall.max(1e-9);
            eprintln!(
                "kecsim: t = {:.2} s of {:.2} s simulated ({:.0} %), {:.0} s wall, {:.2}× real time, ETA {:.0} s",
                sample.t,
                self.duration_s,
                100.0 * sample.t / self.duration_s.max(1e-12),
                wall,
                rate,
                (self.duration_s - sample.t).max(0.0) / rate.max(1e-12)
            );
        }
        Ok(())
    }

    fn finish(&mut self, _summary: &RunSummary) -> Result<(), ObserverError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}

/// Holds the run back so that simulated time passes at `factor` times wall time (never faster).
pub struct Pace {
    factor: f64,
    start: Instant,
    /// The run's stop request: a wait ends at once when it is asked.
    cancel: CancelToken,
}

impl Pace {
    pub fn new(factor: f64, cancel: CancelToken) -> Pace {
        Pace {
            factor,
            start: Instant::now(),
            cancel,
        }
    }
}

impl RunObserver for Pace {
    fn start(&mut self, _run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.start = Instant::now();
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        let due = Duration::from_secs_f64((sample.t / self.factor).clamp(0.0, 1e9));
        // Sleep in slices so that an interrupt (Ctrl-C, SIGTERM) ends the wait at once.
        while !self.cancel.requested() {
            let elapsed = self.start.elapsed();
            if due <= elapsed {
                break;
            }
            std::thread::sleep((due - elapsed).min(Duration::from_millis(50)));
        }
        Ok(())
    }
}

/// A progress bar over a count of items (points, cases), with the ETA; silent when stderr is not
/// a terminal. Safe to tick from several threads.
pub struct Counter {
    bar: ProgressBar,
}

impl Counter {
    /// `total` items of `what` (e.g. "points").
    pub fn new(total: u64, what: &str) -> Counter {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr_with_hz(10)
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(total), target);
        bar.set_style(
            ProgressStyle::with_template(&format!(
                "{{wide_bar}} {{pos}}/{{len}} {what} · {{elapsed_precise}} elapsed, ETA {{eta}}"
            ))
            .expect("a valid template"),
        );
        Counter { bar }
    }

    /// One more item done.
    pub fn tick(&self) {
        self.bar.inc(1);
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// A progress bar over several runs one after the other (`compare`, `paper`): the share of the
/// runs' simulated time done, the run and its name, the ETA; silent when stderr is not a terminal.
pub struct Runs {
    bar: ProgressBar,
    names: Vec<String>,
    /// The run now going (1-based; 0 before the first).
    index: usize,
    duration_s: f64,
}

impl Runs {
    /// One run per name, in order.
    pub fn new(names: &[String]) -> Runs {
        let bar = ProgressBar::with_draw_target(Some(1000 * names.len() as u64), draw_target());
        bar.set_style(
            ProgressStyle::with_template(
                "{wide_bar} {percent:>3}% · {msg} · {elapsed_precise} elapsed, ETA {eta}",
            )
            .expect("a valid template"),
        );
        bar.set_message("preprocessing");
        bar.enable_steady_tick(Duration::from_millis(200));
        Runs {
            bar,
            names: names.to_vec(),
            index: 0,
            duration_s: 1.0,
        }
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl RunObserver for Runs {
    fn start(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.index += 1;
        self.duration_s = run.duration_s.max(1e-9);
        self.bar.set_position(1000 * (self.index as u64 - 1));
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        let share = (sample.t / self.duration_s).clamp(0.0, 1.0);
        self.bar
            .set_position(1000 * (self.index.max(1) as u64 - 1) + (1000.0 * share) as u64);
        let name = self
            .names
            .get(self.index.wrapping_sub(1))
            .map_or("", String::as_str);
        self.bar.set_message(format!(
            "run {} of {} ({name}): t = {:.1} of {:.1} s",
            self.index,
            self.names.len(),
            sample.t,
            self.duration_s
        ));
        Ok(())
    }
}

/// A spinner naming the stage a command is in, with the time elapsed, for the commands whose work
/// has no count to show (a wheel's design, an accuracy sweep, a benchmark); silent when stderr is
/// not a terminal.
pub struct Stage {
    bar: ProgressBar,
}

impl Stage {
    pub fn new(what: &str) -> Stage {
        let bar = ProgressBar::with_draw_target(None, draw_target());
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} · {elapsed_precise} elapsed")
                .expect("a valid template"),
        );
        bar.set_message(what.to_string());
        bar.enable_steady_tick(Duration::from_millis(200));
        Stage { bar }
    }

    /// The next stage.
    pub fn set(&self, what: &str) {
        self.bar.set_message(what.to_string());
    }

    /// Removes the spinner from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Stage {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// stderr when it is a terminal, else nothing.
fn draw_target() -> ProgressDrawTarget {
    if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr_with_hz(10)
    } else {
        ProgressDrawTarget::hidden()
    }
}
