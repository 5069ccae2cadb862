//! `kecsim generate-profiles`: the standard profiles (S1002, 60E1, 54E1) as CSV files, mm.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::profile::{io, StandardProfile};

#[derive(Args)]
pub(super) struct GenerateArgs {
    /// Output directory.
    #[arg(long, default_value = "profiles")]
    dir: PathBuf,
}

pub(super) fn run(a: GenerateArgs) -> Result<()> {
    let dir = a.dir;
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for std in StandardProfile::ALL {
        let path = dir.join(format!("{}.csv", std.name()));
        io::write_csv(&std.profile(), &path).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
