//! Desorption: the rate at which thermal motion carries an adsorbed
//! molecule (C60 on graphene) out of its adhesion well, on the height
//! coordinate (docs/physics.md#desorption).
//!
//! # Model
//!
//! The shell's centre at height `Z` above the top layer feels the
//! continuum Lennard-Jones energy `U(Z)` of [`crate::physics::adhesion`]
//! (its well: depth `E_b`, bottom `Z₀`, frequency `ω₀ = sqrt(U″(Z₀)/m)`).
//! `U` depends on `Z` alone (the smeared sheet has no lateral or
//! orientational corrugation), so `(Z, Ż)` is a closed Markov process:
//!
//! `m Z̈ = −U′(Z) − m γ Ż + sqrt(2 m γ kT) ξ(t)`,
//!
//! `γ` the translational damping of `[thermal]` (the substrate's friction on
//! a vertical motion is taken equal to the in-plane one). Gravity (`m g Z`,
//! 1e-13 of the binding) is left out. The molecule has **desorbed** when `Z`
//! first reaches `z_out`, the height where the binding has fallen to the
//! thermal energy: `U(z_out) = −kT`.
//!
//! # The rate: `k = κ k_TST`
//!
//! - `k_TST = sqrt(kT/2πm) e^{−U(z_out)/kT} / ∫ e^{−U/kT} dZ` (the well's
//!   population below `z_out`): the one-way flux through `z_out` per
//!   molecule in the well, by quadrature; an upper bound on the rate.
//! - `κ`, the transmission: the fraction of the outward crossings of `z_out`
//!   that come from the thermalised well rather than from a recrossing. The
//!   equilibrium Langevin dynamics is reversible under `v → −v`, so it is
//!   the probability that a path started at `z_out` with an *inward* speed
//!   drawn from the flux law (Rayleigh, density `∝ v e^{−mv²/2kT}`) falls
//!   into the well, its energy below `E_cap = U(z_out) − c`, `c` the
//!   smaller of 12 kT and half the well's depth, before it returns to
//!   `z_out` (the effective positive
//!   flux of Anderson, J. Chem. Phys. 58, 4684 (1973); van Erp, Moroni &
//!   Bolhuis, J. Chem. Phys. 118, 7762 (2003)). A captured path climbs back
//!   with probability ~`e^{−c/kT}` before it thermalises (6e-6 for C60 at
//!   300 K, 0.7 % at the smallest depth allowed, [`MIN_DEPTH_KT`]): the
//!   bias of the capture rule, below the intervals here.
//! - `κ` is the count of captured paths over `paths` independent ones, with
//!   the Wilson 95 % interval (a path cut by its step budget is undecided:
//!   the lower end counts it returned, the upper end captured). Paths are
//!   integrated with the BAOAB splitting (Leimkuhler & Matthews, the
//!   Langevin engine's, [`crate::integrate::langevin`]), written out here
//!   for one coordinate: the engine integrates a top on a plane, whose
//!   height is a constraint. A crossing is checked at each step's end.
//! - The step check: the same count at `dt/2` with independent noise
//!   ([`StepCheck`], on the log scale).
//!
//! # Cross-checks (the tests)
//!
//! - Strong damping (`γ ≫ ω₀`): `k` tends to `1/τ`, `τ` the mean
//!   first-passage time from `Z₀` to `z_out` of the Smoluchowski equation,
//!   exact by quadrature ([`Diffusion::mean_exit_time`]).
//! - Weak damping (`γ ≪ ω₀`): `k` tends to Mel'nikov & Meshkov's
//!   `A(δ) k_TST` (J. Chem. Phys. 85, 1018 (1986)), `δ = γ I/kT` the
//!   energy lost per orbit in units of kT, `I = ∮ p dZ` the action of the
//!   orbit at `U(z_out)`, `A(δ) = exp[(1/2π) ∫ ln(1 − e^{−δ(x² + 1/4)})
//!   dx/(x² + 1/4)]` (`A → δ` as `δ → 0`: Kramers' energy diffusion;
//!   `A → 1` as `δ → ∞`: TST).

use std::f64::consts::PI;

use serde::Serialize;

use crate::Error;
use crate::analysis::bit::wilson;
use crate::analysis::ensemble::Z95;
use crate::analysis::rare::exact::Diffusion;
use crate::analysis::step_check::{AtStep, REFINED_SEED_OFFSET, Scale, StepCheck};
use crate::analysis::sweep::run_ordered;
use crate::input::thermal::BOLTZMANN;
use crate::physics::adhesion::{Adhesion, bisect, gauss_legendre};
use crate::random::Stream;

/// Smallest depth of the well below `z_out`, `U(z_out) − U₀`, in kT: below
/// it the capture rule's bias (`~e^{−depth/2}`) is not negligible and the
/// molecule is hardly bound.
pub const MIN_DEPTH_KT: f64 = 10.0;

/// How far below `U(z_out)` a path's energy must fall to count as
/// captured, in kT (at most half the well's depth): a captured path climbs
/// back with probability ~`e^{−12}` = 6e-6 before it thermalises.
pub const CAPTURE_KT: f64 = 12.0;

/// Largest number of paths (`paths`): the path index is a noise stream's
/// run (< 2³²).
pub const MAX_PATHS: usize = 100_000_000;

/// The default step: this fraction of the well's period `2π/ω₀`.
pub const STEP_FRACTION: f64 = 1.0 / 400.0;

/// A molecule on a surface at a temperature, damped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Desorption {
    /// The shell and the substrate (the well `U(Z)`).
    pub adhesion: Adhesion,
    /// The molecule's mass \[kg\].
    pub mass: f64,
    /// The temperature \[K\].
    pub temperature: f64,
    /// The damping of the height `γ` \[1/s\] (`thermal.damping_translational`).
    pub damping: f64,
}

/// How many paths, which noise, which step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sizes {
    /// Paths of the transmission count (1 ..= [`MAX_PATHS`]).
    pub paths: usize,
    /// The noise seed (path `i` draws from the stream `(seed, i)`).
    pub seed: u64,
    /// The step \[s\] (`None`: [`STEP_FRACTION`] of the well's period).
    pub dt: Option<f64>,
    /// Run the step check (the count again at `dt/2`).
    pub step_check: bool,
}

impl Default for Sizes {
    fn default() -> Self {
        Sizes {
            paths: 20_000,
            seed: 1,
            dt: None,
            step_check: true,
        }
    }
}

/// The well on the height coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Well {
    /// Binding energy `E_b = −U(Z₀)` \[J\].
    pub binding: f64,
    /// `E_b/kT` \[1\].
    pub binding_kt: f64,
    /// The bottom `Z₀` (the centre's height above the top layer) \[m\].
    pub height: f64,
    /// Where the molecule counts as desorbed, `U(z_out) = −kT` \[m\].
    pub exit_height: f64,
    /// The well's frequency `ω₀/2π` \[Hz\].
    pub frequency: f64,
    /// The capture energy above the bottom, `E_cap − U₀` \[J\].
    pub capture_energy: f64,
}

/// The transmission count at one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Count {
    /// The step \[s\].
    pub dt: f64,
    /// Paths run.
    pub paths: u64,
    /// Paths captured by the well (its energy below `E_cap`).
    pub captured: u64,
    /// Paths back at `z_out` first.
    pub returned: u64,
    /// Paths cut by their step budget (undecided).
    pub censored: u64,
    /// Steps over all paths.
    pub steps: u64,
    /// `κ` = captured / paths \[1\].
    pub transmission: f64,
    /// Its Wilson 95 % interval.
    pub transmission_ci95: [f64; 2],
    /// `κ k_TST` \[1/s\].
    pub rate: f64,
    /// Its 95 % interval \[1/s\].
    pub ci95: [f64; 2],
}

/// The desorption rate and its cross-checks.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesorptionRate {
    /// Temperature \[K\].
    pub temperature: f64,
    /// Damping `γ` \[1/s\].
    pub damping: f64,
    /// `γ/ω₀` \[1\]: below ~0.1 weak, above ~10 strong.
    pub damping_over_frequency: f64,
    /// Mass \[kg\].
    pub mass: f64,
    /// The well.
    pub well: Well,
    /// The rate `κ k_TST` \[1/s\] (the count at the step `dt`).
    pub rate: f64,
    /// Its 95 % interval \[1/s\].
    pub ci95: [f64; 2],
    /// `ln` of the rate (finite where the rate underflows).
    pub ln_rate: f64,
    /// The mean residence `1/k` \[s\] (`None` past f64).
    pub residence: Option<f64>,
    /// `log10` of the residence in seconds.
    pub log10_residence: f64,
    /// Transition-state theory's rate `k_TST` \[1/s\] (an upper bound).
    pub tst_rate: f64,
    /// `ln k_TST`.
    pub ln_tst_rate: f64,
    /// The strong-damping limit: `1/τ` of the Smoluchowski equation \[1/s\].
    pub overdamped_rate: f64,
    /// The weak-damping limit: Mel'nikov–Meshkov `A(δ) k_TST` \[1/s\].
    pub underdamped_rate: f64,
    /// `δ = γ I/kT`, the energy lost per orbit at `U(z_out)` in kT \[1\].
    pub energy_loss_kt: f64,
    /// The transmission count at `dt`.
    pub count: Count,
    /// The step check (`None` when not asked).
    pub step_check: Option<StepCheck>,
    /// Whether the step check found the rate converged in the step
    /// (`None`: not checked).
    pub dt_converged: Option<bool>,
}

/// What `U` and the geometry give, precomputed for the paths.
#[derive(Debug, Clone, Copy)]
struct Geometry {
    kt: f64,
    u0: f64,
    z0: f64,
    z_out: f64,
    z_lo: f64,
    e_cap: f64,
    omega: f64,
}

/// How a path ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum End {
    Captured,
    Returned,
    Censored,
}

impl Desorption {
    /// C60 on one graphene sheet ([`Adhesion::c60_on_graphene`]), its mass
    /// `mass` \[kg\], at `temperature` \[K\] with damping `damping` \[1/s\].
    pub fn c60_on_graphene(mass: f64, temperature: f64, damping: f64) -> Desorption {
        Desorption {
            adhesion: Adhesion::c60_on_graphene(),
            mass,
            temperature,
            damping,
        }
    }

    fn kt(&self) -> f64 {
        BOLTZMANN * self.temperature
    }

    fn validate(&self) -> Result<(), Error> {
        let range = |key: &str, v: f64, lo: f64, hi: f64, unit: &str| {
            if v.is_finite() && v > lo && v <= hi {
                Ok(())
            } else {
                Err(Error::invalid(
                    key,
                    format!("{v:e} is not allowed"),
                    format!("above {lo:e} and at most {hi:e} {unit}"),
                ))
            }
        };
        range("temperature", self.temperature, 0.0, 1e4, "K")?;
        range("mass", self.mass, 1e-27, 1e-15, "kg")?;
        range("damping_translational", self.damping, 0.0, 1e17, "1/s")?;
        self.adhesion.validate()
    }

    fn geometry(&self) -> Result<Geometry, Error> {
        self.validate()?;
        let b = self.adhesion.binding()?;
        let kt = self.kt();
        let u = |z: f64| self.adhesion.energy(z);
        let u0 = -b.energy;
        if b.energy - kt < MIN_DEPTH_KT * kt {
            return Err(Error::invalid(
                "temperature",
                format!(
                    "{} K: the binding {:.4e} J is only {:.4} kT, not a well to desorb from",
                    self.temperature,
                    b.energy,
                    b.energy / kt
                ),
                format!(
                    "a temperature where the binding exceeds {} kT",
                    MIN_DEPTH_KT + 1.0
                ),
            ));
        }
        // U rises monotonically from U₀ at Z₀ towards 0 far out.
        let mut far = b.pull_off_height;
        while u(far) < -kt {
            far = b.height + 2.0 * (far - b.height);
        }
        let z_out = bisect(|z| u(z) + kt, b.height, far);
        // The repulsive side, where the density is e^{-60} of the bottom's.
        let r = self.adhesion.shell.radius;
        let mut near = b.height - 0.5 * (b.height - r);
        while u(near) - u0 < 60.0 * kt {
            near = r + 0.5 * (near - r);
        }
        let z_lo = bisect(|z| 60.0 * kt - (u(z) - u0), near, b.height);
        Ok(Geometry {
            kt,
            u0,
            z0: b.height,
            z_out,
            z_lo,
            e_cap: -kt - (0.5 * (-kt - u0)).min(CAPTURE_KT * kt),
            omega: (b.stiffness / self.mass).sqrt(),
        })
    }

    /// `ln k_TST` (module docs) by composite Gauss–Legendre over the well.
    fn ln_tst(&self, g: &Geometry) -> f64 {
        let shifted = |z: f64| (-(self.adhesion.energy(z) - g.u0) / g.kt).exp();
        let q = integrate(&shifted, g.z_lo, g.z_out, 4000);
        0.5 * (g.kt / (2.0 * PI * self.mass)).ln() - (-g.kt - g.u0) / g.kt - q.ln()
    }

    /// The Smoluchowski mean first-passage time from `Z₀` to `z_out` \[s\].
    fn overdamped_residence(&self, g: &Geometry) -> Result<f64, Error> {
        let (a, u0, kt) = (self.adhesion, g.u0, g.kt);
        let d = kt / (self.mass * self.damping);
        let diffusion = Diffusion::new(
            g.z_lo,
            g.z_out,
            move |z| -(a.energy(z) - u0) / kt,
            move |_| d,
        );
        Ok(diffusion.mean_exit_time(None, Some(g.z_out), g.z0)?.value)
    }

    /// `δ = γ I/kT`, `I = 2 ∫ sqrt(2m(E − U)) dZ` over the orbit at
    /// `E = U(z_out)`.
    fn energy_loss_kt(&self, g: &Geometry) -> f64 {
        let e = -g.kt;
        let u = |z: f64| self.adhesion.energy(z);
        let z_in = bisect(|z| e - u(z), g.z_lo, g.z0);
        let (a, b) = (z_in, g.z_out);
        // z = a + (b − a)(1 − cos t)/2: the square-root ends become smooth.
        let f = |t: f64| {
            let z = a + 0.5 * (b - a) * (1.0 - t.cos());
            (2.0 * self.mass * (e - u(z)).max(0.0)).sqrt() * 0.5 * (b - a) * t.sin()
        };
        let action = 2.0 * integrate(&f, 0.0, PI, 2000);
        self.damping * action / g.kt
    }

    /// The transmission count at step `dt` over `paths` paths of noise
    /// seed `seed`.
    fn count(
        &self,
        g: &Geometry,
        dt: f64,
        paths: usize,
        seed: u64,
        threads: Option<usize>,
    ) -> Result<Count, Error> {
        let budget = self.budget(g, dt);
        const CHUNK: usize = 256;
        let chunks = paths.div_ceil(CHUNK);
        let job = |c: usize| -> [u64; 4] {
            let mut t = [0u64; 4];
            for i in c * CHUNK..((c + 1) * CHUNK).min(paths) {
                let (end, steps) = self.path(g, dt, &Stream::new(seed, i as u64), budget);
                t[match end {
                    End::Captured => 0,
                    End::Returned => 1,
                    End::Censored => 2,
                }] += 1;
                t[3] += steps;
            }
            t
        };
        let mut total = [0u64; 4];
        run_ordered(0..chunks, threads, &job, &mut |t| {
            for k in 0..4 {
                total[k] += t[k];
            }
            true
        })?;
        let [captured, returned, censored, steps] = total;
        let n = paths;
        let lo = wilson(captured as usize, n, Z95).map_or(0.0, |w| w[0]);
        let hi = wilson((captured + censored) as usize, n, Z95).map_or(1.0, |w| w[1]);
        let ln_tst = self.ln_tst(g);
        let kappa = captured as f64 / n as f64;
        let tst = ln_tst.exp();
        Ok(Count {
            dt,
            paths: n as u64,
            captured,
            returned,
            censored,
            steps,
            transmission: kappa,
            transmission_ci95: [lo, hi],
            rate: kappa * tst,
            ci95: [lo * tst, hi * tst],
        })
    }

    /// A path's step budget: 60 damping times (under weak damping the
    /// energy relaxes as `e^{−γt}`: a captured path needs a few) plus 20
    /// times the diffusion time across the well, `(z_out − Z₀)²/D` with `D =
    /// kT/(mγ)` (under strong damping), at least 1e6 steps and at most 1e10.
    fn budget(&self, g: &Geometry, dt: f64) -> u64 {
        let l = g.z_out - g.z0;
        let diffusion = l * l * self.mass * self.damping / g.kt;
        ((60.0 / self.damping + 20.0 * diffusion) / dt).clamp(1e6, 1e10) as u64
    }

    /// One path from `z_out` inwards (module docs), BAOAB at `dt`.
    fn path(&self, g: &Geometry, dt: f64, noise: &Stream, budget: u64) -> (End, u64) {
        let m = self.mass;
        let c = (-self.damping * dt).exp();
        let kick = ((1.0 - c * c) * g.kt / m).sqrt();
        let force = |z: f64| -self.adhesion.energy_slope(z) / m;
        let mut z = g.z_out;
        let mut v = -(-2.0 * g.kt / m * noise.uniform(0, 0).ln()).sqrt();
        let mut f = force(z);
        let mut xi = [0.0; 2];
        let kin_cap = g.e_cap - g.u0;
        for k in 0..budget {
            if k % 2 == 0 {
                noise.normals(1 + k / 2, &mut xi);
            }
            v += 0.5 * dt * f;
            z += 0.5 * dt * v;
            v = c * v + kick * xi[(k % 2) as usize];
            z += 0.5 * dt * v;
            f = force(z);
            v += 0.5 * dt * f;
            if z >= g.z_out {
                return (End::Returned, k + 1);
            }
            let kinetic = 0.5 * m * v * v;
            if kinetic < kin_cap && self.adhesion.energy(z) + kinetic < g.e_cap {
                return (End::Captured, k + 1);
            }
        }
        (End::Censored, budget)
    }

    /// The desorption rate with its cross-checks and, with
    /// `sizes.step_check`, its step check. Errors: a parameter out of
    /// range, or a binding below [`MIN_DEPTH_KT`] + 1 kT (naming the key);
    /// `sizes` out of range.
    pub fn rate(&self, sizes: Sizes, threads: Option<usize>) -> Result<DesorptionRate, Error> {
        let g = self.geometry()?;
        if !(1..=MAX_PATHS).contains(&sizes.paths) {
            return Err(Error::invalid(
                "paths",
                format!("{} is not allowed", sizes.paths),
                format!("an integer from 1 to {MAX_PATHS}"),
            ));
        }
        let period = 2.0 * PI / g.omega;
        let dt = sizes.dt.unwrap_or(STEP_FRACTION * period);
        if !(dt.is_finite() && dt > 0.0 && dt <= 0.05 * period) {
            return Err(Error::invalid(
                "dt",
                format!("{dt:e} s is not allowed"),
                format!(
                    "above 0 and at most 1/20 of the well's period, {:.4e} s",
                    0.05 * period
                ),
            ));
        }
        let count = self.count(&g, dt, sizes.paths, sizes.seed, threads)?;
        let step_check = if sizes.step_check {
            let half = self.count(
                &g,
                0.5 * dt,
                sizes.paths,
                sizes.seed.wrapping_add(REFINED_SEED_OFFSET),
                threads,
            )?;
            let at = |c: &Count| AtStep {
                dt: c.dt,
                estimate: c.rate,
                ci95: c.ci95,
            };
            Some(StepCheck::new(at(&count), at(&half), Scale::Log))
        } else {
            None
        };
        let ln_tst = self.ln_tst(&g);
        let ln_rate = ln_tst + count.transmission.ln();
        let delta = self.energy_loss_kt(&g);
        let b = self.adhesion.binding()?;
        Ok(DesorptionRate {
            temperature: self.temperature,
            damping: self.damping,
            damping_over_frequency: self.damping / g.omega,
            mass: self.mass,
            well: Well {
                binding: b.energy,
                binding_kt: b.energy / g.kt,
                height: g.z0,
                exit_height: g.z_out,
                frequency: g.omega / (2.0 * PI),
                capture_energy: g.e_cap - g.u0,
            },
            rate: count.rate,
            ci95: count.ci95,
            ln_rate,
            residence: Some((-ln_rate).exp()).filter(|s| s.is_finite()),
            log10_residence: -ln_rate / std::f64::consts::LN_10,
            tst_rate: ln_tst.exp(),
            ln_tst_rate: ln_tst,
            overdamped_rate: 1.0 / self.overdamped_residence(&g)?,
            underdamped_rate: melnikov_meshkov(delta) * ln_tst.exp(),
            energy_loss_kt: delta,
            count,
            dt_converged: step_check.map(|c| c.converged),
            step_check,
        })
    }
}

impl Desorption {
    /// This molecule with its binding scaled to `binding` \[J\] (both
    /// Lennard-Jones constants times the same factor: the well's shape and
    /// height are kept, its depth and stiffness scale).
    pub fn with_binding(&self, binding: f64) -> Result<Desorption, Error> {
        let b = self.adhesion.binding()?;
        let f = binding / b.energy;
        let mut d = *self;
        d.adhesion.lj.a *= f;
        d.adhesion.lj.b *= f;
        d.validate()?;
        Ok(d)
    }

    /// `ln` of transition-state theory's residence `1/k_TST` \[ln s\], a
    /// lower bound on the mean residence (`κ <= 1`).
    pub fn ln_tst_residence(&self) -> Result<f64, Error> {
        let g = self.geometry()?;
        Ok(-self.ln_tst(&g))
    }

    /// The smallest binding \[J\] whose TST residence (a lower bound)
    /// reaches `seconds`: bisection to 1e-6 relative between
    /// ([`MIN_DEPTH_KT`] + 2) kT and 100 eV; `None` if even 100 eV does not
    /// (or if the smallest binding already does: `Some` of it).
    pub fn binding_for(&self, seconds: f64) -> Result<Option<f64>, Error> {
        let want = seconds.ln();
        let ev = crate::physics::adhesion::EV;
        let ln_tau = |e: f64| self.with_binding(e)?.ln_tst_residence();
        let (mut a, mut b) = ((MIN_DEPTH_KT + 2.0) * self.kt(), 100.0 * ev);
        if ln_tau(b)? < want {
            return Ok(None);
        }
        if ln_tau(a)? >= want {
            return Ok(Some(a));
        }
        while (b - a) > 1e-6 * b {
            let m = 0.5 * (a + b);
            if ln_tau(m)? < want {
                a = m;
            } else {
                b = m;
            }
        }
        Ok(Some(b))
    }
}

/// Mel'nikov & Meshkov's depopulation factor `A(δ)` (module docs), by the
/// substitution `x = tan(φ)/2`: `A = exp[(2/π) ∫₀^{π/2} ln(1 − e^{−δ/(4
/// cos²φ)}) dφ]`.
pub fn melnikov_meshkov(delta: f64) -> f64 {
    let f = |phi: f64| {
        let c = phi.cos();
        if c <= 0.0 {
            return 0.0;
        }
        let x = delta / (4.0 * c * c);
        (-(-x).exp_m1()).ln().min(0.0)
    };
    (2.0 / PI * integrate(&f, 0.0, 0.5 * PI, 2000)).exp()
}

/// `∫_a^b f` by `panels` panels of 8-point Gauss–Legendre.
fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let nodes = gauss_legendre(8);
    let h = (b - a) / panels as f64;
    (0..panels)
        .map(|p| {
            let mid = a + (p as f64 + 0.5) * h;
            nodes
                .iter()
                .map(|&(x, w)| w * f(mid + 0.5 * h * x))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// C60's mass \[kg\] (720 u).
    const M: f64 = 720.0 * 1.660_539_066_60e-27;

    #[test]
    fn melnikov_meshkov_limits() {
        // A → δ for small δ, → 1 for large δ, monotone in between.
        for d in [1e-4, 1e-3] {
            let a = melnikov_meshkov(d);
            assert!((a / d - 1.0).abs() < 0.05, "A({d}) = {a}");
        }
        assert!((melnikov_meshkov(50.0) - 1.0).abs() < 0.02);
        let mut last = 0.0;
        for d in [0.01, 0.1, 1.0, 3.0, 10.0] {
            let a = melnikov_meshkov(d);
            assert!(a > last && a < 1.0);
            last = a;
        }
    }

    #[test]
    fn tst_rate_is_the_harmonic_well_at_large_binding() {
        // ln k_TST → ln(ω₀/2π) − (U(z_out) − U₀)/kT as the well becomes
        // harmonic on the scale kT (low T): 1 % at 30 K.
        let d = Desorption::c60_on_graphene(M, 30.0, 1e12);
        let g = d.geometry().unwrap();
        let harmonic = (g.omega / (2.0 * PI)).ln() - (-g.kt - g.u0) / g.kt;
        assert!(
            (d.ln_tst(&g) - harmonic).abs() < 0.01,
            "{} {}",
            d.ln_tst(&g),
            harmonic
        );
    }

    fn no_check(paths: usize, dt: f64) -> Sizes {
        Sizes {
            paths,
            seed: 1,
            dt: Some(dt),
            step_check: false,
        }
    }

    #[test]
    fn strong_damping_tends_to_the_smoluchowski_answer() {
        // γ/ω₀ = 5.4: the exact mean first-passage time of the overdamped
        // equation, within the count's 95 % interval (inertial corrections
        // O(ω₀²/γ²) = 3 %, below the interval's ±8 %).
        let d = Desorption::c60_on_graphene(M, 300.0, 3e13);
        let r = d.rate(no_check(20_000, 1.4e-15), None).unwrap();
        assert!(r.damping_over_frequency > 5.0);
        let exact = r.overdamped_rate;
        assert!(
            r.ci95[0] <= exact && exact <= r.ci95[1],
            "{exact} outside {:?} (rate {})",
            r.ci95,
            r.rate
        );
        assert!(r.rate < r.tst_rate);
    }

    #[test]
    fn weak_damping_tends_to_melnikov_meshkov() {
        // γ/ω₀ = 0.002 at 77 K (E_b = 110 kT, δ = 3.8): Mel'nikov–Meshkov's
        // rate within the count's 95 % half-width on the log scale plus the
        // theory's own leading correction, (kT/E_b) ln(E_b/kT) = 4.3 %
        // (Mel'nikov, Phys. Rev. E 48, 3271 (1993)).
        let d = Desorption::c60_on_graphene(M, 77.0, 1e10);
        let r = d.rate(no_check(2_000, 2.8e-15), None).unwrap();
        assert!(r.damping_over_frequency < 0.01);
        let e = r.well.binding_kt;
        let theory = (1.0 / e) * e.ln();
        let half = 0.5 * (r.ci95[1] / r.ci95[0]).ln();
        let off = (r.rate / r.underdamped_rate).ln().abs();
        assert!(
            off < half + theory,
            "off {off}, half-width {half}, theory {theory}"
        );
        // Below TST by the factor A(δ), not at it.
        assert!(r.rate < 0.9 * r.tst_rate);
    }

    #[test]
    fn the_binding_for_ten_years_gives_ten_years() {
        let d = Desorption::c60_on_graphene(M, 300.0, 2.2e12);
        let ten = 10.0 * 365.25 * 86400.0;
        let e = d.binding_for(ten).unwrap().unwrap();
        let at = d.with_binding(e).unwrap().ln_tst_residence().unwrap();
        assert!((at - ten.ln()).abs() < 1e-4, "{at} vs {}", ten.ln());
        // The harmonic estimate kT ln(ν τ) (ν = ω₀/2π at that binding,
        // the -kT of z_out): within 0.05 eV.
        let g = d.with_binding(e).unwrap().geometry().unwrap();
        let rough = g.kt * ((g.omega / (2.0 * PI)) * ten).ln() + g.kt;
        assert!(
            (e - rough).abs() < 0.05 * crate::physics::adhesion::EV,
            "{e} vs {rough}"
        );
    }

    #[test]
    fn a_shallow_well_is_refused_naming_the_temperature() {
        let e = Desorption::c60_on_graphene(M, 3000.0, 1e12)
            .rate(Sizes::default(), Some(1))
            .unwrap_err();
        assert!(e.to_string().contains("temperature"), "{e}");
    }
}
