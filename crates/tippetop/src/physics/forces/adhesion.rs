//! Van der Waals adhesion, the `[adhesion]` table (docs/physics.md#adhesion):
//! pull-off force `F_a` \[N\] and binding energy `E_b` \[J\], a force along
//! the vertical through the sphere's centre, pulling the top onto the plane.
//!
//! - In contact: a load `F_a`. Its line is the vertical through the
//!   sphere's centre, which passes through the contact point `P`, so it
//!   enters exactly as a vertical load at `P` (§vertical-load): the closure is
//!   `N_c D(σ) = Q + F_a D₀`, the plane's reaction `N_c` (the `N` column)
//!   is `F_a` plus what the contact must supply besides, the friction sees
//!   `N_c`; without friction the motion is that without adhesion and
//!   `N_c = F_a + N`. Rolling: `N_c = F_Z + F_a`. Under unilateral contact
//!   the top leaves the plane when `N_c` falls below zero, i.e. when a pull
//!   exceeds `F_a` plus what holds it down otherwise.
//! - In flight (rigid model): the force `−U′(z) Z` with
//!   `U(z) = −E_b exp(−F_a z/E_b)`, `z` the gap: `U(0) = −E_b`,
//!   `−U′(0) = F_a` (continuous at lift-off), monotone, separation work `E_b`.
//! - Jellett's J: conserved (a force whose line passes through `P`, §invariants).
//! - Energy: a potential. In contact it is the constant `U(0)`, and the
//!   force does no work (`v_Pz = 0`); the energy the models report counts it
//!   from contact, `U(z) − U(0) = E_b (1 − exp(−F_a z/E_b))`, zero in contact,
//!   so the energy in contact is the one without adhesion.
//!
//! # The plug-in
//!
//! Everything about the table is here: its keys with their ranges and
//! defaults, its validation (the messages `tippetop` has always given),
//! and its term; one line in [`super::PLUGINS`] registers it, so the
//! scenario parser, `--set`, `to_toml`, `tippetop keys` and docs/keys.md
//! learn it from there. A scenario keeps the table's numbers with the
//! other plug-ins' ([`PluginTables`]).
//!
//! The typed value [`Adhesion`] (`tippetop::Adhesion`) stays the way the
//! rest of the code reaches it: `Scenario::adhesion()` reads it from the
//! scenario's plug-in tables and `Scenario::set_adhesion` writes it. It is
//! read by more than the force term (the rigid model's flight potential
//! through the latched [`CentreVertical`], the tube's and the stem's
//! refusal, the time unit's and the Langevin step's rates, the regime and
//! stability analyses, the `nano-adhesive` preset), and a named struct
//! with `force` and `energy` says what `values[0]` would not. One source
//! of truth: the numbers live in the plug-in tables only; the accessor
//! copies two `f64`s, and nothing reads it inside a run.
//!
//! A table with both numbers zero is no table ([`Plugin::keeps`]): the
//! scenario text of a run without adhesion has no `[adhesion]`, as before
//! the table became a plug-in.

use std::sync::Arc;

use super::{Applied, CentreVertical, Energy, ForceTerm, Kind, Plugin, Properties};
use crate::Error;
use crate::input::{Key, PluginTables, TableSpec};

/// The table's name.
pub const NAME: &str = "adhesion";

/// Valid range of `adhesion.force`, as the error messages state it.
pub const FORCE_RANGE: &str =
    "a finite force >= 0 [N] (pull-off force); > 0 requires adhesion.energy > 0";
/// Valid range of `adhesion.energy`, as the error messages state it.
pub const ENERGY_RANGE: &str =
    "a finite energy >= 0 [J] (binding energy); > 0 requires adhesion.force > 0";

const KEYS: &[Key] = &[
    Key::doc(
        "force",
        FORCE_RANGE,
        "0",
        "F_a, the pull-off force (docs/physics.md#adhesion)",
    ),
    Key::doc("energy", ENERGY_RANGE, "0", "E_b, the binding energy"),
];

/// Van der Waals adhesion between the sphere and the plane (the
/// `[adhesion]` table; docs/physics.md#adhesion). Off when both are zero (the
/// default); otherwise both must be positive.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Adhesion {
    /// Pull-off force `F_a` \[N\], `>= 0`: the force the adhesion adds to the
    /// contact reaction, and the largest pull it resists.
    pub force: f64,
    /// Binding energy `E_b` \[J\], `>= 0`: the work that separates the top
    /// from the plane (rigid model, flight).
    pub energy: f64,
}

impl Adhesion {
    /// No adhesion.
    pub const NONE: Adhesion = Adhesion {
        force: 0.0,
        energy: 0.0,
    };

    /// True when the adhesion is on (`F_a > 0`).
    pub fn is_on(&self) -> bool {
        self.force > 0.0
    }

    /// The adhesion of a scenario's plug-in tables ([`Adhesion::NONE`]
    /// without an `[adhesion]` table).
    pub fn of(tables: &PluginTables) -> Adhesion {
        tables
            .get(NAME)
            .map_or(Adhesion::NONE, Adhesion::from_values)
    }

    /// Write `self` into `tables` (removing the table when both are zero,
    /// as a parsed scenario has it).
    pub fn store(&self, tables: &mut PluginTables) {
        let values = self.values();
        if AdhesionPlugin.keeps(&values) {
            tables.set(NAME, values.to_vec());
        } else {
            tables.remove(NAME);
        }
    }

    /// The table's numbers, in the order of its keys.
    fn values(&self) -> [f64; 2] {
        [self.force, self.energy]
    }

    fn from_values(v: &[f64]) -> Adhesion {
        Adhesion {
            force: v[0],
            energy: v[1],
        }
    }

    /// Check the ranges: both finite and `>= 0`, and either both zero or
    /// both positive (a pull-off force without a binding energy has no
    /// flight potential; a binding energy without a force has no contact
    /// load). The error names the key.
    pub fn validate(&self) -> Result<(), Error> {
        for (key, v, range) in [
            ("adhesion.force", self.force, FORCE_RANGE),
            ("adhesion.energy", self.energy, ENERGY_RANGE),
        ] {
            if !v.is_finite() || v < 0.0 {
                return Err(Error::invalid(
                    key,
                    format!("{} is not allowed", crate::human::exact(v)),
                    range.into(),
                ));
            }
        }
        if self.force > 0.0 && self.energy == 0.0 {
            return Err(Error::invalid(
                "adhesion.energy",
                "missing or 0 with adhesion.force > 0".into(),
                ENERGY_RANGE.into(),
            ));
        }
        if self.energy > 0.0 && self.force == 0.0 {
            return Err(Error::invalid(
                "adhesion.force",
                "missing or 0 with adhesion.energy > 0".into(),
                FORCE_RANGE.into(),
            ));
        }
        Ok(())
    }
}

/// The `[adhesion]` plug-in.
#[derive(Debug, Clone, Copy)]
pub struct AdhesionPlugin;

impl Plugin for AdhesionPlugin {
    fn table(&self) -> TableSpec {
        TableSpec {
            name: NAME,
            array: false,
            doc: "van der Waals adhesion (off by default; docs/physics.md#adhesion)",
            keys: KEYS,
        }
    }
    fn kind(&self) -> Kind {
        Kind::CentreVertical
    }
    fn follows(&self) -> &'static str {
        "surface"
    }
    fn keeps(&self, values: &[f64]) -> bool {
        values.iter().any(|&v| v != 0.0)
    }
    fn handled_by_name(&self) -> bool {
        true
    }
    fn validate(&self, values: &[f64]) -> Result<(), Error> {
        Adhesion::from_values(values).validate()
    }
    fn term(&self, values: &[f64]) -> Option<Arc<dyn ForceTerm>> {
        let a = Adhesion::from_values(values);
        a.is_on().then(|| {
            Arc::new(AdhesionTerm {
                value: CentreVertical {
                    force: a.force,
                    energy: a.energy,
                },
            }) as Arc<dyn ForceTerm>
        })
    }
}

/// The adhesion term of a scenario.
#[derive(Debug, Clone)]
pub struct AdhesionTerm {
    value: CentreVertical,
}

impl ForceTerm for AdhesionTerm {
    fn name(&self) -> &'static str {
        "van der Waals adhesion (adhesion.force, adhesion.energy)"
    }
    fn kind(&self) -> Kind {
        Kind::CentreVertical
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "in contact Q += F_a D0 (N_c = F_a + N); in flight the gap potential U(z) = -E_b exp(-F_a z/E_b) (docs/physics.md#adhesion)",
            conserves_jellett: true,
            energy: Energy::Potential,
        }
    }
    fn add_to(&self, _t: f64, acc: &mut Applied) {
        acc.centre_vertical.force += self.value.force;
        acc.centre_vertical.energy += self.value.energy;
    }
}

#[cfg(test)]
mod tests {
    //! The table as a plug-in keeps the scenario text the file format
    //! documents (input/scenario.rs: `[adhesion]` after `[surface]`, absent
    //! when off). The physics is checked in tests/physics/adhesion.rs and
    //! the messages in tippetop-cli's tests/hardening_cli.rs.

    use super::Adhesion;
    use crate::Scenario;

    /// `[adhesion]` is written after `[surface]` and before `[[force]]`,
    /// and the text parses back to the same scenario.
    #[test]
    fn adhesion_table_keeps_its_place_in_the_text() {
        let sc = Scenario::nano_adhesive();
        let text = sc.to_toml_string();
        let at = |h: &str| text.find(h).unwrap_or_else(|| panic!("{h}: {text}"));
        assert!(at("\n[surface]\n") < at("\n[adhesion]\n"), "{text}");
        assert!(at("\n[adhesion]\n") < at("\n[[force]]\n"), "{text}");
        assert!(text.contains(
            "\n[adhesion]\nforce = 5.915889357711552e-10\nenergy = 1.169645723902958e-19\n"
        ));
        assert_eq!(Scenario::from_toml_str(&text).unwrap(), sc);
    }

    /// A table with both numbers zero is no table: the scenario equals the
    /// one without it, and its text has no `[adhesion]`.
    #[test]
    fn zero_adhesion_is_no_table() {
        let sets = ["adhesion.force=0".to_string(), "adhesion.energy=0".into()];
        let sc = Scenario::load(Some("nano-adhesive"), None, &sets).unwrap();
        assert_eq!(sc.adhesion(), Adhesion::NONE);
        assert!(sc.plugins.is_empty());
        assert!(!sc.to_toml_string().contains("adhesion"));
        let mut bare = Scenario::nano_adhesive();
        bare.set_adhesion(Adhesion::NONE);
        assert_eq!(sc, bare);
    }

    /// Equal scenarios compare equal whatever order their plug-in tables
    /// were set in (the text is parsed in the registry's order).
    #[test]
    fn plugin_tables_compare_equal_in_any_order() {
        let a = Scenario::load(Some("nano-adhesive"), None, &["wind.fx=1e-20".into()]).unwrap();
        let mut b = Scenario::nano();
        b.surface.friction = 1e-3;
        let v = Scenario::nano_adhesive().adhesion();
        b.plugins.set("wind", vec![1e-20, 0.0]);
        b.set_adhesion(v);
        assert_eq!(a, b);
    }
}
