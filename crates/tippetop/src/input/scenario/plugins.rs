//! The force plug-ins' tables in a scenario (`[adhesion]`, `[wind]`, ...):
//! parsed, rendered and validated from the registry
//! ([`crate::physics::forces::PLUGINS`]), so that a new plug-in needs no
//! edit here; a scenario's force terms ([`Forces::of`]); and the typed
//! accessors of the older plug-ins' values ([`Scenario::adhesion`],
//! [`Scenario::wells`]).

use std::sync::Arc;

use toml::{Table, Value};

use crate::input::reader::{Section, range_of};
use crate::input::solver::ModelKind;
use crate::input::{Key, PluginTables};
use crate::physics::forces::Plugin;
use crate::physics::forces::{
    ForceTerm, Forces, Kind, PLUGINS, Window, actuators, retarding, vertical_load, wells,
};
use crate::{Adhesion, Error, Scenario, Well};

/// A key's default as a number (a plug-in's keys are numbers; `""` is 0),
/// or `None` for a required key.
fn default_of(k: &Key) -> Option<f64> {
    (k.default != "required").then(|| k.default.parse().unwrap_or(0.0))
}

/// `a`, `a and b`, `a, b and c`.
fn and_list(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// The numbers of one table (or one entry of an array of tables) at
/// `prefix`: every required key first (the message names what every entry
/// needs), then each key's number or default.
fn entry_values(p: &dyn Plugin, prefix: String, table: Option<&Table>) -> Result<Vec<f64>, Error> {
    let spec = p.table();
    let s = Section {
        prefix,
        keys: spec.keys,
        table,
    };
    let required: Vec<&str> = spec
        .keys
        .iter()
        .filter(|k| default_of(k).is_none())
        .map(|k| k.name)
        .collect();
    if let Some(key) = required.iter().find(|k| s.get(k).is_none()) {
        return Err(Error::invalid(
            &s.full(key),
            "missing".into(),
            format!(
                "every {} needs {}; {}",
                p.entry().0,
                and_list(&required),
                range_of(spec.keys, key)
            ),
        ));
    }
    spec.keys
        .iter()
        .map(|k| s.f64(k.name, default_of(k)))
        .collect()
}

/// The plug-in tables the merged document gives, of the plug-ins whose
/// table follows a scenario table for which `follows` is true (so that the
/// first error is the first table's in document order), into `out`: types
/// and defaults, no range checks; those a plug-in
/// [`keeps`](crate::physics::forces::Plugin::keeps), and an array of
/// tables only with an entry.
pub(super) fn parse(
    merged: &Table,
    follows: impl Fn(&str) -> bool,
    out: &mut PluginTables,
) -> Result<(), Error> {
    for &p in PLUGINS.iter().filter(|p| follows(p.follows())) {
        let spec = p.table();
        let values = match merged.get(spec.name) {
            Some(Value::Table(t)) if !spec.array => {
                entry_values(p, spec.name.to_string(), Some(t))?
            }
            Some(Value::Array(list)) if spec.array => {
                let mut v = Vec::new();
                for (k, w) in list.iter().enumerate() {
                    v.extend(entry_values(p, format!("{}.{k}", spec.name), w.as_table())?);
                }
                v
            }
            _ => continue,
        };
        if !values.is_empty() && p.keeps(&values) {
            out.set(spec.name, values);
        }
    }
    Ok(())
}

/// The plug-in tables of `tables` as TOML tables (an array of tables for
/// `[[well]]`), inserted into `t` (only those given: a scenario without
/// them keeps its text).
pub(super) fn to_table(tables: &PluginTables, t: &mut Table) {
    for (name, values) in tables.iter() {
        let Some(p) = crate::physics::forces::plugin(name) else {
            continue;
        };
        let spec = p.table();
        let mut entries = values.chunks(spec.keys.len().max(1)).map(|c| {
            let mut table = Table::new();
            for (k, v) in spec.keys.iter().zip(c) {
                table.insert(k.name.into(), Value::Float(*v));
            }
            Value::Table(table)
        });
        let value = if spec.array {
            Value::Array(entries.collect())
        } else {
            entries.next().unwrap_or_else(|| Value::Table(Table::new()))
        };
        t.insert(name.into(), value);
    }
}

/// The checks of each plug-in table whose table follows a scenario table
/// for which `follows` is true: every number within its key's bounds (the
/// message names `table.key`, or `table.K.key` in an array of tables, and
/// its range), the model applies its kind, then the plug-in's own checks.
pub(super) fn validate(sc: &Scenario, follows: impl Fn(&str) -> bool) -> Result<(), Error> {
    for (name, values) in sc.plugins.iter() {
        let Some(p) = crate::physics::forces::plugin(name).filter(|p| follows(p.follows())) else {
            continue;
        };
        let spec = p.table();
        let n = spec.keys.len().max(1);
        for (i, &x) in values.iter().enumerate() {
            let k = &spec.keys[i % n];
            if let Some((lo, hi)) = k.bounds {
                if !(lo..=hi).contains(&x) {
                    let key = if spec.array {
                        format!("{name}.{}.{}", i / n, k.name)
                    } else {
                        format!("{name}.{}", k.name)
                    };
                    return Err(Error::invalid(
                        &key,
                        format!("{} is not allowed", crate::human::exact(x)),
                        k.range.into(),
                    ));
                }
            }
        }
        let reduced_applies = matches!(
            p.kind(),
            Kind::ContactPoint | Kind::CentreVertical | Kind::Torque
        );
        if sc.solver.model == ModelKind::Reduced && !reduced_applies {
            return Err(Error::invalid(
                name,
                format!("[{name}] is not available in model = \"reduced\""),
                format!("[{name}] needs model = \"vector\" (the default) or \"rigid\""),
            ));
        }
        p.validate(values)?;
    }
    Ok(())
}

/// The first plug-in table a scenario gives that the analyses do not
/// handle by name ([`crate::physics::forces::Plugin::handled_by_name`]), as
/// `table.key` (`table.K.key` for an array of tables) of the first key
/// that was given a value (a required key, or one off its default; the
/// table's first key if none is), for the analyses that do not model the
/// plug-ins; or `None`.
pub fn first_key(sc: &Scenario) -> Option<String> {
    sc.plugins.iter().find_map(|(name, values)| {
        let p = crate::physics::forces::plugin(name)?;
        if p.handled_by_name() {
            return None;
        }
        let spec = p.table();
        let given = values
            .chunks(spec.keys.len().max(1))
            .enumerate()
            .find_map(|(entry, chunk)| {
                spec.keys
                    .iter()
                    .zip(chunk)
                    .find(|&(k, &v)| default_of(k) != Some(v))
                    .map(|(k, _)| (entry, k.name))
            });
        let (entry, key) = match given {
            Some(g) => g,
            None => (0, spec.keys.first()?.name),
        };
        let entry = if spec.array {
            format!(".{entry}")
        } else {
            String::new()
        };
        Some(format!("{name}{entry}.{key}"))
    })
}

/// True if the scenario gives a plug-in table besides those handled by
/// name (`[adhesion]`): what the stem and the tube refuse as "a force
/// plug-in's table".
pub(super) fn has_other(sc: &Scenario) -> bool {
    first_key(sc).is_some()
}

impl Scenario {
    /// The van der Waals adhesion ([`Adhesion::NONE`] without an
    /// `[adhesion]` table): the `[adhesion]` plug-in's values
    /// (physics/forces/adhesion.rs says why they are reached this way).
    pub fn adhesion(&self) -> Adhesion {
        Adhesion::of(&self.plugins)
    }

    /// Set the van der Waals adhesion (`Adhesion::NONE` removes the table).
    pub fn set_adhesion(&mut self, adhesion: Adhesion) {
        adhesion.store(&mut self.plugins);
    }

    /// The orientation wells (none without `[[well]]`): the `[[well]]`
    /// plug-in's entries (physics/forces/wells.rs).
    pub fn wells(&self) -> Vec<Well> {
        wells::of(&self.plugins)
    }

    /// Set the orientation wells (none removes the table).
    pub fn set_wells(&mut self, list: &[Well]) {
        wells::store(list, &mut self.plugins);
    }
}

impl Forces {
    /// The terms of `sc` (nothing latched: zero force): the scenario's own
    /// terms, then each plug-in's in the registry's order.
    pub fn of(sc: &Scenario) -> Self {
        let windows = &sc.forcing.windows;
        let of = |w: &crate::ForceWindow| (w.start, w.stop);
        let mut terms: Vec<Arc<dyn ForceTerm>> = vec![Arc::new(retarding::Retarding::new(
            windows
                .iter()
                .map(|w| Window::at(of(w), [w.hx, w.hy]))
                .collect(),
        ))];
        if sc.forcing.has_load() {
            terms.push(Arc::new(vertical_load::VerticalLoad::new(
                windows.iter().map(|w| Window::at(of(w), w.hz)).collect(),
            )));
        }
        for kind in ["tip", "magnetic"] {
            let body = sc
                .actuators
                .iter()
                .map(|w| Window::at((w.start, w.stop), w.actuator));
            if let Some(term) = actuators::Actuators::of(body, kind) {
                terms.push(Arc::new(term));
            }
        }
        for p in PLUGINS {
            if let Some(term) = sc.plugins.get(p.table().name).and_then(|v| p.term(v)) {
                terms.push(term);
            }
        }
        Forces::new(terms, sc.switch_times(), sc.top.radius)
    }
}

/// The rates \[1/s\] of the plug-in tables a scenario gives
/// ([`crate::physics::forces::Plugin::rate`]): (rate, table, formula).
pub fn rates(sc: &Scenario) -> Vec<(f64, &'static str, &'static str)> {
    let top = &sc.top;
    sc.plugins
        .iter()
        .filter_map(|(name, values)| {
            let p = crate::physics::forces::plugin(name)?;
            let (r, why) = p.rate(values, top.mass, top.radius, top.inertia_transverse)?;
            Some((r, p.table().name, why))
        })
        .collect()
}
