//! The `kecsim` binary: parses the command line and runs the command (see [`cli`]).

// The binary's `println!` and `print!` go through `say`: a closed or failing stdout never panics
// (`kecsim run | head -1` still writes every file; see src/say.rs). Defined before the modules,
// they shadow the standard macros in all of them.
macro_rules! println {
    () => {
        $crate::say::write(format_args!("\n"))
    };
    ($($t:tt)*) => {
        $crate::say::write(format_args!("{}\n", format_args!($($t)*)))
    };
}
macro_rules! print {
    ($($t:tt)*) => {
        $crate::say::write(format_args!($($t)*))
    };
}

// The same for stderr (`eprintln!`, `eprint!`: warnings, progress lines, the signal handler's
// line, the final error): a closed or failing stderr (`kecsim run 2>&1 | head -1`) drops the
// text and the command goes on to its end, writing every file.
macro_rules! eprintln {
    () => {
        $crate::say::write_err(format_args!("\n"))
    };
    ($($t:tt)*) => {
        $crate::say::write_err(format_args!("{}\n", format_args!($($t)*)))
    };
}
#[allow(unused_macros)]
macro_rules! eprint {
    ($($t:tt)*) => {
        $crate::say::write_err(format_args!($($t)*))
    };
}

mod cli;
mod say;

use std::process::ExitCode;

fn main() -> ExitCode {
    // An output that is stdout itself (`--save /dev/stdout`): every printed line goes to stderr,
    // from the first one on, so that the stream holds only the file.
    if std::env::args_os().skip(1).any(|a| {
        let a = std::path::PathBuf::from(a);
        let value = a
            .to_str()
            .and_then(|t| t.split_once('=').map(|(_, v)| std::path::PathBuf::from(v)));
        kecsim::files::is_stdout(&a) || value.is_some_and(|v| kecsim::files::is_stdout(&v))
    }) {
        say::to_stderr();
    }
    let result = cli::run(cli::parse());
    let stdout = say::finish();
    match result {
        Err(e) => {
            eprintln!("kecsim: error: {}", message(&e));
            ExitCode::FAILURE
        }
        Ok(()) => match stdout {
            Some(why) => {
                eprintln!("kecsim: error: the standard output failed ({why}): the printed summary is incomplete; the files written are whole");
                ExitCode::FAILURE
            }
            None => ExitCode::SUCCESS,
        },
    }
}

/// The error and its causes, each cause once: the library's messages already carry their source's
/// text, so a cause is appended only where the message does not contain it (a context added here).
fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.contains(&c) {
            text = format!("{text}: {c}");
        }
    }
    text
}
