//! `kecsim profiles`: the wheel and rail profiles of both sides placed on the track cross-section.

use anyhow::Result;
use clap::Args;

use kecsim::inspect;

use super::{guard_pair, print_pair, PairArgs, SinkArgs};

#[derive(Args)]
pub(super) struct ProfilesArgs {
    #[command(flatten)]
    pair: PairArgs,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: ProfilesArgs) -> Result<()> {
    let ProfilesArgs { pair, sink } = a;
    let sink = sink.sink();
    let _outputs = guard_pair(&pair, &[], &sink)?;
    let pair = pair.pair()?;
    let delivered = {
        // The stream lives in this scope: returning (even with an error) drops it and writes the footer.
        let rec = inspect::open_recording("kecsim", &sink, inspect::profiles::blueprint)?;
        inspect::profiles::record(&rec, &pair)?;
        inspect::finish_recording(rec, &sink)
    };
    print_pair(&pair);
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
