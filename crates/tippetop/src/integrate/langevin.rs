//! The Langevin engine (`solver.method = "langevin"`): a symmetric
//! splitting `O(h/2) Φ(h) O(h/2)` on a fixed grid.
//!
//! - `O` is the system's exact Ornstein–Uhlenbeck step of its velocities
//!   at fixed configuration ([`OdeSystem::thermostat`]: the damping and its
//!   noise), fed [`OdeSystem::NOISE`] standard normals per half step from
//!   the counter-based stream keyed by (seed, run) with the run's global
//!   step number as counter: normals `0 .. NOISE` for the first half,
//!   `NOISE .. 2 NOISE` for the second. Any step can be replayed from
//!   (seed, run, step) alone; nothing depends on threads or on where a run
//!   was paused.
//! - `Φ` is one classical RK4 step of the deterministic right-hand side
//!   (the conservative forces, the applied force, the contact constraint).
//!
//! Why not BAOAB's `B A O A B`: the top's mass matrix depends on its
//! configuration (the centre's height follows the tilt), so the Hamiltonian
//! is not separable and the kick `B` and drift `A` are not explicit
//! flows. Splitting the dynamics into the Ornstein–Uhlenbeck part (exact:
//! it leaves the Maxwell distribution of the constrained top invariant,
//! whatever the friction matrix) and the deterministic part (RK4: its error
//! in the invariant measure is of order 4) keeps the properties that
//! matter: a symmetric (Strang) splitting, weak order 2 at a fixed time,
//! the right velocity distribution for any configuration, and a bias of
//! the stationary configurational averages that is RK4's alone (the O step
//! and the exact flow each leave the Gibbs law invariant): order 4, and 5
//! on a linear oscillator, whose RK4 energy error is of order 6 per step.
//! Both orders are measured (docs/physics.md#langevin): at a fixed time in
//! tests/integrate/langevin.rs, in the stationary law in `weak_order.rs`.
//!
//! `solver.method = "brownian"` uses the same engine with one
//! [`OdeSystem::overdamped_step`] per step (Euler–Maruyama, weak order 1,
//! also in the stationary law) fed `NOISE` normals of the step.
//!
//! Grid: the run's steps end at `k h` (global `k`); a segment start off
//! the grid (a force switch, a terminal event) takes one shorter step to
//! the next grid point, and a step lands exactly on the segment's end.
//! Dense output: linear interpolation between the step ends (the noise has
//! no smooth interpolant); the run's samples are placed on step ends
//! (`sim::record::RunSetup`), where it is exact.

// Component loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use super::{Engine, Fail, OdeSystem, Stats, eval};
use crate::random::Stream;

/// Relative slack (in units of `h`) within which a time counts as on the
/// grid, and the remaining interval as one step.
const LANDING_SLACK: f64 = 1e-9;

/// Largest number of noise components of a half step.
pub(crate) const MAX_NOISE: usize = 16;

/// The Langevin engine (see the module docs).
#[derive(Clone)]
pub(crate) struct Langevin<const N: usize> {
    h: f64,
    stream: Stream,
    /// Global number of the next step (the stream's counter).
    step: u64,
    /// Overdamped: one `overdamped_step` per step instead of `O Φ O`.
    overdamped: bool,
    t0: f64,
    y0: [f64; N],
    t1: f64,
    y1: [f64; N],
}

impl<const N: usize> Langevin<N> {
    /// New engine with grid step `h > 0`, stream (seed, run) and the global
    /// number of its first step.
    pub(super) fn new(h: f64, seed: u64, run: u64, first_step: u64, overdamped: bool) -> Self {
        assert!(
            h.is_finite() && h > 0.0,
            "Langevin step must be finite and positive, got {h}"
        );
        Langevin {
            h,
            stream: Stream::new(seed, run),
            step: first_step,
            overdamped,
            t0: 0.0,
            y0: [0.0; N],
            t1: 0.0,
            y1: [0.0; N],
        }
    }

    /// Set the stream's counter of the next step (`analysis::rare`'s
    /// branches: a branch continues a path with the counters of its own
    /// noise, [`crate::simulate::noise_counter`]).
    pub(crate) fn set_counter(&mut self, next_step: u64) {
        self.step = next_step;
    }

    /// The grid point after `t`: `(k + 1) h` for `t` within the slack of
    /// `k h`, else the next multiple of `h`. The slack grows with `k`: `t/h`
    /// of a grid time `k h` is `k` only to a few ulps of `k` (2e-9 at
    /// `k = 1e7`), and a fixed slack of 1e-9 then put `t` just below `k`
    /// and returned `t` itself (zero-length steps).
    fn next_grid(&self, t: f64) -> f64 {
        let x = t / self.h;
        let slack = LANDING_SLACK.max(8.0 * f64::EPSILON * x.abs());
        let k = (x + slack).floor() + 1.0;
        k * self.h
    }

    /// [`Engine::step`] in the AVX2 build (the same operations, none
    /// fused: the same bits; docs/performance.md, "The Langevin step").
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn step_avx2<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        self.step_impl(sys, t_stop, stats)
    }

    /// One step (see [`Engine::step`]).
    #[inline(always)]
    fn step_impl<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        let t = self.t1;
        let grid = self.next_grid(t);
        let t_next = if t_stop <= grid || t_stop - t <= self.h * (1.0 + LANDING_SLACK) {
            t_stop
        } else {
            grid
        };
        let hs = t_next - t;
        let (nm, ne) = (S::NOISE, S::NOISE_EXTRA);
        if self.overdamped {
            let mut xi = [0.0; MAX_NOISE];
            let xi = &mut xi[..nm + ne];
            self.stream.normals(self.step, xi);
            let mut y = self.y1;
            sys.overdamped_step(t, &mut y, hs, xi)
                .map_err(|err| Fail::Rhs { t, err })?;
            stats.rhs_evals += 1;
            if !y.iter().all(|v| v.is_finite()) {
                return Err(Fail::NonFinite { t });
            }
            self.t0 = t;
            self.y0 = self.y1;
            self.t1 = t_next;
            self.y1 = y;
            self.step += 1;
            return Ok(());
        }
        let mut all = [0.0; 2 * MAX_NOISE];
        self.stream.normals(self.step, &mut all[..2 * (nm + ne)]);
        let (mut a, mut b) = ([0.0; MAX_NOISE], [0.0; MAX_NOISE]);
        a[..nm].copy_from_slice(&all[..nm]);
        a[nm..nm + ne].copy_from_slice(&all[2 * nm..2 * nm + ne]);
        b[..nm].copy_from_slice(&all[nm..2 * nm]);
        b[nm..nm + ne].copy_from_slice(&all[2 * nm + ne..2 * (nm + ne)]);
        let (first, second) = (&a[..nm + ne], &b[..nm + ne]);

        let mut y = self.y1;
        sys.thermostat(&mut y, 0.5 * hs, first);
        let mut k1 = [0.0; N];
        let mut k2 = [0.0; N];
        let mut k3 = [0.0; N];
        let mut k4 = [0.0; N];
        let mut yt = [0.0; N];
        let th = t + 0.5 * hs;
        eval(sys, t, &y, &mut k1, stats)?;
        for i in 0..N {
            yt[i] = y[i] + 0.5 * hs * k1[i];
        }
        eval(sys, th, &yt, &mut k2, stats)?;
        for i in 0..N {
            yt[i] = y[i] + 0.5 * hs * k2[i];
        }
        eval(sys, th, &yt, &mut k3, stats)?;
        for i in 0..N {
            yt[i] = y[i] + hs * k3[i];
        }
        eval(sys, t_next, &yt, &mut k4, stats)?;
        let mut y_new = [0.0; N];
        for i in 0..N {
            y_new[i] = y[i] + hs / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        sys.thermostat(&mut y_new, 0.5 * hs, second);
        if !y_new.iter().all(|v| v.is_finite()) {
            return Err(Fail::NonFinite { t });
        }
        self.t0 = t;
        self.y0 = self.y1;
        self.t1 = t_next;
        self.y1 = y_new;
        self.step += 1;
        Ok(())
    }
}

/// The grid time `k h` nearest to `t` (how a run's samples are placed on
/// step ends; the engine computes its step ends with the same expression).
pub(crate) fn nearest_grid(t: f64, h: f64) -> f64 {
    (t / h).round() * h
}

impl<const N: usize> Engine<N> for Langevin<N> {
    fn restart<S: OdeSystem<N>>(
        &mut self,
        _sys: &mut S,
        t: f64,
        y: &[f64; N],
        _t_stop: f64,
        _stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        self.t0 = t;
        self.y0 = *y;
        self.t1 = t;
        self.y1 = *y;
        Ok(())
    }

    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { self.step_avx2(sys, t_stop, stats) };
        }
        self.step_impl(sys, t_stop, stats)
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
        let s = (t - self.t0) / (self.t1 - self.t0);
        for i in 0..N {
            out[i] = self.y0[i] + s * (self.y1[i] - self.y0[i]);
        }
    }
}
