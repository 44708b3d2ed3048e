//! Initial state and solver settings.

use crate::{Error, Sample};

/// Initial state of the reduced model (SI units, radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Initial {
    /// Nutation angle θ \[rad\], the tilt of the symmetry axis from the vertical.
    pub theta: f64,
    /// θ̇ \[rad/s\].
    pub theta_dot: f64,
    /// Precession rate Ω = φ̇ \[rad/s\].
    pub precession: f64,
    /// Spin ω = n·k, the angular-velocity component along the symmetry axis \[rad/s\].
    pub spin: f64,
    /// Centre-of-mass velocity along the precessing x axis \[m/s\].
    pub ux: f64,
    /// Centre-of-mass velocity along the precessing y axis \[m/s\].
    pub uy: f64,
    /// Heading φ₀ \[rad\]: the angle from the lab X axis to the horizontal
    /// direction the symmetry axis tilts towards at t = 0 (the precessing
    /// frame's x). The dynamics do not depend on it (the plane is isotropic);
    /// the position and attitude columns are turned by it. Default 0.
    pub heading: f64,
}

impl Initial {
    /// The paper's initial state: θ = 0.1, θ̇ = 0, Ω = 0, ω = 100 rad/s, u = 0.
    pub fn paper() -> Self {
        Initial {
            theta: 0.1,
            theta_dot: 0.0,
            precession: 0.0,
            spin: 100.0,
            ux: 0.0,
            uy: 0.0,
            heading: 0.0,
        }
    }

    /// The initial state from lab-frame vectors (Z up): the symmetry axis
    /// `axis` (any nonzero length; it is normalised), the angular velocity
    /// `angular_velocity` \[rad/s\] and the horizontal centre-of-mass
    /// velocity `velocity` \[m/s\] (the vertical one follows from the
    /// contact). With `k` the unit axis, `s = |k_h|`, `c = k_Z`:
    /// θ = atan2(s, c), the heading φ₀ = atan2(k_Y, k_X), ω = n·k,
    /// θ̇ = n·ŷ, Ω = (n_Z − ω c)/s² (x̂ = k_h/s, ŷ = Z × x̂; the inverse of
    /// `n = (ω − Ω c) s x̂ + θ̇ ŷ + (Ω s² + ω c) Z`), u = (v·x̂, v·ŷ).
    /// With the axis vertical (s = 0) the heading is chosen so that the
    /// horizontal angular velocity lies along ŷ (θ̇ = |n_h|, Ω = 0, ω = n·k).
    /// `Err` names the offending vector.
    pub fn from_lab(
        axis: [f64; 3],
        angular_velocity: [f64; 3],
        velocity: [f64; 2],
    ) -> Result<Self, Error> {
        let finite = |name: &str, v: &[f64]| -> Result<(), Error> {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    format!("{v:?} is not allowed"),
                    "finite components".into(),
                ))
            }
        };
        finite("initial.axis", &axis)?;
        finite("initial.angular_velocity", &angular_velocity)?;
        finite("initial.velocity", &velocity)?;
        let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return Err(Error::invalid(
                "initial.axis",
                format!("{axis:?} has no direction"),
                "a nonzero vector [x, y, z] (it is normalised)".into(),
            ));
        }
        let k = [axis[0] / len, axis[1] / len, axis[2] / len];
        let n = angular_velocity;
        let s = k[0].hypot(k[1]);
        let c = k[2];
        let spin = n[0] * k[0] + n[1] * k[1] + n[2] * k[2];
        let (heading, theta_dot, precession) = if s > 0.0 {
            let yh = [-k[1] / s, k[0] / s];
            (
                k[1].atan2(k[0]),
                n[0] * yh[0] + n[1] * yh[1],
                (n[2] - spin * c) / (s * s),
            )
        } else {
            let nh = n[0].hypot(n[1]);
            // ŷ along n_h: x̂ = ŷ × Z = (ŷ_Y, −ŷ_X).
            let heading = if nh > 0.0 { (-n[0]).atan2(n[1]) } else { 0.0 };
            (heading, nh, 0.0)
        };
        let (sh, ch) = heading.sin_cos();
        let (xh, yh) = ([ch, sh], [-sh, ch]);
        Ok(Initial {
            theta: s.atan2(c),
            theta_dot,
            precession,
            spin,
            ux: velocity[0] * xh[0] + velocity[1] * xh[1],
            uy: velocity[0] * yh[0] + velocity[1] * yh[1],
            heading,
        })
    }

    /// The lab-frame vectors of this state: the unit symmetry axis, the
    /// angular velocity \[rad/s\] and the horizontal centre-of-mass velocity
    /// \[m/s\] (the inverse of [`Initial::from_lab`]).
    pub fn to_lab(&self) -> ([f64; 3], [f64; 3], [f64; 2]) {
        let (s, c) = self.theta.sin_cos();
        let (sh, ch) = self.heading.sin_cos();
        let (xh, yh) = ([ch, sh, 0.0], [-sh, ch, 0.0]);
        let (w, om, thd) = (self.spin, self.precession, self.theta_dot);
        let nx = (w - om * c) * s;
        let nz = om * s * s + w * c;
        let k = [s * xh[0], s * xh[1], c];
        let n = [nx * xh[0] + thd * yh[0], nx * xh[1] + thd * yh[1], nz];
        let v = [
            self.ux * xh[0] + self.uy * yh[0],
            self.ux * xh[1] + self.uy * yh[1],
        ];
        (k, n, v)
    }

    /// Check finiteness (and θ in (0, π) if `reduced`).
    pub fn validate(&self, reduced: bool) -> Result<(), Error> {
        for (k, v) in [
            ("initial.theta", self.theta),
            ("initial.theta_dot", self.theta_dot),
            ("initial.precession", self.precession),
            ("initial.spin", self.spin),
            ("initial.ux", self.ux),
            ("initial.uy", self.uy),
            ("initial.heading", self.heading),
        ] {
            if !v.is_finite() {
                return Err(Error::invalid(
                    k,
                    format!("{v} is not allowed"),
                    "a finite number".into(),
                ));
            }
        }
        if reduced
            && !(self.theta > 0.0
                && self.theta < std::f64::consts::PI
                && self.theta.sin() >= SIN_GUARD)
        {
            return Err(Error::invalid(
                "initial.theta",
                format!("{} is outside the reduced model's range", self.theta),
                "0 < theta < pi [rad] with sin(theta) >= 1e-8 (the reduced model's pole guard); use model = \"vector\" (the default) or \"rigid\" for theta = 0 or pi".into(),
            ));
        }
        if !reduced && !(0.0..=std::f64::consts::PI).contains(&self.theta) {
            return Err(Error::invalid(
                "initial.theta",
                format!("{} is out of range", self.theta),
                "0 <= theta <= pi [rad]".into(),
            ));
        }
        Ok(())
    }
}

/// Integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Adaptive Dormand–Prince 8(5,3) with 7th-order dense output.
    Adaptive,
    /// Classical fixed-step RK4 (the paper's method).
    Rk4,
    /// Linearly implicit Rosenbrock method Rodas4P (L-stable, order 4,
    /// numerical Jacobian), for the stiff regularised friction law near
    /// rolling (time scale `ε / (μ g)`).
    Stiff,
    /// Langevin dynamics with the fixed step `solver.dt`: the exact
    /// Ornstein–Uhlenbeck step of the damping and its noise around an RK4
    /// step of the deterministic forces (a symmetric splitting, weak order
    /// 2; docs/physics.md#langevin). Vector model, no Coulomb friction.
    Langevin,
    /// The overdamped limit of the Langevin dynamics (Brownian motion of
    /// the axis and the centre with the same damping and forces), fixed step
    /// `solver.dt`, Euler–Maruyama (weak order 1; docs/physics.md#langevin): for
    /// windows of microseconds and more, where the Langevin step would need
    /// 1e10 steps.
    Brownian,
}

impl Method {
    /// Whether the method is one of the thermal ones (`"langevin"`,
    /// `"brownian"`): fixed step `solver.dt`, `[thermal]`, noise.
    pub fn is_stochastic(self) -> bool {
        matches!(self, Method::Langevin | Method::Brownian)
    }
}

/// Which equations of motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// The paper's Euler-angle model (App. A).
    Reduced,
    /// Full 3D rigid body with a unit quaternion.
    Rigid,
    /// The reduced model's physics (the sphere stays on the plane) written
    /// with the symmetry-axis vector, the angular velocity and the
    /// centre-of-mass velocity in the space frame: no Euler angles, so no
    /// pole singularity and no trigonometry (docs/physics.md#vector-model).
    Vector,
}

/// The valid range of `solver.max_steps`.
pub(crate) const MAX_STEPS_RANGE: &str =
    "an integer, 1 <= max_steps <= 20000000; default 20000000, 2000000 with method = \"stiff\"";

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Integration method.
    pub method: Method,
    /// End time \[s\].
    pub t_end: f64,
    /// Number of RK4 steps over `[0, t_end]` (RK4 only); a multiple of
    /// `samples - 1`, which is its default.
    pub steps: usize,
    /// Relative tolerance (adaptive and stiff); the absolute tolerance is the same
    /// number in the scaled units (lengths by R, masses by m, see docs/physics.md).
    pub rtol: f64,
    /// Output rows, evenly spaced on `[0, t_end]`.
    pub samples: usize,
    /// Which model.
    pub model: ModelKind,
    /// Largest number of accepted steps of the run (`solver.max_steps`);
    /// `None` for the method's default, [`max_steps_for`].
    /// A run that reaches it stops with a run-time error.
    pub max_steps: Option<u64>,
    /// The fixed step \[s\] of `method = "langevin"` or `"brownian"` (`solver.dt`; the run
    /// takes [`crate::thermal::langevin_steps`] equal steps); `None` otherwise.
    pub dt: Option<f64>,
}

impl SolverSettings {
    /// Defaults: adaptive, rtol 1e-10, 1001 samples, 1000 steps (`samples -
    /// 1`, so that `method = "rk4"` alone is valid), the vector model (the
    /// Euler-angle physics without the pole; `reduced`, the paper's own
    /// form, is what `reproduce` runs), the method's step limit.
    pub fn new(t_end: f64) -> Self {
        SolverSettings {
            method: Method::Adaptive,
            t_end,
            steps: 1000,
            rtol: 1e-10,
            samples: 1001,
            model: ModelKind::Vector,
            max_steps: None,
            dt: None,
        }
    }

    /// The run's step limit: `max_steps`, or the method's default
    /// ([`max_steps_for`]).
    pub fn step_limit(&self) -> u64 {
        self.max_steps.unwrap_or_else(|| max_steps_for(self.method))
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<(), Error> {
        if !self.t_end.is_finite() || self.t_end <= 0.0 {
            return Err(Error::invalid(
                "solver.t_end",
                format!("{} is not allowed", self.t_end),
                "a finite time > 0 [s]".into(),
            ));
        }
        if self.samples < 2 || self.samples > MAX_SAMPLES {
            return Err(Error::invalid(
                "solver.samples",
                format!(
                    "{} is too {}",
                    self.samples,
                    if self.samples < 2 { "few" } else { "many" }
                ),
                format!(
                    "an integer, 2 <= samples <= {}: each row keeps {} bytes in memory",
                    MAX_SAMPLES, BYTES_PER_SAMPLE
                ),
            ));
        }
        if !self.rtol.is_finite() || self.rtol < 1e-14 || self.rtol > 1e-2 {
            return Err(Error::invalid(
                "solver.rtol",
                format!("{} is not allowed", self.rtol),
                "1e-14 <= rtol <= 1e-2".into(),
            ));
        }
        if let Some(n) = self.max_steps {
            if !(1..=MAX_STEPS).contains(&n) {
                return Err(Error::invalid(
                    "solver.max_steps",
                    format!("{n} is not allowed"),
                    MAX_STEPS_RANGE.into(),
                ));
            }
        }
        if self.method == Method::Rk4 {
            if self.steps as u64 > self.step_limit() {
                return Err(Error::invalid(
                    "solver.steps",
                    format!(
                        "{} exceeds the step limit {}",
                        self.steps,
                        self.step_limit()
                    ),
                    "steps <= solver.max_steps (default 20000000), a multiple of samples - 1"
                        .into(),
                ));
            }
            if self.steps == 0 {
                return Err(Error::invalid(
                    "solver.steps",
                    "0 steps".into(),
                    "an integer >= 1, a multiple of samples - 1".into(),
                ));
            }
            if self.steps % (self.samples - 1) != 0 {
                return Err(Error::invalid(
                    "solver.steps",
                    format!(
                        "{} is not a multiple of samples - 1 = {}",
                        self.steps,
                        self.samples - 1
                    ),
                    "a multiple of samples - 1 (method = \"rk4\")".into(),
                ));
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// Bounds of the solver settings (see `limits` for the checks of a whole run).

/// |sin θ| below which the reduced (Euler-angle) equations are declared
/// singular: the pole guard of `model::reduced`, also the bound an initial
/// θ of that model is checked against.
pub const SIN_GUARD: f64 = 1e-8;

/// Largest number of accepted steps of one run, over all its integration
/// segments and every method; a run that reaches it stops with a run-time
/// error (exit code 3). Measured (release build, one core of a shared
/// 2-core machine, classical preset with `initial.spin = 1e8`, which needs
/// far more steps): 20 million DOP853 steps take 39 s (reduced model), 46 s
/// (vector), 47 s (rigid), with memory flat at 6 to 21 MB; so a run that
/// cannot make progress stops within about a minute. The stiff method gets
/// a tenth ([`max_steps_for`]). `solver.max_steps` lowers (or restores) it.
pub const MAX_STEPS: u64 = 20_000_000;

/// Largest number of output rows (`solver.samples`). One row takes
/// [`BYTES_PER_SAMPLE`] (224) bytes in memory (and about 440 bytes of CSV),
/// so 5 000 000 rows need 1.12 GB while the run is kept in memory (and a
/// 2.2 GB trajectory.csv): within [`crate::limits::MEMORY_BUDGET`]. A
/// command that runs several runs at once (sweep, ensemble, bit) runs no
/// more of them at once than fit in that bound
/// ([`crate::limits::fit_threads`]); an ensemble keeps histograms at every
/// sample time and has its own, lower limit
/// (`analysis::ensemble::MAX_SAMPLES`).
pub const MAX_SAMPLES: usize = 5_000_000;

/// Memory of one output row while its run is kept \[bytes\]: the row itself
/// (a [`Sample`]: 25 `f64` and a `u8`, 208 bytes), its sample time and, in a
/// stochastic run, the integral of N over its interval (8 bytes each): 224.
pub const BYTES_PER_SAMPLE: u64 = (std::mem::size_of::<Sample>() + 16) as u64;

/// The default step limit of a run with `method`: [`MAX_STEPS`] for the
/// explicit methods; a tenth of it for the stiff method (Rodas4P), whose
/// steps cost up to about ten DOP853 steps each (a numerical Jacobian, an LU
/// decomposition and five stages): 2 million of them took 4 s (nano preset,
/// `force.0.hy = 1e-12`) to 12 s (rigid model, classical, spin 1e8).
pub fn max_steps_for(method: Method) -> u64 {
    match method {
        Method::Stiff => MAX_STEPS / 10,
        Method::Adaptive | Method::Rk4 | Method::Langevin | Method::Brownian => MAX_STEPS,
    }
}
