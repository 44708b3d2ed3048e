//! The shared test problems (each with its exact solution) and the engines
//! they run on.

use tippetop::integrate::{
    Direction, Event, IntegrateError, OdeSystem, Options, Outcome, Stepper, solve,
};

/// The engine of an [`Options`], for messages and filters.
pub fn name(opts: &Options) -> &'static str {
    match opts.stepper {
        Stepper::Rk4 { .. } => "RK4",
        Stepper::Dop853 { .. } => "DOP853",
        Stepper::Rosenbrock { .. } => "Rodas4P",
    }
}

/// y'' = -y as (y, y'); from (1, 0): y = cos t.
pub struct Osc;
impl OdeSystem<2> for Osc {
    type Error = ();
    fn rhs(&mut self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), ()> {
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    }
}

/// Error of (y, y') against (cos t, −sin t).
pub fn osc_err(t: f64, y: &[f64; 2]) -> f64 {
    (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs())
}

/// Kepler problem (mu = 1), state (x, y, vx, vy): nonlinear and smooth.
pub struct Kepler;
impl OdeSystem<4> for Kepler {
    type Error = ();
    fn rhs(&mut self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) -> Result<(), ()> {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
        Ok(())
    }
}

/// The Kepler orbit's eccentricity.
pub const ECC: f64 = 0.5;

/// Exact Kepler orbit (a = 1, period 2 pi, pericentre at t = 0).
pub fn kepler_exact(t: f64) -> [f64; 4] {
    let e = ECC;
    let mut ea = t; // eccentric anomaly: E - e sin E = t
    for _ in 0..50 {
        let d = (ea - e * ea.sin() - t) / (1.0 - e * ea.cos());
        ea -= d;
        if d.abs() < 1e-16 {
            break;
        }
    }
    let b = (1.0 - e * e).sqrt();
    let den = 1.0 - e * ea.cos();
    [
        ea.cos() - e,
        b * ea.sin(),
        -ea.sin() / den,
        b * ea.cos() / den,
    ]
}

pub fn kepler_y0() -> [f64; 4] {
    [1.0 - ECC, 0.0, 0.0, ((1.0 + ECC) / (1.0 - ECC)).sqrt()]
}

pub fn kepler_err(t: f64, y: &[f64; 4]) -> f64 {
    let ex = kepler_exact(t);
    (0..4).map(|i| (y[i] - ex[i]).abs()).fold(0.0, f64::max)
}

/// y' = -2 t y, y(0) = 1 -> exp(-t^2) (non-autonomous).
pub struct Gauss;
impl OdeSystem<1> for Gauss {
    type Error = ();
    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = -2.0 * t * y[0];
        Ok(())
    }
}

/// y' = y^2, y(0) = 1 -> 1 / (1 - t), blows up at t = 1.
pub struct Blowup;
impl OdeSystem<1> for Blowup {
    type Error = ();
    fn rhs(&mut self, _t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

/// Stiff, non-autonomous (Prothero–Robinson): y' = -L (y - cos t) - sin t,
/// y(0) = 1, exact y = cos t; the transient decays on 1/L.
pub struct StiffCos {
    pub lambda: f64,
}
impl OdeSystem<1> for StiffCos {
    type Error = ();
    fn rhs(&mut self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = -self.lambda * (y[0] - t.cos()) - t.sin();
        Ok(())
    }
}

/// A stiff linear system relaxing onto a moving equilibrium, with
/// eigenvalues `−λ ± i ν` (λ = 1e4, ν = the field): `y' = M (y − g(t)) + g'(t)`,
/// `g(t) = (cos t, sin t)`, solution `g(t)` from `y(0) = g(0)`. DOP853 is
/// held to its stability limit (`h ≈ 6/λ`), not to its accuracy.
pub struct StiffRotor(pub f64);
impl OdeSystem<2> for StiffRotor {
    type Error = ();
    fn rhs(&mut self, t: f64, y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), ()> {
        let (lam, nu) = (1e4, self.0);
        let (s, c) = t.sin_cos();
        let (d0, d1) = (y[0] - c, y[1] - s);
        dy[0] = -lam * d0 + nu * d1 - s;
        dy[1] = -nu * d0 - lam * d1 + c;
        Ok(())
    }
}

/// y' = u, u latched in begin_segment: 1 before t = 1, 0 after. Records
/// the begin_segment times.
pub struct Switch {
    pub u: f64,
    pub begins: Vec<f64>,
}
impl Switch {
    pub fn new() -> Self {
        Switch {
            u: f64::NAN,
            begins: Vec::new(),
        }
    }
}
impl OdeSystem<1> for Switch {
    type Error = ();
    fn begin_segment(&mut self, t: f64, _y: &[f64; 1]) {
        self.u = if t < 1.0 { 1.0 } else { 0.0 };
        self.begins.push(t);
    }
    fn rhs(&mut self, _t: f64, _y: &[f64; 1], dy: &mut [f64; 1]) -> Result<(), ()> {
        dy[0] = self.u;
        Ok(())
    }
}

/// Counts rhs calls and begin_segment calls of an inner system.
pub struct Counting<S> {
    pub inner: S,
    pub calls: u64,
    pub segments: u64,
}
impl<S> Counting<S> {
    pub fn new(inner: S) -> Self {
        Counting {
            inner,
            calls: 0,
            segments: 0,
        }
    }
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

/// `solve` from t = 0 without tstops, samples or events.
pub fn plain<S: OdeSystem<N>, const N: usize>(
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

pub type Samples<const N: usize> = Vec<(f64, [f64; N])>;

/// Run from t = 0 and collect samples and step ends.
#[allow(clippy::type_complexity)]
pub fn run<S: OdeSystem<N, Error = ()>, const N: usize>(
    sys: &mut S,
    opts: &Options,
    y0: [f64; N],
    t_end: f64,
    tstops: &[f64],
    sample_times: &[f64],
    events: &[Event<S, N>],
) -> (Outcome<N>, Samples<N>, Samples<N>) {
    let mut samples = Vec::new();
    let mut steps = Vec::new();
    let out = solve(
        sys,
        opts,
        0.0,
        y0,
        t_end,
        tstops,
        sample_times,
        events,
        &mut |_, t, y| samples.push((t, *y)),
        &mut |_, t, y| steps.push((t, *y)),
    )
    .unwrap();
    (out, samples, steps)
}

/// An event without `step_to_event`.
pub fn ev<S, const N: usize>(
    g: impl Fn(&S, f64, &[f64; N]) -> f64 + 'static,
    direction: Direction,
    terminal: bool,
) -> Event<S, N> {
    Event {
        g: Box::new(g),
        direction,
        terminal,
        step_to_event: false,
    }
}
