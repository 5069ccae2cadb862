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
    /// Replace files that differ from what would be written (an edited profile); without it
    /// such a file is kept and the command fails naming it.
    #[arg(long)]
    force: bool,
}

pub(super) fn run(a: GenerateArgs) -> Result<()> {
    let dir = a.dir;
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    // Every file is checked before any is written: an edited profile is never replaced silently.
    let mut planned = Vec::new();
    let mut differ = Vec::new();
    for std in StandardProfile::ALL {
        let path = dir.join(format!("{}.csv", std.name()));
        let profile = std.profile();
        let bytes = io::csv_bytes(&profile).with_context(|| format!("cannot format {}", path.display()))?;
        let same = match kecsim::files::read_bounded(&path, 16 << 20, true) {
            Ok(old) => Some(old == bytes),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(_) => Some(false),
        };
        if same == Some(false) {
            differ.push(path.display().to_string());
        }
        planned.push((path, profile, same == Some(true)));
    }
    anyhow::ensure!(
        a.force || differ.is_empty(),
        "{}: differs from the standard profile kecsim would write (edited?); kept — pass --force to replace it",
        differ.join(", ")
    );
    for (path, profile, same) in planned {
        if same {
            println!("{} is up to date", path.display());
            continue;
        }
        io::write_csv(&profile, &path).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
