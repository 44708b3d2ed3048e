//! What only the rigid-body model has: a quaternion attitude (its norm, the
//! axis passing over the pole), the contact closure as a constraint on the
//! height of the geometric centre, the world-frame velocity while rolling,
//! and unilateral contact (lift-off where N crosses zero, ballistic flight,
//! touchdown with the impact law, bounces that settle). These read the
//! model's state at every accepted step through `simulate::simulate_rigid_observed`,
//! which the public `simulate` API does not expose.

use crate::spec::{
    Reduced, Rigid, balance_residual, classical_smooth, run, simulate_as, times, uniform_sphere,
};
use tippetop::model::rigid::{self, DIM, Mode, POS, Phase, QUAT, VEL};
use tippetop::{ContactMode, ForceWindow, Forcing, FrictionLaw, Scenario, Trajectory};

fn rigid(mut sc: Scenario) -> Scenario {
    sc.solver.model = Rigid;
    sc
}

/// | |q| − 1 | stays below 1e-9 at every accepted step of the classical 10 s
/// run (the stabilising term −κ(|q|²−1) q keeps it there). Regularised law.
#[test]
fn quaternion_norm_held() {
    let sc = rigid(classical_smooth(1e-2));
    let mut worst: f64 = 0.0;
    let mut steps = 0usize;
    let tr = tippetop::simulate::simulate_rigid_observed(&sc, &mut |_, _, y: &[f64; DIM]| {
        let q = &y[QUAT..QUAT + 4];
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        worst = worst.max((n - 1.0).abs());
        steps += 1;
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    println!("quaternion: max | |q| - 1 | = {worst:.2e} over {steps} steps");
    assert!(steps > 1000);
    assert!(worst <= 1e-9, "quaternion norm drift {worst:e}");
}

/// A frictionless top passing through θ = π (the scenario of
/// `closed_forms::passes_through_theta_pi`, tilted towards +X, rocking about
/// Y): the axis's horizontal projection comes out on the other side
/// (k_X < 0 with k_Z < 0).
#[test]
fn axis_passes_over_theta_pi() {
    let mut sc = rigid(Scenario::classical());
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = std::f64::consts::PI - 0.01;
    sc.initial.theta_dot = 20.0;
    sc.initial.precession = 0.0;
    sc.initial.spin = 0.0;
    sc.solver.t_end = 0.01;
    sc.solver.samples = 1001;
    let mut kx_min = f64::INFINITY;
    let mut kx_first = f64::NAN;
    let mut closest = f64::INFINITY;
    let tr = tippetop::simulate::simulate_rigid_observed(&sc, &mut |m, _, y| {
        let k = m.kin(y).k;
        if kx_first.is_nan() {
            kx_first = k[0];
        }
        if k[2] < 0.0 {
            kx_min = kx_min.min(k[0]);
        }
        closest = closest.min(k[0].hypot(k[1]));
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    println!(
        "through pi: first k_X {kx_first:.3e}, min k_X {kx_min:.3e}, closest sin(theta) at a step {closest:.2e}, theta_max {}, final {}",
        tr.summary.theta_max, tr.summary.theta_final
    );
    assert!(
        kx_first > 0.0 && kx_min < -0.005,
        "did not pass over the pole"
    );
}

/// The normal-force closure N D = Q (derived in 3D) really holds the
/// geometric centre at height R: along the model's own flow, the rate of
/// change of v_Cz (central difference of `gap_rate` along ±h ẏ) vanishes, at
/// states spread over a classical and a nano run (both signs of N in
/// bilateral mode). Independent of how D and Q were written. (The
/// model-independent form of this check, m u̇_z = N − m g from the samples,
/// is `invariants::normal_force_closure_matches_vertical_acceleration`.)
#[test]
fn normal_force_closure_holds_constraint() {
    let mut c = rigid(classical_smooth(1e-2));
    c.solver.t_end = 2.0;
    let mut n = rigid(Scenario::nano());
    n.surface.law = FrictionLaw::CoulombSliding;
    for sc in [c, n] {
        let mut states = Vec::new();
        tippetop::simulate::simulate_rigid_observed(&sc, &mut |_, _, y| states.push(*y));
        let m = rigid::Rigid::new(&sc);
        let (mut worst, mut nmax, mut neg) = (0.0f64, 0.0f64, false);
        for y in states.iter().step_by(37) {
            let e = m.eval(y).unwrap();
            nmax = nmax.max(e.normal.abs());
            neg |= e.normal < 0.0;
            let h = 1e-6;
            let mut yp = *y;
            let mut ym = *y;
            for i in 0..DIM {
                yp[i] += h * e.dy[i];
                ym[i] -= h * e.dy[i];
            }
            let acc = (m.gap_rate(&yp) - m.gap_rate(&ym)) / (2.0 * h);
            worst = worst.max(acc.abs());
        }
        println!(
            "closure: max |d v_Cz/dt| = {worst:.1e} (max |N| = {nmax:.2e}, N < 0 seen: {neg})"
        );
        assert!(worst <= 1e-6 * nmax, "constraint acceleration {worst:e}");
    }
}

/// Centre-of-mass velocity (world, SI) at every accepted step while rolling
/// (the rolling constraint value −n × r, the state's own v differs only by
/// the integration error).
fn rolling_world_velocities(sc: &Scenario) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, _, y| {
        if m.contact.mode == Mode::Rolling {
            let vu = m.scales.velocity();
            out.push([y[VEL] * vu, y[VEL + 1] * vu]);
        }
    });
    assert!(tr.error.is_none());
    out
}

/// Rolling is straight at constant velocity (world frame) once the sliding
/// sphere of `stick_slip::sliding_sphere_reaches_rolling_at_the_coulomb_time`
/// sticks: a free rolling sphere needs no friction. (The speed alone, which
/// that test checks for every model, would not catch a spurious friction
/// perpendicular to the velocity; the other models' outputs are in the
/// precessing frame.)
#[test]
fn rolling_sphere_world_velocity_is_constant() {
    let sc = rigid(uniform_sphere(0.5, 50.0, 0.2));
    let v0 = 0.5f64.sin() * sc.top.radius * 50.0;
    let vel = rolling_world_velocities(&sc);
    let v_stick = vel[0];
    let worst = vel
        .iter()
        .map(|v| (v[0] - v_stick[0]).hypot(v[1] - v_stick[1]) / v0)
        .fold(0.0, f64::max);
    println!("rolling: world velocity constant to {worst:.1e} |v0|");
    assert!(worst <= 1e-8, "rolling velocity changed by {worst:e} |v0|");
}

/// The sphere started at θ = 0 of
/// `stick_slip::sphere_from_theta_zero_sticks_at_the_coulomb_time`: at
/// θ = 0 the precessing x is world X, so the rolling velocity (world) is the
/// vector u0 − (2/7) v_P(0), at every accepted step after the stick.
#[test]
fn sphere_from_theta_zero_rolls_at_the_closed_form_velocity() {
    let sc = rigid(crate::stick_slip::sphere_from_theta_zero(0.2));
    let r = sc.top.radius;
    let (thd0, ux0, uy0) = (10.0, 0.5, 0.3);
    let v0 = [ux0 - r * thd0, uy0];
    let u_roll = [ux0 - 2.0 / 7.0 * v0[0], uy0 - 2.0 / 7.0 * v0[1]];
    let speed_roll = u_roll[0].hypot(u_roll[1]);
    let vel = rolling_world_velocities(&sc);
    assert!(vel.len() > 10);
    let worst = vel
        .iter()
        .map(|v| (v[0] - u_roll[0]).hypot(v[1] - u_roll[1]) / speed_roll)
        .fold(0.0, f64::max);
    println!("rolling world velocity vs u0 - 2/7 v0: {worst:.1e} (relative)");
    assert!(worst <= 1e-8, "rolling velocity off by {worst:e}");
}

/// An eccentric top (classical, a = 0.1 R) rolling end over end about a
/// horizontal axis, started at θ = 0 with θ̇0 = 150 rad/s and the rolling
/// velocity u_x = (R − a) θ̇0: its centre of mass whirls around the
/// geometric centre and the normal force falls as a θ̇² approaches g near
/// the top of the whirl. The friction rolling needs does not vanish there,
/// so the stick margin μ|N| − |F_f| reaches zero before N does: the top
/// first slides off (`slip`, same instant under bilateral and unilateral
/// contact), and under unilateral contact it then lifts off (`lift_off`)
/// exactly where the bilateral run's N crosses zero.
#[test]
fn rolling_slips_then_lifts_off_where_normal_crosses_zero() {
    let mut sc = rigid(Scenario::classical());
    let (r, a) = (sc.top.radius, sc.top.offset);
    sc.initial.theta = 0.0;
    sc.initial.spin = 0.0;
    sc.initial.theta_dot = 150.0;
    sc.initial.ux = (r - a) * 150.0;
    sc.solver.t_end = 0.05;
    sc.solver.rtol = 1e-12;
    let bil = run(&sc, Rigid);
    assert_eq!(times(&bil, "stick")[0], 0.0, "{:?}", bil.events);
    let t_slip = times(&bil, "slip")[0];
    let t_cross = bil
        .summary
        .contact_lost_at
        .expect("N < 0 in the bilateral run");
    assert_eq!(times(&bil, "contact_lost").first(), Some(&t_cross));
    let mut uni = sc.clone();
    uni.surface.contact = ContactMode::Unilateral;
    let tr = run(&uni, Rigid);
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

// ---- unilateral contact: lift-off, flight, touchdown ----

/// One observation of the rigid run (scaled units).
struct Obs {
    t: f64,
    phase: Phase,
    y: [f64; DIM],
    l: [f64; 3],
    gap: f64,
    g: f64,
}

fn observe(sc: &Scenario) -> (Trajectory, Vec<Obs>) {
    let mut obs = Vec::new();
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, t, y| {
        obs.push(Obs {
            t,
            phase: m.phase,
            y: *y,
            l: m.angular_momentum(y),
            gap: m.gap(y),
            g: m.gravity(),
        });
    });
    assert!(tr.error.is_none(), "rigid run failed: {:?}", tr.error);
    (tr, obs)
}

/// The sphere never sinks into the plane: the gap stays above −1e-9 R at
/// every step (a missed touchdown would let it fall through).
fn assert_no_penetration(obs: &[Obs]) {
    let worst = obs.iter().map(|o| o.gap).fold(f64::INFINITY, f64::min);
    assert!(worst >= -1e-9, "penetration: gap {worst:e} R");
}

fn assert_energy_balance(tr: &Trajectory, tol: f64) {
    let worst = balance_residual(tr);
    assert!(worst <= tol, "energy balance {worst:e}");
    assert!(tr.summary.energy_balance_max_rel_error <= tol);
}

/// The nano preset (paper's force, sliding Coulomb law) with contact
/// "unilateral" lifts off exactly when the reduced model's bilateral N first
/// crosses zero.
#[test]
fn nano_lifts_off_where_reduced_normal_crosses_zero() {
    let mut sc = Scenario::nano();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.rtol = 1e-12;
    let red = simulate_as(&sc, Reduced);
    let t_red = red.summary.contact_lost_at.expect("reduced N crosses zero");
    sc.solver.model = Rigid;
    sc.surface.contact = ContactMode::Unilateral;
    let (tr, obs) = observe(&sc);
    let lo = times(&tr, "lift_off");
    let rel = (lo[0] - t_red).abs() / t_red;
    println!(
        "nano: lift-off {:e} s, reduced N = 0 at {t_red:e} s, rel diff {rel:.2e}; {} lift-offs, {} touchdowns, flight fraction {:.3}",
        lo[0],
        lo.len(),
        times(&tr, "touchdown").len(),
        tr.summary.negative_normal_fraction
    );
    assert!(rel <= 1e-9, "lift-off time differs by {rel:e}");
    assert_eq!(tr.summary.contact_lost_at, Some(lo[0]));
    assert!(tr.samples.iter().any(|s| s.normal == 0.0), "never flew");
    assert_no_penetration(&obs);
    assert_energy_balance(&tr, 1e-8);
    assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
}

/// A top built to lift off with no applied force: gravity lowered to 1 m/s²,
/// tilted to 1.2 rad and nutating at 10 rad/s, so the centripetal term
/// m a cos θ θ̇² overcomes m g as θ passes π/2.
fn nutating_hopper() -> Scenario {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Regularized { eps: 1e-2 };
    sc.surface.gravity = 1.0;
    sc.initial.theta = 1.2;
    sc.initial.theta_dot = 10.0;
    sc.solver.t_end = 0.06;
    sc.solver.rtol = 1e-12;
    sc
}

/// Lift-off at the zero of the contact force (the reduced model's bilateral
/// N crossing), then a ballistic flight: z_O(t) on the parabola
/// z_lo + v_lo (t − t_lo) − g (t − t_lo)²/2, horizontal velocity and the
/// angular momentum about the centre of mass constant (H = 0); touchdown;
/// with e = 0 the top stays in contact afterwards (N > 0, gap 0).
#[test]
fn lift_off_ballistic_flight_touchdown_plastic() {
    let mut sc = nutating_hopper();
    let red = simulate_as(&sc, Reduced);
    let t_red = red.summary.contact_lost_at.expect("reduced N crosses zero");
    sc.solver.model = Rigid;
    sc.surface.contact = ContactMode::Unilateral;
    sc.surface.restitution = 0.0;
    let (tr, obs) = observe(&sc);
    let lo = times(&tr, "lift_off");
    let td = times(&tr, "touchdown");
    assert_eq!(lo.len(), 1, "lift-offs {lo:?}");
    assert_eq!(td.len(), 1, "touchdowns {td:?}");
    let rel = (lo[0] - t_red).abs() / t_red;
    assert!(
        rel <= 1e-9,
        "lift-off at {} vs N = 0 at {t_red}: {rel:e}",
        lo[0]
    );

    // The state at lift-off: the observation at the terminal event.
    let tu = tippetop::model::reduced::Scales::of(&sc).time;
    let i_lo = obs
        .iter()
        .position(|o| o.phase == Phase::Flight)
        .expect("a flight")
        - 1;
    let o_lo = &obs[i_lo];
    assert!((o_lo.t * tu - lo[0]).abs() <= 1e-15 * lo[0]);
    let (z0, vz0, g) = (o_lo.y[POS + 2], o_lo.y[VEL + 2], o_lo.g);
    let (vx0, vy0, l0) = (o_lo.y[VEL], o_lo.y[VEL + 1], o_lo.l);
    let lnorm = l0.iter().map(|v| v * v).sum::<f64>().sqrt();
    let (mut dz, mut dl, mut dv, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
    for o in obs.iter().filter(|o| o.phase == Phase::Flight) {
        let s = o.t - o_lo.t;
        let z = z0 + vz0 * s - 0.5 * g * s * s;
        dz = dz.max((o.y[POS + 2] - z).abs());
        dv = dv.max((o.y[VEL] - vx0).abs().max((o.y[VEL + 1] - vy0).abs()));
        dl = dl.max((0..3).map(|i| (o.l[i] - l0[i]).abs()).fold(0.0, f64::max) / lnorm);
        n += 1;
    }
    let zmax = obs.iter().map(|o| o.gap).fold(0.0, f64::max);
    println!(
        "hopper: lift-off {:e} s (reduced N = 0 at {t_red:e}, rel {rel:.1e}), touchdown {:e} s, max gap {zmax:.2e} R; over {n} flight steps: |z - parabola| {dz:.1e} R, |dv_h| {dv:.1e}, |dL|/|L| {dl:.1e}",
        lo[0], td[0]
    );
    assert!(n > 10 && zmax > 1e-3, "no real flight");
    assert!(dz <= 1e-9, "off the parabola by {dz:e} R");
    assert!(dv <= 1e-9, "horizontal velocity changed by {dv:e}");
    assert!(dl <= 1e-9, "angular momentum changed by {dl:e}");

    // After the plastic touchdown: in contact to the end, N > 0, gap 0.
    let after: Vec<&Obs> = obs.iter().filter(|o| o.t * tu > td[0]).collect();
    assert!(after.len() > 10);
    assert!(
        after
            .iter()
            .all(|o| o.phase == Phase::Contact && o.gap.abs() <= 1e-9)
    );
    let s_after: Vec<_> = tr.samples.iter().filter(|s| s.t > td[0]).collect();
    assert!(!s_after.is_empty() && s_after.iter().all(|s| s.normal > 0.0));
    assert_no_penetration(&obs);
    // Touchdown dissipates: the plastic impact removed energy, booked in W_f.
    assert_energy_balance(&tr, 1e-8);
    assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
}

/// Knocked off the plane by a strong applied force (H_x = −2 N for 3 ms on
/// the 15 g top: N < 0 from the start), then bouncing with restitution e:
/// the flight times shrink by the factor e per bounce, the bounces become
/// tiny and the top settles into contact (no stall, no lift-off afterwards).
#[test]
fn bounces_shrink_by_restitution_and_settle() {
    for e in [0.5, 0.8] {
        let mut sc = Scenario::classical();
        sc.surface.law = FrictionLaw::Regularized { eps: 1e-2 };
        sc.surface.contact = ContactMode::Unilateral;
        sc.surface.restitution = e;
        sc.initial.theta = 0.5;
        sc.forcing = Forcing {
            windows: vec![ForceWindow {
                hx: -2.0,
                hy: 0.0,
                hz: 0.0,
                start: 0.0,
                stop: 0.003,
            }],
        };
        sc.solver.t_end = 0.2;
        sc.solver.model = Rigid;
        let (tr, obs) = observe(&sc);
        let td = times(&tr, "touchdown");
        let lo = times(&tr, "lift_off");
        assert_eq!(lo, vec![0.0], "one lift-off at t = 0");
        assert!(td.len() >= 10, "e = {e}: only {} touchdowns", td.len());
        // Flight durations between touchdowns: ratio e (same gap
        // acceleration on the way up and down, rebound speed e × approach).
        let d: Vec<f64> = td.windows(2).map(|w| w[1] - w[0]).collect();
        let mut worst: f64 = 0.0;
        for w in d.windows(2).take(8) {
            worst = worst.max((w[1] / w[0] - e).abs());
        }
        let last_td = *td.last().unwrap();
        println!(
            "e = {e}: {} touchdowns, settled at {last_td:e} s, flight-time ratio off e by {worst:.1e}",
            td.len()
        );
        assert!(worst <= 0.03 * e, "flight-time ratios off e by {worst:e}");
        // Settled: in contact after the last touchdown, to the end.
        assert!(
            tr.events
                .iter()
                .all(|x| x.t <= last_td || x.kind != "lift_off")
        );
        assert!(
            obs.iter()
                .filter(|o| o.t * tippetop::model::reduced::Scales::of(&sc).time > last_td)
                .all(|o| o.phase == Phase::Contact)
        );
        assert!((tr.summary.t_end - 0.2).abs() < 1e-15);
        assert_no_penetration(&obs);
        assert_energy_balance(&tr, 1e-8);
        // Each touchdown removed energy.
        assert!(tr.samples.last().unwrap().work_friction < 0.0);
    }
}
