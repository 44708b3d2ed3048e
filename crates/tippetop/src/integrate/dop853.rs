//! DOP853: Dormand–Prince 8(5,3) with 7th-order dense output, following
//! Hairer's `dop853.f` (error norm, `hinit`, step-size control).

// Component loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use super::dop853_coefficients::{A, BHH, C, D, E5};
use super::{Engine, Fail, OdeSystem, Stats, check_adaptive, eval, eval_accepted, hinit};

/// Safety factor of the step-size controller.
const SAFE: f64 = 0.9;
/// Lower bound of `h_new / h` is `FAC1`, upper bound `FAC2`.
const FAC1: f64 = 0.333;
const FAC2: f64 = 6.0;
/// `1 / FAC1` and `1 / FAC2` as in `dop853.f` (`FACC1`, `FACC2`).
const FACC1: f64 = 1.0 / FAC1;
const FACC2: f64 = 1.0 / FAC2;
/// Order used by `hinit`.
const IORD: i32 = 8;

/// `h ρ` at which `dop853.f` declares a step stiff (`HLAMB > 6.1`): the
/// step-size cap of [`super::Stepper::Dop853::stability_cap`] is `6.1/ρ`.
/// Inside the method's real stability interval `[−6.39, 0]`
/// (`|R(−6.1)| = 0.59`; test `stability_boundary_of_the_coefficients`).
const STIFF_HLAMB: f64 = 6.1;

/// Number of stages of the method proper (without FSAL and dense stages).
const STAGES: usize = 12;

/// The DOP853 stepper state.
#[derive(Clone)]
pub(crate) struct Dop853<const N: usize> {
    rtol: f64,
    atol: f64,
    h_max: f64,
    h0: Option<f64>,
    /// Proposed size of the next step (valid once `initialized`).
    h: f64,
    initialized: bool,
    /// The previous attempt was rejected (`REJECT` in `dop853.f`).
    rejected: bool,
    /// `β` of the stabilised step-size control and the exponent
    /// `1/8 − 0.2 β` (`EXPO1` of `dop853.f`).
    beta: f64,
    expo1: f64,
    /// Cap the next step at `STIFF_HLAMB / ρ` (see `Stepper::Dop853`).
    stability_cap: bool,
    /// Error of the last accepted step, at least 1e-4 (`FACOLD`).
    facold: f64,
    /// `facold^β`, the Lund factor of every attempt until the next
    /// accepted step: computed once when `facold` is set, not once per
    /// attempt (a `powf`, ~125 instructions; the same value).
    facold_beta: f64,
    /// Last accepted step `(t0, y0) -> (t1, y1)` of size `h_step`.
    t0: f64,
    y0: [f64; N],
    t1: f64,
    y1: [f64; N],
    h_step: f64,
    /// `f(t1, y1)`.
    f1: [f64; N],
    /// Stages of the last accepted step: 0–11 method, 12 = `f(t1, y1)`,
    /// 13–15 dense output (valid when `dense_ready`).
    k: [[f64; N]; 16],
    /// Interpolation coefficients (`rcont2..rcont8` of `dop853.f`).
    cont: [[f64; N]; 7],
    dense_ready: bool,
}

/// `sum_j coef[j] * k[j]` over the listed stages `j` (in increasing order)
/// with a non-zero coefficient, one stage at a time from the first term
/// (not from `0 + ` it: one addition less per component and row; the same
/// bits, but for the sign of a sum that is all zeros, `−0` where `0 + …`
/// gave `+0`, which the `y + h·sum` it feeds cannot tell apart unless
/// `y` is `−0` too).
///
/// `coef` is a row of the constant tables and the `j` are literals, so each
/// coefficient and its zero test are known at compile time: the loop over
/// the stages and the tests disappear and only the non-zero terms remain,
/// each added in the same order as a loop over `j` would (the same result,
/// bit for bit).
macro_rules! combine {
    ($coef:expr, $k:expr; $($j:literal)*) => {{
        let mut acc = [0.0; N];
        let mut first = true;
        $(
            let a: f64 = $coef[$j];
            if a != 0.0 {
                if first {
                    first = false;
                    for n in 0..N {
                        acc[n] = a * $k[$j][n];
                    }
                } else {
                    for n in 0..N {
                        acc[n] += a * $k[$j][n];
                    }
                }
            }
        )*
        let _ = first;
        acc
    }};
}

impl<const N: usize> Dop853<N> {
    /// New stepper; `h_max` is the largest step, `h0` the initial step
    /// (`None`: Hairer's `hinit`).
    pub(super) fn new(
        rtol: f64,
        atol: f64,
        beta: f64,
        stability_cap: bool,
        h0: Option<f64>,
        h_max: f64,
    ) -> Self {
        let mut e = Dop853 {
            rtol,
            atol,
            h_max,
            h0,
            h: 0.0,
            initialized: false,
            rejected: false,
            beta,
            expo1: 0.0,
            stability_cap,
            facold: 0.0,
            facold_beta: 0.0,
            t0: 0.0,
            y0: [0.0; N],
            t1: 0.0,
            y1: [0.0; N],
            h_step: 0.0,
            f1: [0.0; N],
            k: [[0.0; N]; 16],
            cont: [[0.0; N]; 7],
            dense_ready: false,
        };
        e.renew(rtol, atol, beta, stability_cap, h0, h_max);
        e
    }

    /// Make this stepper what [`Dop853::new`] with these arguments makes,
    /// keeping only its buffers (the stages, the interpolant and the step's
    /// ends, which `restart` and the next step overwrite before reading):
    /// a new segment without clearing 3 kB (docs/performance.md).
    pub(super) fn renew(
        &mut self,
        rtol: f64,
        atol: f64,
        beta: f64,
        stability_cap: bool,
        h0: Option<f64>,
        h_max: f64,
    ) {
        check_adaptive("DOP853", rtol, atol, h0, h_max);
        assert!(
            (0.0..=0.2).contains(&beta),
            "DOP853 beta must be in [0, 0.2], got {beta}"
        );
        self.rtol = rtol;
        self.atol = atol;
        self.h_max = h_max;
        self.h0 = h0;
        self.h = 0.0;
        self.initialized = false;
        self.rejected = false;
        self.beta = beta;
        self.expo1 = 1.0 / 8.0 - 0.2 * beta;
        self.stability_cap = stability_cap;
        self.facold = 1e-4;
        self.facold_beta = self.facold.powf(beta);
        self.t0 = 0.0;
        self.t1 = 0.0;
        self.h_step = 0.0;
        self.dense_ready = false;
    }
}

/// [`combine!`] over the components in `range` only (the others of the
/// result stay zero): the same additions in the same order for each of them.
macro_rules! combine_in {
    ($coef:expr, $k:expr, $range:expr; $($j:literal)*) => {{
        let mut acc = [0.0; N];
        let mut first = true;
        $(
            let a: f64 = $coef[$j];
            if a != 0.0 {
                if first {
                    first = false;
                    for n in $range {
                        acc[n] = a * $k[$j][n];
                    }
                } else {
                    for n in $range {
                        acc[n] += a * $k[$j][n];
                    }
                }
            }
        )*
        let _ = first;
        acc
    }};
}

/// The stage state's starting value: the components outside
/// `S::STAGE_READ` are never formed; NaN in debug builds (a right-hand side
/// that reads one fails its tests), 0 in release.
#[inline(always)]
fn unread_stage_state<const N: usize>() -> [f64; N] {
    [if cfg!(debug_assertions) {
        f64::NAN
    } else {
        0.0
    }; N]
}

/// Stages 1–11 of the method for the step from `(t, y)` to
/// `t_new = t + hs` into `k[1..12]` (`k[0] = f(t, y)` given); returns the
/// 12th stage's state `ŷ` (at `t_new`). Shared by the step and by
/// [`Engine::state_at`]; always inlined (the step's hot loop).
#[inline(always)]
fn method_stages<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t: f64,
    y: &[f64; N],
    hs: f64,
    t_new: f64,
    k: &mut [[f64; N]; 16],
    stats: &mut Stats,
) -> Result<[f64; N], Fail<S::Error>> {
    let mut yt = unread_stage_state::<N>();
    // Stage s from the stages j < s (row s of A), over the components the
    // right-hand side reads (`OdeSystem::STAGE_READ`).
    macro_rules! stage {
        ($s:literal; $($j:literal)*) => {{
            for r in S::STAGE_READ {
                let acc = combine_in!(A[$s], k, r.clone(); $($j)*);
                for n in r.clone() {
                    yt[n] = y[n] + hs * acc[n];
                }
            }
            let ts = if C[$s] == 1.0 { t_new } else { t + C[$s] * hs };
            eval(sys, ts, &yt, &mut k[$s], stats)?;
        }};
    }
    stage!(1; 0);
    stage!(2; 0 1);
    stage!(3; 0 1 2);
    stage!(4; 0 1 2 3);
    stage!(5; 0 1 2 3 4);
    stage!(6; 0 1 2 3 4 5);
    stage!(7; 0 1 2 3 4 5 6);
    stage!(8; 0 1 2 3 4 5 6 7);
    stage!(9; 0 1 2 3 4 5 6 7 8);
    stage!(10; 0 1 2 3 4 5 6 7 8 9);
    stage!(11; 0 1 2 3 4 5 6 7 8 9 10);
    Ok(yt)
}

impl<const N: usize> Dop853<N> {
    /// The dense output at `t` for the components `..m` (`m <= N`).
    #[inline(always)]
    fn dense_in(&self, t: f64, out: &mut [f64; N], m: usize) {
        debug_assert!(self.dense_ready);
        if t == self.t1 {
            out[..m].copy_from_slice(&self.y1[..m]);
            return;
        }
        if t == self.t0 {
            out[..m].copy_from_slice(&self.y0[..m]);
            return;
        }
        let s = (t - self.t0) / self.h_step;
        let s1 = 1.0 - s;
        let c = &self.cont;
        for n in 0..m {
            let conpar = c[3][n] + s * (c[4][n] + s1 * (c[5][n] + s * c[6][n]));
            out[n] = self.y0[n] + s * (c[0][n] + s1 * (c[1][n] + s * (c[2][n] + s1 * conpar)));
        }
    }

    /// `STIFF_HLAMB / ρ`, `ρ = |f(y₁) − f(ŷ)| / |y₁ − ŷ|` from the accepted
    /// step's end `y₁` and the 12th stage's state `ŷ` (both at `t + h`;
    /// `dop853.f`'s stiffness estimate, a lower bound of the Lipschitz
    /// constant along `y₁ − ŷ`); `+∞` when the two coincide.
    /// Over the controlled components `..controlled` only.
    fn stability_limit(
        &self,
        y_new: &[f64; N],
        y_hat: &[f64; N],
        f_new: &[f64; N],
        controlled: usize,
    ) -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for n in 0..controlled {
            num += (f_new[n] - self.k[11][n]).powi(2);
            den += (y_new[n] - y_hat[n]).powi(2);
        }
        if num > 0.0 && den > 0.0 {
            STIFF_HLAMB * (den / num).sqrt()
        } else {
            f64::INFINITY
        }
    }
}

impl<const N: usize> Engine<N> for Dop853<N> {
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
        self.dense_ready = false;
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

    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        let t = self.t1;
        let y = self.y1;
        self.k[0] = self.f1;
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
            // Land exactly on the stop; as in dop853.f, stretch the step by up
            // to 1 % rather than leave a sliver.
            let (hs, t_new, clipped) = if t + 1.01 * self.h >= t_stop {
                (t_stop - t, t_stop, true)
            } else {
                (self.h, t + self.h, false)
            };
            let yt = method_stages(sys, t, &y, hs, t_new, &mut self.k, stats)?;
            const _: () = assert!(STAGES == 12);
            // 8th-order solution (weights b_j = A[12][j]).
            let incr = combine!(A[STAGES], self.k; 0 1 2 3 4 5 6 7 8 9 10 11);
            // The error estimates over the controlled components only.
            let controlled = S::CONTROLLED;
            let bhh = combine_in!(BHH, self.k, 0..controlled; 0 1 2 3 4 5 6 7 8 9 10 11);
            let e5 = combine_in!(E5, self.k, 0..controlled; 0 1 2 3 4 5 6 7 8 9 10 11);
            let mut y_new = [0.0; N];
            let mut err = 0.0;
            let mut err2 = 0.0;
            let mut finite = true;
            for n in 0..N {
                y_new[n] = y[n] + hs * incr[n];
                finite &= y_new[n].is_finite();
            }
            // The error norm over the controlled components only (the
            // quadratures after them are carried along, see
            // `OdeSystem::CONTROLLED`).
            for n in 0..controlled {
                let sk = self.atol + self.rtol * y[n].abs().max(y_new[n].abs());
                err2 += ((incr[n] - bhh[n]) / sk).powi(2);
                err += (e5[n] / sk).powi(2);
            }
            let mut deno = err + 0.01 * err2;
            if deno <= 0.0 {
                deno = 1.0;
            }
            let err = hs.abs() * err * (1.0 / (controlled as f64 * deno)).sqrt();
            if !finite || !err.is_finite() {
                stats.rejected += 1;
                self.rejected = true;
                last_nonfinite = true;
                self.h = hs / 10.0;
                continue;
            }
            last_nonfinite = false;
            let fac11 = err.powf(self.expo1);
            // Lund stabilisation (a no-op for β = 0: x^0 = 1 exactly).
            let fac = (fac11 / self.facold_beta / SAFE).clamp(FACC2, FACC1);
            if err <= 1.0 {
                let mut f_new = [0.0; N];
                eval_accepted(sys, t_new, &y_new, &mut f_new, stats)?;
                let mut h_new = hs / fac;
                if self.rejected {
                    h_new = h_new.min(hs);
                }
                if self.stability_cap {
                    h_new = h_new.min(
                        self.stability_limit(&y_new, &yt, &f_new, controlled)
                            .max(FAC1 * hs),
                    );
                }
                if clipped && hs < self.h {
                    // A step shortened to land on a stop says little about
                    // the step size: keep the pending proposal if larger.
                    h_new = h_new.max(self.h);
                }
                self.h = h_new.min(self.h_max);
                self.rejected = false;
                self.facold = err.max(1e-4);
                self.facold_beta = self.facold.powf(self.beta);
                self.k[12] = f_new;
                self.f1 = f_new;
                self.t0 = t;
                self.y0 = y;
                self.t1 = t_new;
                self.y1 = y_new;
                self.h_step = hs;
                self.dense_ready = false;
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
        sys: &mut S,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        if self.dense_ready {
            return Ok(());
        }
        let h = self.h_step;
        let mut yt = unread_stage_state::<N>();
        macro_rules! stage {
            ($s:literal; $($j:literal)*) => {{
                for r in S::STAGE_READ {
                    let acc = combine_in!(A[$s], self.k, r.clone(); $($j)*);
                    for n in r.clone() {
                        yt[n] = self.y0[n] + h * acc[n];
                    }
                }
                eval(sys, self.t0 + C[$s] * h, &yt, &mut self.k[$s], stats)?;
            }};
        }
        stage!(13; 0 1 2 3 4 5 6 7 8 9 10 11 12);
        stage!(14; 0 1 2 3 4 5 6 7 8 9 10 11 12 13);
        stage!(15; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14);
        let d = [
            combine!(D[0], self.k; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15),
            combine!(D[1], self.k; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15),
            combine!(D[2], self.k; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15),
            combine!(D[3], self.k; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15),
        ];
        for n in 0..N {
            let dy = self.y1[n] - self.y0[n];
            let bspl = h * self.k[0][n] - dy;
            self.cont[0][n] = dy;
            self.cont[1][n] = bspl;
            self.cont[2][n] = dy - h * self.k[12][n] - bspl;
            for i in 0..4 {
                self.cont[3 + i][n] = h * d[i][n];
            }
        }
        self.dense_ready = true;
        Ok(())
    }

    fn state_at<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        out: &mut [f64; N],
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        if t == self.t1 {
            *out = self.y1;
            return Ok(());
        }
        if t == self.t0 {
            *out = self.y0;
            return Ok(());
        }
        // The method's step from (t0, y0) with h = t − t0; own stage
        // buffer, so the accepted step's interpolant stays valid.
        let hs = t - self.t0;
        let y = self.y0;
        let mut k = [[0.0; N]; 16];
        k[0] = self.k[0];
        method_stages(sys, self.t0, &y, hs, t, &mut k, stats)?;
        let incr = combine!(A[STAGES], k; 0 1 2 3 4 5 6 7 8 9 10 11);
        for n in 0..N {
            out[n] = y[n] + hs * incr[n];
        }
        Ok(())
    }

    fn dense(&self, t: f64, out: &mut [f64; N]) {
        self.dense_in(t, out, N);
    }

    fn dense_prefix(&self, t: f64, out: &mut [f64; N], n: usize) {
        self.dense_in(t, out, n.min(N));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stability function `R(z) = 1 + z bᵀ (I − z A)⁻¹ 1` of the 8th-order
    /// method at real `z`, from the coefficient tables (forward substitution:
    /// `A` is strictly lower triangular).
    fn stability(z: f64) -> f64 {
        let mut g = [0.0; STAGES];
        for i in 0..STAGES {
            let s: f64 = (0..i).map(|j| A[i][j] * g[j]).sum();
            g[i] = 1.0 + z * s;
        }
        1.0 + z * (0..STAGES).map(|j| A[STAGES][j] * g[j]).sum::<f64>()
    }

    /// The cap `STIFF_HLAMB / ρ` keeps `h λ` inside the real stability
    /// interval: `|R|` < 1 on `[−6.1, 0)` and the interval ends between
    /// −6.39 and −6.40; also `R` agrees with `e^z` to 8th order near 0 (a
    /// check that the tables are the method's).
    #[test]
    fn stability_boundary_of_the_coefficients() {
        for i in 1..=610 {
            let z = -(i as f64) * 0.01;
            assert!(
                stability(z).abs() < 1.0,
                "|R({z})| = {}",
                stability(z).abs()
            );
        }
        assert!((stability(-STIFF_HLAMB).abs() - 0.591).abs() < 1e-3);
        assert!(stability(-6.39).abs() < 1.0 && stability(-6.40).abs() > 1.0);
        for z in [-1e-2, 1e-2] {
            let err: f64 = stability(z) - f64::exp(z);
            assert!(err.abs() < 1e-17, "R({z}) − e^z = {err:e}");
        }
    }
}
