//! `tippetop show`: print a scenario, resolved (a preset, a file and every
//! `--set` applied), as the TOML `tippetop run` would write into
//! `scenario.toml`, without running it; each table and key with a comment
//! that gives its unit and what it is (from the keys' own definitions, as
//! `tippetop keys` lists them).

use std::process::ExitCode;

use tippetop::input::{Key, TableSpec};

use crate::scenario_load::input_error;

/// Print a scenario resolved (preset, file, every --set) as TOML.
#[derive(Debug, Clone, clap::Args)]
#[command(
    after_help = "Each key is followed by a comment: its unit and what it is (for a name, the \
                  values it takes); the text is TOML, a scenario file to edit and run.\n\n\
                  Examples:\n  \
                  tippetop show --preset classical\n  \
                  tippetop show --preset nano-physical --set thermal.temperature=77\n  \
                  tippetop show scenarios/nano.toml > mine.toml"
)]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML); or give --preset")),
    mut_arg("sets", |a| a.help("Override a scenario key, e.g. --set initial.spin=3e7 or --set surface.friction_law=contensou (a word needs no quotes; repeatable)")),
)]
pub struct ShowArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,
}

/// Run `tippetop show`: the resolved scenario's TOML on stdout; bad input
/// is one line on stderr and exit code 2.
pub fn run(args: &ShowArgs) -> ExitCode {
    let sc = crate::scenario_load::from_args(
        args.source.scenario.as_deref(),
        args.source.preset.as_deref(),
        &args.source.sets,
    )
    .and_then(|sc| sc.validate().map(|()| sc));
    match sc {
        Ok(sc) => {
            let tables = tippetop::input::scenario::key_tables();
            print!("{}", annotate(&sc.to_toml_string(), &tables));
            ExitCode::SUCCESS
        }
        Err(e) => input_error(e),
    }
}

/// The first line of every annotated scenario, after the serializer's own.
const PREAMBLE: &str =
    "# SI units; after each key its unit and what it is (every key: tippetop keys)";

/// `toml` (a scenario as [`tippetop::Scenario::to_toml_string`] writes it)
/// with a comment after each table header (the table's doc) and after each
/// `key = value` line (`# unit, doc`; for a name, the values it takes),
/// aligned within the table. A line that is not a whole `key = value` of a
/// known key is left as it is: the text stays the same TOML.
pub fn annotate(toml: &str, tables: &[TableSpec]) -> String {
    let mut out = String::with_capacity(toml.len() * 3);
    let mut table: Option<&TableSpec> = None;
    // The lines of the current table: (text, comment).
    let mut block: Vec<(String, Option<String>)> = Vec::new();
    let mut preamble = false;
    let flush = |block: &mut Vec<(String, Option<String>)>, out: &mut String| {
        let width = block
            .iter()
            .filter(|(_, c)| c.is_some())
            .map(|(l, _)| l.chars().count())
            .max()
            .unwrap_or(0);
        for (line, comment) in block.drain(..) {
            match comment {
                Some(c) => {
                    let pad = width - line.chars().count();
                    out.push_str(&format!("{line}{:pad$}  # {c}\n", ""));
                }
                None => {
                    out.push_str(&line);
                    out.push('\n');
                }
            }
        }
    };
    for line in toml.lines() {
        let trimmed = line.trim();
        if let Some(name) = header(trimmed) {
            flush(&mut block, &mut out);
            table = tables.iter().find(|t| t.name == name);
            match table {
                Some(t) => out.push_str(&format!("{line}  # {}\n", t.doc)),
                None => {
                    out.push_str(line);
                    out.push('\n');
                }
            }
            continue;
        }
        if !preamble && trimmed.starts_with('#') {
            out.push_str(line);
            out.push('\n');
            out.push_str(PREAMBLE);
            out.push('\n');
            preamble = true;
            continue;
        }
        let comment = table.and_then(|t| {
            let (key, value) = line.split_once(" = ")?;
            if !balanced(value) || value.contains('#') {
                return None;
            }
            t.keys
                .iter()
                .find(|k| k.name == key.trim())
                .map(key_comment)
        });
        block.push((line.to_string(), comment));
    }
    flush(&mut block, &mut out);
    out
}

/// The table a header line opens (`[top]`, `[[force]]`), or `None`.
fn header(line: &str) -> Option<&str> {
    let inner = line.strip_prefix('[')?.strip_suffix(']')?;
    let inner = inner
        .strip_prefix('[')
        .and_then(|s| s.strip_suffix(']'))
        .unwrap_or(inner);
    (!inner.is_empty() && inner.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        .then_some(inner)
}

/// Whether a value's brackets close on its own line (an array written
/// over several lines gets no comment).
fn balanced(value: &str) -> bool {
    value.matches('[').count() == value.matches(']').count()
}

/// The comment of `key`: its unit (if it has one) and doc; for a name, the
/// values it takes.
fn key_comment(key: &Key) -> String {
    let mut c = match key.unit() {
        Some(u) => format!("{u}, {}", key.doc),
        None => key.doc.to_string(),
    };
    if key.default.starts_with('"') {
        c.push_str(&format!(": {}", key.range));
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers() {
        assert_eq!(header("[top]"), Some("top"));
        assert_eq!(header("[[force]]"), Some("force"));
        assert_eq!(header("radius = 1"), None);
        assert_eq!(header("[1, 2]"), None);
        assert!(balanced("[1, 2]") && !balanced("["));
    }
}
