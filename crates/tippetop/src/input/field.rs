//! A number key of one of the scenario's own tables, defined once
//! (issue #28, 3): its [`Key`] (name, range, default, doc), its default
//! value, the bounds its range states and how to read and write it in the
//! table's struct. The parser ([`Num::read`]), `to_toml` ([`Num::write`]),
//! the range check ([`Num::check`]) and `tippetop keys` (its [`Num::key`]
//! in the table's `KEYS`) are driven from it. A table lists its keys once
//! (`input/surface.rs`'s `KEYS`, `NUMS`); checks that relate two keys stay
//! explicit in the table's `validate`.

use toml::{Table, Value};

use crate::Error;
use crate::input::Key;
use crate::input::reader::Section;

/// The values a number key admits; its [`Key::range`] states them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bounds {
    /// Any finite number.
    Finite,
    /// A finite number `>= lo`.
    AtLeast(f64),
    /// A finite number `> lo`.
    Above(f64),
    /// `lo <= x <= hi` (both finite).
    Within(f64, f64),
}

impl Bounds {
    /// True if `x` is admitted (NaN never is).
    pub fn admits(self, x: f64) -> bool {
        match self {
            Bounds::Finite => x.is_finite(),
            Bounds::AtLeast(lo) => x.is_finite() && x >= lo,
            Bounds::Above(lo) => x.is_finite() && x > lo,
            Bounds::Within(lo, hi) => (lo..=hi).contains(&x),
        }
    }
}

/// A number key of table struct `S` (`Surface`, ...), defined once.
#[derive(Debug, Clone, Copy)]
pub struct Num<S: 'static> {
    /// Name, range (the message's), default as written, one-line doc.
    pub key: Key,
    /// The default value; `None`: required without a preset.
    pub default: Option<f64>,
    /// What the range admits ([`Num::check`]).
    pub bounds: Bounds,
    /// The range a failed [`Num::check`] states, when not the key's own
    /// `range`: the older messages some callers pin (`top.radius: -1 is
    /// not allowed (a finite number > 0)`, tippetop-py's tests); `None`:
    /// the key's range.
    pub check_range: Option<&'static str>,
    /// The value in `S`.
    pub get: fn(&S) -> f64,
    /// Set the value in `S`.
    pub set: fn(&mut S, f64),
}

impl<S> Num<S> {
    /// Read the key from `s` into `into` (types only: a finite number; its
    /// default when absent, or an error naming it when it is required and
    /// there is no preset (`has_preset`), whose tables give every key).
    pub(crate) fn read(&self, s: &Section, has_preset: bool, into: &mut S) -> Result<(), Error> {
        let default = self.default.or(has_preset.then_some(0.0));
        (self.set)(into, s.f64(self.key.name, default)?);
        Ok(())
    }

    /// Write the key's value into a table (`key = value`).
    pub(crate) fn write(&self, from: &S, t: &mut Table) {
        t.insert(self.key.name.into(), Value::Float((self.get)(from)));
    }

    /// Check the value against the bounds; the error names `table.key`
    /// and states the key's range.
    pub fn check(&self, table: &str, from: &S) -> Result<(), Error> {
        let x = (self.get)(from);
        if self.bounds.admits(x) {
            return Ok(());
        }
        Err(Error::invalid(
            &format!("{table}.{}", self.key.name),
            format!("{} is not allowed", crate::human::exact(x)),
            self.check_range.unwrap_or(self.key.range).into(),
        ))
    }
}
