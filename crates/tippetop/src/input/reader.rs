//! The TOML reader of scenario files: the typed reading of one table
//! ([`Section`]: numbers, arrays, names, whole numbers, with errors that
//! name the key and its range), the document's parse (decimal numbers
//! only), `--set` values, key checks and the rendering of `key = value`
//! lines. It knows keys ([`Key`]) but no table: the scenario's tables
//! (input/scenario.rs) and the force terms' keys
//! (physics/forces/) both read through it, so that a term can parse its
//! own keys without a file-level import cycle (issue #28).

use serde::Deserialize as _;
use toml::{Table, Value};

use crate::Error;
use crate::input::Key;

/// A table's keys, in document order.
pub(crate) type Keys = &'static [Key];

pub(crate) fn range_of(keys: Keys, key: &str) -> &'static str {
    keys.iter()
        .find(|k| k.name == key)
        .map(|k| k.range)
        .unwrap_or("")
}

pub(crate) fn unknown_key(full_key: &str, keys: Keys) -> Error {
    let list: Vec<&str> = keys.iter().map(|k| k.name).collect();
    Error::invalid(
        full_key,
        "unknown key".into(),
        format!("valid keys: {}", list.join(", ")),
    )
}

pub(crate) fn name_of<T: PartialEq + Copy>(names: &[(&'static str, T)], v: T) -> &'static str {
    names
        .iter()
        .find(|(_, x)| *x == v)
        .map(|(n, _)| *n)
        .unwrap_or("?")
}

pub(crate) fn to_i64(n: usize) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// A one-line description of a TOML value for error messages.
pub(crate) fn describe(v: &Value) -> String {
    match v {
        Value::String(s) => format!("string {s:?}"),
        Value::Integer(i) => format!("integer {i}"),
        Value::Float(f) => format!("float {f}"),
        Value::Boolean(b) => format!("boolean {b}"),
        Value::Datetime(d) => format!("datetime {d}"),
        Value::Array(_) => "an array".into(),
        Value::Table(_) => "a table".into(),
    }
}

/// Parse a TOML document; a syntax error becomes a one-line `scenario` error.
pub(crate) fn parse_document(text: &str) -> Result<Table, Error> {
    let table = text.parse::<Table>().map_err(|e| {
        let shown = e.to_string();
        let head = shown.lines().next().unwrap_or("TOML parse error").trim();
        let msg: Vec<&str> = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        let what = if msg.is_empty() {
            head.to_string()
        } else {
            format!("{head}: {}", msg.join("; "))
        };
        Error::invalid("scenario", what, "valid TOML".into())
    })?;
    check_decimal(text)?;
    Ok(table)
}

/// Check every key of `t` against `keys`; `prefix` is the full table key.
pub(crate) fn check_keys(t: &Table, prefix: &str, keys: Keys) -> Result<(), Error> {
    for k in t.keys() {
        if !keys.iter().any(|key| key.name == k) {
            return Err(unknown_key(&format!("{prefix}.{k}"), keys));
        }
    }
    Ok(())
}

/// The table `merged[name]`, created empty if absent.
pub(crate) fn table_mut<'a>(merged: &'a mut Table, name: &str) -> &'a mut Table {
    let entry = merged
        .entry(name.to_string())
        .or_insert_with(|| Value::Table(Table::new()));
    if !entry.is_table() {
        *entry = Value::Table(Table::new());
    }
    match entry {
        Value::Table(t) => t,
        _ => unreachable!("just made a table"),
    }
}

/// The list `merged[name]` (`force` windows, `well`s), created empty if absent.
pub(crate) fn windows_mut<'a>(merged: &'a mut Table, name: &str) -> &'a mut Vec<Value> {
    let entry = merged
        .entry(name.to_string())
        .or_insert_with(|| Value::Array(Vec::new()));
    if !entry.is_array() {
        *entry = Value::Array(Vec::new());
    }
    match entry {
        Value::Array(a) => a,
        _ => unreachable!("just made an array"),
    }
}

/// A `--set` value of `key`: a TOML value if it parses as one, else the
/// raw string. Error: a number that is not decimal ([`check_decimal`]).
pub(crate) fn parse_set_value(key: &str, s: &str) -> Result<Value, Error> {
    if has_radix_prefix(s) {
        if let Ok(v) = s.parse::<toml_edit::Value>() {
            non_decimal_value(&v, key).map_or(Ok(()), Err)?;
        }
    }
    Ok(Value::deserialize(toml::de::ValueDeserializer::new(s))
        .unwrap_or_else(|_| Value::String(s.to_string())))
}

/// The valid form of a number in a scenario.
pub(crate) const DECIMAL_RANGE: &str =
    "a decimal number, e.g. 16 or 1.6e1; hexadecimal, octal and binary are not accepted";

/// Whether `text` could hold a TOML integer in hexadecimal, octal or binary
/// (a cheap test before parsing it again with its literal text).
pub(crate) fn has_radix_prefix(text: &str) -> bool {
    ["0x", "0o", "0b"].iter().any(|p| text.contains(p))
}

/// The first number of a TOML value written in hexadecimal, octal or binary
/// (TOML's `0x10`, `0o20`, `0b10000`), as an error naming `key`: in a
/// scenario every number is decimal (`0x10` is not 16 m).
pub(crate) fn non_decimal_value(v: &toml_edit::Value, key: &str) -> Option<Error> {
    match v {
        toml_edit::Value::Integer(i) => {
            let raw = i.as_repr().and_then(|r| r.as_raw().as_str())?;
            let digits = raw.trim_start_matches(['+', '-']);
            ["0x", "0o", "0b"]
                .iter()
                .any(|p| digits.starts_with(p))
                .then(|| {
                    Error::invalid(
                        key,
                        format!("{raw} is not a decimal number"),
                        DECIMAL_RANGE.into(),
                    )
                })
        }
        toml_edit::Value::Array(a) => a.iter().enumerate().find_map(|(i, x)| match x {
            toml_edit::Value::InlineTable(_) => non_decimal_value(x, &format!("{key}.{i}")),
            _ => non_decimal_value(x, key),
        }),
        toml_edit::Value::InlineTable(t) => t
            .iter()
            .find_map(|(k, x)| non_decimal_value(x, &join_key(key, k))),
        _ => None,
    }
}

pub(crate) fn join_key(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// The first non-decimal number of a TOML item, as for
/// [`non_decimal_value`]; arrays of tables are named `table.K.key`.
pub(crate) fn non_decimal_item(item: &toml_edit::Item, key: &str) -> Option<Error> {
    match item {
        toml_edit::Item::Value(v) => non_decimal_value(v, key),
        toml_edit::Item::Table(t) => t
            .iter()
            .find_map(|(k, x)| non_decimal_item(x, &join_key(key, k))),
        toml_edit::Item::ArrayOfTables(a) => a.iter().enumerate().find_map(|(i, t)| {
            t.iter()
                .find_map(|(k, x)| non_decimal_item(x, &format!("{key}.{i}.{k}")))
        }),
        toml_edit::Item::None => None,
    }
}

/// Check that every number of a TOML document is decimal (error: the first
/// that is not, naming its key). Parsed again only if the text has a radix
/// prefix at all.
pub(crate) fn check_decimal(text: &str) -> Result<(), Error> {
    if !has_radix_prefix(text) {
        return Ok(());
    }
    match text.parse::<toml_edit::DocumentMut>() {
        Ok(doc) => non_decimal_item(doc.as_item(), "").map_or(Ok(()), Err),
        // Not TOML: the parse that follows reports it.
        Err(_) => Ok(()),
    }
}

/// One table of the merged document, with its full key prefix.
pub(crate) struct Section<'a> {
    /// The full key of the table (`surface`, `force.0`).
    pub(crate) prefix: String,
    /// Its keys (for the ranges in messages).
    pub(crate) keys: Keys,
    /// The table, if the document has it.
    pub(crate) table: Option<&'a Table>,
}

impl Section<'_> {
    pub(crate) fn full(&self, key: &str) -> String {
        format!("{}.{key}", self.prefix)
    }

    pub(crate) fn get(&self, key: &str) -> Option<&Value> {
        self.table.and_then(|t| t.get(key))
    }

    pub(crate) fn missing(&self, key: &str) -> Error {
        Error::invalid(
            &self.full(key),
            "missing".into(),
            "required without a preset".into(),
        )
    }

    pub(crate) fn wrong_type(&self, key: &str, expected: &str, v: &Value) -> Error {
        Error::invalid(
            &self.full(key),
            format!("expected {expected}, found {}", describe(v)),
            range_of(self.keys, key).into(),
        )
    }

    /// A finite float (whole numbers accepted); `default` `None` = required.
    pub(crate) fn f64(&self, key: &str, default: Option<f64>) -> Result<f64, Error> {
        let x = match self.get(key) {
            None => return default.ok_or_else(|| self.missing(key)),
            Some(Value::Float(f)) => *f,
            Some(Value::Integer(i)) => *i as f64,
            Some(v) => return Err(self.wrong_type(key, "a number", v)),
        };
        if !x.is_finite() {
            return Err(Error::invalid(
                &self.full(key),
                format!("{} is not allowed", crate::human::exact(x)),
                range_of(self.keys, key).into(),
            ));
        }
        Ok(x)
    }

    /// An array of `N` finite numbers; `default` `None` = required.
    pub(crate) fn f64s<const N: usize>(
        &self,
        key: &str,
        default: Option<[f64; N]>,
    ) -> Result<[f64; N], Error> {
        let v = match self.get(key) {
            None => return default.ok_or_else(|| self.missing(key)),
            Some(v) => v,
        };
        let expected = format!("an array of {N} numbers");
        let Value::Array(a) = v else {
            return Err(self.wrong_type(key, &expected, v));
        };
        if a.len() != N {
            return Err(self.wrong_type(key, &expected, v));
        }
        let mut out = [0.0; N];
        for (o, x) in out.iter_mut().zip(a) {
            *o = match x {
                Value::Float(f) => *f,
                Value::Integer(i) => *i as f64,
                _ => return Err(self.wrong_type(key, &expected, v)),
            };
            if !o.is_finite() {
                return Err(Error::invalid(
                    &self.full(key),
                    format!("{} is not allowed", crate::human::exact(*o)),
                    range_of(self.keys, key).into(),
                ));
            }
        }
        Ok(out)
    }

    /// A non-negative whole number (a whole float is accepted).
    pub(crate) fn usize(&self, key: &str, default: usize) -> Result<usize, Error> {
        const MAX_EXACT: f64 = 9_007_199_254_740_992.0; // 2^53
        let expected = "a non-negative whole number";
        match self.get(key) {
            None => Ok(default),
            Some(v @ Value::Integer(i)) => {
                usize::try_from(*i).map_err(|_| self.wrong_type(key, expected, v))
            }
            Some(v @ Value::Float(f)) => {
                if f.is_finite() && *f >= 0.0 && f.fract() == 0.0 && *f <= MAX_EXACT {
                    Ok(*f as usize)
                } else {
                    Err(self.wrong_type(key, expected, v))
                }
            }
            Some(v) => Err(self.wrong_type(key, expected, v)),
        }
    }

    /// One of `names`; `default` is used when the key is absent.
    pub(crate) fn name<T: Copy>(
        &self,
        key: &str,
        names: &[(&str, T)],
        default: T,
    ) -> Result<T, Error> {
        match self.get(key) {
            None => Ok(default),
            Some(Value::String(s)) => names
                .iter()
                .find(|(n, _)| n == s)
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    Error::invalid(
                        &self.full(key),
                        format!("unknown value {s:?}"),
                        format!("valid: {}", range_of(self.keys, key)),
                    )
                }),
            Some(v) => Err(self.wrong_type(key, "a string", v)),
        }
    }
}

/// Append `key = value` lines for the keys of `t`, in `keys` order.
pub(crate) fn render_keys(out: &mut String, t: &Table, keys: Keys) {
    for k in keys.iter().map(|k| k.name) {
        if let Some(v) = t.get(k) {
            out.push_str(&format!("{k} = {}\n", render_value(v)));
        }
    }
}

/// A scalar as TOML; floats in Rust's shortest round-trip form.
pub(crate) fn render_value(v: &Value) -> String {
    match v {
        Value::Float(f) if f.is_nan() => "nan".into(),
        Value::Float(f) if f.is_infinite() => {
            if *f > 0.0 {
                "inf".into()
            } else {
                "-inf".into()
            }
        }
        Value::Float(f) => format!("{f:?}"),
        other => other.to_string(),
    }
}
