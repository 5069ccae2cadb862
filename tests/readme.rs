//! The README's commands, as a user types them: every `kecsim …` command of its shell blocks and
//! of its text is parsed by the binary (each with `--help` after it: a renamed command or flag, or
//! a value clap refuses, fails here, not for a user), and the cheap ones run for real in a fresh
//! directory. The docs' commands likewise, in `docs/cli.md`'s examples.

use std::path::{Path, PathBuf};

use crate::common::{kecsim, tmpdir};

/// The repository's root (the README's relative paths are from there).
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `kecsim …` command of `text`: the lines of its fenced blocks (continuations joined,
/// `# comments` dropped, `cargo run --release --` read as `kecsim`) and its inline code spans
/// that start with `kecsim ` (those with a placeholder — `…`, `|`, `[`, capitals — are left).
pub fn commands(text: &str) -> Vec<(usize, Vec<String>)> {
    commands_where(text).into_iter().map(|(n, a, _)| (n, a)).collect()
}

/// A word that stands for a value (`FILE.toml`, `N`, `M_S`, `Y1,Y2`) or a choice (`[`, `|`,
/// `…`, `<`): a synopsis, not a command.
fn placeholder(words: &str) -> bool {
    words.contains(['…', '|', '[', '<', '{'])
        || words.split_whitespace().any(|w| {
            let stem = w.split('.').next().unwrap_or("");
            stem.chars().any(|c| c.is_ascii_uppercase())
                && stem
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || "_,-".contains(c))
        })
}

/// [`commands`], each with whether it stands in a fenced block (the README's shell lines).
pub fn commands_where(text: &str) -> Vec<(usize, Vec<String>, bool)> {
    let mut out = Vec::new();
    let mut in_block = false;
    let mut pending: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block {
            let joined = match pending.take() {
                Some((start, head)) => (start, format!("{head} {}", line.trim())),
                None => (n, line.trim().to_string()),
            };
            if let Some(head) = joined.1.strip_suffix('\\') {
                pending = Some((joined.0, head.trim_end().to_string()));
                continue;
            }
            let code = joined.1.split(" #").next().unwrap_or("").trim().to_string();
            let code = code
                .strip_prefix("cargo run --release -- ")
                .map(|rest| format!("kecsim {rest}"))
                .unwrap_or(code);
            if let Some(rest) = code.strip_prefix("kecsim ").filter(|r| !placeholder(r)) {
                out.push((
                    joined.0,
                    rest.split_whitespace().map(String::from).collect(),
                    true,
                ));
            }
        } else {
            // A span still open at the line's end goes on in the next line: left.
            let ticks = line.matches('`').count();
            let closed = line
                .split('`')
                .enumerate()
                .filter(|(k, _)| k % 2 == 1 && *k < ticks - ticks % 2 + 1);
            for (_, span) in closed {
                let Some(rest) = span.strip_prefix("kecsim ") else {
                    continue;
                };
                if !placeholder(rest) {
                    out.push((n, rest.split_whitespace().map(String::from).collect(), false));
                }
            }
        }
    }
    out
}

/// Each command of `file` parses: `kecsim ARGS --help` succeeds (clap reads the arguments in
/// order and stops at the first it does not know, before the help).
fn every_command_parses(file: &str) -> usize {
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let cmds = commands(&text);
    let dir = tmpdir("readme-parse");
    let mut failures = Vec::new();
    for (line, args) in &cmds {
        let mut a: Vec<&str> = args.iter().map(String::as_str).collect();
        a.push("--help");
        let out = kecsim(&a, &dir);
        if !out.status.success() {
            failures.push(format!(
                "{file}:{line}: `kecsim {}`: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr).lines().next().unwrap_or("")
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "commands that no longer parse:\n{}",
        failures.join("\n")
    );
    cmds.len()
}

#[test]
fn the_readmes_commands_parse() {
    let n = every_command_parses("README.md");
    // The tour alone has more than a dozen: an empty list would mean the reader broke.
    assert!(n >= 15, "only {n} commands found in README.md");
}

#[test]
fn the_docs_commands_parse() {
    for file in [
        "docs/cli.md",
        "docs/outputs.md",
        "docs/studies.md",
        "docs/python.md",
    ] {
        every_command_parses(file);
    }
}

/// The README's cheap commands (a second or less each) run as written, in a fresh directory (the
/// paths into `assets/` made absolute), and write what the README says they write.
#[test]
fn the_readmes_cheap_commands_run() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let cheap = ["profiles", "contact", "creep", "track", "generate-profiles"];
    let dir = tmpdir("readme-run");
    let mut ran = Vec::new();
    for (line, args, block) in commands_where(&text) {
        if !block || !args.first().is_some_and(|c| cheap.contains(&c.as_str())) || ran.contains(&args[0]) {
            continue;
        }
        let abs: Vec<String> = args
            .iter()
            .map(|a| {
                if a.starts_with("assets/") {
                    root().join(a).display().to_string()
                } else {
                    a.clone()
                }
            })
            .collect();
        let a: Vec<&str> = abs.iter().map(String::as_str).collect();
        let out = kecsim(&a, &dir);
        assert!(
            out.status.success(),
            "README.md:{line}: `kecsim {}` failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
        // The files it names (`--csv FILE`, `--dir DIR`) are there.
        for pair in args.windows(2) {
            if matches!(pair[0].as_str(), "--csv" | "--dir") {
                assert!(
                    Path::new(&dir).join(&pair[1]).exists(),
                    "README.md:{line}: `kecsim {}` did not write {}",
                    args.join(" "),
                    pair[1]
                );
            }
        }
        ran.push(args[0].clone());
    }
    assert_eq!(
        ran.len(),
        cheap.len(),
        "the README lost one of {cheap:?}: ran {ran:?}"
    );
}

#[test]
fn the_command_reader_finds_blocks_continuations_and_spans() {
    let text = "x\n```sh\nkecsim run --csv out   # comment\nkecsim bench precision --a 1 \\\n  --b 2\ncargo run --release -- paper\nrerun x.rrd\n```\nsee `kecsim compare s.toml --duration 10` or `kecsim run FILE.toml`\n```\nkecsim bench [--calls N]\n```\n";
    let c = commands(text);
    let args: Vec<String> = c.iter().map(|(_, a)| a.join(" ")).collect();
    assert_eq!(
        args,
        [
            "run --csv out",
            "bench precision --a 1 --b 2",
            "paper",
            "compare s.toml --duration 10"
        ]
    );
    assert_eq!(c[1].0, 4);
}

/// The README is a guide, not a record: at most 450 lines (the figures' history is
/// CHANGELOG.md's), and no heading names an issue or a session in it or in docs/.
#[test]
fn the_readme_is_a_guide_and_the_docs_are_by_topic() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let n = readme.lines().count();
    assert!(
        n <= 450,
        "README.md has {n} lines (at most 450: details go to docs/)"
    );
    let mut files = vec![root().join("README.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        files.push(e.unwrap().path());
    }
    for f in files.iter().filter(|p| p.extension().is_some_and(|e| e == "md")) {
        let text = std::fs::read_to_string(f).unwrap();
        for (i, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            let heading = line.starts_with('#');
            assert!(
                !(heading && (lower.contains("issue ") || lower.contains("session"))),
                "{}:{}: a heading names an issue or a session: {line}",
                f.display(),
                i + 1
            );
        }
    }
}
