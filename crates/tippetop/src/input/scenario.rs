//! Scenarios: everything that defines one run (top, surface, forcing,
//! initial state, solver), parsed from TOML with presets and `--set`
//! overrides, validated with errors that name the key and the valid range.
//!
//! # File format
//!
//! ```toml
//! preset = "classical"        # optional: start from a preset, then override
//! [surface]
//! friction = 0.2
//! [[force]]                   # a window of the applied-force schedule
//! hx = 1e-3                   # [N]
//! stop = 0.5                  # [s]
//! [solver]
//! t_end = 5.0                 # [s]
//! ```
//!
//! Every table and key, with its unit, default, range and meaning, is in
//! docs/keys.md, generated from the keys' own definitions (`tippetop keys`):
//! each table's in its file (`input/surface.rs`, ...; the `[[force]]`
//! window's in `input/forcing.rs` and its terms' files), the force
//! plug-ins' in `physics/forces/`. The tables in document order: `TABLES`
//! and the plug-ins placed by `table_specs`.
//!
//! Without a preset the required keys are the five `[top]` keys,
//! `surface.friction`, `initial.theta`, `initial.spin` and `solver.t_end`;
//! everything else has a default. With a preset every key defaults to the
//! preset's (literal) value, and a file's `[[force]]` list (even `force = []`)
//! replaces the preset's list. Precedence: preset < file < `--set`.
//! Whole numbers are accepted wherever a float is expected; every number is
//! decimal (`0x10`, `0o20`, `0b10000` are refused, naming the key).

pub mod bit;
pub mod langevin;
pub mod limits;
pub mod plugins;
pub mod search;

use toml::{Table, Value};

use crate::input::reader::{
    Keys, Section, check_keys, describe, name_of, parse_document, parse_set_value, render_keys,
    table_mut, unknown_key, windows_mut,
};
use crate::input::{PluginTables, TableSpec};
use crate::{
    ActuatorWindow, Adhesion, ContactMode, Error, Forcing, Initial, SolverSettings, Surface,
    Thermal, Top, Well,
    input::solver::{Method, ModelKind},
};

/// One complete run description.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The body.
    pub top: Top,
    /// The plane.
    pub surface: Surface,
    /// Applied force schedule.
    pub forcing: Forcing,
    /// The body actuators (`[[force]]` windows of `kind = "tip"` or
    /// `"magnetic"`, docs/physics.md#actuators; none by default), in the order
    /// given; written after the contact windows.
    pub actuators: Vec<ActuatorWindow>,
    /// Initial state.
    pub initial: Initial,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Temperature and damping ([`Thermal::NONE`]: none; docs/physics.md#langevin).
    pub thermal: Thermal,
    /// The force plug-ins' tables given (`[adhesion]`, `[wind]`, ...;
    /// [`crate::physics::forces::PLUGINS`]); none by default. The van der
    /// Waals adhesion is read with [`Scenario::adhesion`].
    pub plugins: PluginTables,
}

impl Scenario {
    /// The paper's nano preset (Sec. 3): C60 top, μ = 0.13, H_x = H_y = 0.1 zN
    /// from t = 0, g = 9.8, paper initial state, adaptive rtol 1e-10,
    /// 1001 samples over 100 µs.
    pub fn nano() -> Self {
        Scenario {
            top: Top::nano(),
            surface: Surface {
                friction: 0.13,
                ..Surface::defaults()
            },
            forcing: Forcing::constant(1e-22, 1e-22),
            actuators: Vec::new(),
            initial: Initial::paper(),
            solver: SolverSettings::new(1e-4),
            thermal: Thermal::NONE,
            plugins: PluginTables::NONE,
        }
    }

    /// The paper's classical benchmark (end of App. A): μ = 0.1, no applied
    /// force, paper initial state, adaptive rtol 1e-10, 1001 samples over 10 s.
    pub fn classical() -> Self {
        Scenario {
            top: Top::classical(),
            surface: Surface {
                friction: 0.1,
                ..Surface::defaults()
            },
            forcing: Forcing::none(),
            actuators: Vec::new(),
            initial: Initial::paper(),
            solver: SolverSettings::new(10.0),
            thermal: Thermal::NONE,
            plugins: PluginTables::NONE,
        }
    }

    /// C60 on graphene with van der Waals adhesion, deterministic (issue
    /// #14, docs/physics.md#adhesion): the nano preset's top, applied force,
    /// initial state and window, with the adhesion of one graphene sheet
    /// from [`crate::physics::adhesion`] (`F_a = 5.92e-10 N`, `E_b = 0.73
    /// eV`, Girifalco–Hodak–Lee constants, §adhesion-c60) and superlubric friction:
    /// the exact Coulomb law with `μ = 1e-3`, the upper bound measured for
    /// graphene/C60/graphene (Sasaki et al., Tribology Online 7, 96 (2012)).
    /// No temperature (`--preset nano-adhesive`; [`Scenario::nano_physical`]
    /// is the same top at 300 K).
    /// The two adhesion values are those `Adhesion::c60_on_graphene().binding()`
    /// gives (`tippetop adhesion`), written out so that the preset shows the
    /// same digits as the command (tests/scenario.rs checks they agree).
    pub fn nano_adhesive() -> Self {
        let (force, energy) = (5.915889357711552e-10, 1.169645723902958e-19);
        let mut sc = Scenario {
            surface: Surface {
                friction: 1e-3,
                ..Self::nano().surface
            },
            ..Self::nano()
        };
        sc.set_adhesion(Adhesion { force, energy });
        sc
    }

    /// C60 on graphene at 300 K (issue #15, docs/physics.md#langevin): the
    /// [`Scenario::nano_adhesive`] top, adhesion, applied force and initial
    /// state, as a Langevin run:
    ///
    /// - no Coulomb friction (it has no thermal partner); damping
    ///   `γ_t = γ_r = 2.2e12 s⁻¹`, the rotational damping that C60's
    ///   reorientation time in the solid implies (NMR, 9.1 ps at 283 K:
    ///   `γ_r = kT/(A D_r)`, research note §1.5); the translational one is
    ///   not measured and taken equal;
    /// - the lying well of a 1 nm nanotube stem adhering to the plane:
    ///   `θ = π/2`, depth 1.1 eV (0.11 eV/Å of stem, continuum LJ, §wells),
    ///   width 0.3 rad (geometry, not a measurement);
    /// - `dt = 4 fs` (`dt · rate = 0.018` for the well's curvature rate
    ///   `sqrt(d/(w² A)) = 4.4e12 s⁻¹`, the fastest), 1 ns (250 000
    ///   steps), 1001 samples, seed 1.
    pub fn nano_physical() -> Self {
        let ev = 1.602176634e-19;
        let mut sc = Self::nano_adhesive();
        sc.surface.friction = 0.0;
        sc.set_wells(&[Well {
            theta: std::f64::consts::FRAC_PI_2,
            depth: 1.1 * ev,
            width: 0.3,
        }]);
        sc.thermal = Thermal {
            temperature: 300.0,
            damping_translational: 2.2e12,
            damping_rotational: 2.2e12,
            damping_contact: 0.0,
            seed: Some(1),
            run: 0,
        };
        sc.solver.method = Method::Langevin;
        sc.solver.dt = Some(4e-15);
        sc.solver.t_end = 1e-9;
        sc
    }

    /// C60 on supported graphene at 300 K with the damping of the LAMMPS
    /// calibration (md/README.md):
    /// [`Scenario::nano_physical`] with `[thermal]`'s two damping rates
    /// replaced by those of the committed fragment
    /// `md/results/nano-md-300K.toml` (tests/scenario.rs checks that they
    /// agree), everything else unchanged.
    ///
    /// The rates and why these: [`Scenario::MD_GAMMA_T`],
    /// [`Scenario::MD_GAMMA_R`].
    pub fn nano_md() -> Self {
        let mut sc = Self::nano_physical();
        sc.thermal.damping_translational = Self::MD_GAMMA_T;
        sc.thermal.damping_rotational = Self::MD_GAMMA_R;
        sc
    }

    /// `nano-md`'s translational damping γ_t [1/s]: the upper end of the
    /// 95 % interval of 5 slide-downs at 300 K (1.792e10 ± 2.48e10 1/s, not
    /// resolved: the interval includes 0), so an upper bound.
    pub const MD_GAMMA_T: f64 = 4.272e10;

    /// `nano-md`'s rotational damping γ_r [1/s]: the upper end of the
    /// 95 % interval of 4 spin-downs of 450 ps at 300 K (2.637e8 ± 3.93e8
    /// 1/s, not resolved), an upper bound; an escape rate in the
    /// underdamped regime grows with γ, so the bound errs towards shorter
    /// retention. `nano-physical` keeps the NMR 2.2e12 1/s.
    pub const MD_GAMMA_R: f64 = 6.572e8;

    /// A preset by name, one of [`PRESETS`].
    pub fn preset(name: &str) -> Result<Self, Error> {
        match PRESETS.iter().find(|p| p.name == name) {
            Some(p) => Ok((p.build)()),
            None => Err(Error::invalid(
                "preset",
                format!("unknown preset \"{name}\""),
                preset_range(),
            )),
        }
    }

    /// Validate every part, then what the run needs as a whole
    /// ([`crate::limits::check_run`]: finite scaled units and times,
    /// `t_end` within [`crate::limits::MAX_SCALED_T_END`] time units, a finite
    /// initial energy, the memory of the samples).
    pub fn validate(&self) -> Result<(), Error> {
        self.top.validate()?;
        self.surface.validate()?;
        self.validate_tube()?;
        self.validate_stem()?;
        if let Some((r, _, _)) = self.surface.law.contensou() {
            // Much smaller than the sphere: the patch is a flat disc on it.
            if r > 0.1 * self.top.radius {
                return Err(Error::invalid(
                    "surface.contact_radius",
                    format!("{} is not allowed", crate::human::exact(r)),
                    crate::input::surface::CONTACT_RADIUS_RANGE.into(),
                ));
            }
        }
        // The plug-ins' tables where their tables were checked before
        // they became plug-ins: [adhesion] after [surface], [[well]]
        // after [[force]].
        plugins::validate(self, |t| t == "surface")?;
        self.forcing.validate()?;
        for (j, w) in self.actuators.iter().enumerate() {
            let prefix = format!("force.{}", self.forcing.windows.len() + j);
            w.validate(&prefix)?;
            crate::physics::forces::actuators::check_model(
                &w.actuator,
                &prefix,
                self.solver.model,
            )?;
        }
        plugins::validate(self, |t| t != "surface")?;
        self.initial
            .validate(self.solver.model == ModelKind::Reduced)?;
        self.solver.validate()?;
        self.thermal.validate()?;
        langevin::check(self)?;
        crate::limits::check_run(self)?;
        Ok(())
    }

    /// What the tube (`surface.shape = "tube"`, docs/physics.md#tube-dynamics)
    /// needs: the rigid model, a radius larger than the contact sphere's,
    /// and none of what is written for the plane only: a stem, actuators
    /// (`[[force]]` windows are taken, in the contact's frame; `[adhesion]`
    /// is the tube's load in contact), `[[well]]`s (θ from the vertical), force
    /// plug-ins, the Coulomb–Contensou laws (drilling about Z), and the
    /// overdamped method (its drift correction is the plane's). Langevin
    /// with `[thermal]` is taken (docs/physics.md#tube-langevin).
    fn validate_tube(&self) -> Result<(), Error> {
        let Some((b, _)) = self.surface.shape.tube() else {
            return Ok(());
        };
        let key = "surface.shape";
        if self.solver.model != ModelKind::Rigid {
            return Err(Error::invalid(
                key,
                format!(
                    "\"tube\" with solver.model = \"{}\"",
                    name_of(crate::input::solver::MODELS, self.solver.model)
                ),
                "the tube needs solver.model = \"rigid\"".into(),
            ));
        }
        if b <= self.top.radius {
            return Err(Error::invalid(
                "surface.tube_radius",
                format!(
                    "{} is not allowed (top.radius = {})",
                    crate::human::exact(b),
                    crate::human::exact(self.top.radius)
                ),
                crate::input::surface::TUBE_RADIUS_RANGE.into(),
            ));
        }
        if self.solver.method == crate::Method::Brownian {
            return Err(Error::invalid(
                "solver.method",
                "\"brownian\" with surface.shape = \"tube\": its drift correction is derived for the plane only".into(),
                "solver.method = \"adaptive\", \"rk4\", \"stiff\" or \"langevin\" in the tube (docs/physics.md#tube-langevin)".into(),
            ));
        }
        let plane_only: [(&str, bool); 5] = [
            ("top.stem_radius", self.top.stem.is_some()),
            ("an actuator (force.K.kind)", !self.actuators.is_empty()),
            ("well", !self.wells().is_empty()),
            ("a force plug-in's table", plugins::has_other(self)),
            (
                "surface.friction_law",
                self.surface.law.contensou().is_some(),
            ),
        ];
        if let Some((what, _)) = plane_only.iter().find(|(_, on)| *on) {
            return Err(Error::invalid(
                key,
                format!("\"tube\" with {what}, which is modelled on the plane only"),
                "shape = \"tube\" with gravity, [[force]] windows, [adhesion] (the tube's, in contact) and the point friction laws only (and method = \"langevin\" with [thermal]): no stem, actuator, [[well]], force plug-in or contensou* law (docs/physics.md#tube-dynamics)".into(),
            ));
        }
        Ok(())
    }

    /// What a stem (docs/physics.md#stem) needs besides its geometry: the
    /// deterministic methods, and in the rigid model unilateral contact
    /// (the main sphere lifts off when the stem lands).
    fn validate_stem(&self) -> Result<(), Error> {
        if self.top.stem.is_none() {
            return Ok(());
        }
        if !self.forcing.windows.is_empty()
            || !self.actuators.is_empty()
            || self.adhesion().is_on()
            || !self.wells().is_empty()
            || plugins::has_other(self)
        {
            return Err(Error::invalid(
                "top.stem_radius",
                "a stem with [[force]], [adhesion], [[well]] or a force plug-in's table is not modelled".into(),
                "a stem with gravity and friction only (docs/physics.md#stem)".into(),
            ));
        }
        if self.solver.method.is_stochastic() {
            return Err(Error::invalid(
                "top.stem_radius",
                "a stem with solver.method = \"langevin\" or \"brownian\" is not modelled".into(),
                "a stem with solver.method = \"adaptive\", \"rk4\" or \"stiff\" only".into(),
            ));
        }
        if let Some(c_td) = self.top.stem_touchdown_cos() {
            if self.initial.theta.is_nan() || self.initial.theta.cos() <= c_td {
                return Err(Error::invalid(
                    "initial.theta",
                    format!("{} puts the stem on or below the plane", self.initial.theta),
                    format!(
                        "0 <= theta < theta_td = {} rad, where the stem touches (cos theta_td = -(radius - stem_radius)/(stem_distance - offset))",
                        c_td.acos()
                    ),
                ));
            }
        }
        if self.solver.model == ModelKind::Rigid && self.surface.contact != ContactMode::Unilateral
        {
            return Err(Error::invalid(
                "surface.contact",
                format!(
                    "\"{}\" with a stem (top.stem_radius) and model = \"rigid\"",
                    self.surface.contact.name()
                ),
                "\"unilateral\" with a stem in the rigid model (the main sphere lifts off when the stem lands)".into(),
            ));
        }
        Ok(())
    }

    /// Build a scenario from an optional preset name (the CLI's `--preset`),
    /// an optional TOML document (see the [module docs](self) for the keys)
    /// and `--set` overrides of the form `TABLE.KEY=VALUE` (force windows:
    /// `force.K.KEY`, 0-based `K`; `K` equal to the number of windows appends
    /// one). Precedence: preset < file < `--set`, later `--set`s win.
    ///
    /// Errors are [`Error::Invalid`] naming the full key (`top.radius`,
    /// `force.0.stop`, ...): syntax, unknown keys and tables, missing keys and
    /// wrong types are reported first, then the physical ranges of
    /// [`Scenario::validate`].
    pub fn load(
        preset: Option<&str>,
        toml_text: Option<&str>,
        sets: &[String],
    ) -> Result<Scenario, Error> {
        let file = match toml_text {
            Some(text) => parse_document(text)?,
            None => Table::new(),
        };
        Scenario::load_table(preset, &file, sets)
    }

    /// [`Scenario::load`] from an already parsed document.
    fn load_table(preset: Option<&str>, file: &Table, sets: &[String]) -> Result<Scenario, Error> {
        // The preset: command line and file must agree.
        let file_preset = match file.get("preset") {
            None => None,
            Some(Value::String(s)) => Some(s.as_str()),
            Some(other) => {
                return Err(Error::invalid(
                    "preset",
                    format!("expected a string, found {}", describe(other)),
                    preset_range(),
                ));
            }
        };
        let preset_name = match (preset, file_preset) {
            (Some(arg), Some(f)) if arg != f => {
                return Err(Error::invalid(
                    "preset",
                    format!("given both on the command line (\"{arg}\") and in the file (\"{f}\")"),
                    "give it once, or the same name in both".into(),
                ));
            }
            (Some(arg), _) => Some(arg),
            (None, f) => f,
        };
        let mut merged = match preset_name {
            Some(name) => Scenario::preset(name)?.to_table(),
            None => Table::new(),
        };

        let mut eps_explicit = merge_file(&mut merged, file)?;
        for set in sets {
            eps_explicit |= apply_set(&mut merged, set)?;
        }

        let sc = from_table(&merged, preset_name.is_some(), eps_explicit)?;
        sc.validate()?;
        Ok(sc)
    }

    /// Every force switch time \[s\]: the `[[force]]` windows' starts and
    /// finite stops, the body actuators' included; sorted, deduplicated.
    pub fn switch_times(&self) -> Vec<f64> {
        let mut v = self.forcing.switch_times();
        v.extend(
            self.actuators
                .iter()
                .flat_map(|w| [w.start, w.stop])
                .filter(|t| t.is_finite()),
        );
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// Parse a TOML scenario document; the same as `load(None, Some(text), &[])`.
    pub fn from_toml_str(text: &str) -> Result<Scenario, Error> {
        Scenario::load(None, Some(text), &[])
    }

    /// A complete TOML document for this scenario: every key explicit, no
    /// `preset` line, floats written so that they parse back exactly
    /// (`Scenario::from_toml_str(&s.to_toml_string())` gives `s` back for
    /// any valid `s`). A force window that never stops has no `stop` key.
    pub fn to_toml_string(&self) -> String {
        let table = self.to_table();
        let mut out = String::from("# tippetop scenario\n");
        for (name, keys) in all_tables() {
            match table.get(name) {
                Some(Value::Table(t)) => {
                    out.push_str(&format!("\n[{name}]\n"));
                    render_keys(&mut out, t, keys);
                }
                Some(Value::Array(windows)) => {
                    for w in windows {
                        if let Value::Table(t) = w {
                            out.push_str(&format!("\n[[{name}]]\n"));
                            render_keys(&mut out, t, keys);
                        }
                    }
                }
                _ => {}
            }
        }
        out
    }

    /// The scenario as a complete TOML table (the layout of the file format).
    fn to_table(&self) -> Table {
        let top = crate::input::top::to_table(&self.top);
        let surface = crate::input::surface::to_table(&self.surface);
        let force = self.force_list();

        let initial = crate::input::initial::to_table(&self.initial);
        let solver = crate::input::solver::to_table(&self.solver);

        let mut t = Table::new();
        t.insert("top".into(), Value::Table(top));
        t.insert("surface".into(), Value::Table(surface));
        t.insert("force".into(), Value::Array(force));
        plugins::to_table(&self.plugins, &mut t);
        t.insert("initial".into(), Value::Table(initial));
        t.insert("solver".into(), Value::Table(solver));
        // Written only when set (scenario texts without it unchanged).
        if self.thermal.is_set() {
            let thermal = crate::input::thermal::to_table(&self.thermal);
            t.insert("thermal".into(), Value::Table(thermal));
        }
        t
    }

    /// The `[[force]]` list: contact-point windows, then the body actuators.
    fn force_list(&self) -> Vec<Value> {
        crate::input::forcing::to_list(&self.forcing, &self.actuators)
    }
}

// ---------------------------------------------------------------------------
// Key specification: every table, its keys and each key's valid range.

/// A built-in scenario: its name, what it is in a phrase (for `--help`),
/// and its constructor.
pub struct Preset {
    /// The name `--preset` and a file's `preset = "..."` take.
    pub name: &'static str,
    /// What the preset is, in a phrase with where it is documented.
    pub about: &'static str,
    /// The scenario.
    pub build: fn() -> Scenario,
}

/// Every preset, in the order `--help` lists them.
pub const PRESETS: [Preset; 5] = [
    Preset {
        name: "nano",
        about: "C60, the paper's Sec. 3",
        build: Scenario::nano,
    },
    Preset {
        name: "nano-physical",
        about: "the same C60 on graphene at 300 K: van der Waals adhesion, a stem's lying well, \
                Langevin damping from NMR, 2.2e12 1/s, and noise, 1 ns, docs/physics.md#langevin",
        build: Scenario::nano_physical,
    },
    Preset {
        name: "nano-md",
        about: "nano-physical with the damping measured by molecular dynamics of C60 on graphene \
                with LAMMPS, upper bounds, md/README.md",
        build: Scenario::nano_md,
    },
    Preset {
        name: "nano-adhesive",
        about: "the same C60 without temperature: adhesion and superlubric Coulomb friction, \
                docs/physics.md#adhesion",
        build: Scenario::nano_adhesive,
    },
    Preset {
        name: "classical",
        about: "the 15 g toy of the paper's App. A",
        build: Scenario::classical,
    },
];

/// The valid preset names in words: `"nano", ... or "classical"`.
pub fn preset_range() -> String {
    let names: Vec<String> = PRESETS.iter().map(|p| format!("\"{}\"", p.name)).collect();
    let (last, rest) = names.split_last().expect("presets exist");
    format!("{} or {last}", rest.join(", "))
}

/// `--preset`'s help: every preset with what it is.
pub fn preset_help() -> String {
    let list: Vec<String> = PRESETS
        .iter()
        .map(|p| format!("  {}: {}", p.name, p.about))
        .collect();
    format!("Start from a built-in scenario:\n{}", list.join("\n"))
}

/// The `[initial]` keys of the lab-frame form (the Euler-angle form's:
/// `initial::NUMS`).
const INITIAL_LAB: [&str; 3] = ["axis", "angular_velocity", "velocity"];

/// Insert `[initial]` key `k`: a lab-frame key replaces the Euler-angle
/// keys of earlier layers (the preset, a file); an Euler-angle key after
/// a lab-frame key is an error (the two forms do not mix).
fn insert_initial(dst: &mut Table, k: &str, v: Value) -> Result<(), Error> {
    if INITIAL_LAB.contains(&k) {
        for e in crate::input::initial::NUMS {
            dst.remove(e.key.name);
        }
    } else if let Some(lab) = INITIAL_LAB.iter().find(|l| dst.contains_key(**l)) {
        return Err(Error::invalid(
            &format!("initial.{k}"),
            format!("cannot be combined with initial.{lab}"),
            "the initial state either as theta, theta_dot, precession, spin, ux, uy, heading or as axis, angular_velocity, velocity".into(),
        ));
    }
    dst.insert(k.to_string(), v);
    Ok(())
}

/// One line per table of [`TABLES`], for `tippetop keys` and docs/keys.md.
const TABLE_DOCS: &[(&str, &str)] = &[
    ("top", "the body: a sphere with an offset centre of mass"),
    ("surface", "the plane: gravity, friction, contact"),
    (
        "force",
        "force windows: at the contact point (precessing frame), a tip or a magnet (none by default)",
    ),
    (
        "initial",
        "the initial state: Euler angles and rates, or lab-frame vectors",
    ),
    ("solver", "the integrator, duration, output and model"),
    (
        "thermal",
        "Langevin dynamics: temperature and damping (off by default)",
    ),
];

/// The scenario's own tables in document order (the force plug-ins' are
/// placed by [`table_specs`]); `force` is an array of tables.
const TABLES: &[(&str, Keys)] = &[
    ("top", crate::input::top::KEYS),
    ("surface", crate::input::surface::KEYS),
    ("force", &crate::input::forcing::KEYS),
    ("initial", crate::input::initial::KEYS),
    ("solver", crate::input::solver::KEYS),
    ("thermal", crate::input::thermal::KEYS),
];

/// The scenario's own tables with, after each, the force plug-ins' that
/// follow it ([`crate::physics::forces::Plugin::follows`], in the
/// registry's order): every table in document order.
fn table_specs() -> Vec<TableSpec> {
    let mut v = Vec::new();
    for &(name, keys) in TABLES {
        v.push(TableSpec {
            name,
            array: name == "force",
            doc: TABLE_DOCS
                .iter()
                .find(|(n, _)| *n == name)
                .map_or("", |(_, d)| *d),
            keys,
        });
        v.extend(
            crate::physics::forces::PLUGINS
                .iter()
                .filter(|p| p.follows() == name)
                .map(|p| p.table()),
        );
    }
    v
}

/// Every table in document order: (name, keys).
fn all_tables() -> Vec<(&'static str, Keys)> {
    table_specs().iter().map(|t| (t.name, t.keys)).collect()
}

/// The valid top-level entries, for the unknown-table error.
fn top_level_range() -> String {
    let names: Vec<String> = table_specs()
        .iter()
        .map(|t| {
            if t.array {
                format!("[[{}]]", t.name)
            } else {
                format!("[{}]", t.name)
            }
        })
        .collect();
    format!("valid top-level entries: preset, {}", names.join(", "))
}

/// True if `table` is an array of tables (`force`, `well`).
fn is_array(table: &str) -> bool {
    table_specs().iter().any(|t| t.array && t.name == table)
}

/// What one entry of the array of tables `table` is called, singular and
/// plural: a force `window`, a plug-in's ([`crate::physics::forces::Plugin::entry`]).
fn entry_of(table: &str) -> (&'static str, &'static str) {
    match crate::physics::forces::plugin(table) {
        Some(p) => p.entry(),
        None => ("window", "windows"),
    }
}

/// The unit of a scenario key as its valid range states it (`"m"` for
/// `top.offset`, `"N"` for `force.0.hx`; the last `[...]` of the range), or
/// None (a dimensionless key, or one not in the scenario's tables).
pub fn key_unit(full_key: &str) -> Option<&'static str> {
    let table = full_key.split('.').next()?;
    let key = full_key.rsplit('.').next()?;
    keys_of(table)?.iter().find(|k| k.name == key)?.unit()
}

/// Every scenario table with its keys, the force plug-ins' included: what
/// `tippetop keys` lists and docs/keys.md shows.
pub fn key_tables() -> Vec<TableSpec> {
    table_specs()
}

fn keys_of(table: &str) -> Option<Keys> {
    TABLES
        .iter()
        .find(|(n, _)| *n == table)
        .map(|(_, k)| *k)
        .or_else(|| crate::physics::forces::plugin(table).map(|p| p.table().keys))
}

// ---------------------------------------------------------------------------
// Parsing and merging.

/// Merge the file's tables into `merged` key by key (the force list is
/// replaced as a whole). Returns whether the file gives `surface.friction_eps`.
fn merge_file(merged: &mut Table, file: &Table) -> Result<bool, Error> {
    // Unknown top-level entries first.
    for (name, v) in file {
        if matches!(name.as_str(), "bit" | "write" | "erase") {
            return Err(Error::invalid(
                name,
                "a memory bit's table: this command runs plain scenarios".into(),
                "run a file with [bit], [[write]], [[erase]] with tippetop bit".into(),
            ));
        }
        if name != "preset" && keys_of(name).is_none() {
            let what = if v.is_table() {
                "unknown table"
            } else {
                "unknown key"
            };
            return Err(Error::invalid(name, what.into(), top_level_range()));
        }
    }
    let mut eps_explicit = false;
    for spec in table_specs() {
        let (name, keys) = (spec.name, spec.keys);
        let Some(v) = file.get(name) else { continue };
        if spec.array {
            let (one, _) = entry_of(name);
            let Value::Array(windows) = v else {
                return Err(Error::invalid(
                    name,
                    format!("expected an array of tables, found {}", describe(v)),
                    format!("[[{name}]] sections, one per {one}"),
                ));
            };
            for (k, w) in windows.iter().enumerate() {
                let Value::Table(t) = w else {
                    return Err(Error::invalid(
                        &format!("{name}.{k}"),
                        format!("expected a table, found {}", describe(w)),
                        format!("[[{name}]] sections, one per {one}"),
                    ));
                };
                check_keys(t, &format!("{name}.{k}"), keys)?;
            }
            *windows_mut(merged, name) = windows.clone();
        } else {
            let Value::Table(t) = v else {
                return Err(Error::invalid(
                    name,
                    format!("expected a table, found {}", describe(v)),
                    format!("a [{name}] section"),
                ));
            };
            check_keys(t, name, keys)?;
            if name == "surface" && t.contains_key("friction_eps") {
                eps_explicit = true;
            }
            if name == "initial" {
                let euler = crate::input::initial::NUMS
                    .iter()
                    .map(|e| e.key.name)
                    .find(|e| t.contains_key(*e));
                let lab = INITIAL_LAB.iter().find(|l| t.contains_key(**l));
                if let (Some(e), Some(l)) = (euler, lab) {
                    return Err(Error::invalid(
                        &format!("initial.{e}"),
                        format!("cannot be combined with initial.{l}"),
                        "the initial state either as theta, theta_dot, precession, spin, ux, uy, heading or as axis, angular_velocity, velocity".into(),
                    ));
                }
            }
            let dst = table_mut(merged, name);
            for (k, v) in t {
                if name == "initial" {
                    insert_initial(dst, k, v.clone())?;
                } else {
                    dst.insert(k.clone(), v.clone());
                }
            }
        }
    }
    Ok(eps_explicit)
}

/// Apply one `--set TABLE.KEY=VALUE`. Returns whether it sets
/// `surface.friction_eps`.
fn apply_set(merged: &mut Table, set: &str) -> Result<bool, Error> {
    let Some((key, value)) = set.split_once('=') else {
        return Err(Error::invalid(
            "--set",
            format!("{set:?} is not of the form TABLE.KEY=VALUE"),
            "e.g. --set surface.friction=0.2 or --set force.0.hx=1e-22".into(),
        ));
    };
    let key = key.trim();
    let value = parse_set_value(key, value.trim())?;
    let parts: Vec<&str> = key.split('.').collect();
    match parts.as_slice() {
        ["preset"] => Err(Error::invalid(
            "preset",
            "cannot be given with --set".into(),
            "use --preset NAME, or preset = \"NAME\" in the file".into(),
        )),
        [list, idx, k] if is_array(list) => {
            let keys = keys_of(list).unwrap_or(&[]);
            let (one, _) = entry_of(list);
            if !idx.bytes().all(|b| b.is_ascii_digit()) || idx.is_empty() {
                return Err(Error::invalid(
                    key,
                    format!("{idx:?} is not a {one} index"),
                    format!("{list}.K.KEY with K = 0, 1, ... (0-based)"),
                ));
            }
            if !keys.iter().any(|key| key.name == *k) {
                return Err(unknown_key(key, keys));
            }
            let windows = windows_mut(merged, list);
            let n = windows.len();
            let kk = idx.parse::<usize>().unwrap_or(usize::MAX);
            if kk > n {
                let what = if *list == "force" { "force window" } else { one };
                return Err(Error::invalid(
                    key,
                    format!("there is no {what} {idx} ({n} defined)"),
                    format!("K <= {n}: 0-based, K = {n} appends a new {one}"),
                ));
            }
            if kk == n {
                windows.push(Value::Table(Table::new()));
            }
            if let Value::Table(t) = &mut windows[kk] {
                t.insert((*k).to_string(), value);
            }
            Ok(false)
        }
        ["force", ..] => Err(Error::invalid(
            key,
            "force windows are set one key at a time".into(),
            "force.K.KEY with K = 0, 1, ... and KEY one of kind, hx, hy, hz, start, stop, point, force, moment, field, gradient".into(),
        )),
        [list, ..] if is_array(list) => Err(Error::invalid(
            key,
            format!("{} are set one key at a time", entry_of(list).1),
            format!(
                "{list}.K.KEY with K = 0, 1, ... and KEY one of {}",
                keys_of(list)
                    .unwrap_or(&[])
                    .iter()
                    .map(|k| k.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
        [table, k] if keys_of(table).is_some() => {
            let keys = keys_of(table).unwrap_or(&[]);
            if !keys.iter().any(|key| key.name == *k) {
                return Err(unknown_key(key, keys));
            }
            if *table == "initial" {
                insert_initial(table_mut(merged, table), k, value)?;
            } else {
                table_mut(merged, table).insert((*k).to_string(), value);
            }
            Ok(*table == "surface" && *k == "friction_eps")
        }
        [table, ..] if keys_of(table).is_some() => {
            let list: Vec<&str> = keys_of(table)
                .unwrap_or(&[])
                .iter()
                .map(|k| k.name)
                .collect();
            Err(Error::invalid(
                key,
                format!("not a key: expected {table}.KEY"),
                format!("valid keys: {}", list.join(", ")),
            ))
        }
        [table, ..] => Err(Error::invalid(
            key,
            format!("unknown table \"{table}\""),
            format!(
                "valid tables: {}",
                all_tables()
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
        [] => unreachable!("split always yields one part"),
    }
}

// ---------------------------------------------------------------------------
// Typed extraction from the merged table.

fn section<'a>(merged: &'a Table, name: &str) -> Section<'a> {
    Section {
        prefix: name.to_string(),
        keys: keys_of(name).unwrap_or(&[]),
        table: merged.get(name).and_then(Value::as_table),
    }
}

/// Convert the merged table to a scenario (types, required keys and
/// defaults; no range checks). `eps_explicit`: `surface.friction_eps` was
/// given by the file or a `--set` (not only inherited from the preset).
fn from_table(merged: &Table, has_preset: bool, eps_explicit: bool) -> Result<Scenario, Error> {
    // Each table in document order (the first error is the first table's).
    let top = crate::input::top::parse(&section(merged, "top"), has_preset)?;
    let surface =
        crate::input::surface::parse(&section(merged, "surface"), has_preset, eps_explicit)?;
    // The plug-ins' tables where their tables were read before they
    // became plug-ins ([adhesion] after [surface], [[well]] after
    // [[force]]), the others' last.
    let mut plugins = PluginTables::NONE;
    plugins::parse(merged, |t| t == "surface", &mut plugins)?;

    let (forcing, actuators) = forces_of(merged)?;
    plugins::parse(merged, |t| t == "force", &mut plugins)?;
    let initial = crate::input::initial::parse(&section(merged, "initial"), has_preset)?;
    let solver = crate::input::solver::parse(&section(merged, "solver"), has_preset)?;
    let thermal = crate::input::thermal::parse(&section(merged, "thermal"))?;

    plugins::parse(merged, |t| !matches!(t, "surface" | "force"), &mut plugins)?;

    Ok(Scenario {
        top,
        surface,
        forcing,
        actuators,
        initial,
        solver,
        thermal,
        plugins,
    })
}

/// The `[[force]]` windows: contact-point windows and body actuators
/// (the schedule's parse, input/forcing.rs).
fn forces_of(merged: &Table) -> Result<(Forcing, Vec<ActuatorWindow>), Error> {
    let Some(Value::Array(list)) = merged.get("force") else {
        return Ok((Forcing::none(), Vec::new()));
    };
    crate::input::forcing::parse(list, || {
        section(merged, "solver").name(
            "model",
            crate::input::solver::MODELS,
            SolverSettings::new(1.0).model,
        )
    })
}
