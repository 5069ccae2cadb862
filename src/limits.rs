//! Resource limits: the sizes an input implies (grid points, samples, irregularity nodes, track
//! length) are estimated before anything is allocated, and refused above the limits below with an
//! error that says what to change — instead of an allocation that aborts the process or a run
//! that eats the machine. The limits are far above every documented use; `kecsim --no-limits`
//! lifts them (for a machine that has the memory and a user who has the time).

use std::sync::atomic::{AtomicBool, Ordering};

/// Largest number of irregularity nodes generated (each 4 × 3 values: ~100 B; 2e6 nodes ≈ 200 MB:
/// 200 km at the default 0.1 m).
pub const MAX_IRREGULARITY_NODES: f64 = 2e6;
/// Largest number of cosines per irregularity (the automatic count grows with the track length
/// and the band: 1 km over 3–80 m needs 640).
pub const MAX_COSINES: f64 = 2e5;
/// Largest generation work, cosines × nodes × 4 irregularities (~1 ns each: 1e10 ≈ 10–20 s).
pub const MAX_GENERATION_WORK: f64 = 1e10;
/// Longest track, m.
pub const MAX_TRACK_LENGTH_M: f64 = 500e3;
/// Most points of a sampled curve or grid (contact sweeps, track samples, table rows).
pub const MAX_GRID_POINTS: f64 = 1e6;
/// Most contact solutions of a lookup table (each a search on the real profiles, ~0.1 ms):
/// grid points × gauge variations.
pub const MAX_TABLE_NODES: f64 = 2e5;
/// Most output rows of a run, samples × wheelsets (each ~250 B kept for the summary: 4e6 ≈ 1 GB).
pub const MAX_RUN_SAMPLES: f64 = 4e6;

/// Most rigid bodies, wheelsets or joints in a vehicle table (a ten-car train: ~30 bodies, 40
/// wheelsets).
pub const MAX_VEHICLE_BODIES: f64 = 1e3;
/// Most bodies and wheelsets of a vehicle together: its state and dense Jacobian grow with them,
/// the Jacobian's factorisation with their cube (a 399-wheelset train settled for 54 s and took
/// no step in 60 s). A ten-car train has 70.
pub const MAX_VEHICLE_PARTS: f64 = 200.0;
/// Most force elements in a vehicle table (a ten-car train: a few hundred).
pub const MAX_VEHICLE_ELEMENTS: f64 = 1e4;

/// Most threads (`KECSIM_THREADS`) or cases at once (`study --jobs`) per core of the machine:
/// beyond a few per core they only contend (`KECSIM_THREADS=100000` turned a 0.05 s run into
/// 40 s), and a count near `usize::MAX` cannot be allocated at all.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// The most threads or concurrent cases allowed here: [`MAX_THREADS_PER_CORE`] × the cores
/// (unbounded with `--no-limits`).
pub fn max_threads() -> usize {
    if lifted() {
        return usize::MAX;
    }
    MAX_THREADS_PER_CORE * std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// `Ok` if `n` threads (named `what`) are within [`max_threads`], else the problem.
pub fn check_threads(what: &str, n: usize) -> Result<(), String> {
    let max = max_threads();
    if n <= max {
        return Ok(());
    }
    Err(format!(
        "{what} {n}: at most {max} ({MAX_THREADS_PER_CORE} per core of this machine's {}; more only contend; `kecsim --no-limits` lifts the limit)",
        max / MAX_THREADS_PER_CORE
    ))
}

/// Largest input file read (profiles, scenarios, tracks, irregularity and table CSVs), bytes.
pub const MAX_INPUT_FILE_BYTES: u64 = 256 << 20;

/// Reads an input text file: a regular file (not a device such as `/dev/zero`, a FIFO or a
/// directory, which would be read without end or block) of at most [`MAX_INPUT_FILE_BYTES`].
pub fn read_text(path: &std::path::Path) -> std::io::Result<String> {
    use std::io::{Error, ErrorKind};
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "not a regular file (a directory, a device or a pipe)",
        ));
    }
    if meta.len() > MAX_INPUT_FILE_BYTES && !lifted() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{} bytes, above the limit of {} MB for an input file (`kecsim --no-limits` lifts it)",
                meta.len(),
                MAX_INPUT_FILE_BYTES >> 20
            ),
        ));
    }
    std::fs::read_to_string(path)
}

static LIFTED: AtomicBool = AtomicBool::new(false);

/// Lifts every limit for the rest of the process (`kecsim --no-limits`).
pub fn lift() {
    LIFTED.store(true, Ordering::Relaxed);
}

/// Whether the limits were lifted.
pub fn lifted() -> bool {
    LIFTED.load(Ordering::Relaxed)
}

/// `Ok` if `needed` (a count the input implies) is within `limit` or the limits are lifted; else
/// the problem: what it is, how many, the limit, and `advice` (which input to change).
pub fn check(what: &str, needed: f64, limit: f64, advice: &str) -> Result<(), String> {
    if lifted() || (needed.is_finite() && needed <= limit) {
        return Ok(());
    }
    Err(format!(
        "{what}: {needed:.3e} needed, above the limit of {limit:.0e} ({advice}; `kecsim --no-limits` lifts the limits)"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_refuses_above_the_limit_and_names_the_advice() {
        assert!(check("points", 10.0, 100.0, "use a coarser step").is_ok());
        let e = check("points", 1e9, 1e6, "use a coarser step").unwrap_err();
        assert!(
            e.contains("1.000e9") && e.contains("coarser step") && e.contains("--no-limits"),
            "{e}"
        );
        assert!(check("points", f64::INFINITY, 1e6, "x").is_err());
    }
}
