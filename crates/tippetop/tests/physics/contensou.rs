//! Coulomb–Contensou friction (docs/physics.md#contensou): the law itself against
//! 30-digit references and its closed-form limits, the Padé form's error,
//! the flat disc of Farkas et al. (2003), and the law in the models.

use tippetop::physics::contensou::{self, Pressure};

/// `(pressure, d, f, m)` from mpmath at 30 digits (`mp.quad` of the same
/// ring integrals, split at ρ = d; the ring reduction itself checked against
/// the direct double integral over the disc to 1e-6 at d = 0.3 and 2).
#[allow(clippy::excessive_precision)] // the references as mpmath printed them
const REFERENCE: &[(Pressure, f64, f64, f64)] = &[
    (
        Pressure::Uniform,
        1e-3,
        0.00099999987499998437,
        0.66666616666676042,
    ),
    (Pressure::Uniform, 0.3, 0.296585919232925, 0.622435826100654),
    (
        Pressure::Uniform,
        0.5,
        0.48384375563012582,
        0.54774835477220136,
    ),
    (
        Pressure::Uniform,
        0.999,
        0.84839945953657801,
        0.28336881084085941,
    ),
    (
        Pressure::Uniform,
        1.001,
        0.84924828807077896,
        0.28251998555506066,
    ),
    (Pressure::Uniform, 2.0, 0.967687511260252, 0.127809198284151),
    (
        Pressure::Uniform,
        10.0,
        0.99874843259571238,
        0.025020892172477348,
    ),
    (
        Pressure::Uniform,
        1000.0,
        0.99999987499998437,
        0.00025000002083333919,
    ),
    (
        Pressure::Hertz,
        1e-3,
        0.0011780969505718612,
        0.58904803349968458,
    ),
    (Pressure::Hertz, 0.3, 0.345477017124453, 0.537823481709748),
    (
        Pressure::Hertz,
        0.5,
        0.55223308363883084,
        0.45559229400203545,
    ),
    (
        Pressure::Hertz,
        0.999,
        0.88327752623244579,
        0.22118849319423252,
    ),
    (
        Pressure::Hertz,
        1.001,
        0.88386661003154604,
        0.22059941054768339,
    ),
    (Pressure::Hertz, 2.0, 0.974278579257493, 0.101909332919339),
    (
        Pressure::Hertz,
        10.0,
        0.99899892558334329,
        0.02001432156449366,
    ),
    (
        Pressure::Hertz,
        1000.0,
        0.99999989999998929,
        0.00020000001428571786,
    ),
];

#[test]
fn exact_law_matches_30_digit_references() {
    let mut worst: f64 = 0.0;
    for &(p, d, f, m) in REFERENCE {
        let (fe, me) = contensou::exact(p, d);
        worst = worst.max((fe - f).abs()).max((me - m).abs());
    }
    // Measured 6e-16 (a few ulps); the references at 0.3 and 2 carry 15
    // digits, the rest 17.
    assert!(worst < 1e-14, "worst error {worst:e}");
}

/// The closed-form limits of §contensou: the torque at zero slip `⟨ρ⟩` (2/3
/// uniform, 3π/16 Hertz), the force at small slip `f'(0) d` (1, 3π/8),
/// and the large-slip tails `1 − f ≈ ⟨ρ²⟩/(4d²)`, `m ≈ ⟨ρ²⟩/(2d)` — each
/// through the quadrature (d >= 1e-5, above the series cut at 1e-6).
#[test]
fn exact_law_has_its_closed_form_limits() {
    use std::f64::consts::PI;
    for (p, m0, s1, r2) in [
        (Pressure::Uniform, 2.0 / 3.0, 1.0, 0.5),
        (Pressure::Hertz, 3.0 * PI / 16.0, 3.0 * PI / 8.0, 0.4),
    ] {
        assert_eq!(p.zero_slip_torque(), m0);
        // Zero slip: exactly (0, m0).
        assert_eq!(contensou::exact(p, 0.0), (0.0, m0));
        // Small slip, d = 1e-5: f/d − f'(0) and m − m0 are O(d²).
        let d = 1e-5;
        let (f, m) = contensou::exact(p, d);
        assert!((f / d - s1).abs() < 1e-9, "{p:?}: f/d = {}", f / d);
        assert!((m - m0).abs() < 1e-9, "{p:?}: m = {m}");
        // Slip dominating: f → 1 (μN), m → 0, with the tails' coefficients
        // (next terms O(1/d⁴), O(1/d³); at d = 1e4, 1 − f = 1e-9 is left with
        // 1e-7 of rounding, so the force tail is checked to 1e3).
        for d in [1e2, 1e3] {
            let (f, m) = contensou::exact(p, d);
            let tail_f = (1.0 - f) * 4.0 * d * d / r2;
            let tail_m = m * 2.0 * d / r2;
            assert!(
                (tail_f - 1.0).abs() < 30.0 / (d * d),
                "{p:?} d {d}: {tail_f}"
            );
            assert!(
                (tail_m - 1.0).abs() < 30.0 / (d * d),
                "{p:?} d {d}: {tail_m}"
            );
        }
        assert_eq!(contensou::exact(p, f64::INFINITY), (1.0, 0.0));
        // Monotone: the force grows and the torque falls with d.
        let mut last = (0.0, m0);
        for i in 1..=200 {
            let d = 10f64.powf(-4.0 + 8.0 * i as f64 / 200.0);
            let (f, m) = contensou::exact(p, d);
            assert!(f > last.0 && m < last.1, "{p:?} d {d}: not monotone");
            last = (f, m);
        }
    }
}

/// The Padé form within its stated error [`contensou::PADE_MAX_ERROR`] of
/// the exact law over 10⁻⁴ <= d <= 10⁴ (beyond, both are at their limits),
/// and the stated error not loose by more than a factor 1.5 (measured
/// 0.038 uniform, 0.033 Hertz, fitted on a coarser grid).
#[test]
fn pade_form_within_its_stated_error() {
    for p in [Pressure::Uniform, Pressure::Hertz] {
        let mut worst: f64 = 0.0;
        for i in 0..=800 {
            let d = 10f64.powf(-4.0 + 8.0 * i as f64 / 800.0);
            let (fe, me) = contensou::exact(p, d);
            let (fp, mp) = contensou::pade(p, d);
            worst = worst.max((fe - fp).abs()).max((me - mp).abs());
        }
        println!("{p:?}: Padé max error {worst:.4}");
        assert!(worst <= contensou::PADE_MAX_ERROR, "{p:?}: {worst}");
        assert!(worst > contensou::PADE_MAX_ERROR / 1.5, "{p:?}: {worst}");
        // Its limits are the exact ones.
        assert_eq!(contensou::pade(p, 0.0), (0.0, p.zero_slip_torque()));
        let d = 1e-7;
        assert!((contensou::pade(p, d).0 / d - p.small_slip_slope()).abs() < 1e-5);
    }
}

/// The stick set: with no force the disc holds a torque up to m(0); with no
/// torque a force up to μN; a pair on the limit curve is held, just outside
/// it is not.
#[test]
fn stick_bounds_are_the_zero_slip_torque_and_mu_n() {
    for p in [Pressure::Uniform, Pressure::Hertz] {
        let m0 = p.zero_slip_torque();
        assert!(contensou::sticks(p, 0.0, m0));
        assert!(!contensou::sticks(p, 0.0, m0 * (1.0 + 1e-12)));
        assert!(contensou::sticks(p, 1.0, 0.0));
        assert!(!contensou::sticks(p, 1.0 + 1e-12, 0.0));
        for d in [0.1, 0.653, 1.0, 3.0] {
            let (f, m) = contensou::exact(p, d);
            assert!(contensou::sticks(p, f, m * (1.0 - 1e-9)), "{p:?} d {d}");
            assert!(!contensou::sticks(p, f, m * (1.0 + 1e-9)), "{p:?} d {d}");
        }
    }
}

/// Farkas, Bartels, Unger & Wolf, Phys. Rev. Lett. 90, 248302 (2003): a flat uniform disc (radius R,
/// I = m R²/2, uniform pressure over its face, r_c = R) sliding and spinning
/// on a plane stops sliding and spinning at the same instant, with
/// v/(R ω) → 0.653 whatever the start. Equations: v̇ = −μ g f(ε),
/// ω̇ = −2 μ g m(ε)/R, ε = v/(R ω). In the time τ, dτ = μ g dt/(R ω) (a
/// change of clock: the motion is the same), they read dε/dτ = 2 ε m − f,
/// d ln ω/dτ = −2 m; RK4 in τ to ω = 1e-12 ω0, with t = ∫ R ω dτ/(μ g)
/// alongside: t converges (the disc stops at a finite time) while ε
/// converges to a finite, non-zero value (v and ω vanish together).
#[test]
fn flat_disc_stops_sliding_and_spinning_together_at_0_653() {
    let (mu, g, r, w0) = (0.3, 9.8, 0.05, 50.0f64);
    for eps0 in [0.05, 0.5, 3.0, 20.0] {
        // (ε, ln ω, t)
        let rhs = |y: [f64; 3]| {
            let (f, m) = contensou::exact(Pressure::Uniform, y[0]);
            [2.0 * y[0] * m - f, -2.0 * m, r * y[1].exp() / (mu * g)]
        };
        let mut y = [eps0, w0.ln(), 0.0];
        let dtau = 1e-3;
        let mut t_half = None;
        while y[1] > (1e-12 * w0).ln() {
            let k1 = rhs(y);
            let k2 = rhs(std::array::from_fn(|i| y[i] + 0.5 * dtau * k1[i]));
            let k3 = rhs(std::array::from_fn(|i| y[i] + 0.5 * dtau * k2[i]));
            let k4 = rhs(std::array::from_fn(|i| y[i] + dtau * k3[i]));
            for i in 0..3 {
                y[i] += dtau / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if t_half.is_none() && y[1] < (1e-6 * w0).ln() {
                t_half = Some(y[2]);
            }
        }
        let t_half = t_half.unwrap();
        println!(
            "eps0 {eps0}: ratio {:.6}, stop at {:.6} s ({:.3e} s after w = 1e-6 w0)",
            y[0],
            y[2],
            y[2] - t_half
        );
        // The published 0.653 (three digits; the fixed point of
        // f(ε) = 2 ε m(ε) is 0.653002, mpmath).
        assert!((y[0] - 0.653).abs() < 1e-3, "eps0 {eps0}: {}", y[0]);
        // Finite stopping time: from ω = 1e-6 ω0 on, t moves by O(1e-6) of
        // the initial scale R ω0 (1 + ε0)/(μ g).
        assert!(y[2] - t_half < 1e-5 * r * w0 * (1.0 + eps0) / (mu * g));
    }
}

fn classical_contensou(radius: f64, pade: bool) -> tippetop::Scenario {
    let mut sc = tippetop::Scenario::classical();
    sc.surface.law = tippetop::FrictionLaw::Contensou {
        radius,
        pressure: Pressure::Hertz,
        pade,
    };
    sc
}

/// r_c = 0 is today's point law, bit for bit, in every model.
#[test]
fn zero_contact_radius_is_the_point_law_bit_for_bit() {
    use crate::spec::*;
    each_model(&[], |m| {
        let a = run(&tippetop::Scenario::classical(), m);
        let b = run(&classical_contensou(0.0, false), m);
        assert_eq!(a.samples.len(), b.samples.len());
        for (x, y) in a.samples.iter().zip(&b.samples) {
            assert_eq!(format!("{x:?}"), format!("{y:?}"));
        }
        assert_eq!(a.events.len(), b.events.len());
    });
}

/// The classical top (R = 15 mm): under the point law it rolls and never
/// inverts (θ stays below π/2 over the preset's 10 s); with a Hertz
/// contact disc of r_c = 0.3 mm it slides, inverts (θ > 3 rad at the end)
/// in every model, and the energy balance E − E0 = W_f + W_a, the drilling
/// torque's work M n_Z inside W_f, holds to 1e-9 of max|E| (measured
/// 2e-13 … 1.2e-10, the point law's bar). The Padé form inverts too.
#[test]
fn classical_top_inverts_with_its_contact_patch() {
    use crate::spec::*;
    each_model(&[], |m| {
        let point = run(&tippetop::Scenario::classical(), m);
        let max_point = point.samples.iter().map(|s| s.theta).fold(0.0, f64::max);
        assert!(max_point < std::f64::consts::FRAC_PI_2, "{max_point}");
        for pade in [false, true] {
            let tr = run(&classical_contensou(3e-4, pade), m);
            let last = tr.samples.last().unwrap();
            let res = balance_residual(&tr);
            println!(
                "{m:?} pade {pade}: theta_end {:.6}, balance {res:.2e}",
                last.theta
            );
            assert!(last.theta > 3.0, "theta_end {}", last.theta);
            assert!(res < 1e-9, "balance {res:e}");
            // Friction dissipated a visible part of the energy.
            assert!(last.work_friction < -0.3 * tr.summary.energy_initial);
        }
    });
}

/// Langevin dynamics refuses friction (μ > 0) with the Contensou law too.
#[test]
fn langevin_refuses_contensou_friction() {
    let toml = r#"
preset = "nano"
[surface]
friction = 0.1
friction_law = "contensou"
contact_radius = 1e-11
[solver]
method = "langevin"
model = "vector"
dt = 1e-12
[thermal]
temperature = 300
seed = 1
damping_translational = 1e10
damping_rotational = 1e10
"#;
    let err = tippetop::Scenario::from_toml_str(toml)
        .unwrap_err()
        .to_string();
    assert!(err.contains("no thermal partner"), "{err}");
}

/// Bad input names the key and the range.
#[test]
fn contact_radius_and_pressure_are_validated() {
    for (extra, key) in [
        (
            "friction_law = \"contensou\"\ncontact_radius = -1e-4",
            "surface.contact_radius",
        ),
        (
            "friction_law = \"contensou\"\ncontact_radius = 2e-3",
            "surface.contact_radius",
        ),
        ("friction_law = \"contensou\"", "surface.contact_radius"),
        (
            "friction_law = \"coulomb\"\ncontact_radius = 1e-4",
            "surface.contact_radius",
        ),
        (
            "friction_law = \"contensou\"\ncontact_radius = 1e-4\ncontact_pressure = \"flat\"",
            "surface.contact_pressure",
        ),
        (
            "friction_law = \"contensou\"\ncontact_radius = 1e-4\ncontact = \"paper\"",
            "surface.friction_law",
        ),
    ] {
        let toml = format!("preset = \"classical\"\n[surface]\n{extra}\n");
        let err = tippetop::Scenario::from_toml_str(&toml)
            .unwrap_err()
            .to_string();
        assert!(err.contains(key), "{extra}: {err}");
    }
    let ok = "preset = \"classical\"\n[surface]\nfriction_law = \"contensou_pade\"\ncontact_radius = 1e-3\ncontact_pressure = \"uniform\"\n";
    let sc = tippetop::Scenario::from_toml_str(ok).unwrap();
    // The resolved scenario (scenario.toml of a run) reads back the same.
    let back = tippetop::Scenario::from_toml_str(&sc.to_toml_string()).unwrap();
    assert_eq!(back.surface.law, sc.surface.law);
    assert_eq!(
        sc.surface.law,
        tippetop::FrictionLaw::Contensou {
            radius: 1e-3,
            pressure: Pressure::Uniform,
            pade: true
        }
    );
}

/// `n_Z = Ω sin²θ + ω cos θ` of an output row \[rad/s\].
fn spin_about_z(s: &tippetop::Sample) -> f64 {
    s.precession * s.theta.sin().powi(2) + s.spin * s.theta.cos()
}

/// Sliding and spinning both stop, then the stick: a uniform sphere
/// (a = 0, A = C = I) spinning at 50 rad/s about an axis tilted by 0.5 rad,
/// μ = 0.2, Hertz disc r_c = 0.3 mm. Its n_Z changes only by the drilling
/// torque (the friction force at P = −R Z has no moment about Z),
/// `I ṅ_Z = −μ m g r_c m(d)`, and `m(d) <= m(0)`, so the spin about Z
/// stops no earlier than `t₀ = n_Z0 I/(μ m g r_c m(0))` = 11.40 s, and only
/// a little later (the slip relaxes within a fraction of a second, after
/// which d ≈ 0). Every model records the `contensou_stick` event there
/// (the three times agree to 1e-7) and runs on to its end in the stick:
/// the sphere needs no wrench to roll without drilling, so it stays stuck
/// (the flat disc of Farkas et al. likewise stays at rest), and rolls on a
/// straight line with the closed form of a rolling sphere,
/// `E − m g R = (7/10) m |u|²` (½ m u² + ½ (2/5 m R²)(u/R)², which holds
/// only with zero slip and zero spin about Z), |u| constant, no
/// dissipation (`W_f` constant), the energy balance to 1e-10 of max|E|.
#[test]
fn sphere_stops_sliding_and_spinning_then_rolls_in_the_stick() {
    use crate::spec::*;
    let mut sc = uniform_sphere(0.5, 50.0, 0.2);
    sc.surface.law = tippetop::FrictionLaw::Contensou {
        radius: 3e-4,
        pressure: Pressure::Hertz,
        pade: false,
    };
    sc.solver.t_end = 20.0;
    sc.solver.samples = 201;
    let (m, r, g) = (sc.top.mass, sc.top.radius, sc.surface.gravity);
    let inertia = 0.4 * m * r * r;
    let t0 =
        50.0 * 0.5f64.cos() * inertia / (0.2 * m * 9.8 * 3e-4 * Pressure::Hertz.zero_slip_torque());
    let stops = std::sync::Mutex::new(Vec::new());
    each_model(&[], |model| {
        let tr = run(&sc, model);
        let t = times(&tr, "contensou_stick");
        assert_eq!(t.len(), 1, "{:?}", tr.events);
        assert!(times(&tr, "slip").is_empty(), "{:?}", tr.events);
        assert!(t[0] >= t0 && t[0] <= 1.01 * t0, "{} vs {t0}", t[0]);
        assert!(balance_residual(&tr) < 1e-10, "{:e}", balance_residual(&tr));
        let stuck: Vec<_> = tr.samples.iter().filter(|s| s.t > t[0]).collect();
        assert!(stuck.len() > 80);
        let speed = |s: &tippetop::Sample| s.ux.hypot(s.uy);
        let (u0, wf0) = (speed(stuck[0]), stuck[0].work_friction);
        let (mut closed, mut du, mut dw, mut nz) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for s in &stuck {
            assert_eq!(s.rolling, 1);
            assert_eq!(s.slip, 0.0);
            nz = nz.max(spin_about_z(s).abs());
            let u = speed(s);
            closed = closed.max((s.energy - m * g * r - 0.7 * m * u * u).abs() / s.energy);
            du = du.max((u - u0).abs() / u0);
            dw = dw.max((s.work_friction - wf0).abs() / s.energy);
        }
        println!(
            "{model:?}: stick at {} s (bound {t0} s); in the stick |u| = {u0:.6} m/s: closed form off {closed:.1e}, |u| drift {du:.1e}, W_f drift {dw:.1e}, |n_Z| <= {nz:.1e} rad/s",
            t[0]
        );
        assert!(u0 > 0.05, "{u0}");
        assert!(
            closed < 1e-9 && du < 1e-9 && dw < 1e-12,
            "{closed:e} {du:e} {dw:e}"
        );
        assert!(nz < 1e-8, "{nz:e}");
        stops.lock().unwrap().push(t[0]);
    });
    let s = stops.into_inner().unwrap();
    let (lo, hi) = s
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(hi - lo < 1e-7 * hi, "{s:?}");
}

/// The gauge of the limit curve: on the ray through `λ (f(d), m(d))` it
/// finds `λ` and `d` back (both laws, both pressures, `d` from 1e-3 to 1e3),
/// and `λ <= 1` is the exact law's `sticks`.
#[test]
fn gauge_finds_the_limit_curve_on_each_ray() {
    for p in [Pressure::Uniform, Pressure::Hertz] {
        for pade in [false, true] {
            for d in [1e-3, 0.05, 0.3, 0.653, 1.0, 1.7, 10.0, 1e3] {
                let (f, m) = contensou::law(p, pade, d);
                for lambda in [0.2, 0.999, 1.0, 1.5] {
                    let (l, dg) = contensou::gauge(p, pade, lambda * f, lambda * m);
                    assert!(
                        (l - lambda).abs() < 1e-12,
                        "{p:?} {pade} d {d}: {l} vs {lambda}"
                    );
                    assert!(
                        (dg - d).abs() < 1e-9 * d.max(1.0),
                        "{p:?} {pade}: d {dg} vs {d}"
                    );
                    if !pade && (lambda - 1.0).abs() > 1e-6 {
                        assert_eq!(contensou::sticks(p, lambda * f, lambda * m), l <= 1.0);
                    }
                }
            }
            let m0 = p.zero_slip_torque();
            assert_eq!(contensou::gauge(p, pade, 0.0, 0.5 * m0), (0.5, 0.0));
            assert_eq!(contensou::gauge(p, pade, 0.7, 0.0), (0.7, f64::INFINITY));
            assert_eq!(contensou::gauge(p, pade, 0.0, 0.0), (0.0, 0.0));
        }
    }
}

/// The classical top (a = 0.1 R) started rolling without drilling
/// (θ = 0.5, Ω = 5 rad/s, ω = −Ω sin²θ/cos θ so that n_Z = 0, u the rolling
/// velocity), μ = 0.03, Hertz disc r_c = 0.3 mm, 2 s. The wrench the stick
/// needs at t = 0 is outside the limit curve (it slips off at once); then
/// it sticks and slips again and again. Checked in all three models, whose
/// stick equations are derived independently (the reduced model's 2×2
/// system in its Euler angles, the vector and rigid models' 4×4 one):
/// - the same stick and slip times (to 2e-5 s; measured 6e-6), at least
///   four of each;
/// - in the stick (rolling = 1): zero slip, |n_Z| < 1e-8 rad/s, no
///   dissipation (W_f constant within each stick), and the needed wrench
///   — recomputed at each output row by the reduced model's stick
///   equations — inside the limit curve (gauge <= 1 + 1e-9);
/// - the energy balance, the drilling torque's work and the stick
///   projections' inside W_f, to 1e-10 of max|E|.
#[test]
fn eccentric_top_sticks_and_slips_within_the_limit_curve() {
    use crate::spec::*;
    use tippetop::model::reduced::{Mode, Reduced, TH};
    let mut sc = classical_contensou(3e-4, false);
    let (th, om) = (0.5f64, 5.0);
    let (s, c) = th.sin_cos();
    let a = sc.top.offset / sc.top.radius;
    sc.initial.theta = th;
    sc.initial.precession = om;
    sc.initial.spin = -om * s * s / c;
    sc.initial.uy = -s * (sc.initial.spin - om * c + a * om) * sc.top.radius;
    sc.surface.friction = 0.03;
    sc.solver.t_end = 2.0;
    sc.solver.samples = 401;
    let rc = 3e-4 / sc.top.radius;
    let events = std::sync::Mutex::new(Vec::new());
    each_model(&[], |model| {
        let tr = run(&sc, model);
        let st = times(&tr, "contensou_stick");
        let sl = times(&tr, "slip");
        assert!(st.len() >= 4 && sl.len() >= 4, "{:?}", tr.events);
        assert_eq!(sl[0], 0.0, "slips off at t = 0");
        let res = balance_residual(&tr);
        assert!(res < 1e-10, "balance {res:e}");
        let mut red = Reduced::new(&sc);
        red.plane.mode = Mode::Rolling;
        let (mut worst, mut nz, mut dw, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        let em = emax(&tr);
        for w in tr.samples.windows(2) {
            let x = &w[1];
            if x.rolling != 1 {
                continue;
            }
            assert_eq!(x.slip, 0.0);
            nz = nz.max(spin_about_z(x).abs());
            if w[0].rolling == 1 {
                dw = dw.max((x.work_friction - w[0].work_friction).abs() / em);
            }
            let mut init = sc.initial;
            init.theta = x.theta;
            init.theta_dot = x.theta_dot;
            init.precession = x.precession;
            init.spin = x.spin;
            init.ux = x.ux;
            init.uy = x.uy;
            let y = red.scale_state(&init);
            assert_eq!(y[TH], x.theta);
            let e = red.eval(&y).unwrap();
            let cap = 0.03 * e.normal;
            let (l, _) = contensou::gauge(
                Pressure::Hertz,
                false,
                e.friction[0].hypot(e.friction[1]) / cap,
                e.torque.abs() / (cap * rc),
            );
            worst = worst.max(l);
            n += 1;
        }
        println!(
            "{model:?}: stick {st:?}, slip {sl:?}; {n} stuck rows: gauge <= {worst:.6}, |n_Z| <= {nz:.1e}, W_f step {dw:.1e}; balance {res:.1e}"
        );
        assert!(n > 100, "{n}");
        assert!(worst <= 1.0 + 1e-9 && worst > 0.1, "{worst}");
        assert!(nz < 1e-8 && dw < 1e-12, "{nz:e} {dw:e}");
        events.lock().unwrap().push((st, sl));
    });
    let ev = events.into_inner().unwrap();
    for (st, sl) in &ev[1..] {
        assert_eq!(st.len(), ev[0].0.len());
        assert_eq!(sl.len(), ev[0].1.len());
        for (x, y) in st.iter().chain(sl).zip(ev[0].0.iter().chain(&ev[0].1)) {
            assert!((x - y).abs() < 2e-5, "{x} vs {y}");
        }
    }
}

/// r_c → 0 approaches the point law continuously: on the classical top up
/// to 0.04 s (sliding; the point law sticks at 0.047 s) the largest
/// difference in θ, ω/(100 rad/s) and the slip from the point law's run
/// shrinks like r_c²: while d = |v|/(r_c |n_Z|) is large, the force's
/// correction is `1 − f ≈ ⟨ρ²⟩/(4d²)` and the torque
/// `μ N r_c m ≈ μ N ⟨ρ²⟩ r_c² |n_Z|/(2|v|)`, both O(r_c²) (§contensou): ×10
/// smaller r_c, ×100 smaller difference within 10 % (measured 99.997).
#[test]
fn small_contact_radius_approaches_the_point_law() {
    use crate::spec::*;
    each_model(&[], |m| {
        let mut point = tippetop::Scenario::classical();
        point.solver.t_end = 0.04;
        point.solver.samples = 41;
        let p = run(&point, m);
        let diff = |rc: f64| {
            let mut sc = classical_contensou(rc, false);
            sc.solver.t_end = 0.04;
            sc.solver.samples = 41;
            let tr = run(&sc, m);
            tr.samples
                .iter()
                .zip(&p.samples)
                .map(|(a, b)| {
                    (a.theta - b.theta)
                        .abs()
                        .max((a.spin - b.spin).abs() / 100.0)
                        .max((a.slip - b.slip).abs())
                })
                .fold(0.0, f64::max)
        };
        let (d5, d6) = (diff(1e-5), diff(1e-6));
        println!(
            "{m:?}: r_c 1e-5: {d5:.3e}, 1e-6: {d6:.3e}, ratio {:.3}",
            d5 / d6
        );
        assert!(d5 > 0.0 && d5 < 1e-4, "{d5:e}");
        assert!((d5 / d6 - 100.0).abs() < 10.0, "{}", d5 / d6);
    });
}

/// The rigid model's touchdown impulse under Coulomb–Contensou friction
/// (docs/physics.md#contensou), on a state of the classical top (θ = 0.5) given a
/// downward velocity (restitution e = 0.5), with `Π = Δv` (m = 1, scaled)
/// and the angular impulse about Z `Π_M = (I Δn − r × Π)_Z` read off the
/// state's jump:
/// - sliding (slip 0.3, n_Z = 5, scaled): `Π_t = −μ f(d) Π_n t̂`,
///   `Π_M = −μ r_c m(d) Π_n sign n_Z`, `d` the pre-impact ratio; P's normal
///   velocity after is `−e v_n⁻`; the kinetic energy does not grow;
/// - sticking (slip and spin 1e-4 of that): no slip and no spin about Z
///   after, the impulse inside the limit curve;
/// - r_c = 1e-9 m: the point law's impulse (to 1e-9).
#[test]
fn rigid_impact_follows_the_contensou_law() {
    use tippetop::model::rigid::{self, Rigid as RigidModel};
    let mut sc = classical_contensou(3e-4, false);
    sc.surface.contact = tippetop::ContactMode::Unilateral;
    sc.surface.restitution = 0.5;
    sc.initial.theta = 0.5;
    let (e, mu) = (0.5, sc.surface.friction);
    let make = |sc: &tippetop::Scenario, slip: f64, nz: f64| {
        let m = RigidModel::new(sc);
        let mut y = m.scale_state(&sc.initial);
        y[rigid::OMEGA + 2] = nz;
        let kin = m.kin(&y);
        // v = slip X − n × r, then a downward 0.4.
        let nr = [
            kin.n[1] * kin.r[2] - kin.n[2] * kin.r[1],
            kin.n[2] * kin.r[0] - kin.n[0] * kin.r[2],
        ];
        y[rigid::VEL] = slip - nr[0];
        y[rigid::VEL + 1] = -nr[1];
        y[rigid::VEL + 2] -= 0.4;
        (m, y)
    };
    let scales = tippetop::model::reduced::Scales::of(&sc);
    let (ia, ic) = (
        sc.top.inertia_transverse / scales.inertia(),
        sc.top.inertia_axial / scales.inertia(),
    );
    let rc = 3e-4 / sc.top.radius;
    let jump = |m: &RigidModel, y: &[f64; rigid::DIM], yn: &[f64; rigid::DIM]| {
        let kin = m.kin(y);
        let p: Vec<f64> = (0..3)
            .map(|i| yn[rigid::VEL + i] - y[rigid::VEL + i])
            .collect();
        let dn: Vec<f64> = (0..3)
            .map(|i| yn[rigid::OMEGA + i] - y[rigid::OMEGA + i])
            .collect();
        let k = kin.k;
        let dnk = dn[0] * k[0] + dn[1] * k[1] + dn[2] * k[2];
        let ldz = ia * dn[2] + (ic - ia) * dnk * k[2];
        let rxp = kin.r[0] * p[1] - kin.r[1] * p[0];
        ([p[0], p[1], p[2]], ldz - rxp, kin)
    };
    let kinetic = |y: &[f64; rigid::DIM]| {
        let v: f64 = (0..3).map(|i| y[rigid::VEL + i].powi(2)).sum();
        let n = [y[rigid::OMEGA], y[rigid::OMEGA + 1], y[rigid::OMEGA + 2]];
        let k = [y[rigid::AXIS], y[rigid::AXIS + 1], y[rigid::AXIS + 2]];
        let nk = n[0] * k[0] + n[1] * k[1] + n[2] * k[2];
        0.5 * v + 0.5 * (ia * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + (ic - ia) * nk * nk)
    };
    // Sliding.
    let (m, y) = make(&sc, 0.3, 5.0);
    let (yn, _, stuck) = m.impact(&y).unwrap();
    assert!(!stuck);
    let (p, pm, kin) = jump(&m, &y, &yn);
    let d = kin.vp[0].hypot(kin.vp[1]) / (rc * 5.0);
    let (f, mm) = contensou::exact(Pressure::Hertz, d);
    let scale = p[2];
    assert!(scale > 0.0);
    assert!((p[0] + mu * f * p[2]).abs() < 1e-12 * scale, "{p:?}");
    assert!(p[1].abs() < 1e-12 * scale, "{p:?}");
    assert!(
        (pm + mu * rc * mm * p[2]).abs() < 1e-12 * scale,
        "{pm} d {d}"
    );
    let after = m.kin(&yn).vp;
    assert!((after[2] + e * kin.vp[2]).abs() < 1e-12, "{after:?}");
    assert!(kinetic(&yn) <= kinetic(&y));
    println!(
        "sliding: d {d:.4}, Π_n {:.4}, Π_M/(μ r_c Π_n) {:.4} (m(d) {mm:.4})",
        p[2],
        -pm / (mu * rc * p[2])
    );
    // Sticking.
    let (m, y) = make(&sc, 3e-5, 5e-4);
    let (yn, _, stuck) = m.impact(&y).unwrap();
    assert!(stuck);
    let (p, pm, kin) = jump(&m, &y, &yn);
    let after = m.kin(&yn);
    assert!(after.vp[0].hypot(after.vp[1]) < 1e-15, "{:?}", after.vp);
    assert!(after.n[2].abs() < 1e-15, "{}", after.n[2]);
    assert!((after.vp[2] + e * kin.vp[2]).abs() < 1e-12);
    let (l, _) = contensou::gauge(
        Pressure::Hertz,
        false,
        p[0].hypot(p[1]) / (mu * p[2]),
        pm.abs() / (mu * rc * p[2]),
    );
    assert!(l <= 1.0, "{l}");
    assert!(kinetic(&yn) <= kinetic(&y));
    // r_c → 0: the point law's impulse.
    let mut tiny = sc.clone();
    tiny.surface.law = tippetop::FrictionLaw::Contensou {
        radius: 1e-9,
        pressure: Pressure::Hertz,
        pade: false,
    };
    let mut point = sc.clone();
    point.surface.law = tippetop::FrictionLaw::Coulomb;
    let (mt, yt) = make(&tiny, 0.3, 5.0);
    let (mp, yp) = make(&point, 0.3, 5.0);
    let (a, _, _) = mt.impact(&yt).unwrap();
    let (b, _, _) = mp.impact(&yp).unwrap();
    let diff = (0..rigid::DIM)
        .map(|i| (a[i] - b[i]).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-9, "{diff:e}");
}

/// Bouncing under Coulomb–Contensou friction (the rigid model, unilateral
/// contact, e = 0.5; knocked off the plane by H_x = −2 N for 3 ms, as the
/// point-law test in rigid.rs): many touchdowns, each impact booked in
/// W_f, the energy balance to 1e-8 of max|E| (the point law's bar), and the
/// touchdowns removed energy.
#[test]
fn contensou_bounces_keep_the_energy_balance() {
    use crate::spec::*;
    let mut sc = classical_contensou(3e-4, false);
    sc.surface.contact = tippetop::ContactMode::Unilateral;
    sc.surface.restitution = 0.5;
    sc.initial.theta = 0.5;
    sc.forcing = tippetop::Forcing {
        windows: vec![tippetop::ForceWindow {
            hx: -2.0,
            hy: 0.0,
            hz: 0.0,
            start: 0.0,
            stop: 0.003,
        }],
    };
    sc.solver.t_end = 0.2;
    let tr = run(&sc, Rigid);
    let td = times(&tr, "touchdown");
    let res = balance_residual(&tr);
    println!(
        "{} touchdowns, balance {res:.1e}, W_f {:e} J",
        td.len(),
        tr.samples.last().unwrap().work_friction
    );
    assert!(td.len() >= 10, "{}", td.len());
    assert!(res < 1e-8, "{res:e}");
    assert!(tr.samples.last().unwrap().work_friction < 0.0);
}

/// A force switch while stuck: a uniform sphere at rest (θ = 0.5, a = 0,
/// μ = 0.2, Hertz disc r_c = 0.3 mm) starts in the stick (no wrench
/// needed); at 0.05 s a horizontal force H at the contact point switches
/// on. To keep rolling with a force at P the sphere needs the friction
/// `F_f = H` exactly (the contact force's net must vanish: `a_P =
/// (1/m + R²/I) (F_f − H) = 0`) and no drilling torque, so the stick holds
/// iff `H <= μ m g` (the Contensou limit with M = 0 is the point law's):
/// at 0.99 μ m g it stays stuck to the end (and at rest: the friction
/// cancels the force at P), at 1.01 μ m g it slips at the switch, in every
/// model.
#[test]
fn force_switch_while_stuck_slips_at_mu_m_g() {
    use crate::spec::*;
    let mut sc = uniform_sphere(0.5, 0.0, 0.2);
    sc.surface.law = tippetop::FrictionLaw::Contensou {
        radius: 3e-4,
        pressure: Pressure::Hertz,
        pade: false,
    };
    sc.solver.t_end = 0.1;
    sc.solver.samples = 101;
    let limit = 0.2 * sc.top.mass * sc.surface.gravity;
    each_model(&[], |model| {
        for (k, slips) in [(0.99, false), (1.01, true)] {
            let mut sc = sc.clone();
            sc.forcing = tippetop::Forcing {
                windows: vec![tippetop::ForceWindow {
                    hx: k * limit,
                    hy: 0.0,
                    hz: 0.0,
                    start: 0.05,
                    stop: f64::INFINITY,
                }],
            };
            let tr = run(&sc, model);
            assert_eq!(times(&tr, "contensou_stick"), vec![0.0], "{:?}", tr.events);
            let sl = times(&tr, "slip");
            if slips {
                assert_eq!(sl, vec![0.05], "{model:?} {k}: {:?}", tr.events);
            } else {
                assert!(sl.is_empty(), "{model:?} {k}: {:?}", tr.events);
                assert!(tr.samples.iter().all(|s| s.rolling == 1 && s.slip == 0.0));
                // The friction cancels the force at P: the sphere stays at rest.
                let u = tr
                    .samples
                    .iter()
                    .map(|s| s.ux.hypot(s.uy))
                    .fold(0.0, f64::max);
                assert!(u < 1e-15, "{u:e}");
            }
            assert!(balance_residual(&tr) < 1e-10, "{:e}", balance_residual(&tr));
        }
    });
}
