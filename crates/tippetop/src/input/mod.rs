//! Keys that describe themselves (issue 28, 3): each scenario key is one
//! [`Key`], its name, valid range (which states the unit), default and a
//! one-line doc, and each table one [`TableSpec`]. From these come the
//! validation messages (the range), [`crate::input::scenario::key_unit`], the
//! `tippetop keys` listing ([`listing`]) and docs/keys.md ([`markdown`]).
//! The scenario's own tables are each one file here (`top.rs`,
//! `surface.rs`, `initial.rs`, `solver.rs`, `thermal.rs`: the struct, its
//! keys, their parse, rendering and validation; a number key is one
//! [`field::Num`]), listed in document order in `input/scenario.rs`; the
//! `[[force]]` schedule's window keys are `forcing::KEYS` (each term's in
//! its file under `physics/forces/`); a force plug-in's table comes from the
//! registry (`physics::forces::PLUGINS`), whose values a scenario keeps in
//! [`PluginTables`]. The TOML reader they all use is `reader.rs`.

pub mod field;
pub mod forcing;
pub mod initial;
pub(crate) mod reader;
pub mod scenario;
pub mod solver;
pub mod surface;
pub mod thermal;
pub mod top;

/// One scenario key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// The key's name within its table (`radius`).
    pub name: &'static str,
    /// Its valid range, as the validation messages state it; the unit is
    /// its last `[...]` ([`Key::unit`]).
    pub range: &'static str,
    /// Its default as written in a scenario (`"0"`, `"\"coulomb\""`), or
    /// `"required"`, or `""` when there is none to state.
    pub default: &'static str,
    /// One line: what the key is.
    pub doc: &'static str,
    /// For a plug-in's number: the closed interval `[lo, hi]` it must lie
    /// in (checked with the message `range`); `None` for the scenario's
    /// own keys, whose structs validate them.
    pub bounds: Option<(f64, f64)>,
}

impl Key {
    /// A key with its range (no default, no doc: `bit` files' keys).
    pub const fn new(name: &'static str, range: &'static str) -> Key {
        Key {
            name,
            range,
            default: "",
            doc: "",
            bounds: None,
        }
    }

    /// A key with its range, default and one-line doc.
    pub const fn doc(
        name: &'static str,
        range: &'static str,
        default: &'static str,
        doc: &'static str,
    ) -> Key {
        Key {
            name,
            range,
            default,
            doc,
            bounds: None,
        }
    }

    /// The same key with numeric bounds `lo <= x <= hi` (a plug-in's).
    pub const fn bounded(self, lo: f64, hi: f64) -> Key {
        Key {
            bounds: Some((lo, hi)),
            ..self
        }
    }

    /// The unit column of `tippetop keys` and docs/keys.md: the unit, `1`
    /// for a dimensionless number, `-` for a name (a quoted default).
    pub fn unit_shown(&self) -> &'static str {
        match self.unit() {
            Some(u) => u,
            None if self.default.starts_with('"') => "-",
            None => "1",
        }
    }

    /// The unit as the range states it (its last `[...]`, `"m"`, `"N"`), or
    /// `None` for a dimensionless key.
    pub fn unit(&self) -> Option<&'static str> {
        let range = self.range;
        let end = range.rfind(']')?;
        let start = range[..end].rfind('[')?;
        let unit = &range[start + 1..end];
        (!unit.is_empty() && !unit.contains(',')).then_some(unit)
    }
}

/// One scenario table and its keys.
#[derive(Debug, Clone, Copy)]
pub struct TableSpec {
    /// The table's name (`surface`, `force`, `wind`).
    pub name: &'static str,
    /// True for an array of tables (`[[force]]`, `[[well]]`).
    pub array: bool,
    /// One line: what the table is.
    pub doc: &'static str,
    /// Its keys, in document order.
    pub keys: &'static [Key],
}

/// The values of the force plug-ins' tables that a scenario gives
/// (`[wind]`, ...): for each table given, its numbers in the order of its
/// keys (a key left out has its default). Empty: no plug-in table.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PluginTables {
    tables: Vec<(&'static str, Vec<f64>)>,
}

impl PluginTables {
    /// No plug-in table.
    pub const NONE: PluginTables = PluginTables { tables: Vec::new() };

    /// The values of table `name`, if the scenario gives it.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.tables
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Set the values of table `name` (in the order of its keys; for an
    /// array of tables, each entry's in turn). The
    /// tables are kept sorted by name, so that equal scenarios compare
    /// equal whatever order their tables were set in.
    pub fn set(&mut self, name: &'static str, values: Vec<f64>) {
        match self.tables.binary_search_by(|(n, _)| (*n).cmp(name)) {
            Ok(i) => self.tables[i].1 = values,
            Err(i) => self.tables.insert(i, (name, values)),
        }
    }

    /// Remove table `name`.
    pub fn remove(&mut self, name: &str) {
        self.tables.retain(|(n, _)| *n != name);
    }

    /// True if no plug-in table is given.
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }

    /// The tables given, sorted by name: (name, values).
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &[f64])> {
        self.tables.iter().map(|(n, v)| (*n, v.as_slice()))
    }
}

/// The `tippetop keys` listing of `tables`: per table a header line, then
/// one line per key: key, unit, default, range, doc.
pub fn listing(tables: &[TableSpec]) -> String {
    let mut out = String::new();
    for (i, t) in tables.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let head = if t.array {
            format!("[[{}]]", t.name)
        } else {
            format!("[{}]", t.name)
        };
        out.push_str(&format!("{head}  {}\n", t.doc));
        let w = t.keys.iter().map(|k| k.name.len()).max().unwrap_or(0);
        let wu = t
            .keys
            .iter()
            .map(|k| k.unit_shown().len())
            .max()
            .unwrap_or(0);
        let wd = t.keys.iter().map(|k| k.default.len()).max().unwrap_or(0);
        for k in t.keys {
            out.push_str(&format!(
                "  {:w$}  {:wu$}  {:wd$}  {}  ({})\n",
                k.name,
                k.unit_shown(),
                k.default,
                k.doc,
                k.range,
            ));
        }
    }
    out
}

/// docs/keys.md: every table as a Markdown table (key, unit, default,
/// range, doc). `command` is the command that writes it.
pub fn markdown(tables: &[TableSpec], command: &str) -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let mut out = format!(
        "# Scenario keys\n\nGenerated by `{command}` from the keys' own definitions \
         (each table's file in `crates/tippetop/src/input/`, the force terms' in \
         `crates/tippetop/src/physics/forces/`); do not edit by hand. The file \
         format and presets: [guide](guide.md); `tippetop keys TABLE` prints one table.\n"
    );
    for t in tables {
        let head = if t.array {
            format!("[[{}]]", t.name)
        } else {
            format!("[{}]", t.name)
        };
        out.push_str(&format!(
            "\n## `{head}`\n\n{}\n\n| key | unit | default | range | what |\n|---|---|---|---|---|\n",
            t.doc
        ));
        for k in t.keys {
            out.push_str(&format!(
                "| `{}` | {} | {} | {} | {} |\n",
                k.name,
                k.unit_shown(),
                if k.default.parse::<f64>().is_ok() || k.default.starts_with(['"', '[']) {
                    format!("`{}`", esc(k.default))
                } else {
                    esc(k.default)
                },
                esc(k.range),
                esc(k.doc),
            ));
        }
    }
    out
}
