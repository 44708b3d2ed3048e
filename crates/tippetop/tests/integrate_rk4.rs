//! Classical RK4 (`Stepper::Rk4`): observed order, time grid, landing on
//! stops, evaluation count, dense output, blow-up.

use tippetop::integrate::{IntegrateError, OdeSystem, Options, Outcome, solve};

/// y'' = -y as (y, y').
struct Osc;
impl OdeSystem<2> for Osc {
    type Error = ();
    fn rhs(&mut self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), ()> {
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    }
}

/// y' = -2 t y, y(0) = 1 -> exp(-t^2) (non-autonomous).
struct Gauss;
impl OdeSystem<1> for Gauss {
    type Error = ();
    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = -2.0 * t * y[0];
        Ok(())
    }
}

/// y' = y^2, y(0) = 1 -> 1 / (1 - t), blows up at t = 1.
struct Blowup;
impl OdeSystem<1> for Blowup {
    type Error = ();
    fn rhs(&mut self, _t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

/// Counts rhs calls and begin_segment calls of an inner system.
struct Counting<S> {
    inner: S,
    calls: u64,
    segments: u64,
}
impl<S: OdeSystem<N>, const N: usize> OdeSystem<N> for Counting<S> {
    type Error = S::Error;
    fn begin_segment(&mut self, t: f64, y: &[f64; N]) {
        self.segments += 1;
        self.inner.begin_segment(t, y);
    }
    fn rhs(&mut self, t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), S::Error> {
        self.calls += 1;
        self.inner.rhs(t, y, dy)
    }
}

fn plain<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    opts: &Options,
    y0: [f64; N],
    t_end: f64,
) -> Result<Outcome<N>, IntegrateError<S::Error>> {
    solve(
        sys,
        opts,
        0.0,
        y0,
        t_end,
        &[],
        &[],
        &[],
        &mut |_, _, _| {},
        &mut |_, _, _| {},
    )
}

fn osc_error(h: f64) -> f64 {
    let out = plain(&mut Osc, &Options::rk4(h), [1.0, 0.0], 10.0).unwrap();
    assert_eq!(out.t, 10.0);
    (out.y[0] - 10f64.cos())
        .abs()
        .max((out.y[1] + 10f64.sin()).abs())
}

/// Halving h must divide the global error by 2^4 = 16. The errors here
/// (1e-5 .. 4e-8) are far above rounding (~1e-15), so the ratio is the
/// asymptotic one up to O(h) corrections: [14, 18] allows ~12 %.
#[test]
fn rk4_order_four_on_oscillator() {
    let e: Vec<f64> = [0.1, 0.05, 0.025].iter().map(|&h| osc_error(h)).collect();
    let r1 = e[0] / e[1];
    let r2 = e[1] / e[2];
    eprintln!("RK4 oscillator errors {e:?}, ratios {r1:.3} {r2:.3}");
    assert!((14.0..=18.0).contains(&r1), "ratio {r1}");
    assert!((14.0..=18.0).contains(&r2), "ratio {r2}");
}

/// Same on a non-autonomous problem. At h = 0.1 the ratio is 18.3 (not yet
/// asymptotic: exp(-t^2) has large high derivatives near t = 1), so the
/// sequence starts at h = 0.05; errors 4e-7 .. 1.4e-9, still far above
/// rounding.
#[test]
fn rk4_order_four_non_autonomous() {
    let err = |h: f64| {
        let out = plain(&mut Gauss, &Options::rk4(h), [1.0], 2.0).unwrap();
        (out.y[0] - (-4.0f64).exp()).abs()
    };
    let e: Vec<f64> = [0.05, 0.025, 0.0125].iter().map(|&h| err(h)).collect();
    let r1 = e[0] / e[1];
    let r2 = e[1] / e[2];
    eprintln!("RK4 exp(-t^2) errors {e:?}, ratios {r1:.3} {r2:.3}");
    assert!((14.0..=18.0).contains(&r1), "ratio {r1}");
    assert!((14.0..=18.0).contains(&r2), "ratio {r2}");
}

fn step_times(h: f64, t_end: f64, tstops: &[f64]) -> Vec<f64> {
    let mut times = Vec::new();
    solve(
        &mut Osc,
        &Options::rk4(h),
        0.0,
        [1.0, 0.0],
        t_end,
        tstops,
        &[],
        &[],
        &mut |_, _, _| {},
        &mut |_, t, _| times.push(t),
    )
    .unwrap();
    times
}

/// The grid is t_seg + k h by multiplication; the last step of a segment
/// lands exactly on the stop; no sliver step when the remaining interval is
/// a grid step up to rounding.
#[test]
fn rk4_grid_and_landing() {
    // 0.3 does not divide 1: steps 0.3, 0.6, 0.9 (as 3 * 0.3), then 1.0.
    let t = step_times(0.3, 1.0, &[]);
    assert_eq!(t, vec![0.3, 2.0 * 0.3, 3.0 * 0.3, 1.0]);

    // 10 * 0.1 != 1.0 exactly in floating point; still exactly 10 steps.
    let t = step_times(0.1, 1.0, &[]);
    assert_eq!(t.len(), 10, "{t:?}");
    for (k, &tk) in t[..9].iter().enumerate() {
        assert_eq!(tk, (k + 1) as f64 * 0.1);
    }
    assert_eq!(t[9], 1.0);

    // A tstop at 0.55 restarts the grid from it.
    let t = step_times(0.1, 1.0, &[0.55]);
    let mut expect: Vec<f64> = (1..=5).map(|k| k as f64 * 0.1).collect();
    expect.push(0.55);
    expect.extend((1..=3).map(|k| 0.55 + k as f64 * 0.1));
    // remaining 1.0 - 0.85 = 0.15 > h: one more grid step, then land.
    expect.push(0.55 + 4.0 * 0.1);
    expect.push(1.0);
    assert_eq!(t, expect);
}

/// rhs_evals = segments + 4 * steps, and equals the real number of calls.
#[test]
fn rk4_counts_evaluations() {
    let mut sys = Counting {
        inner: Osc,
        calls: 0,
        segments: 0,
    };
    let out = solve(
        &mut sys,
        &Options::rk4(0.1),
        0.0,
        [1.0, 0.0],
        3.0,
        &[1.05, 2.0],
        &[0.5, 1.234, 3.0],
        &[],
        &mut |_, _, _| {},
        &mut |_, _, _| {},
    )
    .unwrap();
    assert_eq!(out.stats.rhs_evals, sys.calls);
    assert_eq!(sys.segments, 3);
    assert_eq!(out.stats.rhs_evals, 3 + 4 * out.stats.steps);
    assert_eq!(out.stats.rejected, 0);
    // 11 steps to 1.05 (10 + landing), 10 to 2.0 (grid from 1.05: 0.95 =
    // 9 steps + landing), 10 to 3.0.
    assert_eq!(out.stats.steps, 11 + 10 + 10);
}

/// Hermite dense output: its error is of the size of the RK4 global error.
/// At h = 0.1 the interpolation error (~h^4 |y''''| / 384 = 2.6e-7) is a few
/// per cent of the global error at t = 10 (~8e-6), so the max over 10 000
/// samples may exceed the max over step ends only slightly: bound 1.2.
#[test]
fn rk4_dense_output_error() {
    let mut step_err: f64 = 0.0;
    let mut dense_err: f64 = 0.0;
    let samples: Vec<f64> = (0..10_000).map(|i| i as f64 * 1e-3).collect();
    let err = |t: f64, y: &[f64; 2]| (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs());
    solve(
        &mut Osc,
        &Options::rk4(0.1),
        0.0,
        [1.0, 0.0],
        10.0,
        &[],
        &samples,
        &[],
        &mut |_, t, y| dense_err = dense_err.max(err(t, y)),
        &mut |_, t, y| step_err = step_err.max(err(t, y)),
    )
    .unwrap();
    let ratio = dense_err / step_err;
    eprintln!("RK4 dense {dense_err:.3e} step {step_err:.3e} ratio {ratio:.3}");
    assert!(ratio <= 1.2, "ratio {ratio}");
}

/// y' = y^2 blows up at t = 1; fixed-step RK4 runs past the singularity
/// until the state overflows: a NonFinite error, not a panic or a hang. The
/// RK4 solution stays finite a little beyond t = 1 (it lags the true one),
/// and overflows within a few steps once h y ~ 1: 1 <= t < 1.01 (measured
/// 1.002).
#[test]
fn rk4_blowup_is_non_finite() {
    match plain(&mut Blowup, &Options::rk4(1e-3), [1.0], 2.0) {
        Err(IntegrateError::NonFinite { t, y_last }) => {
            eprintln!("RK4 blow-up: NonFinite at t = {t}, y = {y_last:?}");
            assert!((1.0..1.01).contains(&t), "t = {t}");
            assert!(y_last[0].is_finite());
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
}
