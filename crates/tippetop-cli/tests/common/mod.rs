//! Helpers shared by the end-to-end tests: the `tippetop bit` family
//! (bit_cli.rs, search_cli.rs, device_cli.rs) and the human-output scans
//! (report_md.rs, human_numbers.rs: [`long_numbers`], [`many_digits`],
//! [`huge_times`], [`sentinels`]).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `tippetop` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tippetop"))
}

/// A fresh scratch directory `tippetop-{tag}-{pid}-{name}` in the temp dir.
pub fn scratch(tag: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tippetop-{tag}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A path in the repository.
pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// Assert the command succeeded, showing its output if not.
pub fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Parse a JSON file.
pub fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// FNV-1a 64 of `bytes` (the published algorithm: offset basis
/// 0xcbf29ce484222325, prime 0x100000001b3), the hash of tippetop's
/// checkpoints and checksums.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The checkpoint file (`NAME.partial.sum`) of a partial CSV whose
/// complete text is `csv` (header and rows, each line ending in `\n`),
/// of the run that `shard_json` (its shard description's text) describes:
/// its `fingerprint` line, then one checkpoint after the header and one
/// after every row, as the format of `crates/tippetop-cli/src/partial.rs`
/// says (`ROWS BYTES HASH`).
pub fn checkpoints(shard_json: &str, csv: &str) -> String {
    let info: serde_json::Value = serde_json::from_str(shard_json).unwrap();
    let fp = info["fingerprint"].as_str().unwrap();
    let mut s = format!("# checkpoints\nfingerprint {fp}\n");
    for (rows, (end, _)) in csv.match_indices('\n').enumerate() {
        let bytes = &csv.as_bytes()[..end + 1];
        s.push_str(&format!("{rows} {} {:016x}\n", bytes.len(), fnv1a64(bytes)));
    }
    s
}

/// `shard.json`'s text with the checksum of `file` set to the FNV-1a 64
/// of `bytes` (a shard "edited with its checksum recomputed").
pub fn with_checksum(shard_json: &str, file: &str, bytes: &[u8]) -> String {
    let mut v: serde_json::Value = serde_json::from_str(shard_json).unwrap();
    v["checksums"][file] = format!("fnv1a64:{:016x}", fnv1a64(bytes)).into();
    let mut s = serde_json::to_string_pretty(&v).unwrap();
    s.push('\n');
    s
}

/// Exit code 2 and one line `error: ...` on stderr containing each of
/// `words`.
pub fn refused(o: &Output, words: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "{err}"
    );
    for w in words {
        assert!(err.contains(w), "{w:?} not in {err}");
    }
}

/// The names in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Numbers in `text` with `min` or more significant digits, outside code
/// spans (`...`, which hold command lines a user copies, with full digits).
pub fn long_numbers(text: &str, min: usize) -> Vec<String> {
    let mut found = Vec::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            continue; // inside a code span
        }
        let b = part.as_bytes();
        let mut k = 0;
        while k < b.len() {
            if b[k].is_ascii_digit()
                && (k == 0 || !(b[k - 1].is_ascii_alphanumeric() || b[k - 1] == b'_'))
            {
                let start = k;
                while k < b.len() && (b[k].is_ascii_digit() || b[k] == b'.') {
                    k += 1;
                }
                let num = &part[start..k];
                let digits = num
                    .trim_start_matches(['0', '.'])
                    .chars()
                    .filter(|c| c.is_ascii_digit())
                    .count();
                if digits >= min {
                    found.push(num.to_string());
                }
            } else {
                k += 1;
            }
        }
    }
    found
}

/// Numbers in `text` with `min` or more significant digits, code spans
/// included (a value a user copies is the one that was typed, never the
/// digits of a product). A number is a run of digits and points not
/// preceded by a letter, digit, `_` or point; its exponent (`e-7`) does
/// not count; leading zeros never count, nor the trailing zeros of a
/// number without a point (`1000000` is one figure: a round budget).
pub fn many_digits(text: &str, min: usize) -> Vec<String> {
    let b = text.as_bytes();
    let mut found = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let starts = b[k].is_ascii_digit()
            && (k == 0
                || !(b[k - 1].is_ascii_alphanumeric() || b[k - 1] == b'_' || b[k - 1] == b'.'));
        if !starts {
            k += 1;
            continue;
        }
        let start = k;
        while k < b.len() && (b[k].is_ascii_digit() || b[k] == b'.') {
            k += 1;
        }
        let num = text[start..k].trim_end_matches('.');
        let mut digits: String = num
            .trim_start_matches(['0', '.'])
            .chars()
            .filter(|c| c.is_ascii_digit())
            .collect();
        if !num.contains('.') {
            digits = digits.trim_end_matches('0').to_string();
        }
        if digits.len() >= min {
            found.push(num.to_string());
        }
    }
    found
}

/// Times written with a power of ten beyond 10^100 (`3.131 × 10^775
/// years`, `4.137e+1035 s`): no time scale at all, which the words say.
pub fn huge_times(text: &str) -> Vec<String> {
    const UNITS: [&str; 13] = [
        "s", "ms", "µs", "us", "ns", "ps", "min", "h", "hours", "day", "days", "year", "years",
    ];
    let b = text.as_bytes();
    let mut found = Vec::new();
    for k in 0..b.len() {
        // An exponent starts after `10^`, or after the `e` of a number.
        let exp_at = if b[k..].starts_with(b"10^") {
            k + 3
        } else if (b[k] == b'e' || b[k] == b'E') && k > 0 && b[k - 1].is_ascii_digit() {
            k + 1
        } else {
            continue;
        };
        let mut j = exp_at;
        if j < b.len() && b[j] == b'+' {
            j += 1;
        }
        let d0 = j;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        let Ok(e) = text[d0..j].parse::<u64>() else {
            continue;
        };
        if e <= 100 {
            continue;
        }
        let rest = text[j..].trim_start_matches(' ');
        let word: String = rest.chars().take_while(|c| c.is_alphabetic()).collect();
        if UNITS.contains(&word.as_str()) {
            let from = text[..k]
                .rfind(|c: char| c.is_whitespace() || c == '(')
                .map_or(0, |i| i + 1);
            found.push(format!("{} {word}", &text[from..j]));
        }
    }
    found
}

/// Sentinels a human output must not show: `1e300`-style
/// stand-ins for infinity, `inf`, `NaN`. Outside code spans.
pub fn sentinels(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            continue;
        }
        for w in part.split(|c: char| c.is_whitespace() || "()[],;:=".contains(c)) {
            let bare = w.trim_start_matches(['>', '<', '-', '+']);
            let lower = bare.to_ascii_lowercase();
            if lower.contains("e300") || lower.contains("e+300") || lower == "inf" || lower == "nan"
            {
                found.push(w.to_string());
            }
        }
    }
    found
}

/// The GitHub anchor of a heading: lower case, letters, digits, `_` and
/// `-` kept, spaces as `-`, everything else dropped (readme.rs and
/// doc_anchors.rs; a repeated heading's `-1`, `-2`, ... are the caller's).
pub fn slug(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '_' || c == '-' => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// The anchors of a Markdown text: its headings' slugs (outside code
/// blocks; a repeated heading's later slugs get `-1`, `-2`) and every
/// `<a id="...">` (readme.rs's links, doc_anchors.rs's references).
pub fn anchors(text: &str) -> std::collections::BTreeSet<String> {
    let mut out = std::collections::BTreeSet::new();
    let mut seen: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        if let Some(h) = line.strip_prefix('#') {
            let h = h.trim_start_matches('#');
            if h.starts_with(' ') {
                let s = slug(h.trim());
                let n = seen.entry(s.clone()).or_insert(0);
                out.insert(if *n == 0 {
                    s.clone()
                } else {
                    format!("{s}-{n}")
                });
                *n += 1;
            }
        }
        let mut rest = line;
        while let Some(i) = rest.find("<a id=\"") {
            rest = &rest[i + 7..];
            if let Some(j) = rest.find('"') {
                out.insert(rest[..j].to_string());
            }
        }
    }
    out
}

/// A bit at 300 K in the Langevin mode, a few ps long (bit_cli.rs,
/// trust3_cli.rs).
pub const HOT: &str = r#"preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
samples = 201
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 7
[bit]
hold = 2e-12
phase = 1e-11
[[write]]
hx = 3e-11
hy = 3e-11
stop = 5e-12
[[erase]]
hx = -3e-11
hy = -3e-11
stop = 5e-12
"#;

/// The paper's nano bit at T = 0, 20 us (bit_cli.rs, trust3_cli.rs).
pub const NANO20: &str = r#"preset = "nano"
[solver]
samples = 81
[bit]
hold = 5e-6
phase = 2e-5
[[write]]
hx = 1e-22
hy = 1e-22
[[erase]]
hx = -1e-22
hy = -1e-22
"#;

/// A rare-event question that is fast to set up (a probability from the
/// Brownian lying state at 3000 K; trust3_cli.rs, fuzz_cli.rs): add
/// `--method`.
pub const RARE: &[&str] = &[
    "rare",
    "--preset",
    "nano-physical",
    "--set",
    "solver.method=\"brownian\"",
    "--set",
    "solver.dt=2e-16",
    "--set",
    "initial.theta=1.5707963267948966",
    "--set",
    "thermal.temperature=3000",
    "--set",
    "force.0.hx=1e-10",
    "--target",
    "theta>1.92",
    "--reset",
    "theta<1.22",
    "--quiet",
];
