//! The force plug-ins' tables in a scenario (`[adhesion]`, `[wind]`, ...):
//! parsed, rendered and validated from the registry
//! ([`crate::physics::forces::PLUGINS`]), so that a new plug-in needs no
//! edit here; a scenario's force terms ([`Forces::of`]); and the typed
//! accessors of the older plug-ins' values ([`Scenario::adhesion`]).

use std::sync::Arc;

use toml::{Table, Value};

use super::Section;
use crate::input::solver::ModelKind;
use crate::input::{Key, PluginTables};
use crate::physics::forces::{
    ForceTerm, Forces, Kind, PLUGINS, actuators, retarding, vertical_load, wells,
};
use crate::{Adhesion, Error, Scenario};

/// A key's default as a number (a plug-in's keys are numbers; `""` is 0).
fn default_of(k: &Key) -> f64 {
    k.default.parse().unwrap_or(0.0)
}

/// The plug-in tables the merged document gives (types and defaults; no
/// range checks), those a plug-in [`keeps`](crate::physics::forces::Plugin::keeps).
pub(super) fn parse(merged: &Table) -> Result<PluginTables, Error> {
    let mut out = PluginTables::NONE;
    for p in PLUGINS {
        let spec = p.table();
        let Some(table) = merged.get(spec.name).and_then(Value::as_table) else {
            continue;
        };
        let s = Section {
            prefix: spec.name.to_string(),
            keys: spec.keys,
            table: Some(table),
        };
        let values = spec
            .keys
            .iter()
            .map(|k| s.f64(k.name, Some(default_of(k))))
            .collect::<Result<Vec<_>, _>>()?;
        if p.keeps(&values) {
            out.set(spec.name, values);
        }
    }
    Ok(out)
}

/// The plug-in tables of `tables` as TOML tables, inserted into `t` (only
/// those given: a scenario without them keeps its text).
pub(super) fn to_table(tables: &PluginTables, t: &mut Table) {
    for (name, values) in tables.iter() {
        let Some(p) = crate::physics::forces::plugin(name) else {
            continue;
        };
        let mut table = Table::new();
        for (k, v) in p.table().keys.iter().zip(values) {
            table.insert(k.name.into(), Value::Float(*v));
        }
        t.insert(name.into(), Value::Table(table));
    }
}

/// Each plug-in table's checks: every number within its key's bounds (the
/// message names `table.key` and its range), the model applies its kind,
/// then the plug-in's own checks.
pub(super) fn validate(sc: &Scenario) -> Result<(), Error> {
    for (name, values) in sc.plugins.iter() {
        let Some(p) = crate::physics::forces::plugin(name) else {
            continue;
        };
        let spec = p.table();
        for (k, &x) in spec.keys.iter().zip(values) {
            if let Some((lo, hi)) = k.bounds {
                if !(lo..=hi).contains(&x) {
                    return Err(Error::invalid(
                        &format!("{name}.{}", k.name),
                        format!("{x} is not allowed"),
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
/// `table.key` of its first key (for the analyses that do not model the
/// plug-ins), or `None`.
pub fn first_key(sc: &Scenario) -> Option<String> {
    sc.plugins.iter().find_map(|(name, _)| {
        let p = crate::physics::forces::plugin(name)?;
        if p.handled_by_name() {
            return None;
        }
        Some(format!("{name}.{}", p.table().keys.first()?.name))
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
}

impl Forces {
    /// The terms of `sc` (nothing latched: zero force): the scenario's own
    /// terms, then each plug-in's in the registry's order.
    pub fn of(sc: &Scenario) -> Self {
        let mut terms: Vec<Arc<dyn ForceTerm>> =
            vec![Arc::new(retarding::Retarding::of(&sc.forcing))];
        if sc.forcing.has_load() {
            terms.push(Arc::new(vertical_load::VerticalLoad::of(&sc.forcing)));
        }
        if !sc.wells.is_empty() {
            terms.push(Arc::new(wells::Wells::of(&sc.wells)));
        }
        for kind in ["tip", "magnetic"] {
            if let Some(term) = actuators::Actuators::of(&sc.actuators, kind) {
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
