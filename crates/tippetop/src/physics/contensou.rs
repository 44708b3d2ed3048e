//! Coulomb–Contensou friction: Coulomb's law integrated over a circular
//! contact disc of radius `r_c` that slides with velocity `v` and spins
//! about its normal with `ω_z` (docs/physics.md#contensou).
//!
//! With `d = |v|/(r_c |ω_z|)` the friction force on the body is
//! `F = −μ N f(d) v/|v|` and the drilling torque about the normal
//! `M = −μ N r_c m(d) sign(ω_z)`, where, for the normalised axisymmetric
//! pressure `P(ρ)` (`∫ P dA = 1`, `ρ = |x|/r_c`),
//!
//! ```text
//! f(d) = ∫₀¹ P(ρ) ρ F_ring(ρ, d) dρ,   m(d) = ∫₀¹ P(ρ) ρ T_ring(ρ, d) dρ,
//! ρ < d: F_ring = 4 E(ρ²/d²),          T_ring = 4 ρ (ρ/d) B(ρ²/d²),
//! ρ > d: F_ring = 4 (d/ρ) B(d²/ρ²),    T_ring = 4 ρ E(d²/ρ²),
//! ```
//!
//! `E` the complete elliptic integral of the second kind and
//! `B(k²) = (E − (1 − k²) K)/k²` (parameter `k²`). The ring integrals are
//! exact; the one integral over `ρ` is done here by Gauss–Legendre
//! quadrature, split at the ring through the instantaneous centre of
//! rotation (`ρ = d`), each piece mapped by a quintic smoothstep so that the
//! endpoint singularities (`x ln x` at `ρ = d`, `√(1 − ρ)` of the Hertz
//! pressure) are smoothed. Measured error against 30-digit references:
//! below 1e-12 (tests/physics/contensou.rs).

use std::f64::consts::PI;

pub use crate::input::surface::Pressure;

/// `(K(m), E(m), B(m))` for the parameter `0 <= m < 1` by the
/// arithmetic–geometric mean, with `B = (E − (1 − m) K)/m` (`π/4` at
/// `m = 0`) formed without cancellation: `D = (K − E)/m = K Σ 2ⁿ⁻¹ c_n²/m`
/// with every `c_n²/m` carried directly, and `B = K − D` for `m <= 1/2`,
/// `(E − (1 − m) K)/m` above.
pub fn elliptic_keb(m: f64) -> (f64, f64, f64) {
    let mut a = 1.0;
    let mut b = (1.0 - m).sqrt();
    // γ_n = c_n²/m, c_0² = m.
    let mut gamma = 1.0;
    let mut pow = 0.5;
    let mut s = 0.5;
    for _ in 0..40 {
        let a1 = 0.5 * (a + b);
        // c_{n+1} = (a_n − b_n)/2 = c_n²/(4 a_{n+1}).
        gamma = gamma * gamma * m / (16.0 * a1 * a1);
        b = (a * b).sqrt();
        a = a1;
        pow *= 2.0;
        let term = pow * gamma;
        s += term;
        if term <= 1e-17 * s {
            break;
        }
    }
    let k = PI / (2.0 * a);
    let d = k * s;
    let e = k - m * d;
    let bb = if m <= 0.5 {
        k - d
    } else {
        (e - (1.0 - m) * k) / m
    };
    (k, e, bb)
}

/// Gauss–Legendre nodes and weights on `[0, 1]`, `GL_N` points.
const GL_N: usize = 32;

fn gauss_legendre() -> &'static [(f64, f64); GL_N] {
    static TABLE: std::sync::OnceLock<[(f64, f64); GL_N]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let n = GL_N;
        let mut out = [(0.0, 0.0); GL_N];
        for (i, o) in out.iter_mut().enumerate() {
            // Newton on P_n from the Chebyshev guess.
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            *o = (0.5 * (1.0 + x), 0.5 * w);
        }
        out
    })
}

/// `∫_lo^hi g(ρ) dρ` by the mapped Gauss–Legendre rule: `ρ = lo + (hi − lo)
/// φ(t)`, `φ(t) = t³ (10 − 15 t + 6 t²)` (φ′ = 30 t² (1 − t)², vanishing at
/// both ends, which smooths endpoint singularities).
#[inline]
fn mapped(lo: f64, hi: f64, g: &mut dyn FnMut(f64) -> (f64, f64)) -> (f64, f64) {
    let w = hi - lo;
    let (mut sf, mut sm) = (0.0, 0.0);
    for &(t, wt) in gauss_legendre() {
        let t2 = t * t;
        let phi = t2 * t2 * t * (126.0 + t * (-420.0 + t * (540.0 + t * (-315.0 + 70.0 * t))));
        let u = 1.0 - t;
        let tu = t * u;
        let tu2 = tu * tu;
        let dphi = 630.0 * tu2 * tu2;
        let (f, m) = g(lo + w * phi);
        sf += wt * dphi * f;
        sm += wt * dphi * m;
    }
    (w * sf, w * sm)
}

/// `∫_lo^hi g` by the plain Gauss–Legendre rule (smooth pieces).
#[inline]
fn plain(lo: f64, hi: f64, g: &mut dyn FnMut(f64) -> (f64, f64)) -> (f64, f64) {
    let w = hi - lo;
    let (mut sf, mut sm) = (0.0, 0.0);
    for &(t, wt) in gauss_legendre() {
        let (f, m) = g(lo + w * t);
        sf += wt * f;
        sm += wt * m;
    }
    (w * sf, w * sm)
}

/// Below this `d` the exact law is its leading terms `f = f′(0) d`,
/// `m = m(0)` (the next terms are `O(d³)` and `O(d²)`: below 1e-12 here).
const SMALL_D: f64 = 1e-6;

/// The ring integrands `(P ρ F_ring, P ρ T_ring)/P` at radius `rho`.
#[inline]
fn rings(rho: f64, d: f64) -> (f64, f64) {
    if rho < d {
        let q = rho / d;
        let (_, e, b) = elliptic_keb(q * q);
        (4.0 * rho * e, 4.0 * rho * rho * q * b)
    } else {
        let q = d / rho;
        let (_, e, b) = elliptic_keb(q * q);
        (4.0 * rho * q * b, 4.0 * rho * rho * e)
    }
}

/// Breakpoints of `[lo, hi]` graded geometrically towards `lo` (ratio 4,
/// from `hi − lo` down to `scale`) and appended to `out` (`lo` excluded,
/// `hi` included): the pieces next to a feature of size `scale` at `lo`
/// are as small as the feature.
fn graded_up(lo: f64, hi: f64, scale: f64, out: &mut Vec<f64>) {
    let mut w = hi - lo;
    let mut pts = vec![hi];
    while w > 4.0 * scale {
        w /= 4.0;
        pts.push(lo + w);
    }
    out.extend(pts.into_iter().rev());
}

/// The same graded towards `hi`.
fn graded_down(lo: f64, hi: f64, scale: f64, out: &mut Vec<f64>) {
    let mut w = hi - lo;
    while w > 4.0 * scale {
        w /= 4.0;
        out.push(hi - w);
    }
    out.push(hi);
}

/// The exact law: `(f(d), m(d))` for `d = |v|/(r_c |ω_z|) >= 0` (`+∞`
/// allowed: `(1, 0)`), module doc. Uniform pressure is integrated in `ρ`,
/// Hertz in `θ` (`ρ = sin θ`, which removes the `√(1 − ρ²)`), split at the
/// ring through the instantaneous centre (`ρ = d`) and graded
/// geometrically towards it where it lies just outside the disc and,
/// for small `d`, away from it (the outer rings vary on the scale `d`).
/// Measured error below 1e-12 against 30-digit references.
pub fn exact(p: Pressure, d: f64) -> (f64, f64) {
    if d.is_nan() {
        return (f64::NAN, f64::NAN);
    }
    if d < SMALL_D {
        return (p.small_slip_slope() * d, p.zero_slip_torque());
    }
    if d == f64::INFINITY {
        return (1.0, 0.0);
    }
    let mut pts = vec![0.0];
    let (lo, hi) = (
        0.0,
        match p {
            Pressure::Uniform => 1.0,
            Pressure::Hertz => PI / 2.0,
        },
    );
    // The ring through the instantaneous centre in the variable x.
    let to_x = |rho: f64| match p {
        Pressure::Uniform => rho,
        Pressure::Hertz => rho.asin(),
    };
    if d < 1.0 {
        let xd = to_x(d);
        // Hertz: sin θ = d also at π − θ_d, just beyond π/2 when d is
        // near 1: the pieces next to θ_d are graded to that distance.
        let gap = match p {
            Pressure::Uniform => xd,
            Pressure::Hertz => PI - 2.0 * xd,
        };
        graded_down(lo, xd, gap, &mut pts);
        graded_up(xd, hi, xd.min(gap), &mut pts);
    } else {
        // Distance of the (complex, for Hertz) singular point from x = hi.
        let delta = match p {
            Pressure::Uniform => d - 1.0,
            Pressure::Hertz => (2.0 * (d - 1.0)).sqrt(),
        };
        // At d = 1 exactly the singular point is the edge itself: grade to
        // 1e-12 (a piece that small holds the x ln x to far below
        // rounding), not to zero (which never ends before underflow).
        graded_down(lo, hi, delta.max(1e-12), &mut pts);
    }
    let xd = if d < 1.0 { to_x(d) } else { f64::NAN };
    let (mut f, mut m) = (0.0, 0.0);
    for w in pts.windows(2) {
        // The mapped rule on the two pieces that end at the ring through
        // the instantaneous centre (an `x ln x` there), the plain rule on
        // the smooth ones.
        let rule = if w[0] == xd || w[1] == xd {
            mapped
        } else {
            plain
        };
        let (a, b) = rule(w[0], w[1], &mut |x: f64| match p {
            Pressure::Uniform => rings(x, d),
            Pressure::Hertz => {
                let (s, c) = x.sin_cos();
                let (fr, tr) = rings(s, d);
                // dρ = cos θ dθ, √(1 − ρ²) = cos θ.
                (fr * c * c, tr * c * c)
            }
        });
        f += a;
        m += b;
    }
    let k = match p {
        Pressure::Uniform => 1.0 / PI,
        Pressure::Hertz => 1.5 / PI,
    };
    (k * f, k * m)
}

/// Coefficients `(a, b, g, e)` of the Padé form ([`pade`]) for a pressure,
/// fitted here (minimax over `10⁻³ <= d <= 10³`) with the exact limits
/// imposed (docs/physics.md#contensou).
fn pade_coefficients(p: Pressure) -> (f64, f64, f64, f64) {
    match p {
        Pressure::Uniform => (1.379, 0.5567, 1.301, 0.5123),
        Pressure::Hertz => (1.837, 0.7081, 1.434, 0.6141),
    }
}

/// Largest error of [`pade`] against [`exact`] over all `d >= 0`, for
/// `f` (in units of μN) and for `m` (in units of μ N r_c), as measured
/// (tests/physics/contensou.rs checks it).
pub const PADE_MAX_ERROR: f64 = 0.04;

/// The second-order Padé form (the construction of Zhuravlev 1998 and
/// Kireenkov 2008, coefficients fitted here):
/// `f = d (s₁ + a d)/(1 + b d + a d²)`,
/// `m = m₀ (1 + g d)/(1 + e d + (2 m₀ g/⟨ρ²⟩) d²)`, with `s₁ = f′(0)`,
/// `m₀ = m(0)` and the tail `m ≈ ⟨ρ²⟩/(2d)` exact; within
/// [`PADE_MAX_ERROR`] of [`exact`].
pub fn pade(p: Pressure, d: f64) -> (f64, f64) {
    if d == f64::INFINITY {
        return (1.0, 0.0);
    }
    let (a, b, g, e) = pade_coefficients(p);
    let s1 = p.small_slip_slope();
    let m0 = p.zero_slip_torque();
    let f = d * (s1 + a * d) / (1.0 + b * d + a * d * d);
    let c2 = 2.0 * m0 * g / p.second_moment();
    let m = m0 * (1.0 + g * d) / (1.0 + e * d + c2 * d * d);
    (f, m)
}

/// Stick test of the combined law: with `fn_` the needed force over μN
/// (`>= 0`) and `mn` the needed torque over μ N r_c (`>= 0`), true when
/// `(fn_, mn)` lies inside the limit curve `(f(d), m(d))`, `d >= 0` (the
/// set of force–torque pairs the disc can hold without sliding or
/// spinning): `fn_ <= 1` and `mn <= m(d*)` where `f(d*) = fn_`. `f` is
/// increasing, so `d*` is found by bisection on the exact law.
pub fn sticks(p: Pressure, fn_: f64, mn: f64) -> bool {
    if fn_ > 1.0 || mn > p.zero_slip_torque() {
        return false;
    }
    if fn_ <= 0.0 {
        return true;
    }
    // Bisection in s = d/(1 + d) ∈ (0, 1).
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let d = mid / (1.0 - mid);
        if exact(p, d).0 < fn_ {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let d = hi / (1.0 - hi);
    mn <= exact(p, d).1
}

/// The law in use: [`pade`] if `pade`, else [`exact`].
#[inline]
pub fn law(p: Pressure, pade_form: bool, d: f64) -> (f64, f64) {
    if pade_form { pade(p, d) } else { exact(p, d) }
}

/// The gauge of a force–torque pair with respect to the limit curve of the
/// law (`pade_form` picks it, [`law`]): with `fn_ = |F|/(μN)` and
/// `mn = |M|/(μ N r_c)` (both `>= 0`), `(λ, d)` such that
/// `(fn_, mn) = λ (f(d), m(d))`: the ray from the origin through the pair
/// meets the curve at the point of parameter `d`, and the pair lies inside
/// the admissible set of the stick (docs/physics.md#contensou) iff `λ <= 1`.
/// `d` is also the ratio `|v|/(r_c |n_Z|)` with which the contact slips
/// off where the pair leaves the set there. `(0, 0)` gives `(0, 0)`.
///
/// `d` is the root of `fn_ m(d) − mn f(d)` (decreasing for the exact law:
/// `f` increases, `m` decreases), found by the Illinois variant of regula
/// falsi in `s = d/(1 + d)` to a bracket or a step below `1e-15`, or a
/// residual below `1e-15 (fn_ m(0) + mn)`.
pub fn gauge(p: Pressure, pade_form: bool, fn_: f64, mn: f64) -> (f64, f64) {
    if fn_ <= 0.0 && mn <= 0.0 {
        return (0.0, 0.0);
    }
    if fn_ <= 0.0 {
        return (mn / p.zero_slip_torque(), 0.0);
    }
    if mn <= 0.0 {
        return (fn_, f64::INFINITY);
    }
    let h = |s: f64| {
        let d = if s >= 1.0 {
            f64::INFINITY
        } else {
            s / (1.0 - s)
        };
        let (f, m) = law(p, pade_form, d);
        (fn_ * m - mn * f, d, f, m)
    };
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let (mut hlo, mut hhi) = (fn_ * p.zero_slip_torque(), -mn);
    let scale = hlo - hhi;
    let mut best = (0.0, f64::NAN, f64::NAN, f64::NAN);
    let mut side = 0i8;
    let mut last = f64::NAN;
    for _ in 0..100 {
        if hi - lo <= 1e-15 {
            break;
        }
        // Illinois step, kept inside the bracket.
        let mut s = (lo * hhi - hi * hlo) / (hhi - hlo);
        if !(s > lo && s < hi) {
            s = 0.5 * (lo + hi);
        }
        best = h(s);
        let hs = best.0;
        // Converged: the residual at rounding, or the iterate no longer
        // moving.
        if hs.abs() <= 1e-15 * scale || (s - last).abs() <= 1e-15 {
            break;
        }
        last = s;
        if hs > 0.0 {
            lo = s;
            hlo = hs;
            if side == 1 {
                hhi *= 0.5;
            }
            side = 1;
        } else {
            hi = s;
            hhi = hs;
            if side == -1 {
                hlo *= 0.5;
            }
            side = -1;
        }
    }
    let (_, d, f, m) = best;
    ((fn_ + mn) / (f + m), d)
}
