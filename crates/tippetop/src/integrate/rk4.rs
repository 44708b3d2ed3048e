//! Classical fixed-step RK4 with cubic Hermite dense output.

// Component loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use super::{Engine, Fail, OdeSystem, Stats, eval};

/// Relative slack (in units of `h`) within which the remaining interval is
/// treated as one grid step, to avoid a sliver step before a stop.
const LANDING_SLACK: f64 = 1e-9;

/// RK4 on the grid `t_seg + k h` of the current segment.
#[derive(Clone)]
pub(crate) struct Rk4<const N: usize> {
    h: f64,
    /// Segment start and index of the current grid point.
    t_seg: f64,
    k: u64,
    /// Last accepted step: start (`t0`, `y0`, `f0`) and end (`t1`, `y1`, `f1`).
    t0: f64,
    y0: [f64; N],
    f0: [f64; N],
    t1: f64,
    y1: [f64; N],
    f1: [f64; N],
}

impl<const N: usize> Rk4<N> {
    /// New stepper with step `h > 0`.
    pub(super) fn new(h: f64) -> Self {
        assert!(
            h.is_finite() && h > 0.0,
            "RK4 step must be finite and positive, got {h}"
        );
        Rk4 {
            h,
            t_seg: 0.0,
            k: 0,
            t0: 0.0,
            y0: [0.0; N],
            f0: [0.0; N],
            t1: 0.0,
            y1: [0.0; N],
            f1: [0.0; N],
        }
    }
}

impl<const N: usize> Engine<N> for Rk4<N> {
    fn restart<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        _t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        self.t_seg = t;
        self.k = 0;
        self.t1 = t;
        self.y1 = *y;
        self.t0 = t;
        self.y0 = *y;
        let mut f = [0.0; N];
        eval(sys, t, y, &mut f, stats)?;
        self.f1 = f;
        self.f0 = f;
        Ok(())
    }

    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        let t = self.t1;
        let h = self.h;
        let (t_next, k_next) = if t_stop - t <= h * (1.0 + LANDING_SLACK) {
            (t_stop, self.k + 1)
        } else {
            let k = self.k + 1;
            (self.t_seg + k as f64 * h, k)
        };
        let hs = t_next - t;
        let y = self.y1;
        let k1 = self.f1;
        let mut yt = [0.0; N];
        let mut k2 = [0.0; N];
        let mut k3 = [0.0; N];
        let mut k4 = [0.0; N];
        let th = t + 0.5 * hs;
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
        if !y_new.iter().all(|v| v.is_finite()) {
            return Err(Fail::NonFinite { t });
        }
        let mut f_new = [0.0; N];
        eval(sys, t_next, &y_new, &mut f_new, stats)?;
        self.t0 = t;
        self.y0 = y;
        self.f0 = k1;
        self.t1 = t_next;
        self.y1 = y_new;
        self.f1 = f_new;
        self.k = k_next;
        Ok(())
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
        let hs = self.t1 - self.t0;
        let s = (t - self.t0) / hs;
        let s2 = s * s;
        let s3 = s2 * s;
        let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
        let h10 = s3 - 2.0 * s2 + s;
        let h01 = -2.0 * s3 + 3.0 * s2;
        let h11 = s3 - s2;
        for i in 0..N {
            out[i] =
                h00 * self.y0[i] + h10 * hs * self.f0[i] + h01 * self.y1[i] + h11 * hs * self.f1[i];
        }
    }
}
