//! Rodas4P: a linearly implicit (Rosenbrock) method of order 4 with an
//! embedded order-3 error estimate and an order-3 continuous extension,
//! stiffly accurate and L-stable: Steinebach's variant of Hairer & Wanner's
//! Rodas4 (G. Steinebach, *Order-reduction of ROW-methods for DAEs and
//! method of lines applications*, Preprint 1741, TH Darmstadt, 1995),
//! with the same six-stage structure as `rodas.f` (Hairer & Wanner,
//! *Solving Ordinary Differential Equations II*, §IV.7).
//!
//! # Why Rodas4P and not Rodas4
//!
//! Rodas4 (`rodas.f`, `METH = 1`) was implemented first and measured: on
//! the Prothero–Robinson problem `y' = -1000 (y - cos t) - sin t` it
//! suffers the classical order reduction (3 984 steps at tol 1e-8 against
//! 97 for Rodas4P), and the regularised friction law near rolling has that
//! very structure (the slip relaxes on `ε / (μ g)` to a slowly moving
//! quasi-equilibrium). On the classical preset with ε = 1e-5 m/s at rtol
//! 1e-8 Rodas4 took 184 k steps with a Jellett drift of 1e-6, Rodas4P 133 k
//! steps with 7e-8 (docs/performance.md).
//!
//! # Coefficients
//!
//! Transcribed from OrdinaryDiffEq.jl's `Rodas4PTableau`
//! (`src/tableaus/rosenbrock_tableaus.jl`, which cites Steinebach 1995): the
//! stage coefficients in the transformed form of `rodas.f` (`a_ij`, and
//! `C_ij` entering as `C_ij / h`), the time-derivative weights `d_i`, the
//! nodes `c_i` and the dense-output coefficients `h2j`, `h3j`. The
//! transcription is checked by the observed order 4 with a fixed step
//! (`tests/integrate/`).
//!
//! # Algorithm (as `rodas.f`)
//!
//! With `E = I / (γ h) - J`, `J = ∂f/∂y (t, y)`, `f_t = ∂f/∂t (t, y)`:
//!
//! ```text
//! E k1 = f(t, y)                                   + h d1 f_t
//! E ki = f(t + c_i h, y + Σ_{j<i} a_ij kj) + Σ_{j<i} (C_ij / h) kj + h d_i f_t   (i = 2..4)
//! E k5 = f(t + h, u5) + Σ_{j<5} (C_5j / h) kj,     u5 = y + Σ_{j<5} a_5j kj
//! E k6 = f(t + h, u5 + k5) + Σ_{j<6} (C_6j / h) kj
//! y_new = u5 + k5 + k6   (order 4),   embedded = u5 + k5   (order 3)
//! ```
//!
//! The local error estimate is `k6`; its norm is the RMS of
//! `k6_i / sk_i`, `sk_i = atol + rtol max(|y_i|, |y_new_i|)` (the convention
//! of DOP853 and of `rodas.f`). Step-size control: `h_new = h / fac`,
//! `fac = clamp(err^(1/4) / 0.9, 1/6, 5)` (pure I controller, `rodas.f`'s
//! bounds `FAC1 = 5`, `FAC2 = 1/6`, without its predictive Gustafsson
//! variant, as DOP853 here runs with `beta = 0`); after a rejection the
//! next step does not grow. Dense output (`rodas.f`'s `CONTRO`), with
//! `s = (t - t0) / h`:
//!
//! ```text
//! y(s) = (1 - s) y0 + s (y1 + (1 - s) (H2 + s H3)),   H2 = Σ h2j kj,  H3 = Σ h3j kj
//! ```
//!
//! exact at both ends and free (no extra evaluations).
//!
//! # Jacobian
//!
//! `J` by central differences of `rhs`, column `j` with the step
//! `δ_j = sqrt(eps) max(|y_j|, 1)` (the states are in scaled units, see
//! docs/physics.md#friction-laws), recomputed at every accepted step (N ≤ 15) and
//! reused by the attempts that follow a rejection (same point). Central,
//! not forward: the regularised friction force varies on the slip scale ε,
//! which is 5e-6 in scaled units for ε = 1e-5 m/s on the classical top, so
//! a forward difference with `δ = 1.5e-8` is off by `δ / ε ~ 3e-3` in the
//! stiff entries, and with `h |J| >> 1` that error is not small: forward
//! differences took 902 k steps (ε = 1e-5, rtol 1e-8, Rodas4) against
//! 184 k with central ones. Central differences are off by `(δ / ε)^2`.
//!
//! `f_t` by a forward difference in `t` (step `sqrt(eps) max(|t|, 1)`, one
//! evaluation per accepted step): nothing is assumed about autonomy. The
//! models of this crate latch the applied force in `begin_segment`, so their
//! right-hand sides do not depend on `t` within a segment and `f_t` comes
//! out exactly zero there; the evaluation at `t + δt` may lie just past the
//! segment end, which is harmless for them.
//!
//! # Why in-house
//!
//! Same reasons as DOP853 (see `integrate/mod.rs`): a fixed-size `[f64; N]`
//! state and `[[f64; N]; N]` matrices (dense LU with partial pivoting, no
//! heap), and the shared driver with dense output, events and tstops.
//!
//! # Counting right-hand-side evaluations
//!
//! 1 per segment start (`f(t0, y0)`), 1 for the initial step choice (first
//! segment, only when `Options::h0` is `None`), per accepted step `2 N` for
//! the Jacobian, 1 for `f_t`, 5 for the stages and 1 for `f(t_new, y_new)`
//! (the next step's first stage), and 5 per rejected attempt (Jacobian
//! reused):
//!
//! ```text
//! rhs_evals = segments + [h0 is None] + (2 N + 7) steps + 5 rejected
//! ```
//!
//! An attempt abandoned because `E` is singular costs no evaluation and
//! counts as rejected too (the step is halved).

// Component loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use super::{Engine, Fail, OdeSystem, Stats, check_adaptive, eval, hinit};

/// Rodas4P coefficients (OrdinaryDiffEq.jl `Rodas4PTableau`), digits as
/// published (trailing zeros kept).
#[allow(clippy::excessive_precision)]
mod tableau {
    pub const GAMMA: f64 = 0.25;

    pub const A21: f64 = 3.0;
    pub const A31: f64 = 1.831036793486759;
    pub const A32: f64 = 0.4955183967433795;
    pub const A41: f64 = 2.304376582692669;
    pub const A42: f64 = -0.05249275245743001;
    pub const A43: f64 = -1.176798761832782;
    pub const A51: f64 = -7.170454962423024;
    pub const A52: f64 = -4.741636671481785;
    pub const A53: f64 = -16.31002631330971;
    pub const A54: f64 = -1.062004044111401;

    pub const C21: f64 = -12.0;
    pub const C31: f64 = -8.791795173947035;
    pub const C32: f64 = -2.207865586973518;
    pub const C41: f64 = 10.81793056857153;
    pub const C42: f64 = 6.780270611428266;
    pub const C43: f64 = 19.53485944642410;
    pub const C51: f64 = 34.19095006749676;
    pub const C52: f64 = 15.49671153725963;
    pub const C53: f64 = 54.74760875964130;
    pub const C54: f64 = 14.16005392148534;
    pub const C61: f64 = 34.62605830930532;
    pub const C62: f64 = 15.30084976114473;
    pub const C63: f64 = 56.99955578662667;
    pub const C64: f64 = 18.40807009793095;
    pub const C65: f64 = -5.714285714285717;

    /// Nodes (`c5 = c6 = 1`).
    pub const C2: f64 = 0.75;
    pub const C3: f64 = 0.21;
    pub const C4: f64 = 0.63;

    /// Weights of `h f_t` (`d5 = d6 = 0`).
    pub const D1: f64 = 0.2500000000000000;
    pub const D2: f64 = -0.5000000000000000;
    pub const D3: f64 = -0.0235040000000000;
    pub const D4: f64 = -0.0362000000000000;

    /// Dense output.
    pub const H21: f64 = 25.09876703708589;
    pub const H22: f64 = 11.62013104361867;
    pub const H23: f64 = 28.49148307714626;
    pub const H24: f64 = -5.664021568594133;
    pub const H25: f64 = 0.0;
    pub const H31: f64 = 1.638054557396973;
    pub const H32: f64 = -0.7373619806678748;
    pub const H33: f64 = 8.477918219238990;
    pub const H34: f64 = 15.99253148779520;
    pub const H35: f64 = -1.882352941176471;
}
use tableau::*;

/// Safety factor of the step-size controller.
const SAFE: f64 = 0.9;
/// `h_new / h` lies in `[1 / FACC1, 1 / FACC2]` = `[0.2, 6]` (`rodas.f`).
const FACC1: f64 = 5.0;
const FACC2: f64 = 1.0 / 6.0;
/// Exponent `1 / (q + 1)` with `q = 3` the order of the error estimator.
const EXPO: f64 = 0.25;
/// Order used by the initial step choice.
const IORD: i32 = 4;
/// `sqrt(eps)`, the relative finite-difference step.
const SQRT_EPS: f64 = 1.4901161193847656e-8;

/// LU factorisation with partial pivoting of `a` in place (`L` unit lower,
/// below the diagonal; `U` on and above it; row `k` was swapped with
/// `piv[k]` at step `k`). Returns `false` if a pivot is zero or not finite.
#[cfg(test)]
pub(crate) fn lu_factor<const N: usize>(a: &mut [[f64; N]; N], piv: &mut [usize; N]) -> bool {
    lu_factor_block(a, piv, 0, N)
}

/// Solve `A x = b` in place from [`lu_factor`]'s output.
#[cfg(test)]
pub(crate) fn lu_solve<const N: usize>(lu: &[[f64; N]; N], piv: &[usize; N], b: &mut [f64; N]) {
    lu_solve_block(lu, piv, b, 0, N);
}

/// [`lu_factor`] of the diagonal block `lo..hi` of `a` alone (pivot rows
/// searched and swapped within `lo..hi`; a swap moves whole rows, so the
/// block's rows left of `lo` move with it). For a block lower triangular
/// matrix `[[A, 0], [B, D]]` (the Rosenbrock matrix of a system with
/// quadratures, `OdeSystem::CONTROLLED`) the blocks `A` (`0..c`) and `D`
/// (`c..N`) are factorised separately and [`lu_solve_block`] solves by
/// block forward substitution; over `0..N` this is plain [`lu_factor`].
pub(crate) fn lu_factor_block<const N: usize>(
    a: &mut [[f64; N]; N],
    piv: &mut [usize; N],
    lo: usize,
    hi: usize,
) -> bool {
    for k in lo..hi {
        let mut p = k;
        let mut m = a[k][k].abs();
        for i in k + 1..hi {
            let v = a[i][k].abs();
            if v > m {
                m = v;
                p = i;
            }
        }
        if !(m > 0.0 && m.is_finite()) {
            return false;
        }
        piv[k] = p;
        if p != k {
            a.swap(p, k);
        }
        let inv = 1.0 / a[k][k];
        for i in k + 1..hi {
            let l = a[i][k] * inv;
            a[i][k] = l;
            if l != 0.0 {
                for j in k + 1..hi {
                    a[i][j] -= l * a[k][j];
                }
            }
        }
    }
    true
}

/// Solve for the components `lo..hi` of `x` in place, the components
/// `..lo` of `b` already holding the solution: `D x₂ = b₂ − B x₁` with
/// the block `lo..hi` factorised by [`lu_factor_block`] and `B` the rows
/// `lo..hi` left of `lo` (as permuted by the block's pivoting).
pub(crate) fn lu_solve_block<const N: usize>(
    lu: &[[f64; N]; N],
    piv: &[usize; N],
    b: &mut [f64; N],
    lo: usize,
    hi: usize,
) {
    for k in lo..hi {
        b.swap(k, piv[k]);
    }
    for i in lo..hi {
        let mut s = b[i];
        for j in 0..i {
            s -= lu[i][j] * b[j];
        }
        b[i] = s;
    }
    for i in (lo..hi).rev() {
        let mut s = b[i];
        for j in i + 1..hi {
            s -= lu[i][j] * b[j];
        }
        b[i] = s / lu[i][i];
    }
}

/// Factorise the Rosenbrock matrix of a system whose first `c` components
/// are controlled and the rest quadratures (block lower triangular: no
/// controlled derivative reads a quadrature), block by block; with `c = N`
/// this is [`lu_factor`].
fn factor<const N: usize>(a: &mut [[f64; N]; N], piv: &mut [usize; N], c: usize) -> bool {
    lu_factor_block(a, piv, 0, c) && lu_factor_block(a, piv, c, N)
}

/// Solve with [`factor`]'s output (block forward substitution).
fn solve<const N: usize>(lu: &[[f64; N]; N], piv: &[usize; N], b: &mut [f64; N], c: usize) {
    lu_solve_block(lu, piv, b, 0, c);
    lu_solve_block(lu, piv, b, c, N);
}

/// The Rodas4P stepper state.
#[derive(Clone)]
pub(crate) struct Rodas4p<const N: usize> {
    rtol: f64,
    atol: f64,
    h_max: f64,
    h0: Option<f64>,
    /// Proposed size of the next step (valid once `initialized`).
    h: f64,
    initialized: bool,
    /// The previous attempt was rejected.
    rejected: bool,
    /// Last accepted step `(t0, y0) -> (t1, y1)` of size `h_step`.
    t0: f64,
    y0: [f64; N],
    t1: f64,
    y1: [f64; N],
    h_step: f64,
    /// `f(t1, y1)`.
    f1: [f64; N],
    /// Dense-output coefficients `H2`, `H3` of the last accepted step.
    cont: [[f64; N]; 2],
}

impl<const N: usize> Rodas4p<N> {
    /// New stepper; `h_max` is the largest step, `h0` the initial step
    /// (`None`: Hairer's `hinit` with order 4).
    pub(super) fn new(rtol: f64, atol: f64, h0: Option<f64>, h_max: f64) -> Self {
        check_adaptive("Rosenbrock", rtol, atol, h0, h_max);
        Rodas4p {
            rtol,
            atol,
            h_max,
            h0,
            h: 0.0,
            initialized: false,
            rejected: false,
            t0: 0.0,
            y0: [0.0; N],
            t1: 0.0,
            y1: [0.0; N],
            h_step: 0.0,
            f1: [0.0; N],
            cont: [[0.0; N]; 2],
        }
    }

    /// `J = ∂f/∂y` by central and `f_t = ∂f/∂t` by forward differences at
    /// `(t, y)` (`2 N + 1` evaluations); `f0 = f(t, y)`.
    #[allow(clippy::type_complexity)]
    fn jacobian<S: OdeSystem<N>>(
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        f0: &[f64; N],
        stats: &mut Stats,
    ) -> Result<([[f64; N]; N], [f64; N]), Fail<S::Error>> {
        let mut jac = [[0.0; N]; N];
        let mut fp = [0.0; N];
        let mut fm = [0.0; N];
        let mut yp = *y;
        // Finite differences over the controlled components; the
        // quadratures' columns are zero but for their own block, which the
        // system states (`OdeSystem::quadrature_jacobian`).
        for j in 0..S::CONTROLLED {
            let yj = y[j];
            let dd = SQRT_EPS * yj.abs().max(1.0);
            yp[j] = yj + dd;
            let y_plus = yp[j];
            eval(sys, t, &yp, &mut fp, stats)?;
            yp[j] = yj - dd;
            // The step actually taken (exactly representable difference).
            let d = y_plus - yp[j];
            eval(sys, t, &yp, &mut fm, stats)?;
            for i in 0..N {
                jac[i][j] = (fp[i] - fm[i]) / d;
            }
            yp[j] = yj;
        }
        sys.quadrature_jacobian(t, y, f0, &mut jac);
        let tp = t + SQRT_EPS * t.abs().max(1.0);
        let dt = tp - t;
        eval(sys, tp, y, &mut fp, stats)?;
        let mut ft = [0.0; N];
        for i in 0..N {
            ft[i] = (fp[i] - f0[i]) / dt;
        }
        Ok((jac, ft))
    }
}

impl<const N: usize> Engine<N> for Rodas4p<N> {
    fn restart<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        let mut f = [0.0; N];
        eval(sys, t, y, &mut f, stats)?;
        self.t0 = t;
        self.y0 = *y;
        self.t1 = t;
        self.y1 = *y;
        self.f1 = f;
        self.h_step = 0.0;
        self.cont = [[0.0; N]; 2];
        self.rejected = false;
        if !self.initialized {
            self.h = match self.h0 {
                Some(h) => h.min(self.h_max),
                None => {
                    let h_cap = self.h_max.min(t_stop - t);
                    hinit(sys, t, y, &f, (self.rtol, self.atol), IORD, h_cap, stats)?
                }
            };
            self.initialized = true;
        }
        Ok(())
    }

    /// One accepted step from `(t1, y1)`, retrying with a smaller `h` after
    /// a rejection. A numerical kernel kept whole on purpose (over 150
    /// lines): the Jacobian, the LU factors of `I/(γh) − J`, the six stages,
    /// the embedded error estimate, the step-size control and the dense
    /// output's coefficients share the stage vectors and the factors; split,
    /// a dozen `[f64; N]` arrays would pass between the pieces, and the
    /// stage-by-stage match with Hairer–Wanner's RODAS would be lost.
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        let t = self.t1;
        let y = self.y1;
        let f0 = self.f1;
        let (jac, ft) = Self::jacobian(sys, t, &y, &f0, stats)?;
        let mut last_nonfinite = false;
        let h_min = (16.0 * f64::EPSILON * t.abs()).max(1e-300);
        loop {
            if self.h.is_nan() || self.h < h_min {
                return Err(if last_nonfinite {
                    Fail::NonFinite { t }
                } else {
                    Fail::Underflow { t, h: self.h }
                });
            }
            // Land exactly on the stop; stretch the step by up to 1 % rather
            // than leave a sliver (as DOP853).
            let (hs, t_new, clipped) = if t + 1.01 * self.h >= t_stop {
                (t_stop - t, t_stop, true)
            } else {
                (self.h, t + self.h, false)
            };

            // E = I / (γ h) - J, factorised.
            let mut e = jac;
            for i in 0..N {
                for j in 0..N {
                    e[i][j] = -e[i][j];
                }
                e[i][i] += 1.0 / (GAMMA * hs);
            }
            let mut piv = [0usize; N];
            if !factor(&mut e, &mut piv, S::CONTROLLED) {
                stats.rejected += 1;
                self.rejected = true;
                last_nonfinite = !e.iter().flatten().all(|v| v.is_finite());
                self.h = hs * 0.5;
                continue;
            }

            let inv_h = 1.0 / hs;
            let mut u = [0.0; N];
            let mut du = [0.0; N];
            let mut k1 = [0.0; N];
            let mut k2 = [0.0; N];
            let mut k3 = [0.0; N];
            let mut k4 = [0.0; N];
            let mut k5 = [0.0; N];
            let mut k6 = [0.0; N];

            for n in 0..N {
                k1[n] = f0[n] + hs * D1 * ft[n];
            }
            solve(&e, &piv, &mut k1, S::CONTROLLED);

            for n in 0..N {
                u[n] = y[n] + A21 * k1[n];
            }
            eval(sys, t + C2 * hs, &u, &mut du, stats)?;
            for n in 0..N {
                k2[n] = du[n] + (C21 * inv_h) * k1[n] + hs * D2 * ft[n];
            }
            solve(&e, &piv, &mut k2, S::CONTROLLED);

            for n in 0..N {
                u[n] = y[n] + A31 * k1[n] + A32 * k2[n];
            }
            eval(sys, t + C3 * hs, &u, &mut du, stats)?;
            for n in 0..N {
                k3[n] = du[n] + (C31 * inv_h) * k1[n] + (C32 * inv_h) * k2[n] + hs * D3 * ft[n];
            }
            solve(&e, &piv, &mut k3, S::CONTROLLED);

            for n in 0..N {
                u[n] = y[n] + A41 * k1[n] + A42 * k2[n] + A43 * k3[n];
            }
            eval(sys, t + C4 * hs, &u, &mut du, stats)?;
            for n in 0..N {
                k4[n] = du[n]
                    + (C41 * inv_h) * k1[n]
                    + (C42 * inv_h) * k2[n]
                    + (C43 * inv_h) * k3[n]
                    + hs * D4 * ft[n];
            }
            solve(&e, &piv, &mut k4, S::CONTROLLED);

            for n in 0..N {
                u[n] = y[n] + A51 * k1[n] + A52 * k2[n] + A53 * k3[n] + A54 * k4[n];
            }
            eval(sys, t_new, &u, &mut du, stats)?;
            for n in 0..N {
                k5[n] = du[n]
                    + (C51 * inv_h) * k1[n]
                    + (C52 * inv_h) * k2[n]
                    + (C53 * inv_h) * k3[n]
                    + (C54 * inv_h) * k4[n];
            }
            solve(&e, &piv, &mut k5, S::CONTROLLED);

            // Embedded (order 3) solution.
            for n in 0..N {
                u[n] += k5[n];
            }
            eval(sys, t_new, &u, &mut du, stats)?;
            for n in 0..N {
                k6[n] = du[n]
                    + (C61 * inv_h) * k1[n]
                    + (C62 * inv_h) * k2[n]
                    + (C63 * inv_h) * k3[n]
                    + (C64 * inv_h) * k4[n]
                    + (C65 * inv_h) * k5[n];
            }
            solve(&e, &piv, &mut k6, S::CONTROLLED);

            // Order-4 solution; k6 is the error estimate.
            let mut y_new = [0.0; N];
            let mut err = 0.0;
            let mut finite = true;
            for n in 0..N {
                y_new[n] = u[n] + k6[n];
                finite &= y_new[n].is_finite();
            }
            // The error norm over the controlled components only.
            let controlled = S::CONTROLLED;
            for n in 0..controlled {
                let sk = self.atol + self.rtol * y[n].abs().max(y_new[n].abs());
                err += (k6[n] / sk).powi(2);
            }
            let err = (err / controlled as f64).sqrt();
            if !finite || !err.is_finite() {
                stats.rejected += 1;
                self.rejected = true;
                last_nonfinite = true;
                self.h = hs / 10.0;
                continue;
            }
            last_nonfinite = false;
            let fac11 = err.powf(EXPO);
            let fac = (fac11 / SAFE).clamp(FACC2, FACC1);
            if err <= 1.0 {
                let mut f_new = [0.0; N];
                eval(sys, t_new, &y_new, &mut f_new, stats)?;
                let mut h_new = hs / fac;
                if self.rejected {
                    h_new = h_new.min(hs);
                }
                if clipped && hs < self.h {
                    // A step shortened to land on a stop says little about
                    // the step size: keep the pending proposal if larger.
                    h_new = h_new.max(self.h);
                }
                self.h = h_new.min(self.h_max);
                self.rejected = false;
                for n in 0..N {
                    self.cont[0][n] =
                        H21 * k1[n] + H22 * k2[n] + H23 * k3[n] + H24 * k4[n] + H25 * k5[n];
                    self.cont[1][n] =
                        H31 * k1[n] + H32 * k2[n] + H33 * k3[n] + H34 * k4[n] + H35 * k5[n];
                }
                self.f1 = f_new;
                self.t0 = t;
                self.y0 = y;
                self.t1 = t_new;
                self.y1 = y_new;
                self.h_step = hs;
                return Ok(());
            }
            stats.rejected += 1;
            self.rejected = true;
            self.h = hs / FACC1.min(fac11 / SAFE);
        }
    }

    fn t(&self) -> f64 {
        self.t1
    }

    fn y(&self) -> &[f64; N] {
        &self.y1
    }

    fn t_prev(&self) -> f64 {
        self.t0
    }

    fn prepare_dense<S: OdeSystem<N>>(
        &mut self,
        _sys: &mut S,
        _stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        // The interpolant comes with the step.
        Ok(())
    }

    fn dense(&self, t: f64, out: &mut [f64; N]) {
        if t == self.t1 {
            *out = self.y1;
            return;
        }
        if t == self.t0 {
            *out = self.y0;
            return;
        }
        let s = (t - self.t0) / self.h_step;
        let s1 = 1.0 - s;
        for n in 0..N {
            out[n] =
                s1 * self.y0[n] + s * (self.y1[n] + s1 * (self.cont[0][n] + s * self.cont[1][n]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{factor, lu_factor, lu_solve, solve};

    /// A 4x4 system that needs pivoting (zero leading entry).
    #[test]
    fn lu_solves_with_pivoting() {
        let a = [
            [0.0, 2.0, 1.0, -1.0],
            [3.0, -1.0, 0.5, 2.0],
            [1.0, 1.0, 4.0, 0.0],
            [-2.0, 0.5, 1.0, 3.0],
        ];
        let x = [1.0, -2.0, 0.5, 3.0];
        let mut b = [0.0; 4];
        for i in 0..4 {
            for j in 0..4 {
                b[i] += a[i][j] * x[j];
            }
        }
        let mut lu = a;
        let mut piv = [0; 4];
        assert!(lu_factor(&mut lu, &mut piv));
        lu_solve(&lu, &piv, &mut b);
        for i in 0..4 {
            assert!((b[i] - x[i]).abs() < 1e-14, "{b:?} vs {x:?}");
        }
    }

    /// A block lower triangular matrix `[[A, 0], [B, D]]` (quadratures
    /// after the controlled components), factorised block by block, with a
    /// pivot swap in each block (a[0][0] = 0, d[0][0] small).
    #[test]
    fn block_lu_solves_block_lower_triangular() {
        let a = [
            [0.0, 2.0, 1.0, 0.0, 0.0],
            [3.0, -1.0, 0.5, 0.0, 0.0],
            [1.0, 1.0, 4.0, 0.0, 0.0],
            [-2.0, 0.5, 1.0, 0.1, 3.0],
            [0.7, -1.5, 2.0, -2.0, 1.0],
        ];
        let x = [1.0, -2.0, 0.5, 3.0, -0.25];
        let mut b = [0.0; 5];
        for i in 0..5 {
            for j in 0..5 {
                b[i] += a[i][j] * x[j];
            }
        }
        let mut lu = a;
        let mut piv = [0; 5];
        assert!(factor(&mut lu, &mut piv, 3));
        assert_eq!((piv[0], piv[3]), (1, 4), "both blocks pivot");
        solve(&lu, &piv, &mut b, 3);
        for i in 0..5 {
            assert!((b[i] - x[i]).abs() < 1e-14, "{b:?} vs {x:?}");
        }
    }

    #[test]
    fn lu_reports_singular() {
        let mut a = [[1.0, 2.0], [2.0, 4.0]];
        let mut piv = [0; 2];
        assert!(!lu_factor(&mut a, &mut piv));
    }
}
