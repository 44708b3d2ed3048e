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
            let mut y = [0.0; 8];
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
        Cx((self.0 * o.0 + self.1 * o.1) / d, (self.1 * o.0 - self.0 * o.1) / d)
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
            assert_matches_polynomial(&lin, &poly, &format!("{top:?} mu {mu} upright {upright} w {w}"));
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
            assert!(lin.max_re > -lin.tol, "a conservative system is never asymptotically stable");
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
            assert_eq!(lin.verdict, Verdict::Marginal, "upright at omega {w}: {lin:?}");
        }
    }
}
