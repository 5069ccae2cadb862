//! `kecsim bench [TARGET]`: measured speed with its error, printed (release builds).

use anyhow::Result;
use clap::Args;

#[derive(Args)]
pub(super) struct BenchArgs {
    /// What to measure.
    #[arg(value_enum, default_value = "profiles")]
    target: BenchTarget,
    /// Calls per measurement.
    #[arg(long, default_value_t = DEFAULT_CALLS)]
    calls: usize,
}

/// Calls per measurement by default.
const DEFAULT_CALLS: usize = 5_000_000;
/// Most calls per measurement (the profile target keeps one result per call: 8 bytes each).
const MAX_CALLS: usize = 100_000_000;

#[derive(Clone, Copy, clap::ValueEnum)]
enum BenchTarget {
    /// Profile evaluation: spline vs analytic definition.
    Profiles,
    /// Contact geometry: online solve (cold, warm) vs 1- and 2-entry look-ups, and table builds.
    Contact,
    /// KEC solve (cold, warm) vs 2-entry look-up vs online, with gauge variation.
    Kec,
    /// Hertz, Kalker coefficients, creepages and the creep-force models, with their errors.
    Creep,
    /// Track-frame and irregularity evaluation on the Tab. 6 track.
    Track,
    /// Real-time factor of every scene with every contact model, each model's difference from KEC
    /// on the same scene, the cost of streaming to a recording, and the contact-model dispatch.
    Dynamics,
    /// The cost of calling a contact model through the `dyn ContactModel` interface.
    Dispatch,
}

pub(super) fn run(a: BenchArgs) -> Result<()> {
    if cfg!(debug_assertions) {
        eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
    }
    anyhow::ensure!(
        (1..=MAX_CALLS).contains(&a.calls),
        "--calls {}: expected 1..={MAX_CALLS} calls per measurement",
        a.calls
    );
    let calls = a.calls;
    // Targets whose calls are slow take at most this many (said, not silently).
    let cap = |n: usize| {
        if calls > n {
            eprintln!("kecsim: bench: --calls {calls} capped at {n} for this target");
        }
        calls.min(n)
    };
    if matches!(a.target, BenchTarget::Dynamics | BenchTarget::Dispatch) && calls != DEFAULT_CALLS {
        eprintln!("kecsim: bench: --calls does not apply to this target (it times whole runs)");
    }
    match a.target {
        BenchTarget::Profiles => print!("{}", kecsim::bench::table(&kecsim::bench::profiles(calls))),
        BenchTarget::Contact => {
            let (rows, builds) = kecsim::bench::contact(cap(200_000))?;
            print!("{}{builds}", kecsim::bench::contact_table(&rows));
        }
        BenchTarget::Track => {
            let (rows, notes) = kecsim::bench::track(calls)?;
            print!("{}{notes}", kecsim::bench::table(&rows));
        }
        BenchTarget::Creep => print!("{}", kecsim::bench::creep(cap(1_000_000))?),
        BenchTarget::Kec => {
            let (rows, builds) = kecsim::bench::kec(cap(200_000)).map_err(anyhow::Error::msg)?;
            print!("{}{builds}", kecsim::bench::contact_table(&rows));
        }
        BenchTarget::Dynamics => print!(
            "{}",
            kecsim::bench::dynamics::dynamics().map_err(anyhow::Error::msg)?
        ),
        BenchTarget::Dispatch => print!(
            "{}",
            kecsim::bench::dynamics::dispatch().map_err(anyhow::Error::msg)?
        ),
    }
    Ok(())
}
