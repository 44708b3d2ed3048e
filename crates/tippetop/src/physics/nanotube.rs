//! A fullerene cage inside an infinitely long single-walled carbon nanotube,
//! in the continuum Lennard-Jones approximation of [`super::adhesion`]
//! (the same constants, the same cage as a shell of atoms, the tube's wall a
//! cylinder of carbon at graphene's surface density): the energy against the
//! cage centre's distance `p` from the axis, the equilibrium (on the axis or
//! off it), the binding energy, the radial stiffness, the pull-off force
//! away from the wall, the suction energy, and the tube radius at which the
//! cage leaves the axis (docs/physics.md#nanotube).
//!
//! # Model
//!
//! Carbon atoms interact by `Φ(r) = −A/r⁶ + B/r¹²`. The tube of radius `b`
//! (axis `z`) carries `η_g` atoms per area; the cage of radius `R` carries
//! `N` atoms smeared over its sphere.
//!
//! - **Axial integral (analytic).** A point at distance `s` from one line of
//!   the wall (a generator of the cylinder) meets along it
//!   `∫ (s² + z²)^(−n) dz = √π Γ(n − ½)/Γ(n) s^(1−2n)`, so a line of unit
//!   density contributes `L(s) = −(3π/8) A s⁻⁵ + (63π/256) B s⁻¹¹`.
//! - **Around the wall (quadrature).** A point at distance `δ` from the axis
//!   has the potential `V(δ) = 2 η_g b ∫₀^π L(s(t)) dt`,
//!   `s² = b² + δ² − 2bδ cos t`, by Gauss–Legendre on panels graded towards
//!   `t = 0` (the nearest line; the first panel is `0.2 σ/b` wide, each next
//!   one three times wider; the same panels for every `δ`).
//! - **Over the cage (quadrature).** The cage's atoms at polar angle `α`
//!   (from the tube's axis) and azimuth `ψ` project to the distance
//!   `δ² = p² + ρ² + 2pρ cos ψ`, `ρ = R sin α`, so
//!   `U(p) = (N/π) ∫₀^{π/2} sin α dα ∫₀^π V(δ) dψ` (both halves of the cage
//!   and both sides of the plane through the offset are equal).
//!
//! `U′(p)`, `U″(p)` are the same quadratures of the derivatives taken under
//! the integral sign (chain rule through `δ(p)` and `s(δ)`), so the three
//! agree to rounding with finite differences of the quadrature of `U`. The
//! tests check `V` and `U` against direct quadrature over the wall (angle
//! and axial position) of the pair and the cage–atom potentials, and the
//! large-radius limit against the flat sheet.

use std::f64::consts::PI;
use std::sync::OnceLock;

use super::adhesion::{ANGSTROM, Adhesion, LjConstants, Shell, Substrate, bisect, gauss_legendre};
use crate::Error;

/// The C–C bond length of the tube's wall, `a_CC = 1.42 Å` \[m\].
pub const A_CC: f64 = 1.42 * ANGSTROM;

/// Radius of the `(n, m)` tube, `b = a_CC √(3(n² + nm + m²))/(2π)` \[m\].
pub fn chirality_radius(n: u32, m: u32) -> f64 {
    let (n, m) = (n as f64, m as f64);
    A_CC * (3.0 * (n * n + n * m + m * m)).sqrt() / (2.0 * PI)
}

/// Gauss–Legendre orders: over the wall (per panel), over the cage's polar
/// angle and azimuth. Chosen so that doubling each changes `U` by less than
/// 1e-10 relative over the tubes of the table (docs/physics.md#nanotube).
const N_WALL: usize = 20;
const N_POLAR: usize = 40;
const N_AZIMUTH: usize = 56;

fn nodes(n: usize) -> &'static [(f64, f64)] {
    static WALL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    static POLAR: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    static AZIMUTH: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let cell = match n {
        N_WALL => &WALL,
        N_POLAR => &POLAR,
        _ => &AZIMUTH,
    };
    cell.get_or_init(|| gauss_legendre(n))
}

/// A shell (cage) inside a single-walled tube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nanotube {
    /// The cage.
    pub shell: Shell,
    /// Radius `b` of the tube's wall (atom centres) \[m\].
    pub radius: f64,
    /// Atoms per area of the wall `η_g` \[1/m²\] (graphene's).
    pub density: f64,
    /// The carbon–carbon constants.
    pub lj: LjConstants,
}

/// What [`Nanotube::binding`] derives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeBinding {
    /// Distance of the cage's centre from the axis at equilibrium \[m\]
    /// (0.0 on the axis).
    pub offset: f64,
    /// Whether the equilibrium is on the axis.
    pub on_axis: bool,
    /// Distance of the centre from the wall, `b − offset` \[m\].
    pub wall_distance: f64,
    /// Gap between the cage and the nearest wall, `b − offset − R` \[m\].
    pub gap: f64,
    /// Binding energy `−U(offset)` \[J\].
    pub energy: f64,
    /// Radial stiffness `U″(offset)` \[N/m\].
    pub stiffness: f64,
    /// Off the axis: the largest force pulling the cage back to the wall
    /// when it is pulled towards the axis, `max −U′` over `[0, offset]` \[N\];
    /// `None` on the axis.
    pub pull_off_force: Option<f64>,
    /// Off the axis: the centre's distance from the wall where that force
    /// is largest (`U″ = 0`) \[m\]; `None` on the axis.
    pub pull_off_wall_distance: Option<f64>,
    /// Suction energy: the energy the cage gains entering along the axis
    /// from free space, `−U(0)` \[J\] (Cox, Thamwattana & Hill's definition).
    pub suction_energy: f64,
    /// `U″(0)`: positive where the axis is stable \[N/m\].
    pub axis_curvature: f64,
}

impl Nanotube {
    /// C60 in a tube of radius `radius` \[m\] with graphene's density and
    /// the C60–graphene constants of [`LjConstants::C60_GRAPHENE`].
    pub fn c60_in(radius: f64) -> Nanotube {
        Nanotube {
            shell: Shell::C60,
            radius,
            density: Substrate::graphene_density(),
            lj: LjConstants::C60_GRAPHENE,
        }
    }

    /// The flat graphene sheet with the same cage, density and constants:
    /// the limit of a wide tube.
    pub fn sheet(&self) -> Adhesion {
        Adhesion {
            shell: self.shell,
            substrate: Substrate {
                density: self.density,
                ..Substrate::graphene()
            },
            lj: self.lj,
        }
    }

    /// The smallest tube radius accepted, `R + gap` with the sheet's
    /// equilibrium gap \[m\].
    pub fn min_radius(&self) -> Result<f64, Error> {
        Ok(self.shell.radius + self.sheet().binding()?.gap)
    }

    /// Check the parameters: those of the sheet ([`Adhesion::validate`]),
    /// and `R + gap < b ≤ 1e-6 m` (`tube_radius`).
    pub fn validate(&self) -> Result<(), Error> {
        let min = self.min_radius()?;
        if !(self.radius > min && self.radius <= 1e-6) {
            return Err(Error::invalid(
                "tube_radius",
                if self.radius > min && self.radius.is_finite() {
                    format!("{:e} m: too wide", self.radius)
                } else {
                    format!(
                        "{:e} m: too narrow, it leaves the cage less than the sheet's \
                         equilibrium gap {:.4e} m",
                        self.radius,
                        min - self.shell.radius
                    )
                },
                format!("above R + gap = {min:.4e} m, up to 1e-6 m"),
            ));
        }
        Ok(())
    }

    /// The potential of one atom at distance `delta` from the axis, and its
    /// first two derivatives in `delta`: `[V (J), V′ (N), V″ (N/m)]`.
    /// `0 ≤ delta < b`.
    pub fn point_potential(&self, delta: f64) -> [f64; 3] {
        let b = self.radius;
        let (ca, cb) = (3.0 * PI / 8.0 * self.lj.a, 63.0 * PI / 256.0 * self.lj.b);
        // The same panels for every δ (so U(p) is one smooth rule): the first
        // is 0.2 σ/b wide, a fifth of the narrowest peak (the cage's atoms
        // come no nearer the wall than ~σ at the energies that matter).
        let w0 = (0.2 * self.lj.sigma() / b).clamp(1e-9, PI);
        let gl = nodes(N_WALL);
        let mut acc = [0.0; 3];
        let mut lo = 0.0;
        let mut width = w0;
        while lo < PI {
            let hi = (lo + width).min(PI);
            let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            for &(x, w) in gl {
                let t = c + h * x;
                let s2 = b * b + delta * delta - 2.0 * b * delta * t.cos();
                let s = s2.sqrt();
                let (i5, i11) = (s2.powi(-3) * s, s2.powi(-6) * s);
                // L, L′, L″ of the line potential.
                let l0 = -ca * i5 + cb * i11;
                let l1 = (5.0 * ca * i5 - 11.0 * cb * i11) / s;
                let l2 = (-30.0 * ca * i5 + 132.0 * cb * i11) / s2;
                let sd = (delta - b * t.cos()) / s;
                let sdd = (1.0 - sd * sd) / s;
                acc[0] += w * h * l0;
                acc[1] += w * h * l1 * sd;
                acc[2] += w * h * (l2 * sd * sd + l1 * sdd);
            }
            lo = hi;
            width *= 3.0;
        }
        let k = 2.0 * self.density * b;
        acc.map(|v| k * v)
    }

    /// `[U, U′, U″]`, the energy of the cage with its centre `p` from the
    /// axis and its derivatives in `p`: \[J\], \[N\], \[N/m\]; `U′ > 0` where
    /// the energy rises outwards. `0 ≤ p < b − R`.
    pub fn energy_derivatives(&self, p: f64) -> [f64; 3] {
        let r = self.shell.radius;
        let (ga, gp) = (nodes(N_POLAR), nodes(N_AZIMUTH));
        let mut acc = [0.0; 3];
        for &(xa, wa) in ga {
            let alpha = 0.25 * PI * (xa + 1.0);
            let rho = r * alpha.sin();
            let mut ring = [0.0; 3];
            for &(xp, wp) in gp {
                let psi = 0.5 * PI * (xp + 1.0);
                let d2 = p * p + rho * rho + 2.0 * p * rho * psi.cos();
                let d = d2.sqrt();
                let [v0, v1, v2] = self.point_potential(d);
                let dp = (p + rho * psi.cos()) / d;
                let dpp = (1.0 - dp * dp) / d;
                ring[0] += wp * v0;
                ring[1] += wp * v1 * dp;
                ring[2] += wp * (v2 * dp * dp + v1 * dpp);
            }
            for k in 0..3 {
                acc[k] += wa * alpha.sin() * ring[k];
            }
        }
        // (N/π) (π/4) (π/2) from the two half-ranges' Jacobians.
        let k = self.shell.atoms / PI * (0.25 * PI) * (0.5 * PI);
        acc.map(|v| k * v)
    }

    /// The energy `U(p)` \[J\] with the cage's centre `p` from the axis.
    pub fn energy(&self, p: f64) -> f64 {
        self.energy_derivatives(p)[0]
    }

    /// Equilibrium, binding, stiffness, pull-off and suction.
    pub fn binding(&self) -> Result<TubeBinding, Error> {
        self.validate()?;
        let (b, r) = (self.radius, self.shell.radius);
        let sigma = self.lj.sigma();
        let [u_axis, _, k_axis] = self.energy_derivatives(0.0);
        let slope = |p: f64| self.energy_derivatives(p)[1];
        // Off-axis well: U′ > 0 at a gap of 0.3 σ (repulsion, as on the
        // sheet); walk inwards until U′ < 0 or the axis is reached.
        let p_wall = b - r - 0.3 * sigma;
        let mut off: Option<f64> = None;
        if p_wall > 0.0 && slope(p_wall) > 0.0 {
            // Next to the axis, U′ ≈ U″(0) p: negative where the axis is
            // unstable.
            let p_min = 1e-6 * b;
            let mut p_hi = p_wall;
            while p_hi > p_min {
                let p = (b - r - 1.25 * (b - r - p_hi)).max(p_min);
                if slope(p) < 0.0 {
                    off = Some(bisect(slope, p, p_hi));
                    break;
                }
                p_hi = p;
            }
        }
        let off = off.filter(|&p| self.energy(p) < u_axis || k_axis <= 0.0);
        let (offset, on_axis) = match off {
            Some(p) => (p, false),
            None => (0.0, true),
        };
        let [u0, _, k0] = self.energy_derivatives(offset);
        let (pull_off_force, pull_off_wall_distance) = if on_axis {
            (None, None)
        } else {
            // −U′ rises from 0 at the offset to its largest value where
            // U″ = 0 on the way to the axis (U″ > 0 at the offset).
            let curv = |p: f64| self.energy_derivatives(p)[2];
            let mut lo = 0.0;
            let mut step = 0.05 * offset;
            let mut p = offset;
            while p > 0.0 {
                p = (p - step).max(0.0);
                step *= 1.5;
                if curv(p) < 0.0 {
                    lo = p;
                    break;
                }
            }
            let pi = if curv(lo) < 0.0 {
                bisect(curv, lo, offset)
            } else {
                0.0
            };
            (Some(-slope(pi)), Some(b - pi))
        };
        let out = TubeBinding {
            offset,
            on_axis,
            wall_distance: b - offset,
            gap: b - offset - r,
            energy: -u0,
            stiffness: k0,
            pull_off_force,
            pull_off_wall_distance,
            suction_energy: -u_axis,
            axis_curvature: k_axis,
        };
        let finite = [out.energy, out.stiffness, out.suction_energy, out.gap]
            .iter()
            .all(|v| v.is_finite());
        if !finite || out.energy <= 0.0 || out.stiffness <= 0.0 || out.gap <= 0.0 {
            return Err(Error::invalid(
                "tube_radius",
                format!("{b:e} m gives no bound equilibrium for these parameters"),
                "a tube wide enough to hold the cage".into(),
            ));
        }
        Ok(out)
    }
}

/// The tube radius \[m\] at which the cage leaves the axis (`U″(0) = 0`),
/// for the cage, wall density and constants of `tube` (its radius is
/// ignored), by bisection to a relative 1e-9.
pub fn off_axis_radius(tube: &Nanotube) -> Result<f64, Error> {
    let at = |b: f64| Nanotube { radius: b, ..*tube };
    let lo0 = tube.min_radius()? * (1.0 + 1e-9);
    let curv = |b: f64| -at(b).energy_derivatives(0.0)[2];
    if curv(lo0) >= 0.0 {
        // Already off the axis at the narrowest accepted tube.
        return Ok(lo0);
    }
    let mut hi = lo0 + tube.lj.sigma();
    while curv(hi) < 0.0 {
        hi = lo0 + 2.0 * (hi - lo0);
        if hi > 1e-6 {
            return Err(Error::invalid(
                "tube_radius",
                "the cage stays on the axis in every tube up to 1e-6 m".into(),
                "constants for which a wide tube pulls the cage to its wall".into(),
            ));
        }
    }
    let mut lo = lo0;
    while (hi - lo) > 1e-9 * hi {
        let mid = 0.5 * (lo + hi);
        if curv(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// The narrowest tube radius \[m\] that takes the cage in from free space
/// along its axis (the suction energy `−U(0)` changes sign), for the cage,
/// wall density and constants of `tube` (its radius is ignored). Narrower
/// tubes push the cage out; this is below [`Nanotube::min_radius`], so the
/// command refuses those tubes anyway.
pub fn acceptance_radius(tube: &Nanotube) -> Result<f64, Error> {
    let at = |b: f64| Nanotube { radius: b, ..*tube };
    let hi = tube.min_radius()?;
    let r = tube.shell.radius;
    // On the axis with the wall 0.5 σ from the cage the repulsion wins
    // (as on the sheet at such a gap).
    let lo = r + 0.5 * tube.lj.sigma();
    let f = |b: f64| -at(b).energy(0.0);
    if !(f(lo) < 0.0 && f(hi) > 0.0) {
        return Err(Error::invalid(
            "tube_radius",
            "no sign change of the suction energy between R + 0.5 σ and R + gap".into(),
            "carbon-like constants".into(),
        ));
    }
    Ok(bisect(f, lo, hi))
}
