//! Unilateral contact in the rigid-body model: lift-off where the normal
//! force crosses zero, ballistic flight, touchdown with the impact law,
//! bounces that settle into contact.

use tippetop::model::rigid::{DIM, POS, Phase, VEL};
use tippetop::{
    ContactMode, ForceWindow, Forcing, FrictionLaw, ModelKind, Scenario, Trajectory, simulate,
};

fn times(tr: &Trajectory, kind: &str) -> Vec<f64> {
    tr.events
        .iter()
        .filter(|e| e.kind == kind)
        .map(|e| e.t)
        .collect()
}

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
    let e0 = tr.summary.energy_initial;
    let em = tr
        .samples
        .iter()
        .map(|s| s.energy.abs())
        .fold(0.0, f64::max);
    let worst = tr
        .samples
        .iter()
        .map(|s| (s.energy - e0 - s.work_friction - s.work_applied).abs() / em)
        .fold(0.0, f64::max);
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
    let red = simulate(&sc).unwrap();
    let t_red = red.summary.contact_lost_at.expect("reduced N crosses zero");
    sc.solver.model = ModelKind::Rigid;
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
    let red = simulate(&sc).unwrap();
    let t_red = red.summary.contact_lost_at.expect("reduced N crosses zero");
    sc.solver.model = ModelKind::Rigid;
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
        sc.solver.model = ModelKind::Rigid;
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
