//! Exact one-dimensional answers (see the module [`super`]): the mean
//! first-passage time and the splitting probability of a reversible
//! diffusion on an interval, by quadrature in log space, and the θ
//! diffusion of a scenario where it is exactly one-dimensional (the
//! Brownian mode on the plane; docs/physics.md#rare-exact).
//!
//! # The diffusion
//!
//! A reversible diffusion `x(t)` on `[L, H]` with coefficient `D(x)` and
//! stationary density `π(x)` (unnormalised) has the generator
//! `L f = (π D f′)′/π`. With the scale density `S′(x) = 1/(π D)`:
//!
//! - the splitting probability `P(reach b before a | x0)`, `a < x0 < b`, is
//!   `(S(x0) − S(a))/(S(b) − S(a))` (Gardiner, *Handbook of Stochastic
//!   Methods*, §5.2.8);
//! - the mean exit time from `(a, b)` solves `L τ = −1`, `τ(a) = τ(b) = 0`:
//!   `τ(x0) = ∫ G(x0, z) π(z) dz` with the Green's function
//!   `G(x, z) = (S(x∧z) − S(a)) (S(b) − S(x∨z))/(S(b) − S(a))`
//!   (Gardiner §5.2.7 in a form with positive terms only: no cancellation);
//! - with a reflecting end instead of `a` (the domain's end `L`, where the
//!   flux `π D τ′` vanishes) `τ(x0) = ∫_{x0}^b S′(y) ∫_L^y π(z) dz dy`, and
//!   symmetrically with `b` reflecting.
//!
//! # Log space
//!
//! Every integrand is positive, so each integral is computed as
//! `ln ∫ e^{φ}` with `φ` the log of the integrand, panel by panel: adaptive
//! Gauss–Kronrod (7, 15) panels with the largest `φ` of the panel factored
//! out, split until `|K15 − G7| <= 1e-12 K15` on every panel (a relative
//! accuracy per panel, hence of every sum of panels), and the panels joined
//! by log-sum-exp. The nested integrals read the inner one from a table of
//! its cumulative values at panel breakpoints plus one Kronrod rule on the
//! partial panel. Barriers of hundreds of kT neither overflow nor
//! underflow: the answers carry their logarithm ([`Positive`]), and the
//! value is `inf` only when `e^{ln}` itself exceeds f64 (a barrier beyond
//! ~700 kT).

use crate::analysis::ensemble::Exit;
use crate::{ContactMode, Error, Failure, Method, ModelKind, Scenario};

/// `β = −ζ(1/2)/sqrt(2π)`: a Brownian path watched at steps `dt` exits a
/// window later than the continuous path, as if the window were wider by
/// `β sqrt(2 D dt)` at each edge, to leading order in `sqrt(dt)` (Broadie,
/// Glasserman & Kou, Math. Finance 7, 325 (1997); Siegmund's correction).
pub const BGK_BETA: f64 = 0.582_597_157_939_010_6;

/// Relative tolerance on each panel's Kronrod–Gauss difference.
const PANEL_TOL: f64 = 1e-12;
/// How many roundings of the exponents `f` the Kronrod–Gauss difference
/// may be made of before it counts as a quadrature error: where `|f|` is
/// large (e^{−64000} in the far tail of a 1000 kT well) the values
/// `e^{f}` are known to `ε |f|` relative only, and no panel does better.
const ROUNDING: f64 = 64.0;
/// Most panels one integral may use before it gives up.
const MAX_PANELS: usize = 200_000;

/// A positive quantity that may exceed f64: its value (`inf` past
/// ~1.8e308, `0` below the subnormals) and its natural logarithm (finite
/// unless the quantity is exactly 0 or infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Positive {
    /// The value (its unit: that of the quantity).
    pub value: f64,
    /// `ln` of the value, in the same unit.
    pub ln: f64,
}

impl Positive {
    fn from_ln(ln: f64) -> Positive {
        Positive {
            value: ln.exp(),
            ln,
        }
    }
}

/// Splitting probabilities from `x0` in `(lower, upper)`: each with its log
/// (the small one is computed directly, not as `1 −` the other).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Splitting {
    /// `P(reach upper before lower | x0)`.
    pub upper_first: Positive,
    /// `P(reach lower before upper | x0)`.
    pub lower_first: Positive,
}

// ---------------------------------------------------------------------------
// Quadrature in log space.

/// Gauss–Kronrod (7, 15) abscissae on `[−1, 1]` (QUADPACK's `qk15`): the
/// odd indices are the Gauss nodes, index 7 the centre.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// The Kronrod weights of [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// The Gauss weights of the nodes `XGK[1], XGK[3], XGK[5], XGK[7]`.
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// `ln(e^a + e^b)` without overflow (`−inf` is the log of 0).
fn lse(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    if hi == f64::NEG_INFINITY {
        return hi;
    }
    hi + (lo - hi).exp().ln_1p()
}

/// `ln Σ e^{v_i}` (in order; `−inf` for an empty list).
fn lse_all(v: &[f64]) -> f64 {
    let m = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if m.is_infinite() {
        return m;
    }
    m + v.iter().map(|x| (x - m).exp()).sum::<f64>().ln()
}

/// One Kronrod rule on `[a, b]` of `e^{f}`: `(ln K15, err)`, `err` the
/// relative difference `|K15 − G7|/K15` less the rounding of the exponents
/// (each `e^{f}` is known to `~ε |f|` relative, [`ROUNDING`]): the panel
/// has converged when `err <= PANEL_TOL`. A NaN of `f` makes both NaN.
fn gk15(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let hl = 0.5 * (b - a);
    let mut phi = [0.0; 15];
    for j in 0..7 {
        phi[2 * j] = f(c - hl * XGK[j]);
        phi[2 * j + 1] = f(c + hl * XGK[j]);
    }
    phi[14] = f(c);
    if phi.iter().any(|p| p.is_nan()) {
        return (f64::NAN, f64::NAN);
    }
    let m = phi.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if m == f64::NEG_INFINITY {
        return (f64::NEG_INFINITY, 0.0);
    }
    if m == f64::INFINITY {
        return (f64::INFINITY, 0.0);
    }
    let e = |i: usize| (phi[i] - m).exp();
    let mut k = WGK[7] * e(14);
    let mut g = WG[3] * e(14);
    for j in 0..7 {
        let pair = e(2 * j) + e(2 * j + 1);
        k += WGK[j] * pair;
        if j % 2 == 1 {
            g += WG[j / 2] * pair;
        }
    }
    let ln_k = m + (hl * k).ln();
    let scale = phi.iter().fold(0.0f64, |s, p| s.max(p.abs()));
    let noise = ROUNDING * f64::EPSILON * scale;
    (ln_k, (((k - g) / k).abs() - noise).max(0.0))
}

fn numerics(why: String) -> Error {
    Error::runtime(0.0, Failure::Numerics, why)
}

/// The panels of `[a, b]` (left to right) on which the Kronrod rule of
/// `e^{f}` meets [`PANEL_TOL`], with their `ln` integrals; starts from
/// `start` equal panels.
fn panels(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    start: usize,
) -> Result<Vec<(f64, f64, f64)>, Error> {
    let mut out = Vec::new();
    // A stack, right panels below left ones, so panels come out in order.
    let mut stack: Vec<(f64, f64)> = (0..start)
        .rev()
        .map(|i| {
            let x0 = a + (b - a) * i as f64 / start as f64;
            let x1 = if i + 1 == start {
                b
            } else {
                a + (b - a) * (i + 1) as f64 / start as f64
            };
            (x0, x1)
        })
        .collect();
    let tiny = 1e-14 * (a.abs().max(b.abs()).max(b - a));
    while let Some((x0, x1)) = stack.pop() {
        let (ln_k, rel) = gk15(f, x0, x1);
        if ln_k.is_nan() {
            return Err(numerics(format!(
                "the integrand is not a number on [{x0}, {x1}]"
            )));
        }
        if rel <= PANEL_TOL || x1 - x0 <= tiny {
            out.push((x0, x1, ln_k));
        } else {
            let m = 0.5 * (x0 + x1);
            stack.push((m, x1));
            stack.push((x0, m));
        }
        if out.len() + stack.len() > MAX_PANELS {
            return Err(numerics(format!(
                "the quadrature on [{a}, {b}] needs more than {MAX_PANELS} panels"
            )));
        }
    }
    Ok(out)
}

/// `ln ∫_a^b e^{f(x)} dx` (`a <= b`; `−inf` for `a = b`).
fn ln_integral(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> Result<f64, Error> {
    if b.partial_cmp(&a) != Some(std::cmp::Ordering::Greater) {
        return Ok(f64::NEG_INFINITY);
    }
    let p = panels(f, a, b, 8)?;
    Ok(lse_all(&p.iter().map(|x| x.2).collect::<Vec<_>>()))
}

/// The cumulative integrals of `e^{f}` over `[c, d]`, from either end, at
/// any point: `ln ∫_c^y` and `ln ∫_y^d`.
struct Table<'a> {
    f: &'a dyn Fn(f64) -> f64,
    /// Breakpoints, `c` first and `d` last.
    x: Vec<f64>,
    /// `ln ∫_c^{x_i}`.
    left: Vec<f64>,
    /// `ln ∫_{x_i}^d`.
    right: Vec<f64>,
}

impl<'a> Table<'a> {
    fn new(f: &'a dyn Fn(f64) -> f64, c: f64, d: f64) -> Result<Table<'a>, Error> {
        let p = panels(f, c, d, 16)?;
        let mut x = vec![c];
        let mut left = vec![f64::NEG_INFINITY];
        for &(_, x1, ln) in &p {
            x.push(x1);
            left.push(lse(*left.last().unwrap(), ln));
        }
        let mut right = vec![f64::NEG_INFINITY; x.len()];
        for (i, &(_, _, ln)) in p.iter().enumerate().rev() {
            right[i] = lse(right[i + 1], ln);
        }
        Ok(Table { f, x, left, right })
    }

    /// The panel `[x_j, x_{j+1}]` holding `y` (clamped to the table).
    fn panel(&self, y: f64) -> usize {
        let n = self.x.len() - 1;
        self.x.partition_point(|&v| v <= y).clamp(1, n) - 1
    }

    /// `ln ∫_c^y e^{f}`.
    fn ln_left(&self, y: f64) -> f64 {
        let j = self.panel(y);
        let y = y.clamp(self.x[j], self.x[j + 1]);
        let part = if y > self.x[j] {
            gk15(self.f, self.x[j], y).0
        } else {
            f64::NEG_INFINITY
        };
        lse(self.left[j], part)
    }

    /// `ln ∫_y^d e^{f}`.
    fn ln_right(&self, y: f64) -> f64 {
        let j = self.panel(y);
        let y = y.clamp(self.x[j], self.x[j + 1]);
        let part = if y < self.x[j + 1] {
            gk15(self.f, y, self.x[j + 1]).0
        } else {
            f64::NEG_INFINITY
        };
        lse(self.right[j + 1], part)
    }
}

// ---------------------------------------------------------------------------
// A one-dimensional reversible diffusion.

/// A log-density or diffusion-coefficient function of the position.
pub type PositionFn = Box<dyn Fn(f64) -> f64 + Send + Sync>;

/// A reversible diffusion on `[lower, upper]` with reflecting (or natural)
/// ends: the coefficient `D(x)` \[x-unit²/s\] and the log of the stationary
/// density `ln π(x)` (unnormalised: any additive constant). See the module
/// documentation for the formulas.
pub struct Diffusion {
    /// The lower end of the domain (reflecting or natural).
    pub lower: f64,
    /// The upper end of the domain.
    pub upper: f64,
    ln_density: PositionFn,
    diffusivity: PositionFn,
}

impl std::fmt::Debug for Diffusion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Diffusion")
            .field("lower", &self.lower)
            .field("upper", &self.upper)
            .finish_non_exhaustive()
    }
}

impl Diffusion {
    /// The diffusion on `[lower, upper]` (finite, `lower < upper`) with
    /// `ln π` = `ln_density` and `D` = `diffusivity` (positive and finite
    /// inside the domain).
    pub fn new(
        lower: f64,
        upper: f64,
        ln_density: impl Fn(f64) -> f64 + Send + Sync + 'static,
        diffusivity: impl Fn(f64) -> f64 + Send + Sync + 'static,
    ) -> Diffusion {
        Diffusion {
            lower,
            upper,
            ln_density: Box::new(ln_density),
            diffusivity: Box::new(diffusivity),
        }
    }

    /// `ln π(x)`, the unnormalised stationary density.
    pub fn ln_density(&self, x: f64) -> f64 {
        (self.ln_density)(x)
    }

    /// `D(x)` \[x-unit²/s\].
    pub fn diffusivity(&self, x: f64) -> f64 {
        (self.diffusivity)(x)
    }

    /// The absorbing edges of a path watched at steps `dt` \[s\]: each
    /// moved outwards by `β sqrt(2 D(edge) dt)` ([`BGK_BETA`]; Broadie,
    /// Glasserman & Kou), the leading-order correction in `sqrt(dt)` of the
    /// continuous answers; an edge that would leave the domain is kept.
    pub fn watched_edges(
        &self,
        lower: Option<f64>,
        upper: Option<f64>,
        dt: f64,
    ) -> (Option<f64>, Option<f64>) {
        let moved = |e: f64, sign: f64| {
            let t = e + sign * BGK_BETA * (2.0 * (self.diffusivity)(e) * dt).sqrt();
            if t > self.lower && t < self.upper {
                t
            } else {
                e
            }
        };
        (lower.map(|e| moved(e, -1.0)), upper.map(|e| moved(e, 1.0)))
    }

    /// `ln S′(x) = −ln π(x) − ln D(x)`, the log of the scale density.
    fn ln_scale(&self, x: f64) -> f64 {
        -(self.ln_density)(x) - (self.diffusivity)(x).ln()
    }

    fn check(&self, lower: Option<f64>, upper: Option<f64>, x0: f64) -> Result<(), Error> {
        let (l, h) = (self.lower, self.upper);
        if !(l.is_finite() && h.is_finite() && l < h) {
            return Err(Error::invalid(
                "diffusion",
                format!("the domain [{l}, {h}]"),
                "finite ends, lower < upper".into(),
            ));
        }
        if !(x0 >= l && x0 <= h) {
            return Err(Error::invalid(
                "x0",
                format!("{x0} is outside the domain [{l}, {h}]"),
                "a start within the domain".into(),
            ));
        }
        for (name, e) in [("lower", lower), ("upper", upper)] {
            if let Some(e) = e {
                if !(e >= l && e <= h) {
                    return Err(Error::invalid(
                        name,
                        format!("the edge {e} is outside the domain [{l}, {h}]"),
                        "an absorbing edge within the domain".into(),
                    ));
                }
            }
        }
        if let (Some(a), Some(b)) = (lower, upper) {
            if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) {
                return Err(Error::invalid(
                    "lower",
                    format!("the window ({a}, {b}) is empty"),
                    "lower < upper".into(),
                ));
            }
        }
        Ok(())
    }

    /// The mean first-passage time \[s\] out of `(lower, upper)` from `x0`:
    /// an absent edge is the domain's reflecting end (the time to reach the
    /// other edge). Both absent: `Err` (never leaves). `x0` on or beyond an
    /// absorbing edge: 0.
    pub fn mean_exit_time(
        &self,
        lower: Option<f64>,
        upper: Option<f64>,
        x0: f64,
    ) -> Result<Positive, Error> {
        self.check(lower, upper, x0)?;
        if lower.is_some_and(|a| x0 <= a) || upper.is_some_and(|b| x0 >= b) {
            return Ok(Positive {
                value: 0.0,
                ln: f64::NEG_INFINITY,
            });
        }
        let g = |x: f64| self.ln_scale(x);
        let h = |x: f64| (self.ln_density)(x);
        let ln = match (lower, upper) {
            (None, None) => {
                return Err(Error::invalid(
                    "window",
                    "no absorbing edge: the diffusion never leaves".into(),
                    "at least one edge inside the domain".into(),
                ));
            }
            (Some(a), Some(b)) => {
                // τ = [(S(b) − S(x0)) ∫_a^{x0} (S(z) − S(a)) π dz
                //      + (S(x0) − S(a)) ∫_{x0}^b (S(b) − S(z)) π dz] / (S(b) − S(a)).
                let s = Table::new(&g, a, b)?;
                let j1 = ln_integral(&|z| s.ln_left(z) + h(z), a, x0)?;
                let j2 = ln_integral(&|z| s.ln_right(z) + h(z), x0, b)?;
                lse(s.ln_right(x0) + j1, s.ln_left(x0) + j2) - s.left[s.x.len() - 1]
            }
            (None, Some(b)) => {
                let c = Table::new(&h, self.lower, b)?;
                ln_integral(&|y| g(y) + c.ln_left(y), x0, b)?
            }
            (Some(a), None) => {
                let c = Table::new(&h, a, self.upper)?;
                ln_integral(&|y| g(y) + c.ln_right(y), a, x0)?
            }
        };
        if ln.is_nan() {
            return Err(numerics("the mean exit time is not a number".into()));
        }
        Ok(Positive::from_ln(ln))
    }

    /// The splitting probabilities from `x0` between the absorbing edges
    /// `lower < upper` (`x0` on or beyond an edge: that edge first).
    pub fn splitting(&self, lower: f64, upper: f64, x0: f64) -> Result<Splitting, Error> {
        self.check(Some(lower), Some(upper), x0)?;
        let one = Positive {
            value: 1.0,
            ln: 0.0,
        };
        let zero = Positive {
            value: 0.0,
            ln: f64::NEG_INFINITY,
        };
        if x0 <= lower {
            return Ok(Splitting {
                upper_first: zero,
                lower_first: one,
            });
        }
        if x0 >= upper {
            return Ok(Splitting {
                upper_first: one,
                lower_first: zero,
            });
        }
        let g = |x: f64| self.ln_scale(x);
        let s = Table::new(&g, lower, upper)?;
        let total = s.left[s.x.len() - 1];
        let (up, down) = (s.ln_left(x0) - total, s.ln_right(x0) - total);
        if up.is_nan() || down.is_nan() {
            return Err(numerics("the splitting probability is not a number".into()));
        }
        // Each ≤ 1 up to rounding.
        Ok(Splitting {
            upper_first: Positive::from_ln(up.min(0.0)),
            lower_first: Positive::from_ln(down.min(0.0)),
        })
    }
}

// ---------------------------------------------------------------------------
// The θ diffusion of a scenario.

/// The nutation angle θ of the overdamped (Brownian) top on the plane as a
/// one-dimensional diffusion (docs/physics.md#rare-exact): on `[0, π]`, with
///
/// - `D(θ) = kT/Γ(θ)` \[rad²/s\], `Γ = γ_r A + m γ_t a² sin²θ +
///   c m γ_t ℓ²/(m γ_t + c)`, `ℓ = R − a cos θ` (the tilt's friction: the
///   rotation, the centre's vertical velocity, and the contact damping `c`
///   in series with the centre's translational friction, the lever `ℓ`
///   from the contact point: the θθ element of the inverse of §brownian's
///   5×5 friction matrix);
/// - `π(θ) ∝ sin θ s(θ) e^{−U/kT}`, `s = sqrt(1 + m a² sin²θ/A)`,
///   `U = −m g a cos θ + Σ wells − h_eff (R θ − a sin θ)` \[J\], where
///   `h_eff = H_x m γ_t/(m γ_t + c)` is a constant applied force along the
///   tilt (`[[force]]` on `[0, ∞)`; `H_y`, `h_z` and the adhesion do not
///   move θ).
#[derive(Debug, Clone, PartialEq)]
pub struct ThetaDiffusion {
    /// kT \[J\].
    pub kt: f64,
    /// m \[kg\].
    pub mass: f64,
    /// R \[m\].
    pub radius: f64,
    /// a \[m\].
    pub offset: f64,
    /// A \[kg m²\].
    pub inertia_transverse: f64,
    /// g \[m/s²\].
    pub gravity: f64,
    /// γ_t \[1/s\].
    pub damping_translational: f64,
    /// γ_r \[1/s\].
    pub damping_rotational: f64,
    /// c \[N s/m\].
    pub damping_contact: f64,
    /// The constant `H_x` \[N\] (the sum over the windows; 0 without).
    pub hx: f64,
    /// The orientation wells (docs/physics.md#wells).
    pub wells: Vec<crate::Well>,
}

/// Refusal of the exact answer: the key and the reason, with what would
/// make it exact.
fn not_exact(key: &str, why: String, fix: &str) -> Error {
    Error::invalid(key, format!("no exact 1D answer: {why}"), fix.into())
}

impl ThetaDiffusion {
    /// The θ diffusion of `sc`, or `Err(Error::Invalid)` naming the key
    /// that makes θ not an exactly one-dimensional, time-homogeneous
    /// diffusion (docs/physics.md#rare-exact):
    ///
    /// - `solver.method` other than `"brownian"` (deterministic runs; the
    ///   Langevin run's θ carries θ̇, so θ alone is not Markov);
    /// - `thermal.temperature = 0`;
    /// - `surface.contact = "unilateral"` (the rigid model is then the free
    ///   body above a wall, whose θ couples to the gap; the vector model
    ///   stops at a lift-off);
    /// - `surface.friction > 0` (no Brownian scheme has it either);
    /// - body actuators (`kind = "tip"`, `"magnetic"`): their wrench
    ///   depends on the azimuth, the material axes or time;
    /// - a force window with `H_x != 0` that does not act over the whole
    ///   run (`start = 0`, `stop = inf`): a time-dependent drift.
    ///
    /// Everything else is exact: wells, gravity, adhesion (absorbed by the
    /// normal force on the plane), `h_z` and `H_y` (no θ component of the
    /// mobility), the contact damping (in `D` and `h_eff`), any `T`.
    /// `solver.t_end` and `solver.samples` do not matter (the scenario is
    /// validated with one step and two rows).
    pub fn of(sc: &Scenario) -> Result<ThetaDiffusion, Error> {
        // The run's span and rows do not enter the answer.
        let mut probe = sc.clone();
        probe.solver.samples = 2;
        if let Some(dt) = probe.solver.dt {
            probe.solver.t_end = dt;
        }
        probe.validate()?;
        let so = &sc.solver;
        if so.method != Method::Brownian {
            let why = match so.method {
                Method::Langevin => "solver.method = \"langevin\" has inertia: θ alone is not a Markov process (it carries θ̇)".to_string(),
                _ => "a deterministic method has no diffusion".to_string(),
            };
            return Err(not_exact(
                "solver.method",
                why,
                "solver.method = \"brownian\" (the overdamped mode on the plane)",
            ));
        }
        if !sc.thermal.is_hot() {
            return Err(not_exact(
                "thermal.temperature",
                format!("{} K: no noise", sc.thermal.temperature),
                "thermal.temperature > 0 [K]",
            ));
        }
        if sc.surface.contact == ContactMode::Unilateral {
            let why = if so.model == ModelKind::Rigid {
                "contact = \"unilateral\" makes the rigid model a free body above a wall: θ couples to the gap"
            } else {
                "contact = \"unilateral\" stops the run at a lift-off, which the diffusion does not have"
            };
            return Err(not_exact(
                "surface.contact",
                why.into(),
                "surface.contact = \"bilateral\" (the top held on the plane)",
            ));
        }
        if sc.surface.friction != 0.0 {
            return Err(not_exact(
                "surface.friction",
                format!("{} (dry friction)", sc.surface.friction),
                "surface.friction = 0",
            ));
        }
        if !sc.actuators.is_empty() {
            return Err(not_exact(
                &format!("force.{}", sc.forcing.windows.len()),
                "a body actuator's wrench depends on the azimuth, the material axes or time".into(),
                "no tip or magnetic [[force]] windows",
            ));
        }
        if let Some(key) = crate::input::scenario::plugins::first_key(sc) {
            return Err(not_exact(
                &key,
                "a force plug-in's table is not in the 1D model".into(),
                "no force plug-in tables ([wind], ...)",
            ));
        }
        let mut hx = 0.0;
        for (k, w) in sc.forcing.windows.iter().enumerate() {
            if w.hx != 0.0 {
                if !(w.start == 0.0 && w.stop == f64::INFINITY) {
                    return Err(not_exact(
                        &format!("force.{k}.hx"),
                        format!(
                            "{} N acts on [{}, {}) s only: a time-dependent drift",
                            w.hx, w.start, w.stop
                        ),
                        "H_x = 0, or a window over the whole run (start = 0, no stop)",
                    ));
                }
                hx += w.hx;
            }
        }
        let th = &sc.thermal;
        let top = &sc.top;
        Ok(ThetaDiffusion {
            kt: th.kt(),
            mass: top.mass,
            radius: top.radius,
            offset: top.offset,
            inertia_transverse: top.inertia_transverse,
            gravity: sc.surface.gravity,
            damping_translational: th.damping_translational,
            damping_rotational: th.damping_rotational,
            damping_contact: th.damping_contact,
            hx,
            wells: sc.wells(),
        })
    }

    /// `m γ_t/(m γ_t + c)`: the share of an applied force at the contact
    /// point that turns the tilt (1 without contact damping).
    fn force_share(&self) -> f64 {
        let mg = self.mass * self.damping_translational;
        mg / (mg + self.damping_contact)
    }

    /// The tilt's friction `Γ(θ)` \[kg m²/s\] (see the type's doc).
    pub fn friction(&self, theta: f64) -> f64 {
        let (m, a) = (self.mass, self.offset);
        let s2 = theta.sin().powi(2);
        let mg = m * self.damping_translational;
        let lever = self.radius - a * theta.cos();
        let contact = if self.damping_contact > 0.0 {
            self.damping_contact * mg * lever * lever / (mg + self.damping_contact)
        } else {
            0.0
        };
        self.damping_rotational * self.inertia_transverse + mg * a * a * s2 + contact
    }

    /// `D(θ) = kT/Γ(θ)` \[rad²/s\].
    pub fn diffusivity(&self, theta: f64) -> f64 {
        self.kt / self.friction(theta)
    }

    /// The potential `U(θ)` \[J\] (see the type's doc; 0 at θ = 0 for
    /// gravity and the applied force).
    pub fn potential(&self, theta: f64) -> f64 {
        let mut u = -self.mass * self.gravity * self.offset * theta.cos();
        for w in &self.wells {
            let x = (theta - w.theta) / w.width;
            u -= w.depth * (-0.5 * x * x).exp();
        }
        if self.hx != 0.0 {
            u -= self.hx * self.force_share() * (self.radius * theta - self.offset * theta.sin());
        }
        u
    }

    /// `ln π(θ) = ln sin θ + ln s(θ) − U(θ)/kT` (unnormalised).
    pub fn ln_density(&self, theta: f64) -> f64 {
        let s = theta.sin();
        let ratio = self.mass * self.offset * self.offset / self.inertia_transverse;
        s.ln() + 0.5 * (ratio * s * s).ln_1p() - self.potential(theta) / self.kt
    }

    /// The generic diffusion on `[0, π]` (reflecting at the poles: they
    /// are entrance boundaries, `π ∝ sin θ`).
    pub fn diffusion(&self) -> Diffusion {
        let a = std::sync::Arc::new(self.clone());
        let b = a.clone();
        Diffusion::new(
            0.0,
            std::f64::consts::PI,
            move |t| a.ln_density(t),
            move |t| b.diffusivity(t),
        )
    }
}

// ---------------------------------------------------------------------------
// Targets and resets over θ.

/// What a rare-event computation estimates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// `P(target before reset)` \[1\].
    Probability,
    /// The mean first-passage time to the target \[s\].
    MeanFirstPassageTime,
}

impl Quantity {
    /// `"probability"` or `"mean_first_passage_time"`.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Probability => "probability",
            Quantity::MeanFirstPassageTime => "mean_first_passage_time",
        }
    }

    /// The unit: `""` or `"s"`.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Probability => "",
            Quantity::MeanFirstPassageTime => "s",
        }
    }
}

/// An absorbing edge of the θ window: where, and whether it belongs to the
/// target (else to the reset).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// θ of the edge \[rad\].
    pub theta: f64,
    /// True for the target's edge, false for the reset's.
    pub target: bool,
}

/// The exact answer of [`exact`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exact {
    /// What it is.
    pub quantity: Quantity,
    /// The value for the continuous process (\[1\] or \[s\]).
    pub value: Positive,
    /// The value for the path watched at every step of `solver.dt`
    /// (the window widened by `β sqrt(2 D dt)` at each absorbing edge,
    /// [`BGK_BETA`]); `None` without a step.
    pub watched: Option<Positive>,
    /// The lower absorbing edge (`None`: the pole θ = 0, reflecting).
    pub lower: Option<Edge>,
    /// The upper absorbing edge (`None`: θ = π, reflecting).
    pub upper: Option<Edge>,
    /// The start θ0 \[rad\].
    pub theta0: f64,
}

/// The θ edges of a condition: the largest `θ < v` threshold and the
/// smallest `θ > v` one (`Err` if a term is on another column).
fn theta_edges(cond: &Exit, key: &str) -> Result<(Option<f64>, Option<f64>), Error> {
    let (mut below, mut above): (Option<f64>, Option<f64>) = (None, None);
    for &(i, is_above, v) in cond.terms() {
        let col = crate::trajectory::COLUMNS[i];
        if col != "theta" {
            return Err(not_exact(
                key,
                format!(
                    "{col}{}{v} is not a condition on theta",
                    if is_above { '>' } else { '<' }
                ),
                "conditions on theta only (theta<VALUE, theta>VALUE)",
            ));
        }
        if is_above {
            above = Some(above.map_or(v, |a| a.min(v)));
        } else {
            below = Some(below.map_or(v, |b| b.max(v)));
        }
    }
    Ok((below, above))
}

/// The exact answer for the scenario `sc` (its θ diffusion,
/// [`ThetaDiffusion::of`]) from `initial.theta`: with a `reset`,
/// `P(target before reset)`; without, the mean first-passage time to the
/// target. Both conditions must be on θ only. Where a target and a reset
/// edge coincide, the target wins (as [`super::direct`] counts). A
/// condition `θ < v` with `v <= 0` or `θ > v` with `v >= π` never holds.
/// `Err(Error::Invalid)`: the scenario or a condition is not one where
/// the answer is exact (the reason in the message), or the target is never
/// reached (a mean time without a target edge).
pub fn exact(sc: &Scenario, target: &Exit, reset: Option<&Exit>) -> Result<Exact, Error> {
    let d = ThetaDiffusion::of(sc)?;
    let pi = std::f64::consts::PI;
    let theta0 = sc.initial.theta;
    let (tb, ta) = theta_edges(target, "--target")?;
    let (rb, ra) = match reset {
        Some(r) => theta_edges(r, "--reset")?,
        None => (None, None),
    };
    // Lower edge: the larger threshold is met first coming down; a tie
    // goes to the target.
    let pick_lower = |t: Option<f64>, r: Option<f64>| -> Option<Edge> {
        let t = t.filter(|v| *v > 0.0);
        let r = r.filter(|v| *v > 0.0);
        match (t, r) {
            (Some(t), Some(r)) if r > t => Some(Edge {
                theta: r,
                target: false,
            }),
            (Some(t), _) => Some(Edge {
                theta: t,
                target: true,
            }),
            (None, Some(r)) => Some(Edge {
                theta: r,
                target: false,
            }),
            (None, None) => None,
        }
    };
    let pick_upper = |t: Option<f64>, r: Option<f64>| -> Option<Edge> {
        let t = t.filter(|v| *v < pi);
        let r = r.filter(|v| *v < pi);
        match (t, r) {
            (Some(t), Some(r)) if r < t => Some(Edge {
                theta: r,
                target: false,
            }),
            (Some(t), _) => Some(Edge {
                theta: t,
                target: true,
            }),
            (None, Some(r)) => Some(Edge {
                theta: r,
                target: false,
            }),
            (None, None) => None,
        }
    };
    let lower = pick_lower(tb, rb);
    let upper = pick_upper(ta, ra);
    let diff = d.diffusion();
    let dt = sc.solver.dt;
    // The window of the path watched at every step (kept where that would
    // cross a pole).
    let (wl, wu) = match dt {
        Some(dt) => {
            let (l, u) = diff.watched_edges(lower.map(|e| e.theta), upper.map(|e| e.theta), dt);
            (
                lower.zip(l).map(|(e, t)| Edge { theta: t, ..e }),
                upper.zip(u).map(|(e, t)| Edge { theta: t, ..e }),
            )
        }
        None => (lower, upper),
    };
    let quantity = if reset.is_some() {
        Quantity::Probability
    } else {
        Quantity::MeanFirstPassageTime
    };
    let solve = |lo: Option<Edge>, hi: Option<Edge>| -> Result<Positive, Error> {
        let lo_t = lo.map(|e| e.theta);
        let hi_t = hi.map(|e| e.theta);
        match quantity {
            Quantity::MeanFirstPassageTime => {
                if lo.is_none() && hi.is_none() {
                    return Err(Error::invalid(
                        "--target",
                        format!(
                            "{target} never holds for 0 <= theta <= pi: the mean first-passage time is infinite"
                        ),
                        "a target theta<VALUE with VALUE > 0 or theta>VALUE with VALUE < pi".into(),
                    ));
                }
                diff.mean_exit_time(lo_t, hi_t, theta0)
            }
            Quantity::Probability => {
                let one = Positive {
                    value: 1.0,
                    ln: 0.0,
                };
                let zero = Positive {
                    value: 0.0,
                    ln: f64::NEG_INFINITY,
                };
                let of = |t: bool| if t { one } else { zero };
                Ok(match (lo, hi) {
                    (None, None) => zero,
                    // θ is recurrent on [0, π]: the one edge is met surely.
                    (Some(e), None) | (None, Some(e)) => of(e.target),
                    (Some(a), Some(b)) if a.target == b.target => of(a.target),
                    (Some(a), Some(b)) => {
                        let s = diff.splitting(a.theta, b.theta, theta0)?;
                        if b.target {
                            s.upper_first
                        } else {
                            s.lower_first
                        }
                    }
                })
            }
        }
    };
    let value = solve(lower, upper)?;
    let watched = match dt {
        Some(_) => Some(solve(wl, wu)?),
        None => None,
    };
    Ok(Exact {
        quantity,
        value,
        watched,
        lower,
        upper,
        theta0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The θθ element of the inverse of the code's 5×5 friction matrix
    /// (`model::thermostat::friction_lab`, scaled units m = R = 1) is
    /// [`ThetaDiffusion::friction`]'s closed form, with and without the
    /// contact damping, at several axes.
    #[test]
    fn tilt_friction_is_the_theta_element_of_the_mobility() {
        use crate::model::thermostat::{Bath, Body, friction_lab, modes_basis};
        let body = Body {
            a: 0.4,
            ia: 0.3,
            ic: 0.5,
        };
        for c in [0.0, 0.7, 30.0] {
            let bath = Bath {
                kt: 1.0,
                gt: 1.3,
                gr: 0.9,
                c,
            };
            let d = ThetaDiffusion {
                kt: 1.0,
                mass: 1.0,
                radius: 1.0,
                offset: body.a,
                inertia_transverse: body.ia,
                gravity: 0.0,
                damping_translational: bath.gt,
                damping_rotational: bath.gr,
                damping_contact: c,
                hx: 0.0,
                wells: vec![],
            };
            for (theta, phi) in [(0.3f64, 0.0f64), (1.2, 2.0), (2.5, -1.0), (3.0, 0.4)] {
                let k = [
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ];
                let g = friction_lab(&bath, &body, k, None);
                let mu = g.try_inverse().unwrap();
                let ([_, e, _], _) = modes_basis(k);
                let mut m = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        m += e[i] * mu[(2 + i, 2 + j)] * e[j];
                    }
                }
                let want = 1.0 / d.friction(theta);
                assert!(
                    (m - want).abs() < 1e-13 * want,
                    "c = {c}, θ = {theta}: μ_θθ {m} against {want}"
                );
            }
        }
    }
}
