//! `kecsim bench [TARGET]`: measured speed with its error, printed (release builds).

use anyhow::Result;
use clap::Args;

#[derive(Args)]
pub(super) struct BenchArgs {
    /// What to measure.
    #[arg(value_enum, default_value = "profiles")]
    target: BenchTarget,
    /// Calls per measurement.
    #[arg(long, default_value_t = 5_000_000)]
    calls: usize,
}

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
        a.calls >= 1,
        "--calls {}: expected at least 1 call per measurement",
        a.calls
    );
    let calls = a.calls;
    match a.target {
        BenchTarget::Profiles => print!("{}", kecsim::bench::table(&kecsim::bench::profiles(calls))),
        BenchTarget::Contact => {
            let (rows, builds) = kecsim::bench::contact(calls.min(200_000))?;
            print!("{}{builds}", kecsim::bench::contact_table(&rows));
        }
        BenchTarget::Track => {
            let (rows, notes) = kecsim::bench::track(calls)?;
            print!("{}{notes}", kecsim::bench::table(&rows));
        }
        BenchTarget::Creep => print!("{}", kecsim::bench::creep(calls.min(1_000_000))?),
        BenchTarget::Kec => {
            let (rows, builds) = kecsim::bench::kec(calls.min(200_000)).map_err(anyhow::Error::msg)?;
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
