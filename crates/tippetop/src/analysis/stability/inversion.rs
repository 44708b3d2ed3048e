//! Where a dissipating top ends: the minimum of its energy at fixed
//! Jellett's J (docs/physics.md#stability, "Full inversion").
//!
//! Friction at the contact point conserves `J = L·(R Z − a k)` (§invariants) and
//! dissipates energy, so a top whose friction never stops acting (a smooth
//! law: slip, however small, costs energy) ends at a state of least energy
//! for its J. For a given θ the kinetic energy `½ L·I⁻¹L + ½ m |u|²` at
//! fixed `L·d = J` (`d = R Z − a k`) is least for `u = 0` and `L ∝ I d`
//! (a Lagrange multiplier), and equals `J²/(2 D(θ))` with
//! `D(θ) = d·I d = A R² sin²θ + C (R cos θ − a)²`. The angular velocity is
//! then `∝ d`, parallel to the line from the centre of mass to the contact
//! point, so the contact point does not slip: these least-energy states are
//! exactly the zero-slip steady motions of [`super::linearisation`]. So the
//! top ends at the global minimum over θ of
//!
//! ```text
//! V_J(θ) = J²/(2 D(θ)) + m g (R − a cos θ) + U_wells(θ).
//! ```
//!
//! **Threshold at θ = π.** With `φ = π − θ`, `D = C (R + a)² −
//! [C R (R + a) − A R²] φ² + O(φ⁴)` and the height `R + a − a φ²/2`, so
//! `V_J(π − φ) = V_J(π) + ½ κ φ² + O(φ⁴)` with
//! `κ = J² R [C (R + a) − A R]/(C² (R + a)⁴) − m g a`. The inverted top is a
//! minimum iff `κ > 0`: it needs `C (R + a) > A R` (the upper edge of the
//! inversion window `A/C < 1 + a/R`) and a spin about the vertical at π,
//! `n_π = J/(C (R + a))`, above
//!
//! ```text
//! n_c = (R + a) √(m g a / (R [C (R + a) − A R])).
//! ```
//!
//! A smooth friction law's linearisation at π changes stability at the same
//! spin (the dissipation acts on every non-steady mode, so a strict minimum
//! of `V_J` is stable and a saddle is not): tests check [`inverted_threshold`]
//! against the eigenvalues of [`super::linearise`].
//!
//! **From an initial state.** A top started at θ₀ with spin ω₀ (Ω₀ = 0) has
//! `J = C ω₀ (R cos θ₀ − a)`, so `n_π = ω₀ (R cos θ₀ − a)/(R + a)` and it ends
//! inverted iff `|ω₀| > n_c (R + a)/|R cos θ₀ − a|` (if π is the global
//! minimum there; [`final_theta`] finds the global minimum numerically, and
//! [`initial_spin_threshold`] the smallest |ω₀| whose minimum lies within δ
//! of π). The energy alone gives a weaker necessary condition: `E₀ ≥ V_J(π)`
//! ([`energy_bound_spin`]).

use crate::Well;
use crate::input::top::Top;
use crate::physics::forces::wells;

/// `D(θ) = A R² sin²θ + C (R cos θ − a)²` \[kg m⁴\]: `J²/(2D)` is the least
/// kinetic energy at Jellett's J (always > 0 since a < R).
pub fn jellett_inertia(top: &Top, theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    let d_k = top.radius * c - top.offset;
    top.inertia_transverse * (top.radius * s).powi(2) + top.inertia_axial * d_k * d_k
}

/// `V_J(θ) = J²/(2 D(θ)) + m g (R − a cos θ) + U_wells(θ)` \[J\]: the least
/// energy of a top at θ with Jellett's `j` \[kg m³/s\] (wells in SI).
pub fn potential(top: &Top, gravity: f64, wells_si: &[Well], j: f64, theta: f64) -> f64 {
    j * j / (2.0 * jellett_inertia(top, theta))
        + top.mass * gravity * top.height(theta)
        + wells::potential(wells_si, theta)
}

/// `dV_J/dθ` \[J/rad\]: `−J² D′/(2 D²) + m g a sin θ − τ_wells(θ)`, with
/// `D′ = 2 R sin θ [A R cos θ − C (R cos θ − a)]`.
pub fn potential_slope(top: &Top, gravity: f64, wells_si: &[Well], j: f64, theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    let r = top.radius;
    let d = jellett_inertia(top, theta);
    let d1 =
        2.0 * r * s * (top.inertia_transverse * r * c - top.inertia_axial * (r * c - top.offset));
    -j * j * d1 / (2.0 * d * d) + top.mass * gravity * top.offset * s
        - wells::torque(wells_si, theta)
}

/// The θ in `[0, π]` where [`potential`] is least \[rad\]: a scan of 4 097
/// points; an end point is returned exactly when it wins the scan, else the
/// root of [`potential_slope`] in the best point's two cells by bisection
/// (to rounding: locating a minimum by its values alone is good only to
/// ~√ε).
pub fn final_theta(top: &Top, gravity: f64, wells_si: &[Well], j: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let v = |th: f64| potential(top, gravity, wells_si, j, th);
    const N: usize = 4096;
    let h = pi / N as f64;
    let at = |i: usize| if i == N { pi } else { i as f64 * h };
    let (mut best, mut vbest) = (0usize, f64::INFINITY);
    for i in 0..=N {
        let val = v(at(i));
        if val < vbest {
            best = i;
            vbest = val;
        }
    }
    if best == 0 || best == N {
        return at(best);
    }
    // Interior: V′ < 0 at the left cell's start, > 0 at the right cell's end.
    let slope = |th: f64| potential_slope(top, gravity, wells_si, j, th);
    let (mut lo, mut hi) = (at(best - 1), at(best + 1));
    if !(slope(lo) < 0.0 && slope(hi) > 0.0) {
        return at(best);
    }
    while hi - lo > 0.0 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if slope(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The spin about the vertical at θ = π above which the inverted top is a
/// strict minimum of [`potential`] (no wells):
/// `n_c = (R + a) √(m g a / (R [C (R + a) − A R]))` \[rad/s\]; `None` if
/// `C (R + a) <= A R` (then no spin makes it one).
pub fn inverted_threshold(top: &Top, gravity: f64) -> Option<f64> {
    let (r, a, ia, ic, m) = (
        top.radius,
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
        top.mass,
    );
    let den = r * (ic * (r + a) - ia * r);
    (den > 0.0).then(|| (r + a) * (m * gravity * a / den).sqrt())
}

/// The spin about the vertical at θ = 0 below which the upright top is a
/// strict minimum of [`potential`] (no wells), so a top near it stays:
/// `n_up = (R − a) √(m g a / (R [A R − C (R − a)]))` \[rad/s\]; `None` if
/// `A R <= C (R − a)` (below the window `A/C > 1 − a/R`: upright is a
/// minimum at every spin). From `V_J(φ) = V_J(0) + ½ κ₀ φ² + O(φ⁴)`,
/// `κ₀ = m g a − J² R [A R − C (R − a)]/(C² (R − a)⁴)`.
pub fn upright_threshold(top: &Top, gravity: f64) -> Option<f64> {
    let (r, a, ia, ic, m) = (
        top.radius,
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
        top.mass,
    );
    let den = r * (ia * r - ic * (r - a));
    (den > 0.0).then(|| (r - a) * (m * gravity * a / den).sqrt())
}

/// The initial spin |ω₀| \[rad/s\] (with Ω₀ = 0 at θ₀) whose Jellett's J
/// makes the spin at π equal [`inverted_threshold`]:
/// `n_c (R + a)/|R cos θ₀ − a|`; `None` as there, or if `R cos θ₀ = a`
/// (J = 0 for every spin).
pub fn initial_spin_for_threshold(top: &Top, gravity: f64, theta0: f64) -> Option<f64> {
    let lever = (top.radius * theta0.cos() - top.offset).abs();
    let nc = inverted_threshold(top, gravity)?;
    (lever > 0.0).then(|| nc * (top.radius + top.offset) / lever)
}

/// The smallest |ω₀| \[rad/s\] (Ω₀ = 0 at θ₀) whose least-energy state
/// ([`final_theta`]) lies in `[π − delta, π]`: a scan of |ω₀| over
/// `[1e-3, 1e3] × n_ref` (n_ref = √(m g R²/C)) on a log grid of 601 points,
/// then bisection to 1e-12 relative in the first cell where it starts to
/// hold. `None` if it holds nowhere on the scan.
pub fn initial_spin_threshold(
    top: &Top,
    gravity: f64,
    wells_si: &[Well],
    theta0: f64,
    delta: f64,
) -> Option<f64> {
    let pi = std::f64::consts::PI;
    let lever = top.radius * theta0.cos() - top.offset;
    let holds = |w0: f64| {
        let j = top.inertia_axial * w0 * lever;
        final_theta(top, gravity, wells_si, j) >= pi - delta
    };
    let n_ref = (top.mass * gravity * top.radius * top.radius / top.inertia_axial).sqrt();
    let (lo_e, hi_e) = (-3.0f64, 3.0f64);
    const M: usize = 600;
    let at = |i: usize| n_ref * 10f64.powf(lo_e + (hi_e - lo_e) * i as f64 / M as f64);
    let mut prev = at(0);
    if holds(prev) {
        return Some(prev);
    }
    for i in 1..=M {
        let w = at(i);
        if holds(w) {
            let (mut lo, mut hi) = (prev, w);
            while hi - lo > 1e-12 * hi {
                let mid = 0.5 * (lo + hi);
                if holds(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = w;
    }
    None
}

/// The energy's necessary condition for reaching π from θ₀ with spin ω₀
/// (Ω₀ = θ̇₀ = 0, u = 0): `E₀ >= V_J(π)`, i.e.
/// `ω₀² >= 2 m g a (1 + cos θ₀)/(C [1 − ((R cos θ₀ − a)/(R + a))²])`
/// \[rad/s\]; weaker than [`initial_spin_for_threshold`] (energy can be
/// spent only at fixed J). No wells.
pub fn energy_bound_spin(top: &Top, gravity: f64, theta0: f64) -> f64 {
    let (r, a) = (top.radius, top.offset);
    let q = (r * theta0.cos() - a) / (r + a);
    (2.0 * top.mass * gravity * a * (1.0 + theta0.cos()) / (top.inertia_axial * (1.0 - q * q)))
        .sqrt()
}

/// What [`super::analyse`] reports about full inversion.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Inversion {
    /// Spin about the vertical at π above which the inverted top is a
    /// minimum of `V_J` (`None`: never, `C (R + a) <= A R`) \[rad/s\].
    pub threshold_at_pi: Option<f64>,
    /// Spin about the vertical at θ = 0 below which the upright top is a
    /// minimum of `V_J` (`None`: at every spin) \[rad/s\].
    pub threshold_at_0: Option<f64>,
    /// The scenario's spin at π from its J, `J/(C (R + a))` \[rad/s\].
    pub spin_at_pi: f64,
    /// Initial spin (Ω₀ = 0 at the scenario's θ₀) for the threshold \[rad/s\].
    pub initial_spin_threshold: Option<f64>,
    /// The energy's weaker bound on the initial spin \[rad/s\].
    pub energy_bound: f64,
    /// Where the scenario's top ends by the least energy at its J \[rad\].
    pub final_theta: f64,
}

/// The [`Inversion`] figures of a top started at (θ₀, Ω₀, ω₀) (SI).
pub fn inversion(
    top: &Top,
    gravity: f64,
    wells_si: &[Well],
    theta0: f64,
    precession0: f64,
    spin0: f64,
) -> Inversion {
    let j = super::jellett(top, theta0, precession0, spin0);
    Inversion {
        threshold_at_pi: inverted_threshold(top, gravity),
        threshold_at_0: upright_threshold(top, gravity),
        spin_at_pi: j / (top.inertia_axial * (top.radius + top.offset)),
        initial_spin_threshold: initial_spin_for_threshold(top, gravity, theta0),
        energy_bound: energy_bound_spin(top, gravity, theta0),
        final_theta: final_theta(top, gravity, wells_si, j),
    }
}
