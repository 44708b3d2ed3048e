//! The "Inside a nanotube" section of `reproduce --extended`: each number
//! the verdict rests on against an independent computation (equipartition
//! by quadrature of the Boltzmann weight, the work to reach the wall from
//! the energy itself, the paper's force and the nano top's weight from the
//! paper's values), and the figure's curves against the statics.

use std::sync::OnceLock;

use tippetop::physics::adhesion::{ANGSTROM, Adhesion, EV};
use tippetop::physics::nanotube::chirality_radius;
use tippetop_paper::tube::{FIGURE_STEP, TEMPERATURE, TUBES, TubeRow, TubeStudy, study};

/// Boltzmann's constant \[J/K\] (CODATA 2018, exact).
const K_B: f64 = 1.380649e-23;

fn shared() -> &'static TubeStudy {
    static S: OnceLock<TubeStudy> = OnceLock::new();
    S.get_or_init(|| study(1.0).expect("the study runs"))
}

fn row(n: u32) -> &'static TubeRow {
    shared()
        .rows
        .iter()
        .find(|r| r.n == n)
        .expect("tube in the study")
}

/// Composite Simpson over `[lo, hi]` with `m` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, lo: f64, hi: f64, m: usize) -> f64 {
    let h = (hi - lo) / m as f64;
    let mut s = f(lo) + f(hi);
    for i in 1..m {
        s += f(lo + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

#[test]
fn the_study_has_the_four_tubes_the_paper_force_and_weight() {
    let s = shared();
    assert_eq!(s.rows.iter().map(|r| r.n).collect::<Vec<_>>(), TUBES);
    for r in &s.rows {
        // b = a_CC √(3 · 3n²)/(2π) = 3 a_CC n/(2π) for (n, n).
        let b = 3.0 * 1.42e-10 * r.n as f64 / (2.0 * std::f64::consts::PI);
        assert!((r.tube.radius - b).abs() < 1e-12 * b, "{}", r.n);
        assert_eq!(r.tube.radius, chirality_radius(r.n, r.n));
    }
    // The paper: H_x = H_y = 0.1 zN (Sec. 3), m = 1.196e-24 kg, g = 9.8.
    assert!((s.force - 2f64.sqrt() * 1e-22).abs() < 1e-12 * s.force);
    assert!((s.weight - 1.196e-24 * 9.8).abs() < 1e-12 * s.weight);
    assert!((s.kt - K_B * TEMPERATURE).abs() < 1e-12 * s.kt);
    let sheet = Adhesion::c60_on_graphene().binding().unwrap();
    assert_eq!(s.sheet, sheet);
}

/// The rms excursion √(kT/k) of the harmonic estimate against the
/// Boltzmann distribution of the full potential, by quadrature: on the
/// axis (10,10), ⟨x²⟩ = ½⟨r²⟩ over the disc with the weight
/// exp(−(U(r) − U(0))/kT) r dr; on the wall (15,15), the radial variance
/// about the mean with the weight exp(−ΔU/kT) p dp. The difference is the
/// potential's anharmonicity: measured −2.7 % in (10,10) (the well
/// stiffens towards the wall all round) and +5.6 % in (15,15) (softer
/// towards the axis than towards the wall); the bar is the 6 % the
/// report states (tube.rs).
#[test]
fn thermal_rms_is_the_boltzmann_spread_of_the_potential() {
    let kt = K_B * TEMPERATURE;
    // (10,10), on the axis.
    let r10 = row(10);
    assert!(r10.binding.on_axis);
    let t = r10.tube;
    let u0 = t.energy(0.0);
    let w = |r: f64| (-(t.energy(r) - u0) / kt).exp();
    let hi = 8.0 * r10.rms;
    let m2 = simpson(|r| r * r * r * w(r), 0.0, hi, 64);
    let m0 = simpson(|r| r * w(r), 0.0, hi, 64);
    let rms = (0.5 * m2 / m0).sqrt();
    let rel = rms / r10.rms - 1.0;
    assert!(
        rel.abs() < 6e-2,
        "(10,10): Boltzmann rms {rms:e} against {:e}",
        r10.rms
    );
    // (15,15), on the wall: radial spread about the mean.
    let r15 = row(15);
    assert!(!r15.binding.on_axis);
    let t = r15.tube;
    let p0 = r15.binding.offset;
    let u0 = t.energy(p0);
    let w = |p: f64| p * (-(t.energy(p) - u0) / kt).exp();
    let (lo, hi) = (p0 - 8.0 * r15.rms, p0 + 8.0 * r15.rms);
    let z = simpson(w, lo, hi, 64);
    let mean = simpson(|p| p * w(p), lo, hi, 64) / z;
    let var = simpson(|p| (p - mean).powi(2) * w(p), lo, hi, 64) / z;
    let rel = var.sqrt() / r15.rms - 1.0;
    assert!(
        rel.abs() < 6e-2,
        "(15,15): Boltzmann rms {:e} against {:e}",
        var.sqrt(),
        r15.rms
    );
    // Both small against the gap to the wall (the table's rms / gap).
    for r in &shared().rows {
        assert!(r.rms < 0.05 * r.binding.gap, "({0},{0})", r.n);
    }
}

/// (10,10): to reach the wall (the sheet's gap) the cage moves
/// `b − R − gap_sheet` against a force whose mean is the energy it costs
/// over the distance; the reported largest force is at least that mean and
/// no more than the largest central difference of `U` on a fine grid. The
/// paper's force is some 1e-13 of it.
#[test]
fn on_the_axis_the_force_needed_to_reach_the_wall_dwarfs_h() {
    let s = shared();
    let r = row(10);
    let t = r.tube;
    let sheet = Adhesion::c60_on_graphene().binding().unwrap();
    let pt = t.radius - t.shell.radius - sheet.gap;
    assert!((r.touch_offset - pt).abs() < 1e-12 * pt);
    // b = 6.780 Å, R = 3.55 Å, sheet gap 2.959 Å: 0.271 Å to go.
    assert!((pt / ANGSTROM - 0.271).abs() < 2e-3, "{pt:e}");
    let du = t.energy(pt) - t.energy(0.0);
    assert!((r.barrier - du).abs() < 1e-9 * du);
    let mean = du / pt;
    let h = pt / 100.0;
    let fd_max = (1..=100)
        .map(|i| {
            let p = i as f64 * h;
            (t.energy(p + 0.5 * h) - t.energy(p - 0.5 * h)) / h
        })
        .fold(0.0, f64::max);
    assert!(
        r.holding_force >= mean,
        "{:e} < mean {mean:e}",
        r.holding_force
    );
    assert!(
        r.holding_force <= 1.001 * fd_max,
        "{:e} > {fd_max:e}",
        r.holding_force
    );
    let ratio = s.force / r.holding_force;
    assert!(ratio < 1e-12, "{ratio:e}");
    // The energy to get there: several k_B T (7.5), so the cage spends a
    // fraction exp(−ΔU/kT) < 1e-2 of its time that near the wall.
    let bf = (-du / (K_B * TEMPERATURE)).exp();
    assert!(
        bf < 1e-2 && (r.thermal_factor() - bf).abs() < 1e-9 * bf,
        "{bf}"
    );
    let v = s.verdict();
    assert!(v.contains("(10,10), b = 6.780 Å: no contact point"), "{v}");
    assert!(v.contains("in brief excursions, not at rest"), "{v}");
}

/// From (12,12) on the cage rests on the wall near the sheet's gap; the
/// circle of equilibria around the axis is level but for gravity, whose
/// span 2 m g p₀ is ~1e-12 k_B T (from the paper's mass and g); the
/// holding force (the pull-off force) is ~1e12 |H|.
#[test]
fn on_the_wall_the_circle_has_no_bottom_and_h_is_negligible() {
    let s = shared();
    let sheet = Adhesion::c60_on_graphene().binding().unwrap();
    for n in [12, 15, 20] {
        let r = row(n);
        let b = &r.binding;
        assert!(!b.on_axis && r.touches(), "({n},{n})");
        assert!(
            (b.gap - sheet.gap).abs() < 0.2 * ANGSTROM,
            "({n},{n}) gap {:e}",
            b.gap
        );
        let span = 2.0 * 1.196e-24 * 9.8 * b.offset;
        assert!((s.gravity_span(r) - span).abs() < 1e-12 * span);
        assert!(span / (K_B * TEMPERATURE) < 1e-11, "({n},{n})");
        // Across the axis: U(0) − U(p₀) = E_b − suction.
        let barrier = b.energy - b.suction_energy;
        assert!((r.barrier - barrier).abs() < 1e-9 * b.energy, "({n},{n})");
        // The holding force is the pull-off force: the largest −U′ on the
        // way to the axis (central differences on a grid).
        let t = r.tube;
        let h = b.offset / 200.0;
        let fd = (1..200)
            .map(|i| {
                let p = i as f64 * h;
                -(t.energy(p + 0.5 * h) - t.energy(p - 0.5 * h)) / h
            })
            .fold(0.0, f64::max);
        assert!(
            (r.holding_force - fd).abs() < 1e-3 * fd,
            "({n},{n}): {:e} against {fd:e}",
            r.holding_force
        );
        assert!(s.force / r.holding_force < 1e-12, "({n},{n})");
    }
    let v = s.verdict();
    assert!(
        v.contains("a contact, but on a circle with no bottom"),
        "{v}"
    );
    assert!(v.contains("rests on the wall in wider ones"), "{v}");
}

/// The figure: each curve is `U(p)` in eV on the grid 0, step, …; its first
/// point is minus the suction energy, its lowest point the binding energy
/// to within the grid's resolution `k (step/2)²/2`, and the next grid point
/// after its end is above zero. The reference line is the sheet's binding.
#[test]
fn figure_curves_are_the_energy_with_the_sheet_as_reference() {
    let s = shared();
    let f = s.figure();
    assert_eq!(f.id, "tube_energy");
    assert_eq!(f.x_name, "offset_m");
    assert!((f.x_scale - 1e10).abs() < 1e-3);
    assert_eq!(f.curves.len(), TUBES.len());
    for (r, c) in s.rows.iter().zip(&f.curves) {
        let b = &r.binding;
        assert_eq!(c.t[0], 0.0);
        for (i, &p) in c.t.iter().enumerate() {
            assert!((p - i as f64 * FIGURE_STEP).abs() < 1e-9 * FIGURE_STEP);
        }
        assert!(
            (c.y[0] + b.suction_energy / EV).abs() < 1e-9,
            "({0},{0})",
            r.n
        );
        let lo = c.y.iter().copied().fold(f64::INFINITY, f64::min);
        let res = b.stiffness * (0.5 * FIGURE_STEP).powi(2) / 2.0 / EV;
        assert!(
            lo >= -b.energy / EV - 1e-9,
            "({0},{0}) below the minimum",
            r.n
        );
        assert!(
            lo <= -b.energy / EV + 1.01 * res + 1e-9,
            "({0},{0}) {lo}",
            r.n
        );
        assert!(c.y.iter().all(|&u| u <= 0.0));
        let next = c.t.len() as f64 * FIGURE_STEP;
        assert!(r.tube.energy(next) > 0.0, "({0},{0}) cut early", r.n);
    }
    let sheet = Adhesion::c60_on_graphene().binding().unwrap();
    assert_eq!(f.hlines.len(), 1);
    assert!((f.hlines[0].0 + sheet.energy / EV).abs() < 1e-12);
    // Every curve dips below the sheet (the wall surrounds the cage).
    for c in &f.curves {
        let lo = c.y.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(lo < f.hlines[0].0);
    }
}

#[test]
fn the_section_is_titled_and_links_its_figure() {
    let (title, body) = shared().section();
    assert_eq!(title, "Inside a nanotube");
    assert!(body.contains("figtube_energy.png"));
    assert_eq!(body.matches("\n| (").count(), TUBES.len());
    if std::env::var_os("TUBE_SECTION_PRINT").is_some() {
        eprintln!("{body}");
    }
}

/// The paper's nano scenario on the wall of each tube where the cage rests
/// (rigid model): the scenario's load is the tube's pull-off force (the
/// largest −dU/dp of the energy, checked by central differences in
/// `on_the_wall_the_circle_has_no_bottom_and_h_is_negligible`), the contact
/// cylinder `p₀ + R`; under Coulomb friction with that load the top rolls
/// (≥ 99.9 % of the window), the force at the rolling contact does no work
/// (`|W_a| ≤ 1e-12 |H| R`, R the cage's radius: the work H would do over a
/// millionth of R) and does not change θ (`|θ − θ(H = 0)| ≤ 1e-9` rad);
/// the reaction stays at the load (`N ≥ 0.999 F_a`).
#[test]
fn on_the_wall_the_paper_force_does_nothing() {
    let s = shared();
    assert_eq!(s.runs.len(), 3);
    for run in &s.runs {
        let r = row(run.n);
        let sc = &run.scenario;
        assert_eq!(sc.adhesion().force, r.holding_force);
        match sc.surface.shape {
            tippetop::input::surface::Shape::Tube { radius, .. } => {
                assert!((radius - r.binding.offset - 3.55e-10).abs() < 1e-12 * radius)
            }
            _ => panic!("not in the tube"),
        }
        let tr = &run.trajectory;
        assert!(tr.error.is_none(), "({0},{0}): {1:?}", run.n, tr.error);
        assert!(tr.summary.rolling_fraction >= 0.999, "({0},{0})", run.n);
        let wa = run.work_applied_max();
        assert!(
            wa <= 1e-12 * s.force * 3.55e-10,
            "({0},{0}): W_a {wa:e}",
            run.n
        );
        assert!(run.force_effect() <= 1e-9, "({0},{0})", run.n);
        assert!(
            run.normal_min() >= 0.999 * sc.adhesion().force,
            "({0},{0})",
            run.n
        );
        assert!(tr.summary.theta_max < std::f64::consts::FRAC_PI_2);
    }
    assert!(s.verdict().contains("the top never lies down"));
}

/// `∫_{-1}^{1} u^{2j} sqrt(1 + q (1 − u²)) du` for j = 0, 1 in closed form
/// (x = √q u, A² = 1 + q: `∫ sqrt(A² − x²) dx = x sqrt(A² − x²)/2 +
/// A² asin(x/A)/2` and `∫ x² sqrt(A² − x²) dx = x (2x² − A²) sqrt(A² −
/// x²)/8 + A⁴ asin(x/A)/8`).
fn tilt_moments(q: f64) -> (f64, f64) {
    let (s, a2) = (q.sqrt(), 1.0 + q);
    let a = a2.sqrt();
    let x = s;
    let r = (a2 - x * x).sqrt();
    let i0 = 2.0 * (x * r / 2.0 + a2 * (x / a).asin() / 2.0) / s;
    let i2 =
        2.0 * (x * (2.0 * x * x - a2) * r / 8.0 + a2 * a2 * (x / a).asin() / 8.0) / (s * s * s);
    (i0, i2)
}

/// The 300 K ensemble on the (15,15) wall against laws that do not come
/// from the code: equipartition, `⟨E_kin⟩ = 5/2 k_B T` (five velocities
/// in one-point contact); the tilt's density `sin θ √(1 + m a² sin²θ/A)` of
/// a top with no torque (gravity's and H's energies are ~1e-12 and ~1e-11
/// k_B T), `⟨cos² θ_n⟩` in closed form; the contact's angle around the axis
/// free (no drift, `⟨Δφ⟩ = 0`) and diffusive (the time-averaged `⟨Δφ²⟩`
/// doubles from τ to 2τ, per run: a contact held at a bottom would not
/// grow); each within 4 standard errors from the runs' spread (16
/// independent seeds), and the section says so.
#[test]
fn at_300_k_the_cage_is_thermal_on_the_wall() {
    let s = shared();
    let h = &s.hot;
    assert_eq!(h.n, 15);
    assert!(h.all_ran);
    assert_eq!(h.on.len(), h.off.len());
    let check = |what: &str, (m, se): (f64, f64), want: f64, max_se: f64| {
        eprintln!(
            "{what}: {m:.5} ± {se:.5} (want {want:.5}, {:+.2} SE)",
            (m - want) / se
        );
        assert!(se < max_se, "{what}: SE {se} too large");
        assert!(
            (m - want).abs() < 4.0 * se,
            "{what}: {m} ± {se}, want {want}"
        );
    };
    check("<E_kin>/kT", h.kinetic_over_kt(), 2.5, 0.1);
    let q = h.ma2_over_a;
    let top = tippetop::Top::nano();
    assert!((q - top.mass * top.offset.powi(2) / top.inertia_transverse).abs() < 1e-12 * q);
    let (i0, i2) = tilt_moments(q);
    check("<cos^2 theta_n>", h.cos2_theta(), i2 / i0, 0.03);
    // The section's reference value (Gauss–Legendre) is the closed form.
    for qq in [q, 0.5, 2.0] {
        let (j0, j2) = tilt_moments(qq);
        let got = tippetop_paper::tube::boltzmann_cos2(qq);
        assert!(
            (got - j2 / j0).abs() < 1e-13,
            "q = {qq}: {got} vs {}",
            j2 / j0
        );
    }
    // ⟨cos θ_n⟩ = 0 by the density's symmetry about π/2.
    let c1: Vec<f64> = h
        .all()
        .map(|r| r.mean(&r.theta_n.iter().map(|x| x.cos()).collect::<Vec<_>>()))
        .collect();
    check(
        "<cos theta_n>",
        tippetop_paper::tube::langevin::mean_se(&c1),
        0.0,
        0.1,
    );
    let travel: Vec<f64> = h.all().map(|r| r.phi_travel()).collect();
    let (m, se) = tippetop_paper::tube::langevin::mean_se(&travel);
    check("<phi(T) - phi(0)>", (m, se), 0.0, f64::INFINITY);
    // Diffusive: ⟨Δφ²⟩ doubles from τ to 2τ (τ = a tenth of the window,
    // some 200 relaxation times 1/γ: the OU correction is 0.5 %), per run.
    let lag = h.lag();
    let ratios: Vec<f64> = h
        .msd_runs(2 * lag)
        .iter()
        .zip(h.msd_runs(lag))
        .map(|(m2, m1)| m2 / m1)
        .collect();
    let tau = lag as f64 * h.sample_step();
    let want = h.ball_msd(2.0 * tau) / h.ball_msd(tau);
    check(
        "<dphi^2>(2 tau)/<dphi^2>(tau), per run",
        tippetop_paper::tube::langevin::mean_se(&ratios),
        want,
        0.2,
    );
    let (_, body) = s.section();
    assert!(body.contains("At 300 K (Langevin dynamics"), "{body}");
    assert!(body.contains("every run ran to its end"));
    assert!(body.contains("figtube_hot_phi.png") && body.contains("figtube_hot_theta.png"));
    // The paper's H: 1e-11 k_B T over a cage radius; it cannot be seen.
    assert!(!h.force_visible(), "{:?}", h.force_effect());
    assert!(body.contains("far below it, no visible effect"));
}
