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
        Stepper::Rodas4P { .. } => "Rodas4P",
        Stepper::Langevin { .. } => "Langevin",
        Stepper::Brownian { .. } => "Brownian",
    }
}

/// The right-hand side of an [`Ode`]: `dy = f(ode, t, y)`.
type Rhs<const N: usize> = fn(&Ode<N>, f64, &[f64; N], &mut [f64; N]) -> Result<(), &'static str>;

/// A test problem `y' = f(t, y)` of dimension `N`. Every problem is this one
/// type (a function pointer and its parameters, not a type per problem), so
/// the engines are compiled once per dimension, not once per problem: the
/// binary's build time is mostly `solve`'s instantiations at opt-level 2.
/// It counts its right-hand-side calls and segments and records the times
/// of `begin_segment`, where it latches its input `u` if it has a `latch`.
pub struct Ode<const N: usize> {
    f: Rhs<N>,
    /// A parameter of `f` (λ, ν).
    pub param: f64,
    /// The input latched at the start of each segment.
    pub u: f64,
    latch: Option<fn(f64) -> f64>,
    /// Right-hand-side calls so far.
    pub calls: u64,
    /// `begin_segment` calls so far.
    pub segments: u64,
    /// The times of the `begin_segment` calls.
    pub begins: Vec<f64>,
}

impl<const N: usize> Ode<N> {
    fn new(f: Rhs<N>) -> Self {
        Ode {
            f,
            param: f64::NAN,
            u: f64::NAN,
            latch: None,
            calls: 0,
            segments: 0,
            begins: Vec::new(),
        }
    }
}

impl<const N: usize> OdeSystem<N> for Ode<N> {
    type Error = &'static str;
    fn begin_segment(&mut self, t: f64, _y: &[f64; N]) {
        self.segments += 1;
        self.begins.push(t);
        if let Some(latch) = self.latch {
            self.u = latch(t);
        }
    }
    fn rhs(&mut self, t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), &'static str> {
        self.calls += 1;
        (self.f)(self, t, y, dy)
    }
}

/// y'' = -y as (y, y'); from (1, 0): y = cos t.
pub fn osc() -> Ode<2> {
    Ode::new(|_, _, y, dy| {
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    })
}

/// Error of (y, y') against (cos t, −sin t).
pub fn osc_err(t: f64, y: &[f64; 2]) -> f64 {
    (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs())
}

/// Kepler problem (mu = 1), state (x, y, vx, vy): nonlinear and smooth.
pub fn kepler() -> Ode<4> {
    Ode::new(|_, _, y, dy| {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
        Ok(())
    })
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
pub fn gauss() -> Ode<1> {
    Ode::new(|_, t, y, dy| {
        dy[0] = -2.0 * t * y[0];
        Ok(())
    })
}

/// y' = y^2, y(0) = 1 -> 1 / (1 - t), blows up at t = 1.
pub fn blowup() -> Ode<1> {
    Ode::new(|_, _, y, dy| {
        dy[0] = y[0] * y[0];
        Ok(())
    })
}

/// Stiff, non-autonomous (Prothero–Robinson): y' = -λ (y - cos t) - sin t,
/// y(0) = 1, exact y = cos t; the transient decays on 1/λ.
pub fn stiff_cos(lambda: f64) -> Ode<1> {
    let mut o = Ode::new(|o, t, y, dy| {
        dy[0] = -o.param * (y[0] - t.cos()) - t.sin();
        Ok(())
    });
    o.param = lambda;
    o
}

/// A stiff linear system relaxing onto a moving equilibrium, with
/// eigenvalues `−λ ± i ν` (λ = 1e4): `y' = M (y − g(t)) + g'(t)`,
/// `g(t) = (cos t, sin t)`, solution `g(t)` from `y(0) = g(0)`. DOP853 is
/// held to its stability limit (`h ≈ 6/λ`), not to its accuracy.
pub fn stiff_rotor(nu: f64) -> Ode<2> {
    let mut o = Ode::new(|o, t, y, dy| {
        let (lam, nu) = (1e4, o.param);
        let (s, c) = t.sin_cos();
        let (d0, d1) = (y[0] - c, y[1] - s);
        dy[0] = -lam * d0 + nu * d1 - s;
        dy[1] = -nu * d0 - lam * d1 + c;
        Ok(())
    });
    o.param = nu;
    o
}

/// y' = u, u latched in begin_segment: 1 before t = 1, 0 after.
pub fn switch() -> Ode<1> {
    let mut o = Ode::new(|o, _, _, dy| {
        dy[0] = o.u;
        Ok(())
    });
    o.latch = Some(|t| if t < 1.0 { 1.0 } else { 0.0 });
    o
}

/// The same jump read from t in rhs (not latched): a step straddles it
/// unless a tstop is placed there.
pub fn unlatched() -> Ode<1> {
    Ode::new(|_, t, _, dy| {
        dy[0] = if t < 1.0 { 1.0 } else { 0.0 };
        Ok(())
    })
}

/// Free fall (height, velocity) under g = 9.81.
pub fn fall() -> Ode<2> {
    Ode::new(|_, _, y, dy| {
        dy[0] = y[1];
        dy[1] = -9.81;
        Ok(())
    })
}

/// y' = 1 whose right-hand side fails ("boom") for t > 0.5.
pub fn failing() -> Ode<1> {
    Ode::new(|_, t, _, dy| {
        if t > 0.5 {
            return Err("boom");
        }
        dy[0] = 1.0;
        Ok(())
    })
}

/// The oscillator whose right-hand side fails ("boom") for t > 10.
pub fn osc_failing_after_10() -> Ode<2> {
    Ode::new(|_, t, y, dy| {
        if t > 10.0 {
            return Err("boom");
        }
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    })
}

/// `solve` from t = 0 without tstops, samples or events.
pub fn plain<const N: usize>(
    sys: &mut Ode<N>,
    opts: &Options,
    y0: [f64; N],
    t_end: f64,
) -> Result<Outcome<N>, IntegrateError<&'static str>> {
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
pub fn run<const N: usize>(
    sys: &mut Ode<N>,
    opts: &Options,
    y0: [f64; N],
    t_end: f64,
    tstops: &[f64],
    sample_times: &[f64],
    events: &[Event<Ode<N>, N>],
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
pub fn ev<const N: usize>(
    g: impl Fn(&Ode<N>, f64, &[f64; N]) -> f64 + Send + Sync + 'static,
    direction: Direction,
    terminal: bool,
) -> Event<Ode<N>, N> {
    Event {
        g: Box::new(g),
        direction,
        terminal,
        step_to_event: false,
    }
}
