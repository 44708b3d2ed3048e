//! Stability analysis (App. B): the axis-vector model against the reduced
//! model, the linearisation against analytic characteristic polynomials, the
//! sleeping-top threshold, and the classical top's verdicts.

use tippetop::{
    FrictionLaw, Scenario, Top,
    analysis::stability::{self, Physics, SmoothLaw, Verdict},
    model::reduced::{Reduced, TH},
};

fn classical_physics(mu: f64, eps: f64) -> Physics {
    Physics {
        top: Top::classical(),
        gravity: 9.8,
        mu,
        law: SmoothLaw::Regularized,
        eps,
    }
}

#[test]
fn axis_model_matches_reduced_model() {
    for (preset, eps) in [("classical", 0.02), ("nano", 1e-7)] {
        let mut sc = Scenario::preset(preset).unwrap();
        sc.surface.law = FrictionLaw::Regularized { eps };
        sc.forcing = tippetop::Forcing::none();
        // The axis model uses N with its sign (the paper's contact); states
        // with N < 0 are included on purpose.
        sc.surface.contact = tippetop::ContactMode::Paper;
        let m = Reduced::new(&sc);
        let (tu, vu) = (m.scales.time, m.scales.velocity());
        let ph = Physics {
            top: sc.top,
            gravity: sc.surface.gravity,
            mu: sc.surface.friction,
            law: SmoothLaw::Regularized,
            eps,
        };
        for (th, thd, om, w, ux, uy) in [
            (0.7, 3.0, 20.0, 90.0, 0.01, -0.02),
            (2.3, -1.0, -15.0, 60.0, -0.03, 0.005),
            (1.5, 0.5, 5.0, -40.0, 0.0, 0.0),
        ] {
            let f = 1.0 / tu;
            let ysi = [th, thd * f, om * f, w * f, ux * vu, uy * vu];
            let mut y = [0.0; tippetop::model::reduced::DIM];
            y[TH] = th;
            for i in 1..4 {
                y[i] = ysi[i] * tu;
            }
            y[4] = ysi[4] / vu;
            y[5] = ysi[5] / vu;
            let e = m.eval(&y).unwrap();
            let d = stability::axis_model_derivatives(&ph, ysi);
            let acc = 1.0 / (tu * tu);
            let checks = [
                (d.theta_ddot, e.dy[1] * acc),
                (d.precession_dot, e.dy[2] * acc),
                (d.spin_dot, e.dy[3] * acc),
                (d.ux_dot, e.dy[4] * vu / tu),
                (d.uy_dot, e.dy[5] * vu / tu),
                (d.normal, e.normal * m.scales.force()),
            ];
            let scale_acc = (w * f).powi(2).max(1.0 / tu / tu);
            for (i, (a, b)) in checks.iter().enumerate() {
                let sc_ = match i {
                    0..=2 => scale_acc,
                    3 | 4 => scale_acc * sc.top.radius,
                    _ => scale_acc * sc.top.radius * sc.top.mass,
                };
                assert!(
                    (a - b).abs() <= 1e-10 * sc_,
                    "{preset} component {i}: axis {a:e} reduced {b:e}"
                );
            }
        }
    }
}

// --- a small complex type for the analytic characteristic polynomials ---

#[derive(Debug, Clone, Copy, PartialEq)]
struct Cx(f64, f64);
impl std::ops::Add for Cx {
    type Output = Cx;
    fn add(self, o: Cx) -> Cx {
        Cx(self.0 + o.0, self.1 + o.1)
    }
}
impl std::ops::Sub for Cx {
    type Output = Cx;
    fn sub(self, o: Cx) -> Cx {
        Cx(self.0 - o.0, self.1 - o.1)
    }
}
impl std::ops::Mul for Cx {
    type Output = Cx;
    fn mul(self, o: Cx) -> Cx {
        Cx(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
}
impl std::ops::Div for Cx {
    type Output = Cx;
    fn div(self, o: Cx) -> Cx {
        let d = o.0 * o.0 + o.1 * o.1;
        Cx(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
}
impl Cx {
    fn abs(self) -> f64 {
        self.0.hypot(self.1)
    }
    fn r(x: f64) -> Cx {
        Cx(x, 0.0)
    }
}

/// Roots of the polynomial with coefficients `c` (highest first) by
/// Durand–Kerner.
fn roots(c: &[Cx]) -> Vec<Cx> {
    let n = c.len() - 1;
    let lead = c[0];
    let c: Vec<Cx> = c.iter().map(|&x| x / lead).collect();
    let scale = c[1..].iter().map(|x| x.abs()).fold(0.0, f64::max) + 1.0;
    let mut z: Vec<Cx> = (0..n)
        .map(|k| {
            let a = 0.4 + 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            Cx(scale * a.cos(), scale * a.sin())
        })
        .collect();
    let p = |x: Cx| c.iter().fold(Cx::r(0.0), |acc, &ci| acc * x + ci);
    for _ in 0..2000 {
        for i in 0..n {
            let mut den = Cx::r(1.0);
            for j in 0..n {
                if j != i {
                    den = den * (z[i] - z[j]);
                }
            }
            z[i] = z[i] - p(z[i]) / den;
        }
    }
    z
}

/// The analytic characteristic polynomial at a pole (derived in the
/// physics-doc section), as coefficients of λ³, λ², λ, 1. With z = p + i q
/// the horizontal part of k and u the complex horizontal velocity,
/// `A z̈ ∓ i C ω ż ± a N z = d F`, `m u̇ = F`, `F = −κ (u + i ω R z + d ż)`,
/// `κ = μ N/ε`, `d = a − R` (θ = 0, upper signs) or `a + R` (θ = π).
fn pole_polynomial(top: &Top, g: f64, mu: f64, eps: f64, upright: bool, w: f64) -> Vec<Cx> {
    let (a, ia, ic, r, m) = (
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
        top.radius,
        top.mass,
    );
    let n = m * g;
    let kappa = mu * n / eps;
    let (sg, d) = if upright { (1.0, a - r) } else { (-1.0, a + r) };
    // (A λ² ∓ i C ω λ ± a N)(m λ + κ) + d κ m λ (i ω R + d λ)
    let q2 = Cx::r(ia);
    let q1 = Cx(0.0, -sg * ic * w);
    let q0 = Cx::r(sg * a * n);
    let (mm, kk) = (Cx::r(m), Cx::r(kappa));
    vec![
        q2 * mm,
        q2 * kk + q1 * mm + Cx::r(d * kappa * m * d),
        q1 * kk + q0 * mm + Cx(0.0, d * kappa * m * w * r),
        q0 * kk,
    ]
}

fn assert_matches_polynomial(lin: &stability::Linearisation, poly: &[Cx], what: &str) {
    let mut analytic = roots(poly);
    let conj: Vec<Cx> = analytic.iter().map(|z| Cx(z.0, -z.1)).collect();
    analytic.extend(conj);
    assert_eq!(lin.eigenvalues.len(), analytic.len(), "{what}");
    let rho = analytic.iter().map(|z| z.abs()).fold(0.0, f64::max);
    let mut used = vec![false; analytic.len()];
    for e in &lin.eigenvalues {
        let (j, dist) = analytic
            .iter()
            .enumerate()
            .filter(|(j, _)| !used[*j])
            .map(|(j, z)| (j, (Cx(e.re, e.im) - *z).abs()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        used[j] = true;
        assert!(
            dist <= 1e-8 * rho,
            "{what}: eigenvalue {e:?} is {dist:e} from the nearest analytic root (rho {rho:e}); analytic {analytic:?}"
        );
    }
}

#[test]
fn pole_eigenvalues_match_the_analytic_characteristic_polynomial() {
    // Classical and nano tops, with and without friction, upright and inverted.
    let cases = [
        (Top::classical(), 9.8, 0.1, 1.5e-3, 100.0),
        (Top::classical(), 9.8, 0.1, 0.05, 60.0),
        (Top::classical(), 9.8, 0.0, 1e-3, 30.0),
        (Top::nano(), 9.8, 0.13, 5.9e-8, 3e5),
        (Top::nano(), 9.8, 0.13, 1e-5, 100.0),
    ];
    for (top, g, mu, eps, w) in cases {
        let ph = Physics {
            top,
            gravity: g,
            mu,
            law: SmoothLaw::Viscous,
            eps,
        };
        for upright in [true, false] {
            let th = if upright { 0.0 } else { std::f64::consts::PI };
            let lin = stability::linearise(&ph, th, 0.0, w, 1e-8).unwrap();
            assert!(lin.residual < 1e-14, "residual {}", lin.residual);
            let poly = pole_polynomial(&top, g, mu, eps, upright, w);
            assert_matches_polynomial(
                &lin,
                &poly,
                &format!("{top:?} mu {mu} upright {upright} w {w}"),
            );
            // Regularised and viscous laws agree at zero slip.
            let ph_r = Physics {
                law: SmoothLaw::Regularized,
                ..ph
            };
            let lin_r = stability::linearise(&ph_r, th, 0.0, w, 1e-8).unwrap();
            assert_matches_polynomial(&lin_r, &poly, "regularised");
        }
    }
}

#[test]
fn sleeping_top_threshold_on_a_frictionless_plane() {
    // μ = 0, H = 0, θ = π: unstable below ω_c = 2 √(A m g a)/C, marginal above.
    for top in [Top::classical(), Top::nano()] {
        let ph = Physics {
            top,
            gravity: 9.8,
            mu: 0.0,
            law: SmoothLaw::Regularized,
            eps: 1e-3,
        };
        let wc = stability::sleeping_threshold(&top, 9.8);
        let unstable = |w: f64| {
            let lin = stability::linearise(&ph, std::f64::consts::PI, 0.0, w, 1e-8).unwrap();
            assert!(
                lin.max_re > -lin.tol,
                "a conservative system is never asymptotically stable"
            );
            lin.verdict == Verdict::Unstable
        };
        assert!(unstable(0.5 * wc) && !unstable(2.0 * wc));
        let (mut lo, mut hi) = (0.5 * wc, 2.0 * wc);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if unstable(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let w_num = 0.5 * (lo + hi);
        let rel = (w_num - wc).abs() / wc;
        eprintln!("sleeping threshold: numerical {w_num:.9e}, analytic {wc:.9e}, rel {rel:.2e}");
        assert!(rel < 1e-3, "numerical threshold {w_num} vs analytic {wc}");
        // Negative spin: the same threshold in |ω|.
        assert!(unstable(-0.9 * wc) && !unstable(-1.1 * wc));
        // Upright (centre of mass lowest): stable for every ω with μ = 0.
        for w in [0.0, 1e-3 * wc, 0.5 * wc, wc, 10.0 * wc, -3.0 * wc] {
            let lin = stability::linearise(&ph, 0.0, 0.0, w, 1e-8).unwrap();
            assert_eq!(
                lin.verdict,
                Verdict::Marginal,
                "upright at omega {w}: {lin:?}"
            );
        }
    }
}

#[test]
fn classical_top_upright_unstable_inverted_stable_with_friction() {
    // The tippe top's instability: regularised friction, ω = 100 rad/s.
    let ph = classical_physics(0.1, 1.5e-3);
    let up = stability::linearise(&ph, 0.0, 0.0, 100.0, 1e-10).unwrap();
    assert_eq!(up.verdict, Verdict::Unstable, "{up:?}");
    // The inverted top with the spin Jellett's J gives it (n_Z = J/(C(R + a))).
    let sc = Scenario::classical();
    let rep = stability::analyse(
        &sc,
        &stability::Options {
            run: false,
            eps: Some(1.5e-3),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(rep.steady[0].with_friction.verdict, Verdict::Unstable);
    assert_eq!(rep.steady[1].with_friction.verdict, Verdict::Stable);
    assert!(rep.steady[1].with_friction.spin.abs() > rep.sleeping_threshold);
    // Frictionless: only marginal.
    assert_eq!(rep.steady[0].frictionless.verdict, Verdict::Marginal);
    assert_eq!(rep.steady[1].frictionless.verdict, Verdict::Marginal);
    // App. B's verdicts for the classical top: B1 (stable upright) is wrong,
    // B3 (always unstable inverted) is wrong.
    assert_eq!(rep.paper[0].agree, "no");
    assert_eq!(rep.paper[2].agree, "no");
}

#[test]
fn inversion_window_of_the_literature() {
    // Upright unstable iff A/C > 1 − a/R, inverted stable iff A/C < 1 + a/R
    // (a/R = 0.1): both, i.e. inversion, iff 1 − a/R < A/C < 1 + a/R. Checked
    // for weak friction (ε = 10 m/s) and near rolling (ε = 1.5 mm/s).
    for eps in [1.5e-3, 10.0] {
        for (ac, up_unstable, inv_stable) in [
            (0.85, false, true),
            (0.95, true, true),
            (1.05, true, true),
            (1.15, true, false),
        ] {
            let mut top = Top::classical();
            top.inertia_axial = top.inertia_transverse / ac;
            let ph = Physics {
                top,
                ..classical_physics(0.1, eps)
            };
            let up = stability::linearise(&ph, 0.0, 0.0, 100.0, 1e-10).unwrap();
            let inv = stability::linearise(&ph, std::f64::consts::PI, 0.0, -81.0, 1e-10).unwrap();
            assert_eq!(
                up.verdict == Verdict::Unstable,
                up_unstable,
                "eps {eps} A/C {ac}"
            );
            assert_eq!(
                inv.verdict == Verdict::Stable,
                inv_stable,
                "eps {eps} A/C {ac}"
            );
        }
    }
}

#[test]
fn relative_equilibria_are_steady_and_the_nano_lying_state_is_found() {
    // The zero-slip family: the residual of the equations vanishes.
    for top in [Top::classical(), Top::nano()] {
        for th in [0.4, 1.2, std::f64::consts::FRAC_PI_2, 1.65] {
            let Some(o2) = stability::relative_equilibrium_precession_sq(&top, 9.8, th) else {
                continue;
            };
            let om = o2.sqrt();
            let w = stability::relative_equilibrium_spin(&top, th, om);
            let lin = stability::linearise(&classical_like(top), th, om, w, 1e-10).unwrap();
            assert!(lin.residual < 1e-10, "residual {} at {th}", lin.residual);
            assert!(lin.jellett_check < 1e-12);
            assert_eq!(lin.eigenvalues.len(), 5);
        }
    }
    // Frozen-spin at a nano lying state (ω = −2.5e7 rad/s, the H-driven run's
    // late state): with Ω from J the quasi-equilibrium is near cos θ = a/R, not
    // π/2, and the oscillation frequency is the nutation frequency C|ω|/A.
    let sc = Scenario::nano();
    let top = sc.top;
    let w = -2.5e7;
    let j = stability::jellett(&top, 0.1, 0.0, 100.0);
    let inp = stability::FrozenInput {
        theta: 1.5,
        spin: w,
        precession: -3.7e4,
        jellett: j,
        u: [0.0, -3e-3],
        t_force: 5e-5,
    };
    let f = stability::frozen_spin(
        &sc,
        SmoothLaw::Regularized,
        1e-7,
        &inp,
        stability::FrozenVariant::PrecessionFromJellett,
        1e-10,
    );
    let tq = f.theta_quasi.unwrap();
    assert!((tq - 0.1f64.acos()).abs() < 0.01, "theta_q {tq}");
    let nu = f.eigenvalues[0].im.abs();
    let nut = top.inertia_axial * w.abs() / top.inertia_transverse;
    assert!((nu / nut - 1.0).abs() < 0.02, "nu {nu} vs C|w|/A {nut}");
    assert!(f.label.contains("not a true equilibrium"));
}

fn classical_like(top: Top) -> Physics {
    Physics {
        top,
        ..classical_physics(0.1, 1e-3 * top.radius * 100.0)
    }
}
