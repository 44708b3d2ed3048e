//! Adaptive multilevel splitting (`analysis::rare::ams`): the sampler
//! against exact answers, against direct simulation, and its contract
//! (determinism, budgets, errors, hooks). docs/physics.md#ams.
//!
//! The exact answers are those of the Brownian mode on the plane, where θ
//! is a one-dimensional reversible diffusion (docs/physics.md#retention): the
//! splitting probability from the scale density `1/(π D)` and the mean
//! exit time from Gardiner's double quadrature, both written here again,
//! independently of the library, and watched every step: each boundary
//! moved out by the Broadie–Glasserman–Kou shift `0.5826 sqrt(2 D dt)`.
//!
//! Fast tests run by default (seconds each in the test profile). The heavy
//! ones are `#[ignore]`d; run them with
//!
//! ```text
//! cargo test --release -p tippetop --test rare_ams -- --ignored --nocapture --test-threads 1
//! ```
//!
//! (each prints its figures; the benchmarks print their wall time).

use std::f64::consts::FRAC_PI_2;
use std::time::Instant;

use tippetop::analysis::ensemble::Exit;
use tippetop::analysis::rare::ams::{
    Ams, Coordinate, Estimate, Hooks, Problem, Quantity, Replica, Settings, Variant,
};
use tippetop::input::thermal::BOLTZMANN;
use tippetop::{Error, Forcing, Method, ModelKind, Scenario, Well};

const T: f64 = 300.0;
const GAMMA: f64 = 2.2e12;
/// Broadie–Glasserman–Kou: −ζ(1/2)/sqrt(2π).
const BGK: f64 = 0.5826;

fn kt() -> f64 {
    BOLTZMANN * T
}

/// The nano top made eccentric (`a = R/2`), no gravity, no force,
/// frictionless, one Gaussian well at π/2, Brownian at 300 K, `dt` the
/// fraction `f` of the step rule's limit.
fn well_top(depth_kt: f64, width: f64, f: f64) -> Scenario {
    let mut sc = Scenario::nano();
    sc.top.offset = 0.5 * sc.top.radius;
    sc.surface.friction = 0.0;
    sc.surface.gravity = 0.0;
    sc.forcing = Forcing { windows: vec![] };
    sc.set_wells(&[Well {
        theta: FRAC_PI_2,
        depth: depth_kt * kt(),
        width,
    }]);
    sc.initial.theta = FRAC_PI_2;
    sc.initial.spin = 0.0;
    sc.solver.method = Method::Brownian;
    let a = sc.top.inertia_transverse;
    let rate = (depth_kt * kt() / (width * width)).max(kt()) / (GAMMA * a);
    sc.solver.dt = Some(f * 0.002 / rate);
    sc.solver.t_end = 1e-9;
    sc.solver.samples = 2;
    sc.thermal.temperature = T;
    sc.thermal.damping_translational = GAMMA;
    sc.thermal.damping_rotational = GAMMA;
    sc.thermal.seed = Some(7);
    sc
}

/// θ's diffusion coefficient `D(θ) = kT/(γ_r A + γ_t m a² sin²θ)` and the
/// log of its stationary density `ln π = ln sin θ + ½ ln(1 + m a² sin²θ/A)
/// − U/kT` (docs/physics.md#langevin–§retention), for the Brownian top `sc`.
struct Diffusion {
    m: f64,
    a: f64,
    big_a: f64,
    wells: Vec<Well>,
}

impl Diffusion {
    fn of(sc: &Scenario) -> Diffusion {
        assert_eq!(sc.thermal.damping_translational, GAMMA);
        assert_eq!(sc.thermal.damping_rotational, GAMMA);
        Diffusion {
            m: sc.top.mass,
            a: sc.top.offset,
            big_a: sc.top.inertia_transverse,
            wells: sc.wells(),
        }
    }
    fn d(&self, th: f64) -> f64 {
        kt() / (GAMMA * self.big_a + GAMMA * self.m * self.a * self.a * th.sin().powi(2))
    }
    fn u_kt(&self, th: f64) -> f64 {
        self.wells
            .iter()
            .map(|w| -w.depth * (-(th - w.theta).powi(2) / (2.0 * w.width * w.width)).exp())
            .sum::<f64>()
            / kt()
    }
    fn ln_pi(&self, th: f64) -> f64 {
        let s2 = th.sin().powi(2);
        th.sin().ln() + 0.5 * (1.0 + self.m * self.a * self.a * s2 / self.big_a).ln()
            - self.u_kt(th)
    }
    /// The scale density's log, `−ln(π D)`.
    fn ln_scale(&self, th: f64) -> f64 {
        -self.ln_pi(th) - self.d(th).ln()
    }
    /// The discretely watched boundary's shift `β sqrt(2 D dt)`.
    fn bgk(&self, th: f64, dt: f64) -> f64 {
        BGK * (2.0 * self.d(th) * dt).sqrt()
    }
}

/// `ln ∫_lo^hi e^{g}` by Simpson's rule on `n` (even) intervals, the
/// largest value factored out.
fn ln_integral(g: &dyn Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> f64 {
    let h = (hi - lo) / n as f64;
    let v: Vec<f64> = (0..=n).map(|i| g(lo + h * i as f64)).collect();
    let top = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut s = 0.0;
    for (i, x) in v.iter().enumerate() {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        s += w * (x - top).exp();
    }
    top + (s * h / 3.0).ln()
}

/// The exact splitting probability `P(hit b before a | x0)` of the θ
/// diffusion, `∫_a^x0 s / ∫_a^b s` with the scale density `s = 1/(π D)`
/// (Gardiner §5.2.8), in log space.
fn splitting(df: &Diffusion, a: f64, x0: f64, b: f64) -> f64 {
    let g = |y: f64| df.ln_scale(y);
    (ln_integral(&g, a, x0, 20_000) - ln_integral(&g, a, b, 40_000)).exp()
}

/// The exact mean exit time from `(lo, hi)` started at `x0` (on the grid)
/// of the θ diffusion: `τ = c I1(x0) − I2(x0)`, `I1 = ∫_lo dy/(π D)`,
/// `I2 = ∫_lo dy (∫_lo^y π)/(π D)`, `c = I2(hi)/I1(hi)` (Gardiner §5.2.7),
/// by Simpson's rule, the densities scaled by their values at `x0`.
fn mean_exit_time(df: &Diffusion, lo: f64, hi: f64, x0: f64) -> f64 {
    let n = 40_000;
    let h = (hi - lo) / n as f64;
    let ys: Vec<f64> = (0..=n).map(|i| lo + h * i as f64).collect();
    let cumulative = |f: &dyn Fn(usize) -> f64| -> Vec<f64> {
        let mut c = vec![0.0; n + 1];
        for i in (0..n).step_by(2) {
            let (f0, f1, f2) = (f(i), f(i + 1), f(i + 2));
            c[i + 1] = c[i] + h / 12.0 * (5.0 * f0 + 8.0 * f1 - f2);
            c[i + 2] = c[i] + h / 3.0 * (f0 + 4.0 * f1 + f2);
        }
        c
    };
    let l0 = df.ln_pi(x0);
    let pv: Vec<f64> = ys.iter().map(|&y| (df.ln_pi(y) - l0).exp()).collect();
    let inner = cumulative(&|i| pv[i]);
    let i1 = cumulative(&|i| 1.0 / (pv[i] * df.d(ys[i])));
    let i2 = cumulative(&|i| inner[i] / (pv[i] * df.d(ys[i])));
    let c = i2[n] / i1[n];
    let k = ((x0 - lo) / h).round() as usize;
    assert!((ys[k] - x0).abs() < 1e-9, "x0 off the grid");
    c * i1[k] - i2[k]
}

/// `b` with `splitting(a, x0, b) = p` (bisection on `(x0, hi)`).
fn target_for(df: &Diffusion, a: f64, x0: f64, p: f64) -> f64 {
    let (mut lo, mut hi) = (x0 + 1e-3, 3.1);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if splitting(df, a, x0, mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

fn report(what: &str, e: &Estimate, want: f64, secs: f64) -> f64 {
    let z = (e.estimate - want) / e.standard_error;
    eprintln!(
        "{what}: {:.4e} ± {:.3e} (95 % {:.3e} .. {:.3e}), exact {want:.4e}: {z:+.2} SE, 3 SE = {:.1} %, {} paths, {} steps, {} truncated, {secs:.1} s",
        e.estimate,
        e.standard_error,
        e.ci95[0],
        e.ci95[1],
        300.0 * e.standard_error / e.estimate,
        e.trajectories,
        e.steps,
        e.truncated
    );
    z
}

fn settings(replicas: usize, particles: usize) -> Settings {
    Settings {
        replicas,
        particles,
        ..Settings::default()
    }
}

fn exit(spec: &str) -> Exit {
    Exit::parse(spec).unwrap()
}

/// Every replica, in order, and the estimate.
fn run_all(ams: &Ams, threads: usize) -> (Vec<Replica>, Estimate) {
    let mut reps = Vec::new();
    let m = ams.settings().replicas;
    assert!(
        ams.run(0..m, Some(threads), Hooks::default(), &mut |r| {
            reps.push(r);
            true
        })
        .unwrap()
    );
    let e = ams.combine(&reps).unwrap();
    (reps, e)
}

/// The splitting-probability problem of the Brownian well: the top starts
/// 0.15 rad up the wall of a 40 kT well (width 0.3 rad), the reset is
/// `delta` below the start, the target `θ > b` with `b` placed so that the
/// continuous process's probability is `p`. Returns the problem and the
/// exact probability of the discretely watched process.
fn brownian_splitting(p: f64, delta: f64, seed: u64) -> (Problem, f64) {
    let x0 = FRAC_PI_2 + 0.15;
    let a = x0 - delta;
    let mut sc = well_top(40.0, 0.3, 1.0);
    sc.initial.theta = x0;
    sc.thermal.seed = Some(seed);
    let df = Diffusion::of(&sc);
    let dt = sc.solver.dt.unwrap();
    let b = target_for(&df, a, x0, p);
    let want = splitting(&df, a - df.bgk(a, dt), x0, b + df.bgk(b, dt));
    let problem = Problem::new(
        sc,
        exit(&format!("theta>{b}")),
        Some(exit(&format!("theta<{a}"))),
    );
    (problem, want)
}

/// AMS against the exact splitting probability: within 3 of its own
/// standard errors, with 3 SE below 30 % of the estimate (a 95 % interval
/// within a factor 1.3).
fn check_probability(p: f64, replicas: usize, particles: usize, seed: u64) {
    let (problem, want) = brownian_splitting(p, 0.02, seed);
    let ams = Ams::new(problem, settings(replicas, particles)).unwrap();
    let t0 = Instant::now();
    let (_, e) = run_all(&ams, 2);
    let z = report(&format!("p ~ {p:e}"), &e, want, t0.elapsed().as_secs_f64());
    assert_eq!(e.quantity, Quantity::Probability);
    assert!(
        3.0 * e.standard_error < 0.3 * e.estimate,
        "3 SE is not below 30 %"
    );
    assert!(z.abs() < 3.0, "{z:+.2} SE from the exact {want:e}");
    assert!(e.ci95[0] < e.estimate && e.estimate < e.ci95[1]);
}

/// The mean exit time from the well `π/2 ± 2w` (w = 0.3 rad) over a
/// barrier of `barrier` kT (the rise at the window's edge), from its
/// bottom: AMS's flux relation against the exact time, within 3 of its
/// own standard errors, with 3 SE below 30 % when `tight`.
fn check_mean_exit_time(barrier: f64, replicas: usize, particles: usize, seed: u64, tight: bool) {
    let w = 0.3;
    let h = 2.0 * w;
    let d = barrier / (1.0 - (-2.0f64).exp());
    let mut sc = well_top(d, w, 1.0);
    sc.thermal.seed = Some(seed);
    let df = Diffusion::of(&sc);
    let dt = sc.solver.dt.unwrap();
    let (lo, hi) = (FRAC_PI_2 - h, FRAC_PI_2 + h);
    let half_w = h + df.bgk(hi, dt).max(df.bgk(lo, dt));
    let want = mean_exit_time(&df, FRAC_PI_2 - half_w, FRAC_PI_2 + half_w, FRAC_PI_2);
    let problem = Problem::new(sc, exit(&format!("theta<{lo},theta>{hi}")), None);
    assert_eq!(
        problem.coordinate,
        Coordinate::Distance {
            column: 1,
            centre: FRAC_PI_2
        }
    );
    let ams = Ams::new(problem, settings(replicas, particles)).unwrap();
    let t0 = Instant::now();
    let (_, e) = run_all(&ams, 2);
    let z = report(
        &format!("tau over {barrier} kT"),
        &e,
        want,
        t0.elapsed().as_secs_f64(),
    );
    let flux = e.flux.clone().unwrap();
    eprintln!(
        "  levels {:.4} .. {:.4} rad, p = {:.3e}, T1 = {:.3e} s, C = {:.3e} s, S = {:.3e} s",
        flux.basin,
        flux.interface,
        flux.probability,
        flux.first_crossing_time,
        flux.cycle_time,
        flux.transit_time.unwrap_or(f64::NAN)
    );
    assert_eq!(e.quantity, Quantity::MeanFirstPassageTime);
    assert_eq!(e.interval, "lognormal_delta");
    if tight {
        assert!(
            3.0 * e.standard_error < 0.3 * e.estimate,
            "3 SE is not below 30 %"
        );
    }
    assert!(z.abs() < 3.0, "{z:+.2} SE from the exact {want:e} s");
    assert!((flux.rate * e.estimate - 1.0).abs() < 1e-12);
}

#[test]
fn probability_1e_3_is_the_exact_splitting_probability() {
    check_probability(1e-3, 20, 100, 11);
}

/// 20 M steps; ~40 s in release on 2 cores.
#[test]
#[ignore]
fn probability_1e_6_is_the_exact_splitting_probability() {
    check_probability(1e-6, 30, 100, 12);
}

/// 95 M steps; ~3 min in release on 2 cores. 40 replicas of 100 rather
/// than 20 of 200 (the same cost): the replicas' law is skewed (at 1e-6
/// the median replica is 0.86 of the mean), and a mean of 20 of them
/// underestimates its own standard error too often (seed 13 with 20 of
/// 200: 8.26e-13 ± 3.9e-14, an SE half the expected 8 %, −3.4 SE).
#[test]
#[ignore]
fn probability_1e_12_is_the_exact_splitting_probability() {
    check_probability(1e-12, 40, 100, 14);
}

/// The flux relation on a small barrier (6 kT), small sizes: it agrees
/// within 3 SE (the tight bound is the ignored tests').
#[test]
fn mean_exit_time_over_6_kt_is_the_exact_one() {
    check_mean_exit_time(6.0, 10, 50, 21, false);
}

/// 30 M steps; ~1 min in release on 2 cores.
#[test]
#[ignore]
fn mean_exit_time_over_10_kt_is_the_exact_one() {
    check_mean_exit_time(10.0, 20, 100, 22, true);
}

/// 60 M steps; ~2 min in release on 2 cores.
#[test]
#[ignore]
fn mean_exit_time_over_20_kt_is_the_exact_one() {
    check_mean_exit_time(20.0, 20, 100, 23, true);
}

/// 240 M steps; ~8 min in release on 2 cores (50 replicas: at 20, 3 SE
/// was 35 % of the estimate, at 40 30.4 %).
#[test]
#[ignore]
fn mean_exit_time_over_30_kt_is_the_exact_one() {
    check_mean_exit_time(30.0, 50, 100, 24, true);
}

/// Unbiasedness: the mean of 3 000 replicas of 4 particles at p ~ 1e-2
/// against 200 000 direct runs of the same discrete dynamics, within 5
/// combined standard errors. The reset is 0.004 rad (~1.5 rms steps)
/// below the start, so paths are short and ties frequent; the algorithm
/// that ignores them in its weight ([`Variant::TieBlindWeight`]: weight
/// `1 − k/n` while killing every particle at the level) is 28 % high,
/// 7.7 combined SE: it must fail the same check.
#[test]
fn splitting_is_unbiased_and_the_tie_blind_weight_is_not() {
    let (problem, exact) = brownian_splitting(1e-2, 0.004, 31);
    let mut s = settings(3000, 4);
    let ams = Ams::new(problem.clone(), s.clone()).unwrap();
    let t0 = Instant::now();
    let direct = ams
        .direct(200_000, Some(2), Hooks::default())
        .unwrap()
        .unwrap();
    report("direct", &direct, exact, t0.elapsed().as_secs_f64());
    assert_eq!(direct.method, "direct");
    let z = |e: &Estimate| {
        (e.estimate - direct.estimate)
            / (e.standard_error.powi(2) + direct.standard_error.powi(2)).sqrt()
    };
    let t0 = Instant::now();
    let (_, e) = run_all(&ams, 2);
    report("ams", &e, exact, t0.elapsed().as_secs_f64());
    s.variant = Variant::TieBlindWeight;
    let biased = Ams::new(problem, s).unwrap();
    let (_, b) = run_all(&biased, 2);
    report("tie-blind", &b, exact, 0.0);
    eprintln!(
        "against direct: {:+.2} SE, tie-blind {:+.2} SE",
        z(&e),
        z(&b)
    );
    assert!(z(&e).abs() < 5.0, "AMS is {:+.2} SE from direct", z(&e));
    assert!(
        z(&b).abs() > 5.0,
        "the biased variant passes ({:+.2} SE)",
        z(&b)
    );
    // Same paths, other weights: the variant moved the estimate only.
    assert_eq!(b.trajectories, e.trajectories);
}

/// The Langevin scenario of the cross-checks: `nano-physical` with its
/// well made 8 kT deep, started 0.1 rad up the wall at rest; reset 0.04 rad
/// below, target 0.3 rad above the bottom (a rise of 3.3 kT).
fn langevin_problem(model: ModelKind, seed: u64) -> Problem {
    let mut sc = Scenario::nano_physical();
    {
        let mut wells = sc.wells();
        wells[0].depth = 8.0 * kt();
        sc.set_wells(&wells);
    }
    sc.solver.model = model;
    sc.thermal.seed = Some(seed);
    let x0 = FRAC_PI_2 + 0.1;
    sc.initial.theta = x0;
    Problem::new(
        sc,
        exit(&format!("theta>{}", FRAC_PI_2 + 0.3)),
        Some(exit(&format!("theta<{}", x0 - 0.04))),
    )
}

fn check_langevin(model: ModelKind, seed: u64) {
    let ams = Ams::new(langevin_problem(model, seed), settings(20, 50)).unwrap();
    let t0 = Instant::now();
    let d = ams
        .direct(20_000, Some(2), Hooks::default())
        .unwrap()
        .unwrap();
    report("direct", &d, d.estimate, t0.elapsed().as_secs_f64());
    let t0 = Instant::now();
    let (_, e) = run_all(&ams, 2);
    report("ams", &e, d.estimate, t0.elapsed().as_secs_f64());
    let se = (e.standard_error.powi(2) + d.standard_error.powi(2)).sqrt();
    let z = (e.estimate - d.estimate) / se;
    eprintln!(
        "{model:?}: AMS - direct = {z:+.2} combined SE ({:.1} % of p)",
        100.0 * se / d.estimate
    );
    assert!(
        d.estimate > 3e-3 && d.estimate < 3e-2,
        "p = {} is not ~1e-2",
        d.estimate
    );
    assert!(se < 0.15 * d.estimate, "combined SE too large to test");
    assert!(
        z.abs() < 3.0,
        "AMS {:e}, direct {:e}: {z:+.2} SE",
        e.estimate,
        d.estimate
    );
    // The 95 % intervals overlap.
    assert!(e.ci95[0] < d.ci95[1] && d.ci95[0] < e.ci95[1]);
}

#[test]
fn langevin_vector_model_agrees_with_direct_runs() {
    check_langevin(ModelKind::Vector, 41);
}

#[test]
fn langevin_rigid_model_agrees_with_direct_runs() {
    check_langevin(ModelKind::Rigid, 42);
}

/// The flux relation in the Langevin mode against direct runs:
/// `nano-physical` with its well made 8 kT deep, the exit from π/2 ± 0.35
/// (a rise of 4.0 kT), from the well's bottom, with the default
/// coordinate (the tilt energy): within 3 combined SE of 400 direct runs'
/// mean exit time. ~2e7 steps.
#[test]
#[ignore]
fn langevin_mean_exit_time_agrees_with_direct_runs() {
    let mut sc = Scenario::nano_physical();
    {
        let mut wells = sc.wells();
        wells[0].depth = 8.0 * kt();
        sc.set_wells(&wells);
    }
    sc.initial.theta = FRAC_PI_2;
    sc.thermal.seed = Some(44);
    let problem = Problem::new(
        sc,
        exit(&format!(
            "theta<{},theta>{}",
            FRAC_PI_2 - 0.35,
            FRAC_PI_2 + 0.35
        )),
        None,
    );
    assert_eq!(problem.coordinate, Coordinate::TiltEnergy);
    let ams = Ams::new(problem, settings(20, 50)).unwrap();
    let t0 = Instant::now();
    let d = ams.direct(400, Some(2), Hooks::default()).unwrap().unwrap();
    report("direct", &d, d.estimate, t0.elapsed().as_secs_f64());
    assert_eq!(d.truncated, 0);
    let t0 = Instant::now();
    let (_, e) = run_all(&ams, 2);
    report("ams", &e, d.estimate, t0.elapsed().as_secs_f64());
    let se = (e.standard_error.powi(2) + d.standard_error.powi(2)).sqrt();
    let z = (e.estimate - d.estimate) / se;
    eprintln!(
        "flux {:?}\nAMS - direct = {z:+.2} combined SE ({:.1} %)",
        e.flux,
        100.0 * se / d.estimate
    );
    assert!(se < 0.15 * d.estimate);
    assert!(z.abs() < 3.0);
}

/// The same inputs give the same bits on 1 and 2 threads: every replica
/// (levels, counts, estimates) and the estimate, for a Brownian probability,
/// a Brownian mean exit time and a rigid Langevin probability.
#[test]
fn same_bits_on_one_and_two_threads() {
    let (p, _) = brownian_splitting(1e-3, 0.02, 51);
    let mut tau = well_top(6.0 / (1.0 - (-2.0f64).exp()), 0.3, 1.0);
    tau.thermal.seed = Some(52);
    let tau = Problem::new(
        tau,
        exit(&format!(
            "theta<{},theta>{}",
            FRAC_PI_2 - 0.6,
            FRAC_PI_2 + 0.6
        )),
        None,
    );
    let rigid = langevin_problem(ModelKind::Rigid, 53);
    for problem in [p, tau, rigid] {
        let ams = Ams::new(problem, settings(3, 8)).unwrap();
        let (r1, e1) = run_all(&ams, 1);
        let (r2, e2) = run_all(&ams, 2);
        assert_eq!(r1, r2);
        assert_eq!(e1, e2);
        assert!(e1.iterations > 0);
        // A shard's replicas are the whole run's.
        let mut tail = Vec::new();
        ams.run(1..3, Some(2), Hooks::default(), &mut |r| {
            tail.push(r);
            true
        })
        .unwrap();
        assert_eq!(tail, r1[1..]);
    }
}

/// Bad input is one line naming the option, with its range.
#[test]
fn bad_input_names_the_option() {
    let (problem, _) = brownian_splitting(1e-3, 0.02, 61);
    let key_of = |r: Result<Ams, Error>| match r {
        Err(Error::Invalid { key, what, range }) => {
            let line = format!("{key}: {what} ({range})");
            assert!(!line.contains('\n'), "{line}");
            key
        }
        Err(e) => panic!("not bad input: {e}"),
        Ok(_) => panic!("accepted"),
    };
    let x0 = problem.scenario.initial.theta;
    let with = |f: &dyn Fn(&mut Problem, &mut Settings)| {
        let (mut p, mut s) = (problem.clone(), Settings::default());
        f(&mut p, &mut s);
        Ams::new(p, s)
    };
    // A target or a reset that holds at the start.
    assert_eq!(
        key_of(with(&|p, _| p.target = exit(&format!("theta>{}", x0 - 0.1)))),
        "--target"
    );
    assert_eq!(
        key_of(with(
            &|p, _| p.reset = Some(exit(&format!("theta<{}", x0 + 0.1)))
        )),
        "--reset"
    );
    // No noise.
    assert_eq!(
        key_of(with(&|p, _| p.scenario.thermal.temperature = 0.0)),
        "thermal.temperature"
    );
    let mut det = problem.clone();
    det.scenario.solver.method = Method::Adaptive;
    det.scenario.thermal = tippetop::Thermal::NONE;
    assert_eq!(key_of(Ams::new(det, Settings::default())), "solver.method");
    // A coordinate that is not a column.
    match Coordinate::parse("tilt") {
        Err(Error::Invalid { key, .. }) => assert_eq!(key, "--coordinate"),
        other => panic!("{other:?}"),
    }
    assert!(Coordinate::parse("|theta-x|").is_err());
    // Budgets out of range.
    for (key, f) in [
        (
            "--replicas",
            &(|s: &mut Settings| s.replicas = 1) as &dyn Fn(&mut Settings),
        ),
        ("--particles", &|s: &mut Settings| s.particles = 1),
        ("--kill", &|s: &mut Settings| s.kill = 0),
        ("--kill", &|s: &mut Settings| s.kill = s.particles),
        ("--max-trajectories", &|s: &mut Settings| {
            s.max_trajectories = 99
        }),
        ("--max-trajectories", &|s: &mut Settings| {
            s.max_trajectories = 1 << 24
        }),
        ("--max-steps", &|s: &mut Settings| s.max_steps = 0),
        ("--max-steps", &|s: &mut Settings| s.max_steps = 10_000_001),
        ("--crossings", &|s: &mut Settings| s.crossings = 0),
        ("--direct-steps", &|s: &mut Settings| s.direct_steps = 0),
        ("--pilot-steps", &|s: &mut Settings| s.pilot_steps = 10),
        ("--basin", &|s: &mut Settings| s.basin = Some(f64::NAN)),
    ] {
        assert_eq!(key_of(with(&|_, s| f(s))), key, "{key}");
    }
    // Horizons: zero, negative, beyond the step limit, without a reset.
    for t in [0.0, -1e-12, 1.0, f64::NAN] {
        assert_eq!(
            key_of(with(&|p, _| p.horizon = Some(t))),
            "--horizon",
            "{t}"
        );
    }
    assert_eq!(
        key_of(with(&|p, _| {
            p.reset = None;
            p.horizon = Some(1e-12);
        })),
        "--horizon"
    );
    // Mean first-passage time: an interface below the start, or below the basin.
    let mut mfpt = problem.clone();
    mfpt.reset = None;
    let mut s = Settings::default();
    (s.basin, s.interface) = (Some(0.1), Some(0.05));
    assert_eq!(key_of(Ams::new(mfpt.clone(), s.clone())), "--interface");
    (s.basin, s.interface) = (Some(-10.0), Some(0.1));
    assert_eq!(key_of(Ams::new(mfpt, s)), "--interface");
}

/// No particle can meet the target along a coordinate that never moves
/// (`rolling` is 0 throughout a Langevin run): every replica dies at its
/// first level, and the estimate is 0 with the upper bound
/// `1 − 0.05^{1/(nM)}` of nM independent runs that all failed (the rule of
/// three), never NaN.
#[test]
fn extinction_is_zero_with_an_upper_bound() {
    let (mut problem, _) = brownian_splitting(1e-3, 0.02, 71);
    problem.coordinate = Coordinate::parse("rolling").unwrap();
    let ams = Ams::new(problem, settings(4, 10)).unwrap();
    let e = ams.estimate(Some(2), Hooks::default()).unwrap().unwrap();
    assert!(e.extinct);
    assert_eq!(e.estimate, 0.0);
    assert_eq!(e.interval, "rule_of_three");
    let bound = 1.0 - 0.05f64.powf(1.0 / 40.0);
    assert!((e.ci95[1] - bound).abs() < 1e-15 && e.ci95[0] == 0.0);
    assert!((e.ci95[1] - 3.0 / 40.0).abs() < 0.005, "~3/N");
    assert_eq!(e.iterations, 0);
    assert!(e.standard_error == 0.0 && e.ci95_lognormal.is_none());
}

/// A replica that runs out of paths has no estimate: combining is a
/// run-time error naming the budget; paths cut by the step budget are
/// counted.
#[test]
fn budgets_bound_the_work() {
    let (problem, _) = brownian_splitting(1e-6, 0.02, 81);
    let mut s = settings(2, 10);
    s.max_trajectories = 30;
    let ams = Ams::new(problem.clone(), s).unwrap();
    let (mut reps, mut n) = (Vec::new(), 0);
    ams.run(0..2, Some(2), Hooks::default(), &mut |r| {
        reps.push(r);
        true
    })
    .unwrap();
    for r in &reps {
        assert!(r.status.contains("--max-trajectories 30"), "{}", r.status);
        assert!(r.trajectories <= 30);
        n += 1;
    }
    assert_eq!(n, 2);
    match ams.combine(&reps) {
        Err(e @ Error::Runtime { .. }) => {
            assert!(e.to_string().contains("max-trajectories"), "{e}");
            assert!(!e.to_string().contains('\n'));
        }
        other => panic!("{other:?}"),
    }
    // Paths of at most 3 steps never reach the target 0.2 rad away.
    let mut s = settings(2, 10);
    s.max_steps = 3;
    let e = Ams::new(problem, s)
        .unwrap()
        .estimate(Some(1), Hooks::default())
        .unwrap()
        .unwrap();
    assert!(e.truncated >= 20, "{} truncated", e.truncated);
    assert_eq!(e.estimate, 0.0);
}

/// The progress hook sees the fraction of replicas done, rising to 1; a
/// set cancel flag stops the run with no estimate.
#[test]
fn progress_and_cancel() {
    let (problem, _) = brownian_splitting(1e-2, 0.02, 91);
    let ams = Ams::new(problem, settings(4, 10)).unwrap();
    let seen = std::sync::Mutex::new(Vec::new());
    let progress = |f: f64| seen.lock().unwrap().push(f);
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: None,
        steps: None,
    };
    assert!(ams.estimate(Some(2), hooks).unwrap().is_some());
    assert_eq!(*seen.lock().unwrap(), vec![0.25, 0.5, 0.75, 1.0]);
    let cancel = std::sync::atomic::AtomicBool::new(true);
    let hooks = Hooks {
        progress: None,
        cancel: Some(&cancel),
        steps: None,
    };
    assert!(ams.estimate(Some(2), hooks).unwrap().is_none());
    assert!(ams.direct(100, Some(2), hooks).unwrap().is_none());
}

/// A horizon: `P(target before reset and before T)` with `T` about the
/// time a path takes, so that it binds (a third of the runs that would
/// have gone on are stopped by it), against direct runs with the same
/// horizon, within 3 combined SE.
#[test]
fn horizon_probability_agrees_with_direct_runs() {
    let (mut problem, _) = brownian_splitting(1e-2, 0.02, 101);
    let dt = problem.scenario.solver.dt.unwrap();
    problem.horizon = Some(150.0 * dt);
    let ams = Ams::new(problem.clone(), settings(20, 20)).unwrap();
    let d = ams
        .direct(20_000, Some(2), Hooks::default())
        .unwrap()
        .unwrap();
    let (_, e) = run_all(&ams, 2);
    let se = (e.standard_error.powi(2) + d.standard_error.powi(2)).sqrt();
    let z = (e.estimate - d.estimate) / se;
    eprintln!(
        "horizon: AMS {:.4e}, direct {:.4e}: {z:+.2} SE",
        e.estimate, d.estimate
    );
    assert!(z.abs() < 3.0);
    // Without the horizon the probability is clearly larger.
    problem.horizon = None;
    let free = Ams::new(problem, settings(20, 20)).unwrap();
    let f = free
        .direct(20_000, Some(2), Hooks::default())
        .unwrap()
        .unwrap();
    assert!(
        f.estimate - d.estimate
            > 4.0 * (f.standard_error.powi(2) + d.standard_error.powi(2)).sqrt()
    );
}

/// The coordinate grammar and its default.
#[test]
fn coordinate_grammar() {
    for (spec, canonical) in [
        ("theta", "theta"),
        (" -theta ", "-theta"),
        ("omega", "omega"),
        ("|theta-1.5|", "|theta-1.5|"),
        ("|theta--0.5|", "|theta--0.5|"),
    ] {
        let c = Coordinate::parse(spec).unwrap();
        assert_eq!(c.to_string(), canonical);
        assert_eq!(Coordinate::parse(&c.to_string()).unwrap(), c);
    }
    let v = |c: Coordinate, theta: f64| c.value(&|i| if i == 1 { theta } else { f64::NAN });
    assert_eq!(v(Coordinate::parse("-theta").unwrap(), 2.0), -2.0);
    assert_eq!(v(Coordinate::parse("|theta-1.5|").unwrap(), 1.0), 0.5);
    assert_eq!(Coordinate::toward(&exit("theta>2")), Coordinate::THETA);
    assert_eq!(Coordinate::toward(&exit("theta<1")).to_string(), "-theta");
    assert_eq!(
        Coordinate::toward(&exit("theta<1,theta>2")).to_string(),
        "|theta-1.5|"
    );
    assert_eq!(Coordinate::toward(&exit("omega>1")), Coordinate::THETA);
    // The tilt energy: at the bottom of nano-physical's well, at rest,
    // the well's depth and gravity's share; plus ½ (A + m a²) θ̇² at π/2.
    let sc = Scenario::nano_physical();
    let e = Coordinate::parse("tilt_energy").unwrap();
    assert_eq!(e.to_string(), "tilt_energy");
    assert!(e.value(&|_| 0.0).is_nan());
    let at = |theta: f64, theta_dot: f64| {
        e.value_in(&sc, &|i| match i {
            1 => theta,
            2 => theta_dot,
            _ => f64::NAN,
        })
    };
    let (m, a, big_a) = (sc.top.mass, sc.top.offset, sc.top.inertia_transverse);
    let bottom = -sc.wells()[0].depth - m * sc.surface.gravity * a * FRAC_PI_2.cos();
    assert!((at(FRAC_PI_2, 0.0) - bottom).abs() < 1e-12 * bottom.abs());
    let kinetic = 0.5 * (big_a + m * a * a) * 1e12 * 1e12;
    assert!((at(FRAC_PI_2, 1e12) - bottom - kinetic).abs() < 1e-9 * kinetic);
    // Its default: a Langevin escape from a θ window; not a Brownian one,
    // nor a one-sided target.
    let window = exit("theta<1.2,theta>1.9");
    assert_eq!(
        Coordinate::default_for(&sc, &window),
        Coordinate::TiltEnergy
    );
    assert_eq!(
        Coordinate::default_for(&sc, &exit("theta>1.9")),
        Coordinate::THETA
    );
    let mut brownian = sc.clone();
    brownian.solver.method = Method::Brownian;
    assert_eq!(
        Coordinate::default_for(&brownian, &window),
        Coordinate::toward(&window)
    );
    for bad in ["", "|theta|", "|tilt-1|", "-", "|theta-inf|", "tilt"] {
        assert!(Coordinate::parse(bad).is_err(), "{bad:?}");
    }
}

/// Benchmark: a probability of ~1e-12 in the Brownian mode at the default
/// sizes (10 replicas of 100 particles), with its 95 % interval within a
/// factor 2 (docs/performance.md, "Rare events"). ~25 M steps.
#[test]
#[ignore]
fn benchmark_probability_1e_12() {
    let (problem, want) = brownian_splitting(1e-12, 0.02, 111);
    let ams = Ams::new(problem, Settings::default()).unwrap();
    let t0 = Instant::now();
    let e = ams.estimate(None, Hooks::default()).unwrap().unwrap();
    let secs = t0.elapsed().as_secs_f64();
    report("benchmark p ~ 1e-12", &e, want, secs);
    eprintln!(
        "  95 % interval / estimate: {:.3} .. {:.3}; lognormal {:?}",
        e.ci95[0] / e.estimate,
        e.ci95[1] / e.estimate,
        e.ci95_lognormal
            .map(|c| [c[0] / e.estimate, c[1] / e.estimate])
    );
    assert!(e.ci95[1] <= 2.0 * e.estimate && e.ci95[0] >= 0.5 * e.estimate);
}

/// Benchmark: the mean residence of `nano-physical`'s lying state at
/// 300 K (exit from π/2 ± 0.35, the bit's `one` window), Langevin mode,
/// default options (docs/performance.md, "Rare events").
#[test]
#[ignore]
fn benchmark_nano_physical_retention() {
    let sc = Scenario::nano_physical();
    let (lo, hi) = (FRAC_PI_2 - 0.35, FRAC_PI_2 + 0.35);
    let mut sc = sc;
    sc.initial.theta = FRAC_PI_2;
    let problem = Problem::new(sc, exit(&format!("theta<{lo},theta>{hi}")), None);
    let t0 = Instant::now();
    let ams = Ams::new(problem, Settings::default()).unwrap();
    let e = ams.estimate(None, Hooks::default()).unwrap().unwrap();
    let secs = t0.elapsed().as_secs_f64();
    eprintln!("{e:#?}");
    eprintln!(
        "nano-physical lying state at 300 K: mean residence {:.4e} s, 95 % {:.4e} .. {:.4e} s (x{:.2} / x{:.2}), {} paths, {} steps, {secs:.1} s",
        e.estimate,
        e.ci95[0],
        e.ci95[1],
        e.estimate / e.ci95[0],
        e.ci95[1] / e.estimate,
        e.trajectories,
        e.steps
    );
}
