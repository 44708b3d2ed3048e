//! The heat bath of the Langevin method for a top on the plane: the exact
//! Ornstein–Uhlenbeck step of its generalised velocities `(v_x, v_y, w)` at
//! fixed axis `k` (docs/physics.md#langevin), written over plain vectors so the
//! models that keep the sphere on a surface share it ([`ou_in_contact`]: the
//! vector model, the rigid model in contact with the plane or, in the
//! contact's frame, the tube's wall; [`ou_free`] in flight), with a cache of its
//! coefficients ([`OuCache`]); and the overdamped (Brownian) step on the
//! plane, without ([`overdamped_on_plane`]) and with the contact damping
//! ([`overdamped_coupled`], §brownian). The coupled step is not cached: the
//! axis moves at every Brownian step, so a cache keyed by its bits would
//! never hit.

use super::vec3::{V3, add, cross, dot, scale};
use crate::Scenario;
use crate::physics::body::Inertia;
use crate::physics::units::Scales;

/// The heat bath in scaled units (m = R = 1, the model's time unit): kT,
/// γ_t, γ_r and the contact damping c/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bath {
    pub kt: f64,
    pub gt: f64,
    pub gr: f64,
    pub c: f64,
}

impl Bath {
    /// The bath of a scenario with a stochastic method, in `scales`.
    pub fn of(sc: &Scenario, scales: &Scales) -> Option<Bath> {
        sc.solver.method.is_stochastic().then(|| {
            let th = &sc.thermal;
            Bath {
                kt: th.kt() / scales.energy(),
                gt: th.damping_translational * scales.time,
                gr: th.damping_rotational * scales.time,
                c: th.damping_contact * scales.time / scales.mass,
            }
        })
    }
}

/// The orthonormal basis `(k̂, ê, f̂)` of the rotational modes for the axis
/// `k` (`ê = k × Z/|k × Z|`, any horizontal unit vector at the poles,
/// `f̂ = k̂ × ê`) and `sin²θ`.
pub(crate) fn modes_basis(kr: V3) -> ([V3; 3], f64) {
    let kn = scale(1.0 / dot(kr, kr).sqrt(), kr);
    let e = [kn[1], -kn[0], 0.0];
    let s2 = e[0] * e[0] + e[1] * e[1];
    let eh = if s2 > 0.0 {
        scale(1.0 / s2.sqrt(), e)
    } else {
        [1.0, 0.0, 0.0]
    };
    ([kn, eh, cross(kn, eh)], s2)
}

/// The body's scaled constants: offset `a`, moments `A`, `C`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Body {
    pub a: f64,
    pub ia: f64,
    pub ic: f64,
}

/// The generalised velocities of one Euler–Maruyama step of the
/// overdamped dynamics on the plane (`solver.method = "brownian"`,
/// docs/physics.md#langevin), in the basis `(X, Y | k̂, ê, f̂)` where `Γ` is
/// diagonal: `p_i = M_i a_i/Γ_i + sqrt(2 kT/(Γ_i h)) ξ_i` with `a` the
/// acceleration at rest in that basis, plus along `ê` the drift
/// `−kT [(μ_θ − μ_φ) cot θ + μ_θ ∂_θ ln s + ∂_θ μ_θ]` that makes the Langevin
/// run's configuration density stationary (`μ_θ = 1/Γ_ê`, `μ_φ = 1/Γ_f̂`,
/// `s = sqrt(1 + m a² sin²θ/A)`; the geodesic step supplies `kT μ_φ cot θ`).
/// `s2 = sin²θ`, `cos_theta` of the unit axis. Returns `(p, drift)`: the
/// velocities with noise and their drift part.
pub(crate) fn overdamped_on_plane(
    b: &Bath,
    body: &Body,
    (s2, cos_theta): (f64, f64),
    acc: [f64; 5],
    h: f64,
    xi: &[f64],
) -> ([f64; 5], [f64; 5]) {
    let (a2, ia, ic) = (body.a * body.a, body.ia, body.ic);
    let beta = a2 * s2;
    let m = [1.0, 1.0, ic, ia + beta, ia];
    let g = [b.gt, b.gt, b.gr * ic, b.gr * ia + b.gt * beta, b.gr * ia];
    let mut drift = [0.0; 5];
    let mut p = [0.0; 5];
    for i in 0..5 {
        drift[i] = m[i] * acc[i] / g[i];
        p[i] = drift[i] + (2.0 * b.kt / (g[i] * h)).sqrt() * xi[i];
    }
    let (sn, cs) = (s2.sqrt(), cos_theta);
    let (mu_t, mu_p) = (1.0 / g[3], 1.0 / g[4]);
    let dmu_t = -2.0 * b.gt * a2 * sn * cs * mu_t * mu_t;
    let dln_s = a2 * sn * cs / (ia + beta);
    let corr = -b.gt * a2 * sn * cs * mu_t * mu_p + mu_t * dln_s + dmu_t;
    // w·ê = −θ̇.
    p[3] -= b.kt * corr;
    drift[3] -= b.kt * corr;
    (p, drift)
}

/// One Euler–Maruyama step of the overdamped dynamics on the plane: the
/// generalised velocities `(p, drift)` in the basis `(X, Y | k̂, ê, f̂)`
/// (`basis` = `[k̂, ê, f̂]` of [`modes_basis`], `s2 = sin²θ`, `acc` the
/// acceleration at rest in that basis, `xi` 5 standard normals).
/// Without contact damping it is [`overdamped_on_plane`] (the same call,
/// the same bits); with it, [`overdamped_coupled`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn overdamped(
    b: &Bath,
    body: &Body,
    basis: [V3; 3],
    s2: f64,
    acc: [f64; 5],
    h: f64,
    xi: &[f64],
) -> ([f64; 5], [f64; 5]) {
    if b.c > 0.0 {
        overdamped_coupled(b, body, basis, s2, acc, h, xi)
    } else {
        overdamped_on_plane(b, body, (s2, basis[0][2]), acc, h, xi)
    }
}

/// The friction matrix `Γ(k)` of the top on the plane in the lab basis
/// (scaled, m = R = 1): generalised velocity `(v_x, v_y, w_x, w_y, w_z)`,
/// `Γ = diag(γ_t, γ_t, γ_r I(k)) + γ_t a² n nᵀ + c Pᵀ P` with
/// `I(k) = A 1 + (C − A) k kᵀ`, `n = k × Z` (the centre's vertical velocity
/// is `−a n·w`) and `P = [1₂ | P_r]` the map to the horizontal slip
/// `v_h + (w × r)_h`, `r = a k − Z`. With `dk` in place of `k` (and
/// `deriv`), its directional derivative along `dk` instead (`Γ` is a
/// quadratic polynomial in `k`: `r` moves by `a dk`).
pub(crate) fn friction_lab(b: &Bath, body: &Body, k: V3, dk: Option<V3>) -> nalgebra::Matrix5<f64> {
    use nalgebra::Matrix5;
    let (a, ia, ic) = (body.a, body.ia, body.ic);
    // Columns β of P_r: (e_β × r)_h for r.
    let pr = |r: V3| -> [[f64; 2]; 3] { [[0.0, -r[2]], [r[2], 0.0], [-r[1], r[0]]] };
    let nz = |k: V3| -> V3 { [k[1], -k[0], 0.0] };
    let r = [a * k[0], a * k[1], a * k[2] - 1.0];
    let (p0, n0) = (pr(r), nz(k));
    let mut g = Matrix5::zeros();
    match dk {
        None => {
            for i in 0..2 {
                g[(i, i)] = b.gt + b.c;
            }
            for i in 0..3 {
                for j in 0..3 {
                    let id = if i == j { ia } else { 0.0 };
                    let pp = p0[i][0] * p0[j][0] + p0[i][1] * p0[j][1];
                    g[(2 + i, 2 + j)] = b.gr * (id + (ic - ia) * k[i] * k[j])
                        + b.gt * a * a * n0[i] * n0[j]
                        + b.c * pp;
                }
                for t in 0..2 {
                    g[(t, 2 + i)] = b.c * p0[i][t];
                    g[(2 + i, t)] = b.c * p0[i][t];
                }
            }
        }
        Some(v) => {
            // d r = a v, d n = v × Z.
            let (p1, n1) = (pr([a * v[0], a * v[1], a * v[2]]), nz(v));
            for i in 0..3 {
                for j in 0..3 {
                    let dpp = p1[i][0] * p0[j][0]
                        + p1[i][1] * p0[j][1]
                        + p0[i][0] * p1[j][0]
                        + p0[i][1] * p1[j][1];
                    g[(2 + i, 2 + j)] = b.gr * (ic - ia) * (v[i] * k[j] + k[i] * v[j])
                        + b.gt * a * a * (n1[i] * n0[j] + n0[i] * n1[j])
                        + b.c * dpp;
                }
                for t in 0..2 {
                    g[(t, 2 + i)] = b.c * p1[i][t];
                    g[(2 + i, t)] = b.c * p1[i][t];
                }
            }
        }
    }
    g
}

/// The overdamped step with the contact damping (docs/physics.md#brownian):
/// in the lab basis `(X, Y | X, Y, Z)` of `(v_h, w)`, with the full
/// friction matrix `Γ(k)` of [`friction_lab`] and the mobility `μ = Γ⁻¹`
/// (5×5, coupling the translation with the rotations),
///
/// ```text
/// p = μ (Q + kT ∇ ln s) + kT ∇·μ + sqrt(2 kT/h) L⁻ᵀ ξ,    Γ = L Lᵀ (Cholesky),
/// ```
///
/// `Q` the generalised force at rest, `∇` the derivatives along the lab
/// rotations of the body (`R_β f(k) = ∇f·(e_β × k)`), `s = sqrt(1 + m a²
/// sin²θ/A)` (so `∇ ln s = −a² cos θ n/(A + a² sin²θ)`, `n = k × Z`) and
/// `(∇·μ)_α = Σ_β R_β μ_αβ = −Σ_β (μ (R_β Γ) μ)_αβ` (the translations do not
/// change `μ`). With the geodesic step (a lab rotation by `w h`) this is
/// the reversible diffusion whose density is the Langevin run's
/// configuration marginal; at `c = 0` it is [`overdamped_on_plane`]'s drift
/// (test `coupled_step_at_zero_contact_damping_is_the_diagonal_one`).
/// Returns `(p, drift)` in the basis `(X, Y | k̂, ê, f̂)` of the callers.
#[allow(clippy::too_many_arguments)]
pub(crate) fn overdamped_coupled(
    b: &Bath,
    body: &Body,
    basis: [V3; 3],
    s2: f64,
    acc: [f64; 5],
    h: f64,
    xi: &[f64],
) -> ([f64; 5], [f64; 5]) {
    use nalgebra::Vector5;
    let [kn, eh, fh] = basis;
    let (a2, ia, ic) = (body.a * body.a, body.ia, body.ic);
    let gam = friction_lab(b, body, kn, None);
    // Γ is positive definite (γ_t, γ_r > 0) and the validation bounds its
    // conditioning (`thermal::MAX_BROWNIAN_CONTACT_RATIO`); should rounding
    // still defeat the factorisation, NaN velocities stop the run with the
    // engine's non-finite-state error instead of a panic.
    let Some(chol) = nalgebra::Cholesky::new(gam) else {
        return ([f64::NAN; 5], [f64::NAN; 5]);
    };
    let mu = chol.inverse();
    // The generalised force at rest, and kT ∇ ln s, in the lab basis.
    let mm = [ic, ia + a2 * s2, ia];
    let mut f = Vector5::new(acc[0], acc[1], 0.0, 0.0, 0.0);
    let gl = -b.kt * a2 * kn[2] / (ia + a2 * s2);
    let n = [kn[1], -kn[0], 0.0];
    for j in 0..3 {
        let tq = mm[0] * acc[2] * kn[j] + mm[1] * acc[3] * eh[j] + mm[2] * acc[4] * fh[j];
        f[2 + j] = tq + gl * n[j];
    }
    let mut drift = mu * f;
    // kT ∇·μ: the derivative along the lab rotation β moves k by e_β × k.
    for beta in 0..3 {
        let mut e = [0.0; 3];
        e[beta] = 1.0;
        let dg = friction_lab(b, body, kn, Some(cross(e, kn)));
        let col = mu.column(2 + beta).into_owned();
        drift -= b.kt * (mu * (dg * col));
    }
    // The noise: covariance (2 kT/h) μ = (2 kT/h) L⁻ᵀ L⁻¹.
    let mut z = Vector5::from_fn(|i, _| xi[i]);
    let solved = chol.l().tr_solve_lower_triangular_mut(&mut z);
    debug_assert!(solved, "L has a positive diagonal");
    let amp = (2.0 * b.kt / h).sqrt();
    let lab = |v: Vector5<f64>| -> [f64; 5] {
        let w = [v[2], v[3], v[4]];
        [v[0], v[1], dot(w, kn), dot(w, eh), dot(w, fh)]
    };
    (lab(drift + amp * z), lab(drift))
}

/// The exact Ornstein–Uhlenbeck step over `h` of a free body (in flight):
/// the centre's velocity `v` (3 modes of mass 1 at γ_t) and the angular
/// velocity `w` in the basis `(k̂, ê, f̂)` (masses `C, A, A`, each at γ_r),
/// with 6 standard normals `xi` (`v_x, v_y`, the three rotational modes,
/// `v_z`: the first five in the order the contact step uses them). No
/// contact damping (no contact).
pub(crate) fn ou_free(b: &Bath, body: &Body, k: V3, v: &mut V3, w: &mut V3, h: f64, xi: &[f64]) {
    let mode = |x: f64, rate: f64, mass: f64, z: f64| {
        let decay = (-rate * h).exp();
        let var = -(b.kt / mass) * (-2.0 * rate * h).exp_m1();
        decay * x + var.sqrt() * z
    };
    v[0] = mode(v[0], b.gt, 1.0, xi[0]);
    v[1] = mode(v[1], b.gt, 1.0, xi[1]);
    v[2] = mode(v[2], b.gt, 1.0, xi[5]);
    let ([kn, eh, fh], _) = modes_basis(k);
    let mut wn = *w;
    for (j, (dir, mass)) in [(kn, body.ic), (eh, body.ia), (fh, body.ia)]
        .into_iter()
        .enumerate()
    {
        let x = dot(wn, dir);
        let dx = mode(x, b.gr, mass, xi[2 + j]) - x;
        wn = add(wn, scale(dx, dir));
    }
    *w = wn;
}

/// What [`ou_on_plane_cached`] computed, with the bits of their
/// inputs, so a call with the same inputs reuses it: the same expressions on
/// the same bits, hence the same results.
///
/// - The factors of the modes whose rate is constant (`v_x`, `v_y`, `k̂`,
///   `f̂`) depend on the half step `h` only. The engine's steps are
///   differences of grid times `(j + 1) h₀ − j h₀`, which take a few
///   distinct values an ulp apart, so the last [`OU_H_SLOTS`] are kept.
/// - The basis, the `ê` mode's rate and mass and the coupled step's
///   eigendecomposition depend on the axis `k` only: the two half steps
///   between two RK4 steps (the second of step n, the first of step n + 1)
///   share it (`O` does not move `k`); their factors depend on `h` too and
///   are redone when `h` differs.
#[derive(Debug, Clone, Default)]
pub(crate) struct OuCache {
    /// `(h bits, [(e^{−λh}, sqrt(kT (1 − e^{−2λh})/M)) of v_x (and v_y), k̂,
    /// f̂])`, most recent in slot `next − 1`.
    consts: [Option<(u64, [Factors; 3])>; OU_H_SLOTS],
    /// The slot the next new `h` goes into (round robin).
    next: usize,
    /// The uncoupled step's data at one axis.
    axis: Option<AxisModes>,
    /// The coupled step's data at one axis.
    coupled: Option<Box<Coupled>>,
    /// The kinetic energy at the end of the last [`ou_in_contact`] and the
    /// bits of what it reads (`k`, `w`, `v_t` in the contact's frame): the
    /// next call's starting energy when nothing moved in between (the first
    /// half step after the second).
    kinetic: Option<([u64; 8], f64)>,
}

/// A mode's `(e^{−λh}, sqrt(kT (1 − e^{−2λh})/M))` over a step `h`: its
/// velocity decays by the first and gains the second times a standard
/// normal (scaled velocity units).
type Factors = (f64, f64);

/// Number of half steps `h` whose constant-rate factors [`OuCache`] keeps.
const OU_H_SLOTS: usize = 4;

/// The uncoupled step at one axis: the basis `(k̂, ê, f̂)`, the `ê` mode's
/// rate and mass, and its factors at one `h`.
#[derive(Debug, Clone, Copy)]
struct AxisModes {
    /// `k` bits.
    key: [u64; 3],
    basis: [V3; 3],
    rate: f64,
    mass: f64,
    /// `(h bits, the ê mode's factors at that h)`.
    factors: (u64, Factors),
}

/// The contact-damped step at one axis (see [`ou_on_plane_cached`]):
/// the basis, `sqrt(M_i)`, the eigenvectors and rates `λ_j`, and the
/// per-mode `(e^{−λ_j h}, sqrt(kT (1 − e^{−2λ_j h})))` at one `h`.
#[derive(Debug, Clone)]
struct Coupled {
    /// `k` bits.
    key: [u64; 3],
    dirs: [V3; 3],
    sq: [f64; 5],
    vecs: nalgebra::Matrix5<f64>,
    lams: [f64; 5],
    /// `h` bits of `factors`.
    h: u64,
    factors: [Factors; 5],
}

/// The exact Ornstein–Uhlenbeck step over `h` of `(v_h, w)` on the plane
/// at axis `k`, with 5 standard normals `xi` (docs/physics.md#langevin). Without
/// contact damping `M` and `Γ` are diagonal in `(X, Y | k̂, ê, f̂)`; with it,
/// the 5×5 problem is solved in the eigenbasis of `M^{−1/2} Γ M^{−1/2}`
/// (`Γ` gains `c Pᵀ P`, `P` the map to the horizontal slip
/// `v_h + (w × r)_h`). Its coefficients are kept in `cache` between calls:
/// the same expressions on the same bits, so the same results (the
/// constant-rate modes' factors per `h`; the basis, the `ê` mode and the
/// coupled step's eigendecomposition per axis `k`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn ou_on_plane_cached(
    b: &Bath,
    body: &Body,
    cache: &mut OuCache,
    k: V3,
    vh: &mut [f64; 2],
    w: &mut V3,
    h: f64,
    xi: &[f64],
) {
    if b.c > 0.0 {
        return ou_coupled_cached(b, body, cache, k, vh, w, h, xi);
    }
    // One mode: `(e^{−λh}, sqrt(var))` of a mode of mass `mass` relaxing
    // at `rate`, and the update of its velocity `x`.
    let factors = |rate: f64, mass: f64| {
        let decay = (-rate * h).exp();
        let var = -(b.kt / mass) * (-2.0 * rate * h).exp_m1();
        (decay, var.sqrt())
    };
    let mode = |x: f64, (decay, amp): Factors, z: f64| decay * x + amp * z;
    let hb = h.to_bits();
    let c = cache;
    let cached = c.consts.iter().flatten().find(|(k, _)| *k == hb);
    let [ft, fk, ff] = match cached {
        Some((_, f)) => *f,
        None => {
            let f = [
                factors(b.gt, 1.0),
                factors(b.gr, body.ic),
                factors(b.gr, body.ia),
            ];
            c.consts[c.next] = Some((hb, f));
            c.next = (c.next + 1) % OU_H_SLOTS;
            f
        }
    };
    for j in 0..2 {
        vh[j] = mode(vh[j], ft, xi[j]);
    }
    let key = [k[0].to_bits(), k[1].to_bits(), k[2].to_bits()];
    let ax = match c.axis {
        Some(ax) if ax.key == key => ax,
        _ => {
            let (basis, s2) = modes_basis(k);
            let beta = body.a * body.a * s2;
            let rate = (b.gr * body.ia + b.gt * beta) / (body.ia + beta);
            let mass = body.ia + beta;
            AxisModes {
                key,
                basis,
                rate,
                mass,
                factors: (hb, factors(rate, mass)),
            }
        }
    };
    let ax = if ax.factors.0 == hb {
        ax
    } else {
        AxisModes {
            factors: (hb, factors(ax.rate, ax.mass)),
            ..ax
        }
    };
    c.axis = Some(ax);
    let [kn, eh, fh] = ax.basis;
    let modes = [(kn, fk), (eh, ax.factors.1), (fh, ff)];
    let mut wn = *w;
    for (j, (dir, f)) in modes.into_iter().enumerate() {
        let x = dot(wn, dir);
        let dx = mode(x, f, xi[2 + j]) - x;
        wn = add(wn, scale(dx, dir));
    }
    *w = wn;
}

/// The kinetic energy (scaled, m = 1) of a top in one-sphere contact from
/// its generalised velocities in the contact's frame (the normal along `Z`):
/// `½ (|v_t|² + v_n²) + ½ w·I w`, `v_t` the centre of mass's tangent
/// velocity, `v_n = −a (w × k)_Z` the constraint's normal velocity
/// ([`normal_velocity`]).
pub(crate) fn kinetic_in_contact(a: f64, inertia: &Inertia, k: V3, vt: [f64; 2], w: V3) -> f64 {
    let vn = normal_velocity(a, k, w);
    0.5 * (vt[0] * vt[0] + vt[1] * vt[1] + vn * vn) + 0.5 * dot(w, inertia.apply(k, w))
}

/// The centre of mass's velocity along the contact normal (`Z` in the
/// contact's frame) that keeps the sphere's centre on the surface:
/// `v_n = −a (w × k)_Z` (scaled).
#[inline]
pub(crate) fn normal_velocity(a: f64, k: V3, w: V3) -> f64 {
    -a * cross(w, k)[2]
}

/// The bits of what [`kinetic_in_contact`] reads: `k`, `w`, `v_t`.
fn kinetic_key(k: V3, w: V3, vt: [f64; 2]) -> [u64; 8] {
    [k[0], k[1], k[2], w[0], w[1], w[2], vt[0], vt[1]].map(f64::to_bits)
}

/// The heat bath's step of a top in one-sphere contact, written once for
/// the vector model, the rigid model on the plane and the rigid model in the
/// tube (docs/physics.md#langevin, #tube-langevin): in the contact's frame
/// (the contact normal along `Z`; the lab frame on the plane) the constrained
/// top's kinetic energy and friction matrix are the plane's, so its exact
/// Ornstein–Uhlenbeck step at fixed configuration is
/// [`ou_on_plane_cached`]'s. `k`, the centre of mass's tangent velocity `vt`
/// and `w` are in that frame; `vt` and `w` are updated. Returns the normal
/// velocity after the step ([`normal_velocity`]) and the bath's work, the
/// change of [`kinetic_in_contact`] (for `W_f`). The energy at the end is
/// kept in `cache` and reused as the next call's starting energy when its
/// inputs have the same bits (the second half step of a step and the first
/// of the next).
#[allow(clippy::too_many_arguments)]
pub(crate) fn ou_in_contact(
    b: &Bath,
    body: &Body,
    inertia: &Inertia,
    cache: &mut OuCache,
    k: V3,
    vt: &mut [f64; 2],
    w: &mut V3,
    h: f64,
    xi: &[f64],
) -> (f64, f64) {
    let key = kinetic_key(k, *w, *vt);
    let e0 = match cache.kinetic {
        Some((kk, e)) if kk == key => e,
        _ => kinetic_in_contact(body.a, inertia, k, *vt, *w),
    };
    ou_on_plane_cached(b, body, cache, k, vt, w, h, xi);
    let e1 = kinetic_in_contact(body.a, inertia, k, *vt, *w);
    cache.kinetic = Some((kinetic_key(k, *w, *vt), e1));
    (normal_velocity(body.a, k, *w), e1 - e0)
}

/// The contact-damped step of [`ou_on_plane_cached`].
#[allow(clippy::too_many_arguments)]
fn ou_coupled_cached(
    b: &Bath,
    body: &Body,
    cache: &mut OuCache,
    k: V3,
    vh: &mut [f64; 2],
    w: &mut V3,
    h: f64,
    xi: &[f64],
) {
    use nalgebra::Vector5;
    let key = [k[0].to_bits(), k[1].to_bits(), k[2].to_bits()];
    let hb = h.to_bits();
    match &mut cache.coupled {
        Some(c) if c.key == key => {
            if c.h != hb {
                c.factors = coupled_factors(&c.lams, h, b);
                c.h = hb;
            }
        }
        _ => cache.coupled = Some(Box::new(coupled_modes(b, body, k, key, h))),
    }
    let Coupled {
        dirs,
        sq,
        vecs,
        factors,
        ..
    } = cache.coupled.as_deref().expect("just set");
    let p = [
        vh[0],
        vh[1],
        dot(*w, dirs[0]),
        dot(*w, dirs[1]),
        dot(*w, dirs[2]),
    ];
    let z = Vector5::from_fn(|i, _| sq[i] * p[i]);
    let mut q = vecs.transpose() * z;
    for j in 0..5 {
        let (decay, amp) = factors[j];
        q[j] = decay * q[j] + amp * xi[j];
    }
    let z = vecs * q;
    vh[0] = z[0] / sq[0];
    vh[1] = z[1] / sq[1];
    let mut wn = *w;
    for j in 0..3 {
        wn = add(wn, scale(z[2 + j] / sq[2 + j] - p[2 + j], dirs[j]));
    }
    *w = wn;
}

/// The coupled step's modes at the axis `k` (bits `key`), with their
/// factors at step `h`.
fn coupled_modes(b: &Bath, body: &Body, k: V3, key: [u64; 3], h: f64) -> Coupled {
    use nalgebra::{Matrix5, SymmetricEigen};
    let ([kn, eh, fh], s2) = modes_basis(k);
    let (a, ia, ic) = (body.a, body.ia, body.ic);
    let beta = a * a * s2;
    let m = [1.0, 1.0, ic, ia + beta, ia];
    let g = [b.gt, b.gt, b.gr * ic, b.gr * ia + b.gt * beta, b.gr * ia];
    let r = [a * kn[0], a * kn[1], a * kn[2] - 1.0];
    let cols: [[f64; 2]; 5] = {
        let c = |d: V3| {
            let x = cross(d, r);
            [x[0], x[1]]
        };
        [[1.0, 0.0], [0.0, 1.0], c(kn), c(eh), c(fh)]
    };
    let sq: [f64; 5] = m.map(f64::sqrt);
    let smat = Matrix5::from_fn(|i, j| {
        let pp = cols[i][0] * cols[j][0] + cols[i][1] * cols[j][1];
        let gij = if i == j { g[i] } else { 0.0 } + b.c * pp;
        gij / (sq[i] * sq[j])
    });
    let eig = SymmetricEigen::new(smat);
    let lams = std::array::from_fn(|j| eig.eigenvalues[j].max(0.0));
    Coupled {
        key,
        dirs: [kn, eh, fh],
        sq,
        vecs: eig.eigenvectors,
        lams,
        h: h.to_bits(),
        factors: coupled_factors(&lams, h, b),
    }
}

/// `(e^{−λ_j h}, sqrt(kT (1 − e^{−2λ_j h})))` of the coupled modes.
fn coupled_factors(lams: &[f64; 5], h: f64, b: &Bath) -> [Factors; 5] {
    lams.map(|lam| {
        let decay = (-lam * h).exp();
        let var = -b.kt * (-2.0 * lam * h).exp_m1();
        (decay, var.sqrt())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::vec3::rotate;

    const BODY: Body = Body {
        a: 0.6,
        ia: 0.18,
        ic: 0.25,
    };

    fn axis(theta: f64, phi: f64) -> V3 {
        [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ]
    }

    const AXES: [(f64, f64); 6] = [
        (0.3, 0.2),
        (1.0, -1.3),
        (1.5, 2.0),
        (2.2, 0.7),
        (3.0, -2.9),
        (1e-3, 0.4),
    ];

    /// The general step's drift at `c = 0` is the hand-derived diagonal one
    /// of [`overdamped_on_plane`] (its `cot θ` and `∂_θ` terms): the lab
    /// divergence `−Σ_β (μ (R_β Γ) μ)_αβ` and `μ ∇ ln s` reproduce them.
    #[test]
    fn coupled_step_at_zero_contact_damping_is_the_diagonal_one() {
        let b = Bath {
            kt: 0.7,
            gt: 1.3,
            gr: 2.1,
            c: 0.0,
        };
        let acc = [0.3, -0.2, 0.5, -0.7, 0.4];
        for (th, ph) in AXES {
            let (basis, s2) = modes_basis(axis(th, ph));
            let (_, want) = overdamped_on_plane(&b, &BODY, (s2, basis[0][2]), acc, 1e-3, &[0.0; 5]);
            let (_, got) = overdamped_coupled(&b, &BODY, basis, s2, acc, 1e-3, &[0.0; 5]);
            for i in 0..5 {
                assert!(
                    (got[i] - want[i]).abs() < 1e-12 * (1.0 + want[i].abs()),
                    "θ = {th}, component {i}: {} vs {}",
                    got[i],
                    want[i]
                );
            }
        }
    }

    /// With the contact damping on, the drift is `μ (Q + kT ∇ ln s) +
    /// kT ∇·μ` (lab basis), `∇·μ` here from central differences of `Γ⁻¹`
    /// along the lab rotations of the axis (step 1e-5: error ~1e-10), and
    /// the noise's covariance is `(2 kT/h) μ`.
    #[test]
    fn coupled_step_drift_and_noise_against_finite_differences() {
        use nalgebra::{Matrix5, Vector5};
        let b = Bath {
            kt: 0.7,
            gt: 1.3,
            gr: 2.1,
            c: 3.4,
        };
        let h = 1e-3;
        let acc = [0.3, -0.2, 0.5, -0.7, 0.4];
        let inv = |k: V3| friction_lab(&b, &BODY, k, None).try_inverse().unwrap();
        for (th, ph) in AXES {
            let k = axis(th, ph);
            let (basis, s2) = modes_basis(k);
            let [kn, eh, fh] = basis;
            let mu = inv(kn);
            // Non-diagonal: the translation is coupled to the rotations.
            assert!(mu[(0, 3)].abs() + mu[(1, 4)].abs() + mu[(0, 2)].abs() > 1e-3);
            let eps = 1e-5;
            let mut div = Vector5::zeros();
            for beta in 0..3 {
                let mut e = [0.0; 3];
                e[beta] = eps;
                let d = (inv(rotate(e, kn)) - inv(rotate(e.map(|x: f64| -x), kn))) / (2.0 * eps);
                div += d.column(2 + beta);
            }
            let mm = [BODY.ic, BODY.ia + BODY.a * BODY.a * s2, BODY.ia];
            let mut f = Vector5::new(acc[0], acc[1], 0.0, 0.0, 0.0);
            let gl = -b.kt * BODY.a * BODY.a * kn[2] / (BODY.ia + BODY.a * BODY.a * s2);
            for j in 0..3 {
                f[2 + j] = mm[0] * acc[2] * kn[j]
                    + mm[1] * acc[3] * eh[j]
                    + mm[2] * acc[4] * fh[j]
                    + gl * [kn[1], -kn[0], 0.0][j];
            }
            let want = mu * f + b.kt * div;
            let frame = |v: Vector5<f64>| {
                let w = [v[2], v[3], v[4]];
                [v[0], v[1], dot(w, kn), dot(w, eh), dot(w, fh)]
            };
            let want = frame(want);
            let (_, got) = overdamped_coupled(&b, &BODY, basis, s2, acc, h, &[0.0; 5]);
            for i in 0..5 {
                assert!(
                    (got[i] - want[i]).abs() < 1e-8 * (1.0 + want[i].abs()),
                    "θ = {th}, component {i}: {} vs {}",
                    got[i],
                    want[i]
                );
            }
            // The noise map B (columns: unit normals) has B Bᵀ = (2 kT/h) μ
            // in the frame basis E μ Eᵀ.
            let mut bm = Matrix5::zeros();
            for j in 0..5 {
                let mut xi = [0.0; 5];
                xi[j] = 1.0;
                let (p, d) = overdamped_coupled(&b, &BODY, basis, s2, acc, h, &xi);
                for i in 0..5 {
                    bm[(i, j)] = p[i] - d[i];
                }
            }
            let mut e = Matrix5::zeros();
            e[(0, 0)] = 1.0;
            e[(1, 1)] = 1.0;
            for (r, d) in basis.iter().enumerate() {
                for j in 0..3 {
                    e[(2 + r, 2 + j)] = d[j];
                }
            }
            let want = e * mu * e.transpose() * (2.0 * b.kt / h);
            let got = bm * bm.transpose();
            assert!(
                (got - want).norm() < 1e-9 * want.norm(),
                "θ = {th}: noise covariance"
            );
        }
    }
}
