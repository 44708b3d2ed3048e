//! Scenario files: presets, overrides, `--set`, round-trips and bad input.

use tippetop::{ContactMode, Error, ForceWindow, FrictionLaw, Method, ModelKind, Scenario};

/// A minimal complete file without a preset (classical-like numbers).
const MINIMAL: &str = r#"
[top]
radius = 0.015
offset = 0.0015
mass = 0.015
inertia_transverse = 1.35e-6
inertia_axial = 1.35e-6
[surface]
friction = 0.1
[initial]
theta = 0.1
spin = 100.0
[solver]
t_end = 10.0
"#;

fn sets(s: &[&str]) -> Vec<String> {
    s.iter().map(|x| x.to_string()).collect()
}

/// Load and expect an `Error::Invalid` naming `key`; the Display must be one
/// line of the form `key: what (range)`. Returns the Display.
fn expect_err(preset: Option<&str>, text: Option<&str>, set: &[&str], key: &str) -> String {
    let e = match Scenario::load(preset, text, &sets(set)) {
        Ok(sc) => panic!("expected an error on {key}, got {sc:?}"),
        Err(e) => e,
    };
    let shown = e.to_string();
    match &e {
        Error::Invalid { key: k, .. } => assert_eq!(k, key, "wrong key in: {shown}"),
        other => panic!("expected Error::Invalid, got {other:?}"),
    }
    assert!(!shown.contains('\n'), "multi-line error: {shown:?}");
    assert!(shown.starts_with(&format!("{key}: ")), "{shown}");
    assert!(shown.ends_with(')'), "{shown}");
    shown
}

/// `MINIMAL` with `line` appended to `[section]` (appended as a new section
/// header, which TOML allows only once: so we replace the header).
fn minimal_with(section: &str, line: &str) -> String {
    let header = format!("[{section}]\n");
    assert!(MINIMAL.contains(&header));
    MINIMAL.replacen(&header, &format!("{header}{line}\n"), 1)
}

/// `MINIMAL` with `key = ...` in `[section]` replaced by `key = value`.
fn minimal_replacing(section: &str, key: &str, value: &str) -> String {
    let mut out = String::new();
    let mut cur = String::new();
    let mut done = false;
    for l in MINIMAL.lines() {
        if l.starts_with('[') {
            cur = l.trim_matches(|c| c == '[' || c == ']').to_string();
        }
        if cur == section && l.split('=').next().map(str::trim) == Some(key) {
            out.push_str(&format!("{key} = {value}\n"));
            done = true;
        } else {
            out.push_str(l);
            out.push('\n');
        }
    }
    assert!(done, "{section}.{key} not in MINIMAL");
    out
}

fn classical_with(set: &[&str]) -> Result<Scenario, Error> {
    Scenario::load(Some("classical"), None, &sets(set))
}

// --- round trips -----------------------------------------------------------

#[test]
fn round_trip_nano() {
    let s = Scenario::nano();
    let text = s.to_toml_string();
    assert!(!text.contains("preset"), "{text}");
    assert_eq!(Scenario::from_toml_str(&text), Ok(s), "{text}");
}

#[test]
fn round_trip_classical() {
    let s = Scenario::classical();
    let text = s.to_toml_string();
    assert_eq!(Scenario::from_toml_str(&text), Ok(s), "{text}");
}

#[test]
fn round_trip_several_windows_and_other_enums() {
    let mut s = Scenario::nano();
    s.forcing.windows = vec![
        ForceWindow {
            hx: 1e-22,
            hy: -3.3e-23,
            hz: 0.0,
            start: 0.0,
            stop: 1e-5,
        },
        ForceWindow {
            hx: 0.0,
            hy: 2.0 / 3.0 * 1e-22,
            hz: 0.0,
            start: 1e-5,
            stop: f64::INFINITY,
        },
        ForceWindow {
            hx: 5e-23,
            hy: 0.0,
            hz: 0.0,
            start: 2e-5,
            stop: 7e-5,
        },
    ];
    s.surface.law = FrictionLaw::Viscous { eps: 1.0 / 3.0 };
    s.surface.contact = ContactMode::Unilateral;
    s.surface.restitution = 0.25;
    s.solver.method = Method::Rk4;
    s.solver.steps = 2000;
    s.solver.model = ModelKind::Rigid;
    s.initial.theta = 0.0;
    s.initial.ux = -1e-3;
    s.validate().unwrap();
    let text = s.to_toml_string();
    assert_eq!(text.matches("[[force]]").count(), 3, "{text}");
    assert_eq!(text.matches("stop =").count(), 2, "{text}");
    assert_eq!(Scenario::from_toml_str(&text), Ok(s), "{text}");
}

#[test]
fn round_trip_regularized() {
    let mut s = Scenario::classical();
    s.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
    s.surface.contact = ContactMode::Paper;
    let text = s.to_toml_string();
    assert!(text.contains("friction_eps = 0.001"), "{text}");
    assert_eq!(Scenario::from_toml_str(&text), Ok(s), "{text}");
}

#[test]
fn round_trip_stiff() {
    let mut s = Scenario::classical();
    s.surface.law = FrictionLaw::Regularized { eps: 1e-4 };
    s.solver.method = Method::Stiff;
    let text = s.to_toml_string();
    assert!(text.contains("method = \"stiff\""), "{text}");
    assert_eq!(Scenario::from_toml_str(&text), Ok(s), "{text}");
}

// --- presets, files, --set -----------------------------------------------

#[test]
fn presets_load_by_argument_and_by_file() {
    assert_eq!(
        Scenario::load(Some("nano"), None, &[]),
        Ok(Scenario::nano())
    );
    assert_eq!(
        Scenario::from_toml_str("preset = \"classical\""),
        Ok(Scenario::classical())
    );
    // The same name in both places is fine.
    assert_eq!(
        Scenario::load(Some("nano"), Some("preset = \"nano\""), &[]),
        Ok(Scenario::nano())
    );
}

#[test]
fn minimal_file_gets_the_defaults() {
    let s = Scenario::from_toml_str(MINIMAL).unwrap();
    assert_eq!(s.surface.gravity, 9.8);
    assert_eq!(s.surface.law, FrictionLaw::Coulomb);
    assert_eq!(s.surface.contact, ContactMode::Bilateral);
    assert_eq!(s.surface.restitution, 0.0);
    assert!(s.forcing.windows.is_empty());
    assert_eq!(s.initial.theta_dot, 0.0);
    assert_eq!(s.initial.precession, 0.0);
    assert_eq!((s.initial.ux, s.initial.uy), (0.0, 0.0));
    assert_eq!(s.solver.method, Method::Adaptive);
    assert_eq!(s.solver.rtol, 1e-10);
    assert_eq!(s.solver.steps, 1000); // samples - 1, so that method = "rk4" alone is valid
    assert_eq!(s.solver.samples, 1001);
    assert_eq!(s.solver.model, ModelKind::Vector);
}

#[test]
fn preset_plus_override_in_file() {
    let text = "preset = \"classical\"\n[top]\nradius = 0.02\n[solver]\nt_end = 5.0\n";
    let s = Scenario::from_toml_str(text).unwrap();
    let mut want = Scenario::classical();
    want.top.radius = 0.02; // literal: a, A and C are not rescaled
    want.solver.t_end = 5.0;
    assert_eq!(s, want);
}

#[test]
fn file_force_list_replaces_the_presets() {
    let text = "preset = \"nano\"\n[[force]]\nhx = 3e-22\nstop = 1e-5\n";
    let s = Scenario::from_toml_str(text).unwrap();
    assert_eq!(
        s.forcing.windows,
        vec![ForceWindow {
            hx: 3e-22,
            hy: 0.0,
            hz: 0.0,
            start: 0.0,
            stop: 1e-5
        }]
    );
    let s = Scenario::from_toml_str("preset = \"nano\"\nforce = []\n").unwrap();
    assert!(s.forcing.windows.is_empty());
}

#[test]
fn set_beats_file_beats_preset() {
    let text = "preset = \"classical\"\n[surface]\nfriction = 0.2\ngravity = 9.81\n";
    let s = Scenario::load(None, Some(text), &sets(&["surface.friction=0.3"])).unwrap();
    assert_eq!(s.surface.friction, 0.3); // --set
    assert_eq!(s.surface.gravity, 9.81); // file
    assert_eq!(s.top, Scenario::classical().top); // preset
    // Later --set wins over earlier.
    let s = classical_with(&["surface.friction=0.3", "surface.friction=0.4"]).unwrap();
    assert_eq!(s.surface.friction, 0.4);
}

#[test]
fn set_regularized_law_with_eps() {
    let s = classical_with(&[
        "surface.friction_law=regularized",
        "surface.friction_eps=1e-3",
    ])
    .unwrap();
    assert_eq!(s.surface.law, FrictionLaw::Regularized { eps: 1e-3 });
    // Quoted TOML strings work too, and whitespace around '=' is allowed.
    let s = classical_with(&[
        "surface.friction_law = \"viscous\"",
        "surface.friction_eps = 2e-3",
    ])
    .unwrap();
    assert_eq!(s.surface.law, FrictionLaw::Viscous { eps: 2e-3 });
}

#[test]
fn set_modifies_nano_force_window() {
    let s = Scenario::load(Some("nano"), None, &sets(&["force.0.hy=2e-22"])).unwrap();
    let mut want = Scenario::nano();
    want.forcing.windows[0].hy = 2e-22;
    assert_eq!(s, want);
}

#[test]
fn set_appends_force_window() {
    let s = Scenario::load(
        Some("nano"),
        None,
        &sets(&["force.1.start=1e-5", "force.1.hx=-1e-22"]),
    )
    .unwrap();
    assert_eq!(s.forcing.windows.len(), 2);
    assert_eq!(
        s.forcing.windows[1],
        ForceWindow {
            hx: -1e-22,
            hy: 0.0,
            hz: 0.0,
            start: 1e-5,
            stop: f64::INFINITY
        }
    );
    let s = classical_with(&["force.0.hy=1e-3"]).unwrap();
    assert_eq!(s.forcing.windows.len(), 1);
}

#[test]
fn set_force_index_beyond_the_end() {
    let e = expect_err(Some("nano"), None, &["force.2.hx=1"], "force.2.hx");
    assert!(e.contains("force window 2"), "{e}");
}

#[test]
fn set_preset_is_rejected() {
    let e = expect_err(None, Some(MINIMAL), &["preset=nano"], "preset");
    assert!(e.contains("--preset"), "{e}");
}

#[test]
fn set_without_equals_is_rejected() {
    expect_err(Some("nano"), None, &["surface.friction"], "--set");
}

#[test]
fn whole_numbers_for_floats() {
    let text = "preset = \"classical\"\n[solver]\nt_end = 10\n[surface]\ngravity = 10\n\
                [initial]\nspin = 150\n";
    let s = Scenario::from_toml_str(text).unwrap();
    assert_eq!(s.solver.t_end, 10.0);
    assert_eq!(s.surface.gravity, 10.0);
    assert_eq!(s.initial.spin, 150.0);
    let s = classical_with(&["solver.t_end=3", "top.radius=1"]).unwrap();
    assert_eq!((s.solver.t_end, s.top.radius), (3.0, 1.0));
    // ... and whole floats for integers.
    let s = classical_with(&["solver.samples=11.0"]).unwrap();
    assert_eq!(s.solver.samples, 11);
}

#[test]
fn fractional_integer_is_rejected() {
    let e = expect_err(
        Some("classical"),
        None,
        &["solver.samples=10.5"],
        "solver.samples",
    );
    assert!(e.contains("whole number"), "{e}");
    expect_err(
        Some("classical"),
        None,
        &["solver.steps=-4"],
        "solver.steps",
    );
}

#[test]
fn rigid_model_allows_theta_zero() {
    let s = classical_with(&["initial.theta=0", "solver.model=rigid"]).unwrap();
    assert_eq!(s.initial.theta, 0.0);
    assert_eq!(s.solver.model, ModelKind::Rigid);
}

#[test]
fn rk4_with_consistent_steps() {
    let s = classical_with(&["solver.method=rk4", "solver.steps=2000"]).unwrap();
    assert_eq!(s.solver.method, Method::Rk4);
}

#[test]
fn stiff_method_by_name() {
    let s = classical_with(&["solver.method=stiff"]).unwrap();
    assert_eq!(s.solver.method, Method::Stiff);
}

// --- bad input: keys, tables, types ----------------------------------------

#[test]
fn syntax_error_is_one_line() {
    let e = expect_err(None, Some("[top\nradius = "), &[], "scenario");
    assert!(e.contains("valid TOML"), "{e}");
    expect_err(
        None,
        Some("[top]\nradius = 1\nradius = 2\n"),
        &[],
        "scenario",
    );
}

#[test]
fn unknown_key() {
    let text = minimal_with("top", "radiuss = 0.015");
    let e = expect_err(None, Some(&text), &[], "top.radiuss");
    assert_eq!(
        e,
        "top.radiuss: unknown key (valid keys: radius, offset, mass, \
         inertia_transverse, inertia_axial, stem_radius, stem_distance)"
    );
    expect_err(Some("nano"), None, &["solver.tend=1"], "solver.tend");
    expect_err(
        Some("nano"),
        Some("[[force]]\nhx = 1e-22\nduration = 1\n"),
        &[],
        "force.0.duration",
    );
    expect_err(Some("nano"), None, &["force.0.end=1"], "force.0.end");
}

#[test]
fn unknown_table() {
    let text = format!("{MINIMAL}\n[plane]\nfriction = 0.1\n");
    let e = expect_err(None, Some(&text), &[], "plane");
    assert!(e.contains("unknown table"), "{e}");
    expect_err(
        Some("nano"),
        None,
        &["plane.friction=0.1"],
        "plane.friction",
    );
    // A stray top-level key is an unknown key at the top level.
    expect_err(None, Some(&format!("radius = 1\n{MINIMAL}")), &[], "radius");
}

#[test]
fn table_of_wrong_type() {
    expect_err(Some("nano"), Some("top = 5"), &[], "top");
    expect_err(Some("nano"), Some("[force]\nhx = 1.0\n"), &[], "force");
}

#[test]
fn missing_required_key() {
    let text = MINIMAL.replace("t_end = 10.0\n", "");
    let e = expect_err(None, Some(&text), &[], "solver.t_end");
    assert_eq!(e, "solver.t_end: missing (required without a preset)");
    let text = MINIMAL.replace("mass = 0.015\n", "");
    expect_err(None, Some(&text), &[], "top.mass");
    let text = MINIMAL.replace("spin = 100.0\n", "");
    expect_err(None, Some(&text), &[], "initial.spin");
    expect_err(None, None, &[], "top.radius");
}

#[test]
fn wrong_type() {
    let e = expect_err(
        Some("classical"),
        None,
        &["surface.friction=abc"],
        "surface.friction",
    );
    assert!(
        e.starts_with("surface.friction: expected a number, found string \"abc\" ("),
        "{e}"
    );
    let text = minimal_replacing("top", "radius", "\"big\"");
    expect_err(None, Some(&text), &[], "top.radius");
    expect_err(Some("nano"), None, &["solver.method=3"], "solver.method");
    expect_err(Some("nano"), None, &["force.0.stop=true"], "force.0.stop");
    expect_err(Some("nano"), Some("preset = 1"), &[], "preset");
}

#[test]
fn nan_is_rejected() {
    let text = minimal_replacing("surface", "friction", "nan");
    let e = expect_err(None, Some(&text), &[], "surface.friction");
    assert!(e.contains("NaN is not allowed"), "{e}");
    expect_err(Some("nano"), None, &["initial.spin=nan"], "initial.spin");
}

#[test]
fn inf_is_rejected() {
    let text = minimal_replacing("solver", "t_end", "inf");
    let e = expect_err(None, Some(&text), &[], "solver.t_end");
    assert!(
        e.contains("inf is not allowed (a finite time > 0 [s])"),
        "{e}"
    );
    expect_err(Some("nano"), None, &["force.0.stop=+inf"], "force.0.stop");
    expect_err(Some("nano"), None, &["top.mass=-inf"], "top.mass");
}

// --- bad input: physical ranges --------------------------------------------

#[test]
fn radius_not_positive() {
    expect_err(Some("classical"), None, &["top.radius=0"], "top.radius");
    expect_err(Some("classical"), None, &["top.radius=-0.01"], "top.radius");
}

#[test]
fn mass_not_positive() {
    expect_err(Some("classical"), None, &["top.mass=0"], "top.mass");
}

#[test]
fn offset_negative() {
    expect_err(Some("classical"), None, &["top.offset=-1e-4"], "top.offset");
}

#[test]
fn offset_not_below_radius() {
    expect_err(Some("classical"), None, &["top.offset=0.015"], "top.offset");
    expect_err(Some("classical"), None, &["top.offset=0.02"], "top.offset");
}

#[test]
fn inertia_transverse_not_positive() {
    expect_err(
        Some("classical"),
        None,
        &["top.inertia_transverse=0"],
        "top.inertia_transverse",
    );
}

#[test]
fn inertia_axial_not_positive() {
    expect_err(
        Some("classical"),
        None,
        &["top.inertia_axial=-1e-6"],
        "top.inertia_axial",
    );
}

#[test]
fn inertia_axial_above_twice_transverse() {
    let e = expect_err(
        Some("classical"),
        None,
        &["top.inertia_axial=2.8e-6"],
        "top.inertia_axial",
    );
    assert!(e.contains("exceeds 2A"), "{e}");
    // C = 2A exactly is allowed (a flat disc).
    classical_with(&["top.inertia_axial=2.7e-6", "top.inertia_transverse=1.35e-6"]).unwrap();
}

#[test]
fn friction_negative() {
    expect_err(
        Some("nano"),
        None,
        &["surface.friction=-0.1"],
        "surface.friction",
    );
}

#[test]
fn t_end_not_positive() {
    expect_err(Some("nano"), None, &["solver.t_end=0"], "solver.t_end");
    expect_err(Some("nano"), None, &["solver.t_end=-1"], "solver.t_end");
}

#[test]
fn too_few_samples() {
    expect_err(Some("nano"), None, &["solver.samples=1"], "solver.samples");
    expect_err(Some("nano"), None, &["solver.samples=0"], "solver.samples");
}

#[test]
fn force_window_stop_not_after_start() {
    let text = "preset = \"nano\"\n[[force]]\nhx = 1e-22\n\n[[force]]\nhx = 1e-22\n\
                start = 2e-5\nstop = 1e-5\n";
    let e = expect_err(None, Some(text), &[], "force.1.stop");
    assert!(e.contains("not after start"), "{e}");
    expect_err(Some("nano"), None, &["force.0.stop=0"], "force.0.stop");
}

#[test]
fn force_window_start_negative() {
    expect_err(
        Some("nano"),
        None,
        &["force.0.start=-1e-6"],
        "force.0.start",
    );
}

#[test]
fn theta_outside_reduced_range() {
    // The Euler-angle model refuses the pole; the default (vector) model
    // starts there.
    expect_err(
        Some("classical"),
        None,
        &["initial.theta=0", "solver.model=\"reduced\""],
        "initial.theta",
    );
    classical_with(&["initial.theta=0"]).unwrap();
    expect_err(
        Some("classical"),
        None,
        &["initial.theta=3.2"],
        "initial.theta",
    );
    expect_err(
        Some("classical"),
        None,
        &["initial.theta=-0.1"],
        "initial.theta",
    );
    // The rigid model takes theta = 0 and pi, but not beyond.
    classical_with(&["initial.theta=0", "solver.model=\"rigid\""]).unwrap();
    expect_err(
        Some("classical"),
        None,
        &["initial.theta=3.2", "solver.model=rigid"],
        "initial.theta",
    );
}

// --- bad input: names ---------------------------------------------------------

#[test]
fn unknown_preset() {
    let e = expect_err(Some("mega"), None, &[], "preset");
    assert!(
        e.contains("\"nano\", \"nano-physical\", \"nano-md\", \"nano-adhesive\" or \"classical\""),
        "{e}"
    );
    expect_err(None, Some("preset = \"mega\""), &[], "preset");
}

#[test]
fn preset_given_twice_differently() {
    let e = expect_err(Some("nano"), Some("preset = \"classical\""), &[], "preset");
    assert!(
        e.starts_with(
            "preset: given both on the command line (\"nano\") and in the file (\"classical\")"
        ),
        "{e}"
    );
}

#[test]
fn unknown_friction_law() {
    let e = expect_err(
        Some("nano"),
        None,
        &["surface.friction_law=stribeck"],
        "surface.friction_law",
    );
    assert!(e.contains("\"coulomb_sliding\""), "{e}");
}

#[test]
fn unknown_contact() {
    let e = expect_err(
        Some("nano"),
        None,
        &["surface.contact=glued"],
        "surface.contact",
    );
    assert!(e.contains("\"unilateral\""), "{e}");
}

#[test]
fn unknown_method() {
    let e = expect_err(
        Some("nano"),
        None,
        &["solver.method=euler"],
        "solver.method",
    );
    assert!(e.contains("\"rk4\""), "{e}");
    assert!(e.contains("\"stiff\""), "{e}");
}

#[test]
fn unknown_model() {
    let e = expect_err(
        Some("nano"),
        None,
        &["solver.model=quantum"],
        "solver.model",
    );
    assert!(e.contains("\"rigid\""), "{e}");
}

#[test]
fn missing_friction_eps() {
    let e = expect_err(
        Some("nano"),
        None,
        &["surface.friction_law=regularized"],
        "surface.friction_eps",
    );
    assert_eq!(
        e,
        "surface.friction_eps: missing (required with friction_law = \"regularized\": \
         a speed > 0 [m/s])"
    );
    expect_err(
        Some("nano"),
        None,
        &["surface.friction_law=viscous"],
        "surface.friction_eps",
    );
}

#[test]
fn friction_eps_with_a_law_that_does_not_use_it() {
    expect_err(
        Some("nano"),
        None,
        &["surface.friction_eps=1e-3"],
        "surface.friction_eps",
    );
    let text = minimal_with(
        "surface",
        "friction_law = \"coulomb_sliding\"\nfriction_eps = 1e-3",
    );
    expect_err(None, Some(&text), &[], "surface.friction_eps");
}

#[test]
fn friction_eps_not_positive() {
    expect_err(
        Some("nano"),
        None,
        &["surface.friction_law=regularized", "surface.friction_eps=0"],
        "surface.friction_eps",
    );
}

#[test]
fn rk4_steps_not_a_multiple_of_samples_minus_one() {
    let e = expect_err(
        Some("classical"),
        None,
        &["solver.method=rk4", "solver.steps=1500"],
        "solver.steps",
    );
    assert!(e.contains("multiple of samples - 1 = 1000"), "{e}");
}

#[test]
fn coulomb_with_paper_contact() {
    expect_err(
        Some("classical"),
        None,
        &["surface.contact=paper"],
        "surface.friction_law",
    );
}

/// The `nano-adhesive` preset (docs/physics.md#adhesion): the nano preset with
/// graphene adhesion and superlubric friction, everything else unchanged.
/// Its adhesion is the continuum-LJ helper's C60-on-graphene binding, which
/// lies where the literature puts it (nano-physics.md §1.2: E_b 0.73–0.96
/// eV from theory, pull-off ~0.6 nN); μ = 1e-3 is the superlubric bound
/// (μ < 0.001, Sasaki et al. 2012). It validates, round-trips through TOML,
/// and is what `preset = "nano-adhesive"` loads.
#[test]
fn nano_adhesive_preset() {
    use tippetop::physics::adhesion::{Adhesion, EV};
    let p = Scenario::nano_adhesive();
    let nano = Scenario::nano();
    let b = Adhesion::c60_on_graphene().binding().unwrap();
    // The preset writes the helper's values out: equal to a few roundings
    // of the helper's root finding (1e-12 relative).
    assert!((p.adhesion().force - b.pull_off_force).abs() <= 1e-12 * b.pull_off_force);
    assert!((p.adhesion().energy - b.energy).abs() <= 1e-12 * b.energy);
    assert!(
        (0.7..=0.96).contains(&(p.adhesion().energy / EV)),
        "{:?}",
        p.adhesion()
    );
    assert!(
        (0.5e-9..=0.7e-9).contains(&p.adhesion().force),
        "{:?}",
        p.adhesion()
    );
    assert_eq!(p.surface.friction, 1e-3);
    assert_eq!(p.surface.law, nano.surface.law);
    assert_eq!(
        (p.top, p.forcing.clone(), p.initial),
        (nano.top, nano.forcing, nano.initial)
    );
    p.validate().unwrap();
    assert_eq!(Scenario::from_toml_str(&p.to_toml_string()).unwrap(), p);
    assert_eq!(
        Scenario::from_toml_str("preset = \"nano-adhesive\"").unwrap(),
        p
    );
}

/// The `nano-physical` preset (docs/physics.md#langevin): the `nano-adhesive`
/// top at 300 K as a Langevin run, with a 1.1 eV lying well (a 1 nm stem at
/// 0.11 eV/Å) and the NMR damping; valid (so within the step rule), round
/// trip, loaded by name.
#[test]
fn nano_physical_preset() {
    let p = Scenario::nano_physical();
    let a = Scenario::nano_adhesive();
    assert_eq!(p.solver.method, Method::Langevin);
    assert_eq!(p.surface.friction, 0.0);
    assert_eq!(
        (p.top, p.adhesion(), p.initial),
        (a.top, a.adhesion(), a.initial)
    );
    assert_eq!(p.thermal.temperature, 300.0);
    assert_eq!(p.wells().len(), 1);
    let depth_ev = p.wells()[0].depth / 1.602176634e-19;
    assert!((depth_ev - 1.1).abs() < 1e-12, "{depth_ev}");
    p.validate().unwrap();
    assert_eq!(Scenario::from_toml_str(&p.to_toml_string()).unwrap(), p);
    assert_eq!(
        Scenario::from_toml_str("preset = \"nano-physical\"").unwrap(),
        p
    );
}

/// The LAMMPS calibration's scenario fragment (md/README.md), as committed.
const MD_FRAGMENT: &str = include_str!("../../../md/results/nano-md-300K.toml");

/// The `nano-md` preset (md/README.md): `nano-physical`
/// with the damping rates of the committed calibration. `nano-physical`
/// loaded with the fragment over it is `nano-md`, key for key, so the
/// preset's two rates [1/s] are the fragment's digits; `nano-physical`
/// keeps the NMR value 2.2e12 1/s for comparison. Valid (within the step
/// rule), round trip, loaded by name.
#[test]
fn nano_md_preset_is_the_committed_calibration() {
    let p = Scenario::nano_md();
    let from_fragment = Scenario::load(Some("nano-physical"), Some(MD_FRAGMENT), &[]).unwrap();
    assert_eq!(from_fragment, p);
    let n = Scenario::nano_physical();
    assert_eq!(n.thermal.damping_rotational, 2.2e12);
    assert_eq!(n.thermal.damping_translational, 2.2e12);
    assert_ne!(p.thermal.damping_rotational, n.thermal.damping_rotational);
    let mut back = p.clone();
    back.thermal.damping_rotational = n.thermal.damping_rotational;
    back.thermal.damping_translational = n.thermal.damping_translational;
    assert_eq!(
        back, n,
        "nano-md differs from nano-physical only in the damping"
    );
    p.validate().unwrap();
    assert_eq!(Scenario::from_toml_str(&p.to_toml_string()).unwrap(), p);
    assert_eq!(Scenario::from_toml_str("preset = \"nano-md\"").unwrap(), p);
}

/// The `[thermal]` table and `solver.method = "langevin"` (issue #15): a
/// valid hot run, its round trip, and each bad input named by its key.
#[test]
fn thermal_keys_and_their_rules() {
    let hot = [
        "surface.friction=0",
        "solver.method=\"langevin\"",
        "solver.dt=1e-14",
        "solver.t_end=1e-11",
        "solver.samples=11",
        "thermal.temperature=300",
        "thermal.damping_translational=1e11",
        "thermal.damping_rotational=1e11",
        "thermal.seed=3",
    ];
    let sc = Scenario::load(Some("nano"), None, &sets(&hot)).expect("valid");
    assert_eq!(sc.solver.method, Method::Langevin);
    assert_eq!(sc.thermal.seed, Some(3));
    let back = Scenario::from_toml_str(&sc.to_toml_string()).unwrap();
    assert_eq!(back, sc);
    // Without [thermal] the text has no such table (old files unchanged).
    assert!(!Scenario::nano().to_toml_string().contains("thermal"));

    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v: Vec<&'static str> = hot.to_vec();
        v.extend_from_slice(extra);
        v
    };
    let cases: &[(&[&str], &str)] = &[
        (&["thermal.temperature=-1"], "thermal.temperature"),
        (
            &["thermal.damping_rotational=0"],
            "thermal.damping_rotational",
        ),
        (
            &["thermal.damping_translational=0"],
            "thermal.damping_translational",
        ),
        (&["surface.friction=0.1"], "surface.friction"),
        (&["solver.dt=1e-12"], "solver.dt"),
        (&["solver.model=\"reduced\""], "solver.model"),
        (&["solver.samples=2000"], "solver.samples"),
        (&["thermal.run=4294967296"], "thermal.run"),
        (&["thermal.bogus=1"], "thermal.bogus"),
        (&["solver.method=\"adaptive\""], "solver.dt"),
    ];
    for (extra, key) in cases {
        expect_err(Some("nano"), None, &with(extra), key);
    }
    // Missing seed at T > 0.
    let no_seed: Vec<&str> = hot
        .iter()
        .copied()
        .filter(|s| !s.starts_with("thermal.seed"))
        .collect();
    expect_err(Some("nano"), None, &no_seed, "thermal.seed");
    // Temperature without the Langevin method.
    expect_err(
        Some("nano"),
        None,
        &["thermal.temperature=300"],
        "thermal.temperature",
    );
    // Langevin without dt.
    expect_err(
        Some("nano"),
        None,
        &["surface.friction=0", "solver.method=\"langevin\""],
        "solver.dt",
    );
    // The rigid model's Langevin method in bilateral contact: valid.
    Scenario::load(
        Some("nano"),
        None,
        &sets(&with(&["solver.model=\"rigid\""])),
    )
    .expect("rigid Langevin on the plane");
    // The Brownian mode: the same keys, its own step rule and rules.
    let brown = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = with(&["solver.method=\"brownian\"", "solver.dt=1e-15"]);
        v.extend_from_slice(extra);
        v
    };
    Scenario::load(Some("nano"), None, &sets(&brown(&[]))).expect("valid brownian");
    Scenario::load(
        Some("nano"),
        None,
        &sets(&brown(&["solver.model=\"rigid\""])),
    )
    .expect("rigid brownian on the plane");
    // The contact damping (its coupled mobility, physics.md#brownian), for
    // both models on the plane.
    for model in ["solver.model=\"vector\"", "solver.model=\"rigid\""] {
        Scenario::load(
            Some("nano"),
            None,
            &sets(&brown(&["thermal.damping_contact=1e-13", model])),
        )
        .expect("brownian with contact damping");
    }
    for (extra, key) in [
        // The contact damping 1e13 times the bath's: its mobility would be
        // too ill-conditioned (the ratio's limit is 1e8).
        (
            &["thermal.damping_contact=1"][..],
            "thermal.damping_contact",
        ),
        (&["solver.dt=1e-13"][..], "solver.dt"),
        (
            &["thermal.damping_rotational=0"][..],
            "thermal.damping_rotational",
        ),
        (&["solver.model=\"reduced\""][..], "solver.model"),
    ] {
        expect_err(Some("nano"), None, &brown(extra), key);
    }
    // The rigid model above a wall (unilateral contact, docs/physics.md
    // §brownian-wall): valid, with the paper's contact too (on the plane); with
    // graphene's adhesion the wall's thermal length kT/F_a = 7 pm binds the
    // step: 8e-17 s (within the tilt's rule on the plane) is refused,
    // naming that rate.
    for contact in [
        &["surface.contact=\"unilateral\""][..],
        &[
            "surface.contact=\"paper\"",
            "surface.friction_law=\"viscous\"",
            "surface.friction_eps=1e-3",
        ],
    ] {
        let mut set = vec!["solver.model=\"rigid\""];
        set.extend_from_slice(contact);
        Scenario::load(Some("nano"), None, &sets(&brown(&set)))
            .expect("rigid brownian above the wall or on the plane");
    }
    let adhesive = [
        "solver.model=\"rigid\"",
        "surface.contact=\"unilateral\"",
        "adhesion.force=5.9159e-10",
        "adhesion.energy=1.1696e-19",
        "solver.dt=8e-17",
    ];
    let shown = expect_err(Some("nano"), None, &brown(&adhesive), "solver.dt");
    assert!(shown.contains("surface.contact"), "{shown}");
    let mut bilateral = adhesive.to_vec();
    bilateral[1] = "surface.contact=\"bilateral\"";
    Scenario::load(Some("nano"), None, &sets(&brown(&bilateral)))
        .expect("on the plane the wall's rule does not apply");
    // Above the wall the body touches the plane at instants only: a contact
    // damping would have nothing to act on and is refused, not ignored.
    let damped = [
        "solver.model=\"rigid\"",
        "surface.contact=\"unilateral\"",
        "thermal.damping_contact=1e-13",
    ];
    expect_err(
        Some("nano"),
        None,
        &brown(&damped),
        "thermal.damping_contact",
    );
    // T = 0 with damping: a valid deterministic run; no seed needed.
    Scenario::load(
        Some("nano"),
        None,
        &sets(&[
            "surface.friction=0",
            "solver.method=\"langevin\"",
            "solver.dt=1e-9",
            "solver.t_end=1e-6",
            "thermal.damping_rotational=1e6",
        ]),
    )
    .expect("T = 0 with damping is valid");
}

/// `[[force]]` windows of kind "tip" and "magnetic" (docs/physics.md#actuators)
/// parse into `Scenario::actuators` and round-trip through the TOML text.
#[test]
fn round_trip_tip_and_magnetic_windows() {
    let text = r#"preset = "classical"
[[force]]
hx = 0.1
[[force]]
kind = "tip"
point = [0.0, 0.001, 0.002]
force = [0.01, -0.02, 0.03]
start = 0.5
stop = 1.5
[[force]]
kind = "magnetic"
moment = 9.2740100783e-24
field = [0.1, 0.0, 1.0]
gradient = [[1.0, 2.0, 3.0], [4.0, 5, 6.0], [7.0, 8.0, 9.0]]
[solver]
model = "rigid"
"#;
    let sc = Scenario::load(None, Some(text), &[]).unwrap();
    assert_eq!(sc.forcing.windows.len(), 1);
    assert_eq!(sc.actuators.len(), 2);
    assert_eq!(
        sc.actuators[0].actuator,
        tippetop::BodyActuator::Tip {
            point: [0.0, 0.001, 0.002],
            force: [0.01, -0.02, 0.03]
        }
    );
    assert_eq!(sc.actuators[1].stop, f64::INFINITY);
    let back = Scenario::from_toml_str(&sc.to_toml_string()).unwrap();
    assert_eq!(back, sc);
    assert!(sc.switch_times().contains(&1.5));
}

/// Bad actuator input in `[[force]]`: one line naming the key.
#[test]
fn bad_tip_and_magnetic_windows() {
    let tip = "[[force]]\nkind = \"tip\"\n";
    let f = |body: &str| format!("{tip}{body}");
    expect_err(
        Some("classical"),
        Some(&f("force = [0.0, 0.0, 1.0]\n")),
        &[],
        "force.0.point",
    );
    expect_err(
        Some("classical"),
        Some(&f("point = [0.0, 0.0, 0.0]\n")),
        &[],
        "force.0.force",
    );
    expect_err(
        Some("classical"),
        Some(&f(
            "point = [0.0, 0.0, 0.0]\nforce = [0.0, 0.0, 1.0]\nhx = 1.0\n",
        )),
        &[],
        "force.0.hx",
    );
    expect_err(
        Some("classical"),
        Some(&f(
            "point = [0.0, 0.0, 0.0]\nforce = [0.0, 0.0, 1.0]\nstart = 1.0\nstop = 1.0\n",
        )),
        &[],
        "force.0.stop",
    );
    expect_err(
        Some("classical"),
        Some(&f("point = [0.0, 0.0, 0.0]\nforce = [0.0, nan, 1.0]\n")),
        &[],
        "force.0.force",
    );
    expect_err(
        Some("classical"),
        Some("[[force]]\nkind = \"magnetic\"\nmoment = 1.0\ngradient = [[1.0, 2.0, 3.0]]\n"),
        &[],
        "force.0.gradient",
    );
    expect_err(
        Some("classical"),
        Some("[[force]]\nkind = \"magnetic\"\n"),
        &[],
        "force.0.moment",
    );
    expect_err(
        Some("classical"),
        Some("[[force]]\nkind = \"laser\"\n"),
        &[],
        "force.0.kind",
    );
    expect_err(
        Some("classical"),
        None,
        &["force.0.kind=tip", "force.0.wand=1"],
        "force.0.wand",
    );
    // What a model cannot apply.
    let ok_tip = f("point = [0.0, 0.0, 0.001]\nforce = [0.0, 0.0, 1.0]\n");
    expect_err(
        Some("classical"),
        Some(&ok_tip),
        &["solver.model=reduced"],
        "force.0.kind",
    );
    let off = f("point = [0.001, 0.0, 0.0]\nforce = [0.0, 0.0, 1.0]\n");
    expect_err(Some("classical"), Some(&off), &[], "force.0.point");
    assert!(
        Scenario::load(
            Some("classical"),
            Some(&off),
            &sets(&["solver.model=rigid"])
        )
        .is_ok()
    );
}

/// Issue 26: the Langevin and Brownian step rules blame the largest term
/// of the vertical load that tilts the top, `m g + F_a + max |h_z|`. With
/// graphene-like adhesion (1e-9 N, 1e14 times the nano top's weight) the
/// message said "(from surface.gravity)"; it names `adhesion.force`, the
/// window's `hz` when that dominates, and the gravity when it does.
#[test]
fn dt_rules_name_the_load_that_binds_them() {
    let hot = [
        "surface.friction=0",
        "solver.method=\"langevin\"",
        "solver.t_end=1e-10",
        "solver.samples=11",
        "thermal.temperature=300",
        "thermal.damping_translational=1e11",
        "thermal.damping_rotational=1e11",
        "thermal.seed=1",
    ];
    for (method, dt) in [("langevin", "1e-13"), ("brownian", "1e-9")] {
        for (load, key) in [
            ("adhesion.force=1e-9", "adhesion.force"),
            ("force.0.hz=1e-9", "force.hz"),
            ("surface.gravity=1e14", "surface.gravity"),
        ] {
            let mut set = hot.to_vec();
            let m = format!("solver.method=\"{method}\"");
            let d = format!("solver.dt={dt}");
            set.extend([m.as_str(), d.as_str(), load]);
            if load.starts_with("adhesion") {
                set.push("adhesion.energy=1e-19");
            }
            let shown = expect_err(Some("nano"), None, &set, "solver.dt");
            assert!(
                shown.contains(&format!("(from {key})")),
                "{method}, {load}: {shown}"
            );
        }
    }
}

/// Sweep axes name their unit from the key's stated range.
#[test]
fn key_units_come_from_the_ranges() {
    use tippetop::input::scenario::key_unit;
    assert_eq!(key_unit("top.offset"), Some("m"));
    assert_eq!(key_unit("top.inertia_axial"), Some("kg m^2"));
    assert_eq!(key_unit("force.0.hx"), Some("N"));
    assert_eq!(key_unit("initial.theta"), Some("rad"));
    assert_eq!(key_unit("surface.friction"), None);
    assert_eq!(key_unit("nosuch.key"), None);
}

/// A value outside `b` (one its range refuses).
fn refused(b: tippetop::input::field::Bounds) -> f64 {
    use tippetop::input::field::Bounds;
    match b {
        Bounds::Finite => f64::INFINITY,
        Bounds::AtLeast(lo) => lo - 1.0,
        Bounds::Above(lo) => lo,
        Bounds::Within(_, hi) => 2.0 * hi + 1.0,
    }
}

/// Every number key of a scenario table (`NUMS`, issue 28 item 3): it is
/// listed by `tippetop keys` with its own definition, written by `to_toml`
/// (`name = ` under its table), read back from a `--set`, and a value its
/// bounds refuse is one error naming `table.key` with the range its
/// definition states. The bounds are the definition's own, so a key whose
/// check, parse or rendering were not driven from it fails here.
fn check_nums<S>(table: &str, nums: &[tippetop::input::field::Num<S>], preset: &str) {
    let spec = tippetop::input::scenario::key_tables()
        .into_iter()
        .find(|t| t.name == table)
        .unwrap();
    // `initial.heading` is written only when set.
    let text = Scenario::load(Some(preset), None, &sets(&["initial.heading=0.5"]))
        .unwrap()
        .to_toml_string();
    let body = text.split(&format!("[{table}]\n")).nth(1).unwrap();
    let body = body.split("\n[").next().unwrap();
    for k in nums {
        let name = k.key.name;
        assert!(spec.keys.contains(&k.key), "{table}.{name} not listed");
        assert!(
            body.lines().any(|l| l.starts_with(&format!("{name} = "))),
            "{table}.{name} not written:\n{body}"
        );
        let bad = refused(k.bounds);
        assert!(!k.bounds.admits(bad), "{table}.{name}: {bad}");
        let key = format!("{table}.{name}");
        let set = format!("{key}={bad:?}");
        match Scenario::load(Some(preset), None, std::slice::from_ref(&set)) {
            Err(Error::Invalid { key: k2, range, .. }) => {
                assert_eq!(k2, key, "{set}");
                // `top.offset` is checked by its rule with `radius`, whose
                // message states the radius's value.
                if key != "top.offset" {
                    let want = k.check_range.unwrap_or(k.key.range);
                    assert!(
                        range == want || range == k.key.range,
                        "{set}: range {range:?}, want {want:?}"
                    );
                }
            }
            other => panic!("{set}: {other:?}"),
        }
    }
}

#[test]
fn every_number_key_is_listed_written_read_and_checked_from_its_definition() {
    use tippetop::input::{initial, solver, surface, thermal, top};
    check_nums("top", &top::NUMS, "nano-physical");
    check_nums("surface", &surface::NUMS, "nano-physical");
    check_nums("initial", &initial::NUMS, "nano-physical");
    check_nums("solver", &[solver::T_END, solver::RTOL], "nano-physical");
    check_nums("thermal", &thermal::NUMS, "nano-physical");
    // A value read through --set lands in the field its definition names.
    let sc = Scenario::load(Some("nano"), None, &sets(&["surface.restitution=0.25"])).unwrap();
    assert_eq!((surface::RESTITUTION.get)(&sc.surface), 0.25);
    assert_eq!(sc.surface.restitution, 0.25);
    // Bounds: the ends of a closed range are admitted, an open end is not.
    use tippetop::input::field::Bounds;
    assert!(Bounds::Within(0.0, 1.0).admits(1.0) && !Bounds::Within(0.0, 1.0).admits(f64::NAN));
    assert!(Bounds::AtLeast(0.0).admits(0.0) && !Bounds::Above(0.0).admits(0.0));
    assert!(!Bounds::Finite.admits(f64::NEG_INFINITY));
}

/// Every preset in the registry builds a valid scenario under its own name,
/// names are unique, and `--preset`'s help lists each one.
#[test]
fn every_preset_validates_and_is_in_the_help() {
    use tippetop::input::scenario::{PRESETS, preset_help};
    let help = preset_help();
    for (i, p) in PRESETS.iter().enumerate() {
        let sc = Scenario::preset(p.name).unwrap();
        sc.validate().unwrap_or_else(|e| panic!("{}: {e}", p.name));
        assert!(help.contains(&format!("  {}: ", p.name)), "{help}");
        assert!(
            PRESETS[..i].iter().all(|q| q.name != p.name),
            "{} twice",
            p.name
        );
    }
}
