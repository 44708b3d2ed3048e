//! Exact (set-valued) Coulomb friction in the rigid-body model: closed forms
//! for sliding → rolling (also from θ = 0 exactly, which the reduced model
//! cannot start from), agreement with the reduced model's stick/slip motion,
//! energy conservation while rolling, the stick limit under an applied
//! force, cost, and chattering detection for the sliding-only law.

mod common;
use tippetop::model::rigid::{Mode, VEL};
use tippetop::{
    ForceWindow, Forcing, FrictionLaw, ModelKind, Sample, Scenario, Trajectory, simulate,
};

fn run(sc: &Scenario) -> Trajectory {
    let tr = simulate(sc).expect("valid scenario");
    assert!(tr.error.is_none(), "run failed: {:?}", tr.error);
    tr
}

fn rigid(mut sc: Scenario) -> Scenario {
    sc.solver.model = ModelKind::Rigid;
    sc
}

fn times(tr: &Trajectory, kind: &str) -> Vec<f64> {
    tr.events
        .iter()
        .filter(|e| e.kind == kind)
        .map(|e| e.t)
        .collect()
}

/// A uniform sphere (a = 0, A = C = 2/5 m R²), rigid model, exact law.
fn sphere(theta: f64, spin: f64, mu: f64) -> Scenario {
    rigid(common::uniform_sphere(theta, spin, mu))
}

/// Sliding sphere (θ0 = 0.5, ω0 = 50 about the tilted axis, μ = 0.2):
/// |v_P| falls linearly at (7/2) μ g, rolling starts at
/// t_r = 2 |v_P(0)| / (7 μ g) with centre-of-mass speed (2/7)|v_P(0)|.
#[test]
fn rigid_sliding_sphere_sticks_at_the_coulomb_time() {
    let (theta, spin, mu, g) = (0.5f64, 50.0, 0.2, 9.8);
    let sc = sphere(theta, spin, mu);
    let tr = run(&sc);
    let v0 = theta.sin() * sc.top.radius * spin;
    let t_roll = 2.0 * v0 / (7.0 * mu * g);
    let sticks = times(&tr, "stick");
    assert_eq!(sticks.len(), 1, "events: {:?}", tr.events);
    let ts = sticks[0];
    println!(
        "rigid sphere: stick at {ts}, closed form {t_roll}, rel {:.1e}, {} rhs",
        (ts - t_roll).abs() / t_roll,
        tr.summary.rhs_evaluations
    );
    // 1e-8 is the requirement; measured 1e-14. Without the smooth
    // continuation of μ v/|v| through zero slip the event is found only to
    // ≈ 3e-11, which the 1e-12 bound catches.
    assert!(
        (ts - t_roll).abs() <= 1e-12 * t_roll,
        "stick at {ts}, Coulomb predicts {t_roll}"
    );
    assert!(times(&tr, "slip").is_empty(), "events: {:?}", tr.events);
    let mut worst_roll = 0.0f64;
    for s in &tr.samples {
        if s.t < ts {
            let expect = v0 - 3.5 * mu * g * s.t;
            assert!(
                (s.slip - expect).abs() <= 1e-8 * v0,
                "t {}: slip {} vs {}",
                s.t,
                s.slip,
                expect
            );
            assert_eq!(s.rolling, 0);
        } else if s.t > ts {
            assert_eq!(s.rolling, 1);
            assert_eq!(s.slip, 0.0);
            let speed = s.ux.hypot(s.uy);
            worst_roll = worst_roll.max((speed - 2.0 / 7.0 * v0).abs() / v0);
        }
    }
    println!("rolling speed: max deviation from 2/7 |v0| = {worst_roll:.1e} |v0|");
    assert!(
        worst_roll <= 1e-8,
        "rolling speed off by {worst_roll:e} |v0|"
    );
    assert!((tr.summary.rolling_fraction - (0.4 - ts) / 0.4).abs() < 1e-9);
    // Rolling is straight at constant velocity (world frame): a free
    // rolling sphere needs no friction. (The speed alone would not catch a
    // spurious friction perpendicular to the velocity.)
    let vel = rolling_world_velocities(&sc);
    let v_stick = vel[0];
    let worst = vel
        .iter()
        .map(|v| (v[0] - v_stick[0]).hypot(v[1] - v_stick[1]) / v0)
        .fold(0.0, f64::max);
    println!("rolling: world velocity constant to {worst:.1e} |v0|");
    assert!(worst <= 1e-8, "rolling velocity changed by {worst:e} |v0|");
    assert!(
        tr.summary.rhs_evaluations < 10_000,
        "{} evaluations",
        tr.summary.rhs_evaluations
    );
}

/// A sphere started exactly at θ = 0 (axis vertical, where the reduced
/// model's Euler angles are singular), spinning about the vertical with
/// ω0 and about the horizontal y axis with θ̇0, its centre moving with
/// (u_x, u_y).
///
/// Derivation: at θ = 0, n = (0, θ̇0, ω0), r = −R Z, so the slip is
/// v_P = u + n × r = (u_x − R θ̇0, u_y, 0): the vertical spin does not slip.
/// For a = 0 the contact matrix on horizontal forces is
/// K F = F/m − r × (r × F)/I = (1/m + R²/I) F = 7/(2m) F and ṙ = 0, so
/// under sliding friction F = −μ m g v̂ the slip obeys v̇_P = −(7/2) μ g v̂:
/// it keeps its direction and falls linearly, rolling starts at
/// t_r = 2|v_P(0)|/(7 μ g). Meanwhile v̇ = −μ g v̂, so the centre's velocity
/// when rolling starts is u0 − (2/7) v_P(0), constant afterwards (a free
/// rolling sphere needs no friction). The friction torque r × F is
/// horizontal and the inertia isotropic, so n_Z = ω0 throughout.
#[test]
fn rigid_sphere_from_theta_zero_sticks_at_the_coulomb_time() {
    let (mu, g) = (0.2, 9.8);
    let mut sc = sphere(0.0, 50.0, mu);
    let r = sc.top.radius;
    let (thd0, ux0, uy0) = (10.0, 0.5, 0.3);
    sc.initial.theta_dot = thd0;
    sc.initial.ux = ux0;
    sc.initial.uy = uy0;
    let tr = run(&sc);
    let v0 = [ux0 - r * thd0, uy0];
    let v0n = v0[0].hypot(v0[1]);
    let t_roll = 2.0 * v0n / (7.0 * mu * g);
    let sticks = times(&tr, "stick");
    assert_eq!(sticks.len(), 1, "events: {:?}", tr.events);
    let ts = sticks[0];
    println!(
        "sphere from theta = 0: stick at {ts}, closed form {t_roll}, rel {:.1e}",
        (ts - t_roll).abs() / t_roll
    );
    assert!((ts - t_roll).abs() <= 1e-12 * t_roll);
    // Centre velocity once rolling, in world axes: the outputs u_x, u_y are
    // in the precessing frame (x̂ along the tilt), so compare the speed.
    let u_roll = [ux0 - 2.0 / 7.0 * v0[0], uy0 - 2.0 / 7.0 * v0[1]];
    let speed_roll = u_roll[0].hypot(u_roll[1]);
    let (mut worst_slip, mut worst_speed, mut worst_nz) = (0.0f64, 0.0f64, 0.0f64);
    for s in &tr.samples {
        // n_Z = Ω sin²θ + ω cos θ (Ω is reported 0 at θ = 0 exactly).
        let nz = s.precession * s.theta.sin().powi(2) + s.spin * s.theta.cos();
        worst_nz = worst_nz.max((nz - 50.0).abs() / 50.0);
        if s.t < ts {
            assert_eq!(s.rolling, 0);
            worst_slip = worst_slip.max((s.slip - (v0n - 3.5 * mu * g * s.t)).abs() / v0n);
        } else if s.t > ts {
            assert_eq!(s.rolling, 1);
            assert_eq!(s.slip, 0.0);
            worst_speed = worst_speed.max((s.ux.hypot(s.uy) - speed_roll).abs() / speed_roll);
        }
    }
    println!(
        "  slip {worst_slip:.1e} |v0|, rolling speed {worst_speed:.1e}, n_Z {worst_nz:.1e} (relative)"
    );
    assert!(worst_slip <= 1e-8, "slip off the line by {worst_slip:e}");
    assert!(worst_speed <= 1e-8, "rolling speed off by {worst_speed:e}");
    assert!(worst_nz <= 1e-8, "n_Z changed by {worst_nz:e}");
    // It did leave θ = 0 (the horizontal rotation tips the body axis).
    assert!(tr.samples.last().unwrap().theta > 0.1);
    // At θ = 0 the precessing x is world X: the rolling velocity (world) is
    // the vector u0 − (2/7) v_P(0), at every accepted step after the stick.
    let vel = rolling_world_velocities(&sc);
    assert!(vel.len() > 10);
    let worst = vel
        .iter()
        .map(|v| (v[0] - u_roll[0]).hypot(v[1] - u_roll[1]) / speed_roll)
        .fold(0.0, f64::max);
    println!("  rolling world velocity vs u0 - 2/7 v0: {worst:.1e} (relative)");
    assert!(worst <= 1e-8, "rolling velocity off by {worst:e}");
}

/// Centre-of-mass velocity (world, SI) at every accepted step while rolling
/// (the rolling constraint value −n × r, the state's own v differs only by
/// the integration error).
fn rolling_world_velocities(sc: &Scenario) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, _, y| {
        if m.mode == Mode::Rolling {
            let vu = m.scales.velocity();
            out.push([y[VEL] * vu, y[VEL + 1] * vu]);
        }
    });
    assert!(tr.error.is_none());
    out
}

/// Largest deviation of each quantity over the samples, relative to its
/// largest |value| over the window: [θ, Ω (where sin θ > 0.05), ω, u_x, u_y].
fn deviations(a: &[Sample], b: &[Sample]) -> [f64; 5] {
    assert_eq!(a.len(), b.len());
    let get: [fn(&Sample) -> f64; 5] = [
        |s| s.theta,
        |s| s.precession,
        |s| s.spin,
        |s| s.ux,
        |s| s.uy,
    ];
    let mut out = [0.0; 5];
    for (q, f) in get.iter().enumerate() {
        let ok = |s: &Sample| q != 1 || s.theta.sin() > 0.05;
        let scale = a
            .iter()
            .filter(|s| ok(s))
            .map(|s| f(s).abs())
            .fold(0.0, f64::max);
        let dev = a
            .iter()
            .zip(b)
            .filter(|(s, _)| ok(s))
            .map(|(x, y)| {
                assert_eq!(x.t, y.t);
                (f(x) - f(y)).abs()
            })
            .fold(0.0, f64::max);
        out[q] = dev / scale;
    }
    out
}

/// The classical preset under the exact law (sticks at ≈ 0.047 s, then
/// rolls) over 0..1 s: the rigid model's rolling equations (3×3 contact
/// solve in 3D) against the reduced model's (Euler angles, §6), rtol 1e-12.
#[test]
fn rigid_rolling_matches_reduced_classical() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Coulomb;
    sc.solver.t_end = 1.0;
    sc.solver.rtol = 1e-12;
    let red = run(&sc);
    let rig = run(&rigid(sc));
    let (sr, sg) = (times(&red, "stick"), times(&rig, "stick"));
    println!("stick times: reduced {sr:?}, rigid {sg:?}");
    assert!(!sr.is_empty());
    assert_eq!(sr.len(), sg.len());
    assert_eq!(times(&red, "slip").len(), times(&rig, "slip").len());
    // Required 1e-9; measured 1e-12 (7e-12 without the continuation of
    // the friction through zero slip in the rigid model).
    for (a, b) in sr.iter().zip(&sg) {
        assert!((a - b).abs() <= 3e-12 * a, "stick {a} vs {b}");
    }
    let d = deviations(&red.samples, &rig.samples);
    println!(
        "classical exact 1 s: max rel deviation theta {:.2e} Omega {:.2e} omega {:.2e} ux {:.2e} uy {:.2e}",
        d[0], d[1], d[2], d[3], d[4]
    );
    for (q, v) in ["theta", "Omega", "omega", "ux", "uy"].iter().zip(d) {
        assert!(v <= 1e-6, "{q} deviates by {v:e} of its max");
    }
    for (x, y) in red.samples.iter().zip(&rig.samples) {
        assert_eq!(x.rolling, y.rolling, "t {}", x.t);
    }
    assert!((red.summary.rolling_fraction - rig.summary.rolling_fraction).abs() <= 1e-9);
}

/// Rolling does no work: after the stick the energy is constant to 1e-10
/// and the friction work frozen (classical preset, rigid model).
#[test]
fn rigid_rolling_dissipates_no_energy() {
    let mut sc = rigid(Scenario::classical());
    sc.solver.t_end = 1.0;
    let tr = run(&sc);
    let stick = times(&tr, "stick")[0];
    let rolling: Vec<_> = tr
        .samples
        .iter()
        .filter(|s| s.t > stick && s.rolling == 1)
        .collect();
    assert!(rolling.len() > 900, "{} rolling samples", rolling.len());
    let e_ref = rolling[0].energy;
    let w_ref = rolling[0].work_friction;
    let mut worst = 0.0f64;
    for s in &rolling {
        worst = worst.max((s.energy - e_ref).abs() / e_ref);
        assert_eq!(s.work_friction, w_ref);
        assert_eq!(s.slip, 0.0);
    }
    println!("rolling: max |E - E(stick)|/E = {worst:.1e}");
    assert!(worst <= 1e-10, "energy drift while rolling {worst:e}");
    assert!(tr.summary.jellett_max_rel_drift <= 1e-9);
    assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
}

/// A rolling sphere needs no friction; an applied force H at P then needs
/// friction |H| (H drops out of the motion). Just above μ m g rolling breaks
/// at the switch; just below it does not.
#[test]
fn rigid_applied_force_step_breaks_rolling_only_above_mu_n() {
    for (factor, breaks) in [(1.01, true), (0.99, false)] {
        let mut sc = sphere(0.5, 50.0, 0.2);
        let (m, r) = (sc.top.mass, sc.top.radius);
        // Start rolling: u = rolling velocity (a = 0, θ̇ = 0, Ω = 0).
        sc.initial.uy = -(0.5f64).sin() * r * 50.0;
        let h = factor * 0.2 * m * 9.8;
        let t1 = 0.1;
        sc.forcing = Forcing {
            windows: vec![ForceWindow {
                hx: h * 0.6,
                hy: h * 0.8,
                hz: 0.0,
                start: t1,
                stop: f64::INFINITY,
            }],
        };
        let tr = run(&sc);
        assert_eq!(times(&tr, "stick").first().copied(), Some(0.0));
        let slip = times(&tr, "slip");
        if breaks {
            assert_eq!(slip, vec![t1], "events {:?}", tr.events);
            assert!(tr.samples.last().unwrap().slip > 0.0);
            // Before the switch it rolled with no friction: nothing changed.
            let s0 = &tr.samples[0];
            for s in tr.samples.iter().filter(|s| s.t < t1) {
                assert_eq!(s.rolling, 1);
                assert!((s.uy - s0.uy).abs() <= 1e-10 * s0.uy.abs());
            }
        } else {
            assert!(slip.is_empty(), "rolling broke: {:?}", tr.events);
            assert!(tr.samples.iter().all(|s| s.rolling == 1 && s.slip == 0.0));
            // H drops out of the motion: the sphere rolls on unchanged.
            let s0 = &tr.samples[0];
            let worst = tr
                .samples
                .iter()
                .map(|s| (s.uy - s0.uy).abs().max(s.ux.abs()) / s0.uy.abs())
                .fold(0.0, f64::max);
            assert!(worst <= 1e-10, "rolling velocity changed by {worst:e}");
        }
    }
}

/// The classical preset with model = "rigid" and the default (exact) law
/// runs the whole 10 s cheaply and ends where the reduced model ends.
#[test]
fn rigid_classical_exact_10s_fast_and_matches_reduced() {
    let sc = Scenario::classical();
    assert_eq!(sc.surface.law, FrictionLaw::Coulomb);
    let red = run(&sc);
    let rig = run(&rigid(sc));
    let (tr, tg) = (red.summary.theta_final, rig.summary.theta_final);
    println!(
        "classical 10 s exact: theta(10) reduced {tr} rigid {tg} (diff {:.1e}); rigid {} rhs, {} steps, rolling {:.3}; events {}",
        (tr - tg).abs(),
        rig.summary.rhs_evaluations,
        rig.summary.steps,
        rig.summary.rolling_fraction,
        rig.events.len()
    );
    assert_eq!(rig.summary.t_end, 10.0);
    assert!(
        rig.summary.rhs_evaluations < 2_000_000,
        "{} evaluations",
        rig.summary.rhs_evaluations
    );
    assert!((tr - tg).abs() <= 1e-6, "theta(10 s): {tr} vs {tg}");
    assert!(!rig.events.iter().any(|e| e.kind.starts_with("note")));
}

/// The sliding-only law chatters at zero slip in the rigid model too: the
/// run stops with the reduced model's chattering error after
/// CHATTER_REVERSALS slip reversals instead of grinding on.
#[test]
fn rigid_coulomb_sliding_chatter_detected() {
    let mut sc = rigid(Scenario::classical());
    sc.surface.law = FrictionLaw::CoulombSliding;
    let tr = simulate(&sc).expect("valid scenario");
    let err = tr.error.as_ref().expect("chattering must stop the run");
    let msg = err.to_string();
    println!(
        "chatter: {msg}\n  at t = {} after {} steps",
        tr.summary.t_end, tr.summary.steps
    );
    assert!(
        msg.contains("the sliding-only Coulomb law chatters"),
        "{msg}"
    );
    assert!(msg.contains("use friction_law = \"coulomb\""), "{msg}");
    assert!(tr.summary.steps < 100_000, "{} steps", tr.summary.steps);
    assert!(tr.summary.steps > 0);
    // The same message as the reduced model's.
    let mut red = sc.clone();
    red.solver.model = ModelKind::Reduced;
    let rt = simulate(&red).unwrap();
    let rmsg = rt.error.expect("reduced chatters too").to_string();
    let cut = |m: &str| m.split("; state").next().unwrap().to_string();
    let strip_time = |m: String| m.split_once(": ").map(|x| x.1.to_string()).unwrap_or(m);
    assert_eq!(strip_time(cut(&msg)), strip_time(cut(&rmsg)));
}

/// An eccentric top (classical, a = 0.1 R) rolling end over end about a
/// horizontal axis, started at θ = 0 with θ̇0 = 150 rad/s and the rolling
/// velocity u_x = (R − a) θ̇0: its centre of mass whirls around the
/// geometric centre and the normal force falls as a θ̇² approaches g near
/// the top of the whirl. The friction rolling needs does not vanish there,
/// so the stick margin μ|N| − |F_f| reaches zero before N does: the top
/// first slides off (same instant under bilateral and unilateral contact),
/// and under unilateral contact it then lifts off exactly where the
/// bilateral run's N crosses zero.
#[test]
fn rigid_rolling_slips_then_lifts_off_where_normal_crosses_zero() {
    let mut sc = rigid(Scenario::classical());
    let (r, a) = (sc.top.radius, sc.top.offset);
    sc.initial.theta = 0.0;
    sc.initial.spin = 0.0;
    sc.initial.theta_dot = 150.0;
    sc.initial.ux = (r - a) * 150.0;
    sc.solver.t_end = 0.05;
    sc.solver.rtol = 1e-12;
    let bil = run(&sc);
    assert_eq!(times(&bil, "stick")[0], 0.0, "{:?}", bil.events);
    let t_slip = times(&bil, "slip")[0];
    let t_cross = bil
        .summary
        .contact_lost_at
        .expect("N < 0 in the bilateral run");
    let mut uni = sc.clone();
    uni.surface.contact = tippetop::ContactMode::Unilateral;
    let tr = run(&uni);
    let lo = times(&tr, "lift_off");
    println!(
        "eccentric roller: slip at {t_slip}, bilateral N = 0 at {t_cross}; unilateral slip {:?}, lift-off {:?}, {} touchdowns, rolling fraction {:.3}",
        times(&tr, "slip").first(),
        lo.first(),
        times(&tr, "touchdown").len(),
        tr.summary.rolling_fraction
    );
    assert!(t_slip < t_cross);
    assert_eq!(times(&tr, "slip")[0], t_slip);
    assert!(!lo.is_empty(), "no lift-off: {:?}", tr.events);
    assert!(
        (lo[0] - t_cross).abs() <= 1e-9 * t_cross,
        "lift-off {} vs N = 0 at {t_cross}",
        lo[0]
    );
    for s in &tr.samples {
        if s.t < t_slip {
            assert_eq!(s.rolling, 1, "t {}", s.t);
        } else if s.t > t_slip && s.t <= lo[0] {
            assert_eq!(s.rolling, 0, "t {}", s.t);
        }
    }
    assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
}
