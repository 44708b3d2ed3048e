//! The stem (docs/physics.md#stem): a second contact sphere of radius r2 on
//! the symmetry axis at d2 from the centre of mass. Its touchdown angle in
//! closed form, the energy balance across the switches of spheres (impact
//! losses booked into the friction work), the stem's own Jellett integral
//! `L·(r2 Z − d2 k)` while on the stem with the point law, the on-plane
//! models' stop at θ_td, the scenario's validation, and the toy.

use crate::spec::{Reduced, Rigid, Vector, balance_residual, times};
use tippetop::{ContactMode, Error, Failure, Scenario, Trajectory, simulate};

/// The fixture `stem_fixture.toml`: the classical body with an illustrative
/// stem (the tests' tolerances and `--set` cases are written for it).
const FIXTURE: &str = include_str!("stem_fixture.toml");

/// The fixture's scenario.
fn toy() -> Scenario {
    Scenario::load(None, Some(FIXTURE), &[]).expect("valid fixture")
}

/// `scenarios/toy_with_stem.toml`: Leine & Glocker's (2003) tippe top.
fn the_toy() -> Scenario {
    let text = std::fs::read_to_string(format!(
        "{}/../../scenarios/toy_with_stem.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("scenarios/toy_with_stem.toml");
    Scenario::load(None, Some(&text), &[]).expect("valid toy")
}

/// θ_td from the geometry alone: the main sphere's centre at height R and
/// the stem sphere's centre, (d2 − a) further along k, at height r2:
/// R + (d2 − a) cos θ = r2.
fn theta_td(sc: &Scenario) -> f64 {
    let st = sc.top.stem.expect("stem");
    ((st.radius - sc.top.radius) / (st.distance - sc.top.offset)).acos()
}

/// The stem touches down at θ_td (closed form). The rigid run of the toy
/// is cut at its first `stem_touchdown` time, where its last row's θ must be
/// θ_td: the event is located on the stem's gap (`rho − r2 + (a − d2) k_Z`
/// with the integrated, not renormalised, axis), so the error is the event
/// location's (roots to ~1e-15 in t, |dθ/dt| ~ 1 rad/s here) plus
/// `|k|`'s drift from 1 (≤ 1e-10 per restart at rtol 1e-10, the bound of
/// `quaternion_norm_held`'s kin): 1e-9 rad.
#[test]
fn stem_touchdown_fires_at_theta_td() {
    let sc = toy();
    let td = theta_td(&sc);
    let tr = simulate(&sc).expect("valid");
    let t_td = tr
        .summary
        .first_stem_contact_at()
        .expect("the stem touches");
    assert_eq!(times(&tr, "stem_touchdown")[0], t_td);
    let mut cut = sc.clone();
    cut.solver.t_end = t_td;
    cut.solver.samples = 3;
    let tc = simulate(&cut).expect("valid");
    let th = tc.samples.last().unwrap().theta;
    println!(
        "stem touchdown at t = {t_td} s: theta = {th}, theta_td = {td}, diff {:e}",
        th - td
    );
    assert!((th - td).abs() <= 1e-9, "theta {th} vs theta_td {td}");
    // θ_td of this toy from its numbers: acos(−12.5/14.5).
    assert!((td - (-12.5f64 / 14.5).acos()).abs() < 1e-15);
}

/// `E − E0 = W_f + W_a` at every row across the stem's touchdowns, the
/// rocking between the spheres and the two-contact phase: every impact's
/// energy loss (and each projection's) is booked into `W_f`. Bar 1e-9 of
/// max|E| (the rigid model's usual 1e-8, with rtol 1e-10 over 6 s); the
/// impacts do remove energy (`E` falls at the stem's touchdown by more
/// than the bar), so the bookkeeping is exercised.
#[test]
fn energy_balance_holds_across_stem_touchdowns() {
    let mut sc = toy();
    // At 100 rad/s the toy rocks between its spheres and sits on both.
    sc.initial.spin = 100.0;
    sc.solver.t_end = 8.0;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let switches = times(&tr, "stem_touchdown").len() + times(&tr, "touchdown").len();
    let worst = balance_residual(&tr);
    println!(
        "spin 100: {switches} touchdowns of either sphere, balance {worst:e}, summary {:e}, stem fraction {}",
        tr.summary.energy_balance_max_rel_error,
        tr.summary.stem_contact_fraction()
    );
    assert!(switches >= 3, "only {switches} touchdowns");
    assert!(worst <= 1e-9, "energy balance {worst:e}");
    assert!(tr.summary.energy_balance_max_rel_error <= 1e-9);
    let full = simulate(&toy()).expect("valid");
    let worst = balance_residual(&full);
    println!("toy: balance {worst:e}");
    assert!(worst <= 1e-9, "energy balance {worst:e}");
    // The first stem impact removes energy: E just after minus E just
    // before (rows 10 ms apart) less the friction work over them is the
    // impact loss plus O(10 ms) of sliding dissipation, both booked in W_f.
    let t_td = full.summary.first_stem_contact_at().unwrap();
    let wf_jump = row_after(&full, t_td).work_friction - row_before(&full, t_td).work_friction;
    assert!(wf_jump < 0.0);
}

fn row_before(tr: &Trajectory, t: f64) -> &tippetop::Sample {
    tr.samples.iter().rev().find(|s| s.t < t).unwrap()
}

fn row_after(tr: &Trajectory, t: f64) -> &tippetop::Sample {
    tr.samples.iter().find(|s| s.t > t).unwrap()
}

/// The stem's Jellett integral. For a sphere of radius ρ centred at `c k`
/// from the centre of mass, with the contact point `r = c k − ρ Z` and any
/// contact force `F` at it, `d/dt (L·r) = (r × F)·r + L·ṙ = L·(c k̇) = c
/// L·(n × k) = c (I n)·(n × k) = c A n·(n × k) = 0` (`I n = A n + (C − A)
/// ω k`): `J_s = −L·r = L·(r2 Z − d2 k)` is conserved on the stem for the
/// point law (r_c = 0), sliding or rolling. From the Euler-angle outputs,
/// `L·Z = A Ω sin²θ + C ω cos θ`, `L·k = C ω`, so
/// `J_s = r2 (A Ω sin²θ + C ω cos θ) − d2 C ω`; the model's own `J` column
/// (the active sphere's `−L·r`) must equal it on the stem.
/// Start: the toy near θ_td rising (θ0 = 2.55, θ̇0 = 2 rad/s), the point
/// law; it lands on the stem, rocks twice and stays, sliding then rolling.
/// Bound: the relative drift over the phase, 1e-8 (rtol 1e-10 over ~10³
/// steps, the bound of the main sphere's J in the rigid tests' classical
/// runs, 1e-8).
#[test]
fn stem_jellett_integral_conserved_with_point_law() {
    let mut sc = toy();
    sc.surface.law = match sc.surface.law {
        tippetop::FrictionLaw::Contensou { pressure, pade, .. } => {
            tippetop::FrictionLaw::Contensou {
                radius: 0.0,
                pressure,
                pade,
            }
        }
        other => panic!("the toy's law is {other:?}"),
    };
    sc.initial.theta = 2.55;
    sc.initial.theta_dot = 2.0;
    sc.solver.t_end = 1.0;
    sc.solver.samples = 1001;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let on = times(&tr, "stem_touchdown");
    let off = times(&tr, "stem_liftoff");
    let t0 = *on.last().unwrap();
    assert!(
        off.iter().all(|&t| t <= t0),
        "the stem lifts after its last touchdown"
    );
    assert!(t0 < 0.2, "on the stem from {t0} s only");
    assert!(!times(&tr, "stick").is_empty(), "never rolled on the stem");
    let top = sc.top;
    let st = top.stem.unwrap();
    let (a, c) = (top.inertia_transverse, top.inertia_axial);
    let js = |s: &tippetop::Sample| {
        let (sn, cs) = s.theta.sin_cos();
        st.radius * (a * s.precession * sn * sn + c * s.spin * cs) - st.distance * c * s.spin
    };
    let rows: Vec<_> = tr.samples.iter().filter(|s| s.t > t0).collect();
    let j0 = js(rows[0]);
    let mut drift: f64 = 0.0;
    let mut column: f64 = 0.0;
    for s in &rows {
        drift = drift.max((js(s) - j0).abs() / j0.abs());
        column = column.max((s.jellett - js(s)).abs() / j0.abs());
    }
    println!(
        "stem from {t0} s ({} rows): J_s0 = {j0:e}, drift {drift:e}, model column vs Euler-angle form {column:e}",
        rows.len()
    );
    assert!(rows.len() > 500);
    assert!(drift <= 1e-8, "J_s drift {drift:e}");
    // The same quantity two ways: rounding only (Ω from a division by sin²θ
    // near θ = π; 1e-9).
    assert!(column <= 1e-9, "J column vs J_s {column:e}");
}

/// The on-plane models cannot follow the stem: they stop where θ reaches
/// θ_td, failure `not_modelled`, with an event `stem_touchdown` and the
/// summary's `first_stem_contact_at` at that time. θ there (the final
/// state, `theta_final`) to 1e-9 (event location, as above); the stop time
/// agrees with the rigid model's touchdown to 1e-6 s (the same motion on
/// the main sphere up to there: §contensou's cross-check of the three models to
/// 1e-6 rad).
#[test]
fn on_plane_models_stop_at_theta_td() {
    let mut sc = toy();
    sc.surface.contact = ContactMode::Bilateral;
    let td = theta_td(&sc);
    let t_rigid = simulate(&toy())
        .expect("valid")
        .summary
        .first_stem_contact_at()
        .unwrap();
    for model in [Vector, Reduced] {
        sc.solver.model = model;
        let tr = simulate(&sc).expect("valid");
        let err = tr.error.as_ref().expect("stops");
        let msg = err.to_string();
        assert_eq!(err.failure(), Some(Failure::NotModelled), "{msg}");
        assert!(
            msg.contains("the stem touches the plane at theta = theta_td"),
            "{msg}"
        );
        assert!(msg.contains("use model = \"rigid\""), "{msg}");
        let th = tr.summary.theta_final;
        println!(
            "{model:?}: stop at t = {} s, theta {th}, theta_td {td}",
            tr.summary.t_end
        );
        assert!((tr.summary.t_end - t_rigid).abs() <= 1e-6);
        assert!((th - td).abs() <= 1e-9, "{model:?}: theta {th} vs {td}");
        assert_eq!(times(&tr, "stem_touchdown"), vec![tr.summary.t_end]);
        assert_eq!(tr.summary.first_stem_contact_at(), Some(tr.summary.t_end));
    }
}

/// The toy shows the whole story: it inverts (θ above π/2) before the stem
/// lands, spends time on the stem, and ends upright on it (θ within 0.05
/// of π, above θ_td, the stem's last event a touchdown), in the rigid model.
#[test]
fn toy_inverts_and_spins_on_its_stem() {
    let sc = toy();
    assert_eq!(sc.solver.model, Rigid);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let s = &tr.summary;
    let inv = s.first_time_theta_above_half_pi.expect("inverts");
    let stem = s.first_stem_contact_at().expect("stem lands");
    let frac = s.stem_contact_fraction();
    println!(
        "toy: above pi/2 at {inv} s, stem at {stem} s, stem fraction {frac}, theta_final {}, omega_final {}",
        s.theta_final, s.omega_final
    );
    assert!(inv < stem);
    assert!(frac > 0.2);
    assert!(s.theta_final > theta_td(&sc));
    assert!(std::f64::consts::PI - s.theta_final < 0.05);
    let last = tr
        .events
        .iter()
        .rev()
        .find(|e| e.kind.starts_with("stem_"))
        .unwrap();
    assert_eq!(last.kind, "stem_touchdown");
    // Spinning on the stem at the end: |ω| well above the precession.
    assert!(s.omega_final.abs() > 50.0);
}

/// `scenarios/toy_with_stem.toml` (Leine & Glocker's 2003 tippe top, every
/// number from the source) shows the whole story: it inverts on its sphere
/// (θ above π/2) before the stem lands, lands on the stem at θ_td, spins
/// on the stem alone (the main sphere lifted) for more than a second, close
/// to upright, while the drilling friction brakes its spin, and the energy
/// balance holds throughout (friction, drilling and impacts).
#[test]
fn the_sourced_toy_tells_the_whole_story() {
    let sc = the_toy();
    assert_eq!(sc.solver.model, Rigid);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let s = &tr.summary;
    let inv = s.first_time_theta_above_half_pi.expect("inverts");
    let landed = s.first_stem_contact_at().expect("stem lands");
    assert!(inv < landed, "inverts at {inv} s, stem at {landed} s");
    // On the stem alone from its first touchdown to the main sphere's next
    // touchdown.
    let back = tr
        .events
        .iter()
        .find(|e| e.kind == "touchdown" && e.t > landed)
        .map_or(s.t_end, |e| e.t);
    println!("toy: above pi/2 at {inv} s, on the stem {landed} .. {back} s");
    assert!(back - landed > 1.0, "on the stem {landed} .. {back} s");
    let on_stem: Vec<_> = tr
        .samples
        .iter()
        .filter(|r| r.t > landed + 0.2 && r.t < back)
        .collect();
    let td = theta_td(&sc);
    assert!(
        on_stem.iter().all(|r| r.theta > td),
        "below theta_td on the stem"
    );
    assert!(
        on_stem.iter().any(|r| r.theta > 3.0),
        "never close to upright"
    );
    // The spin about the axis decays on the stem (drilling and sliding
    // friction, no driving torque about the vertical): |omega| at the end
    // of the stay below its value at the start.
    let (first, last) = (on_stem[0], on_stem[on_stem.len() - 1]);
    assert!(
        last.spin.abs() < first.spin.abs(),
        "{} -> {}",
        first.spin,
        last.spin
    );
    assert!(
        balance_residual(&tr) < 1e-9,
        "energy balance {}",
        balance_residual(&tr)
    );
}

fn load_err(sets: &[&str]) -> Error {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scenario::load(None, Some(FIXTURE), &sets).expect_err("invalid")
}

/// Bad stem input: one error naming the key and the valid range.
#[test]
fn stem_validation_errors_name_the_key() {
    let cases: &[(&[&str], &str, &str)] = &[
        (
            &["top.stem_radius=0"],
            "top.stem_radius",
            "0 < stem_radius < radius",
        ),
        (
            &["top.stem_radius=0.015"],
            "top.stem_radius",
            "0 < stem_radius < radius",
        ),
        (
            &["top.stem_radius=-1e-3"],
            "top.stem_radius",
            "0 < stem_radius < radius",
        ),
        // d2 − a = 0.012 < R − r2 = 0.0125: inside the main sphere.
        (
            &["top.stem_distance=0.0135"],
            "top.stem_distance",
            "stem_distance > offset + radius - stem_radius",
        ),
        (
            &["surface.contact=\"bilateral\""],
            "surface.contact",
            "\"unilateral\" with a stem",
        ),
        (&["initial.theta=2.7"], "initial.theta", "theta < theta_td"),
        (&["solver.method=\"langevin\""], "top.stem_radius", ""),
        (
            &["force.0.hx=1e-3"],
            "top.stem_radius",
            "gravity and friction only",
        ),
    ];
    for (sets, key, range) in cases {
        let e = load_err(sets);
        let msg = e.to_string();
        assert!(
            matches!(&e, Error::Invalid { key: k, .. } if k == key),
            "{sets:?}: {msg}"
        );
        assert!(msg.contains(range), "{sets:?}: {msg}");
        assert!(!msg.contains('\n'));
    }
    // One key without the other.
    let base = "[top]\nradius = 0.015\noffset = 0.0015\nmass = 0.015\ninertia_transverse = 1.35e-6\ninertia_axial = 1.35e-6\n[surface]\nfriction = 0.1\n[initial]\ntheta = 0.1\nspin = 100.0\n[solver]\nt_end = 1.0\n";
    for (extra, key) in [
        ("stem_radius = 0.0025\n", "top.stem_distance"),
        ("stem_distance = 0.016\n", "top.stem_radius"),
    ] {
        let text = base.replace(
            "inertia_axial = 1.35e-6\n",
            &format!("inertia_axial = 1.35e-6\n{extra}"),
        );
        let e = Scenario::load(None, Some(&text), &[]).expect_err("one key alone");
        assert!(
            matches!(&e, Error::Invalid { key: k, .. } if k == key),
            "{e}"
        );
    }
    // Written back: scenario.toml round-trips the stem.
    let sc = toy();
    let again = Scenario::load(None, Some(&sc.to_toml_string()), &[]).expect("round trip");
    assert_eq!(again.top.stem, sc.top.stem);
}

/// The two-contact phase (§stem): while both spheres are on the plane, both
/// constraints hold, so `k_Z = cos θ_td` (to the integration's drift, 1e-9
/// at rtol 1e-10 over the phase's ~10³ steps) and both normal forces are
/// non-negative (the phase ends where one falls through zero). The toy at
/// 100 rad/s sits in it for seconds.
#[test]
fn two_contact_phase_holds_theta_td() {
    let mut sc = toy();
    sc.initial.spin = 100.0;
    sc.solver.t_end = 8.0;
    let c_td = theta_td(&sc).cos();
    let (mut steps, mut worst, mut n_min) = (0usize, 0.0f64, f64::INFINITY);
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    let tr = tippetop::simulate::simulate_rigid_observed(&sc, &mut |m, t, y| {
        if m.both {
            steps += 1;
            let k = &y[tippetop::model::rigid::AXIS..tippetop::model::rigid::AXIS + 3];
            let kz = k[2] / (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
            worst = worst.max((kz - c_td).abs());
            let (na, no) = m.two_normals(y).unwrap();
            n_min = n_min.min(na.min(no));
            if first.is_nan() {
                first = t;
            }
            last = t;
        }
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    println!(
        "two-contact: {steps} steps from {first} to {last} (scaled time), |k_Z - cos theta_td| <= {worst:e}, min N {n_min:e} (scaled)"
    );
    assert!(steps > 100, "only {steps} steps in the two-contact phase");
    assert!(worst <= 1e-9, "k_Z off cos theta_td by {worst:e}");
    assert!(n_min >= -1e-9, "a normal force {n_min:e} < 0");
}

/// Where the top would sit on both spheres but the two-contact phase is not
/// modelled (the exact Coulomb law's stick at two points; restitution > 0),
/// the run stops there: failure `not_modelled`, one line saying the two
/// contacts touch at once, at a time after the stem's first touchdown and
/// with θ at θ_td (1e-9, as above).
#[test]
fn two_contacts_at_once_stop_where_not_modelled() {
    let mut point = toy();
    point.surface.law = match point.surface.law {
        tippetop::FrictionLaw::Contensou { pressure, pade, .. } => {
            tippetop::FrictionLaw::Contensou {
                radius: 0.0,
                pressure,
                pade,
            }
        }
        other => panic!("{other:?}"),
    };
    point.initial.theta = 2.58;
    point.initial.theta_dot = 1.0;
    point.solver.t_end = 1.0;
    let mut bouncy = toy();
    bouncy.surface.restitution = 0.5;
    bouncy.initial.spin = 100.0;
    for (sc, why) in [
        (point, "with the exact Coulomb law"),
        (bouncy, "with restitution > 0"),
    ] {
        let tr = simulate(&sc).expect("valid");
        let err = tr.error.as_ref().expect("stops");
        let msg = err.to_string();
        println!("{why}: {msg:.120}");
        assert_eq!(err.failure(), Some(Failure::NotModelled), "{msg}");
        assert!(
            msg.contains("the main sphere and the stem touch the plane at once at t = "),
            "{msg}"
        );
        assert!(msg.contains(why), "{msg}");
        assert!(!msg.contains('\n'));
        assert!(tr.summary.t_end > tr.summary.first_stem_contact_at().unwrap());
        assert!((tr.summary.theta_final - theta_td(&sc)).abs() <= 1e-9);
    }
}
