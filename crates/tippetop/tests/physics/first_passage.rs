//! Escape out of a window of θ in the overdamped (Brownian) mode, against
//! the exact mean first-passage time of its one-dimensional diffusion
//! (docs/physics.md#retention, "the Kramers check"): what the retention
//! machinery (`--first-passage`, escape rates, `tippetop retention`)
//! measures, checked where the answer is known in closed form.
//!
//! The Brownian mode's θ is a reversible diffusion with coefficient
//! `D(θ) = kT/Γ_θ`, `Γ_θ = γ_r A + γ_t m a² sin²θ` (the tilt mode's
//! friction: the rotation about the horizontal axis and the centre's
//! vertical velocity `a sin θ θ̇`), and stationary density
//! `π(θ) ∝ sin θ s(θ) e^{−U/kT}`, `s = sqrt(1 + m a² sin²θ/A)` (§langevin). Its
//! mean exit time from `(lo, hi)` started at `θ0` solves `L τ = −1`,
//! `τ(lo) = τ(hi) = 0`, `L f = (π D f′)′/π`:
//!
//! ```text
//! τ(θ0) = c I1(θ0) − I2(θ0),  I1(x) = ∫_lo^x dy/(π D),  I2(x) = ∫_lo^x dy (∫_lo^y π)/(π D),
//! c = I2(hi)/I1(hi)
//! ```
//!
//! (Gardiner, Handbook of Stochastic Methods, §5.2.7), computed by the
//! product function `analysis::rare::exact` (its Green's-function form,
//! adaptive Gauss–Kronrod in log space, docs/physics.md#rare-exact). The run is
//! watched at every second step (rows every `2 dt`), and a discretely watched path
//! exits later than the continuous one: to leading order the window is
//! wider by `β sqrt(2 D Δ)` at each edge, `β = −ζ(1/2)/sqrt(2π) = 0.5826`
//! (Broadie, Glasserman & Kou, Math. Finance 7, 325 (1997)); the expected
//! value uses that window (the correction is 1.7 % of τ here, about half
//! the standard error).

use tippetop::analysis::ensemble::{Ensemble, Exit};
use tippetop::analysis::rare::exact::{self, Diffusion, ThetaDiffusion};
use tippetop::input::thermal::BOLTZMANN;
use tippetop::{Forcing, Method, Scenario, Well};

const T: f64 = 300.0;
const GAMMA: f64 = 2.2e12;
const DT: f64 = 5e-16;
const HALF: f64 = 0.35;
/// The rows' spacing [s]: every second step (an ensemble keeps at most
/// 100 000 samples, `analysis::ensemble::MAX_SAMPLES`).
const WATCH: f64 = 2.0 * DT;

/// The nano top made eccentric (`a = R/2`, so `m a²/A = 0.375`: the tilt
/// mode's friction grows by up to 37 % with sin²θ), no gravity, no force,
/// frictionless, a Gaussian well of 2 kT at θ = π/2 (width 0.3 rad), in
/// the Brownian mode at 300 K with `γ_t = γ_r = 2.2e12 s⁻¹` (nano-physical's),
/// `dt = 5e-16 s` (`dt` times the well's rate `d/(w² γ_r A)` = 2e-4),
/// started at θ = π/2 and watched at every second step until 8e-11 s (12
/// mean exit times).
fn escaping_top() -> Scenario {
    let mut sc = Scenario::nano();
    sc.top.offset = 0.5 * sc.top.radius;
    sc.surface.friction = 0.0;
    sc.surface.gravity = 0.0;
    sc.forcing = Forcing { windows: vec![] };
    sc.set_wells(&[Well {
        theta: std::f64::consts::FRAC_PI_2,
        depth: 2.0 * BOLTZMANN * T,
        width: 0.3,
    }]);
    sc.initial.theta = std::f64::consts::FRAC_PI_2;
    sc.initial.spin = 0.0;
    sc.solver.method = Method::Brownian;
    sc.solver.dt = Some(DT);
    sc.solver.t_end = 8e-11;
    sc.solver.samples = 80_001;
    sc.thermal.temperature = T;
    sc.thermal.damping_translational = GAMMA;
    sc.thermal.damping_rotational = GAMMA;
    sc.thermal.seed = Some(20261124);
    sc
}

#[test]
fn brownian_escape_time_is_the_exact_mean_first_passage_time() {
    let sc = escaping_top();
    let centre = std::f64::consts::FRAC_PI_2;
    let (lo, hi) = (centre - HALF, centre + HALF);
    let runs = 1000;
    let e = Ensemble::new(None, Some(sc.to_toml_string()), vec![], runs)
        .unwrap()
        .with_exit(Some(
            Exit::parse(&format!("theta<{lo},theta>{hi}")).unwrap(),
        ));
    let mut times = Vec::with_capacity(runs);
    e.run_streaming(0..runs, Some(2), &mut |row| {
        times.push(
            row.first_passage
                .expect("every run exits before 12 mean times"),
        );
        true
    })
    .unwrap();
    let n = times.len() as f64;
    let mean = times.iter().sum::<f64>() / n;
    let var = times.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();

    // The product function (analysis::rare::exact): the θ diffusion of
    // the scenario, D(θ) = kT/Γ_θ and π(θ) ∝ sin θ s(θ) e^{−U/kT}.
    let kt = BOLTZMANN * T;
    let (m, a, big_a) = (sc.top.mass, sc.top.offset, sc.top.inertia_transverse);
    let theta = ThetaDiffusion::of(&sc).unwrap();
    let diffusion = theta.diffusion();
    let d = |th: f64| kt / (GAMMA * big_a + GAMMA * m * a * a * th.sin().powi(2));
    for th in [0.3, 1.2, centre, 2.8] {
        assert!((theta.diffusivity(th) - d(th)).abs() < 1e-14 * d(th));
    }
    // Discrete watching: the window widened by β sqrt(2 D Δ) at each edge.
    let beta = exact::BGK_BETA;
    let (lo_w, hi_w) = (
        lo - beta * (2.0 * d(lo) * WATCH).sqrt(),
        hi + beta * (2.0 * d(hi) * WATCH).sqrt(),
    );
    let want = diffusion
        .mean_exit_time(Some(lo_w), Some(hi_w), centre)
        .unwrap()
        .value;
    let continuous = diffusion
        .mean_exit_time(Some(lo), Some(hi), centre)
        .unwrap()
        .value;
    // The same through the scenario-level answer and its watched window.
    let cond = Exit::parse(&format!("theta<{lo},theta>{hi}")).unwrap();
    let e = exact::exact(&sc, &cond, None).unwrap();
    assert_eq!(e.value.value, continuous);
    // Its watched value is for a path watched at every step of `dt`.
    let every_step = diffusion
        .mean_exit_time(
            Some(lo - beta * (2.0 * d(lo) * DT).sqrt()),
            Some(hi + beta * (2.0 * d(hi) * DT).sqrt()),
            centre,
        )
        .unwrap()
        .value;
    assert!((e.watched.unwrap().value - every_step).abs() < 1e-12 * every_step);
    let wrong_d = Diffusion::new(
        0.0,
        std::f64::consts::PI,
        move |th| theta.ln_density(th),
        move |_| kt / (GAMMA * big_a),
    );
    // Power: the standard error is a few per cent, and a model that forgot
    // the centre's vertical motion in the tilt's friction (D = kT/(γ_r A))
    // would exit 26 % sooner.
    let wrong = wrong_d
        .mean_exit_time(Some(lo), Some(hi), centre)
        .unwrap()
        .value;
    eprintln!(
        "mean exit time {mean:e} ± {se:e} s over {runs} runs; exact {continuous:e} (continuous), \
         {want:e} (watched every 2 dt); without the vertical motion {wrong:e}"
    );
    assert!(se < 0.04 * want, "SE {se:e} too large to test");
    assert!(
        (wrong - want).abs() > 6.0 * se,
        "no power against {wrong:e}"
    );
    assert!(
        (mean - want).abs() < 4.0 * se,
        "mean exit time {mean:e} ± {se:e}, exact {want:e} ({:.2} SE)",
        (mean - want) / se
    );
}

/// The exact answer where the mobility and the drift have every term the
/// θ diffusion can have (docs/physics.md#rare-exact): the contact damping
/// (`c = m γ_t`, which both slows the tilt, `Γ` +55 % at θ = π/2, and
/// halves the share of the contact-point force that turns it), a constant
/// applied force along the tilt (`H_x R` ≈ 4.5 kT per radian), gravity
/// (`m g a = kT`), a 2 kT well and the nano-physical adhesion (which must
/// do nothing on the plane). 400 runs of the direct runner
/// (`analysis::rare::direct`, every step watched) leave `π/2 ± 0.35`;
/// the fraction leaving above and the mean exit time against the exact
/// splitting probability and mean exit time of the watched window (BGK),
/// each within 4 standard errors, and the models that forget the contact
/// damping's mobility or flip the force's sign are more than 6 SE away.
#[test]
fn brownian_exit_with_contact_damping_force_gravity_and_adhesion() {
    use tippetop::analysis::rare::direct::{Ending, run_replicas};
    let mut sc = escaping_top();
    let kt = BOLTZMANN * T;
    let (m, a) = (sc.top.mass, sc.top.offset);
    sc.surface.gravity = kt / (m * a);
    sc.thermal.damping_contact = m * GAMMA;
    sc.forcing = Forcing::constant(1.25e-11 * 4.0, 0.0);
    sc.set_adhesion(tippetop::Adhesion {
        force: 5.915889357711552e-10,
        energy: 1.169645723902958e-19,
    });
    sc.solver.dt = Some(1.2e-15);
    sc.thermal.seed = Some(7);
    let centre = std::f64::consts::FRAC_PI_2;
    let (lo, hi) = (centre - HALF, centre + HALF);
    let target = Exit::parse(&format!("theta>{hi}")).unwrap();
    let reset = Exit::parse(&format!("theta<{lo}")).unwrap();
    let runs = 400;
    let (mut up, mut times) = (0usize, Vec::with_capacity(runs));
    run_replicas(
        &sc,
        &target,
        Some(&reset),
        1e-9,
        false,
        runs,
        Some(2),
        &mut |_, o| {
            assert!(matches!(o.ending, Ending::Target | Ending::Reset), "{o:?}");
            up += (o.ending == Ending::Target) as usize;
            times.push(o.time);
            true
        },
    )
    .unwrap();
    let n = runs as f64;
    let p = up as f64 / n;
    let p_se = (p * (1.0 - p) / n).sqrt();
    let mean = times.iter().sum::<f64>() / n;
    let se = (times.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();

    let answer = |sc: &tippetop::Scenario| {
        let p = exact::exact(sc, &target, Some(&reset)).unwrap();
        let both = Exit::parse(&format!("theta<{lo},theta>{hi}")).unwrap();
        let t = exact::exact(sc, &both, None).unwrap();
        (p.watched.unwrap().value, t.watched.unwrap().value)
    };
    let (p_want, t_want) = answer(&sc);
    let mut no_contact = sc.clone();
    no_contact.thermal.damping_contact = 0.0;
    let (p_nc, t_nc) = answer(&no_contact);
    let mut flipped = sc.clone();
    flipped.forcing = Forcing::constant(-1.25e-11 * 4.0, 0.0);
    let (p_fl, _) = answer(&flipped);
    eprintln!(
        "P(up) {p:.4} ± {p_se:.4} against {p_want:.4} (no contact damping {p_nc:.4}, force flipped {p_fl:.4}); \
         mean exit {mean:.4e} ± {se:.3e} s against {t_want:.4e} (no contact damping {t_nc:.4e})"
    );
    assert!(
        (p - p_want).abs() < 4.0 * p_se,
        "P(up) {p} ± {p_se}, exact {p_want}"
    );
    assert!(
        (mean - t_want).abs() < 4.0 * se,
        "τ {mean:e} ± {se:e}, exact {t_want:e}"
    );
    assert!(
        (t_nc - t_want).abs() > 6.0 * se,
        "no power against the coupling-free mobility"
    );
    assert!(
        (p_fl - p_want).abs() > 6.0 * p_se,
        "no power against the force's sign"
    );
}
