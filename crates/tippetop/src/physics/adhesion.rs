//! Van der Waals adhesion of a fullerene shell on graphene or graphite, in
//! the continuum Lennard-Jones approximation (Girifalco's "smeared atoms"):
//! the binding energy E_b, the equilibrium height, the pull-off force F_a
//! and the normal stiffness. These set the load that presses a C60 onto the
//! surface, about 5e13 times the weight the paper uses (docs/physics.md#adhesion-c60).
//!
//! # Model
//!
//! Two carbon atoms at distance r interact by `Φ(r) = −A/r⁶ + B/r¹²`. Smear
//! the `N` atoms of the shell uniformly over a sphere of radius `R`
//! (density `η_s = N/(4πR²)`) and the substrate's atoms over planes of
//! density `η_g` (graphene: 2 atoms per hexagonal cell of bond length
//! 1.42 Å, `η_g = 0.3818 Å⁻²`), spaced `d` apart (graphite: 3.35 Å).
//!
//! - A point at height `h` above one plane:
//!   `∫₀^∞ 2πρ Φ(√(ρ² + h²)) η_g dρ = π η_g (−A/(2h⁴) + B/(5h¹⁰))`.
//! - The shell with its centre at height `Z`: the points at polar angle α
//!   are at `h = Z + R cos α`, area `2πR² sin α dα`; with `dh = −R sin α dα`,
//!   `U₁(Z) = 2π R η_s ∫_{Z−R}^{Z+R} π η_g (−A/(2h⁴) + B/(5h¹⁰)) dh`, i.e.
//!   `U₁(Z) = K [−(A/6)(a⁻³ − b⁻³) + (B/45)(a⁻⁹ − b⁻⁹)]`,
//!   `K = π N η_g/(2R)`, `a = Z − R` (the gap), `b = Z + R`.
//! - `n` layers: `U(Z) = Σ_{k<n} U₁(Z + k d)`.
//!
//! From `U`: the equilibrium height `Z₀` (`U′ = 0`), the binding energy
//! `E_b = −U(Z₀)`, the pull-off force `F_a = max_{Z>Z₀} U′(Z)` (the largest
//! restoring force a pull must overcome, at the inflection `U″ = 0`), and
//! the normal stiffness `k = U″(Z₀)`. Derivatives are the closed forms;
//! the tests check `U` against direct quadrature and `U′`, `U″` against
//! finite differences.
//!
//! # Constants and what is verified
//!
//! See [`LjConstants`]: the default carbon–carbon constants for C60 on
//! graphene are those the Wollongong group (the paper's authors) and
//! Girifalco, Hodak & Lee (2000) use, obtained by mixing rules; the
//! numbers themselves could not be checked against the source here. What
//! is checked: the continuum result lies within the spread of published
//! binding energies (0.76 eV DFT on a graphene flake, 0.96 eV linear-response
//! vdW theory on graphite; docs/physics.md#adhesion-c60).

use crate::Error;

/// 1 eV \[J\].
pub const EV: f64 = 1.602_176_634e-19;
/// 1 Å \[m\].
pub const ANGSTROM: f64 = 1e-10;

/// The carbon–carbon Lennard-Jones constants `Φ(r) = −A/r⁶ + B/r¹²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LjConstants {
    /// Attraction `A` \[J m⁶\].
    pub a: f64,
    /// Repulsion `B` \[J m¹²\].
    pub b: f64,
}

impl LjConstants {
    /// C60–graphene: `A = 17.4 eV Å⁶`, `B = 29.0e3 eV Å¹²`, from the
    /// C60–C60 and graphene–graphene constants by the mixing rules of
    /// Girifalco, Hodak & Lee, Phys. Rev. B 62, 13104 (2000). Status: the
    /// paper's abstract (mixing rules, universal curve) is verified; these
    /// two numbers are quoted, not checked against its tables.
    pub const C60_GRAPHENE: LjConstants = LjConstants {
        a: 17.4 * EV * 1e-60,
        b: 29.0e3 * EV * 1e-120,
    };

    /// The same pair from a public parameter file ("Girifalco, from Lu et
    /// al."): `C6 = 18.54 eV Å⁶`, `C12 = 29000 eV Å¹²` (verified as printed
    /// there; its provenance is not).
    pub const C60_GRAPHENE_LU: LjConstants = LjConstants {
        a: 18.54 * EV * 1e-60,
        b: 29.0e3 * EV * 1e-120,
    };

    /// The length `σ = (B/A)^(1/6)` where `Φ = 0` \[m\].
    pub fn sigma(&self) -> f64 {
        (self.b / self.a).powf(1.0 / 6.0)
    }
}

/// A spherical shell of atoms (a fullerene cage).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shell {
    /// Radius `R` of the cage (atom centres) \[m\].
    pub radius: f64,
    /// Number of atoms `N`.
    pub atoms: f64,
}

impl Shell {
    /// C60: `R = 3.55 Å` (the paper's radius), 60 atoms.
    pub const C60: Shell = Shell {
        radius: 3.55 * ANGSTROM,
        atoms: 60.0,
    };
}

/// A stack of flat atomic layers under the shell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Substrate {
    /// Atoms per unit area of one layer `η_g` \[1/m²\].
    pub density: f64,
    /// Number of layers (1: graphene).
    pub layers: u32,
    /// Distance between layers `d` \[m\].
    pub spacing: f64,
}

impl Substrate {
    /// Atoms per area of graphene: 2 per hexagonal cell of area
    /// `(3√3/2) a_CC²` with the C–C bond `a_CC = 1.42 Å` \[1/m²\].
    pub fn graphene_density() -> f64 {
        let a_cc = 1.42 * ANGSTROM;
        2.0 / (1.5 * 3f64.sqrt() * a_cc * a_cc)
    }

    /// One graphene sheet.
    pub fn graphene() -> Substrate {
        Substrate {
            density: Self::graphene_density(),
            layers: 1,
            spacing: 3.35 * ANGSTROM,
        }
    }

    /// Graphite as `layers` graphene sheets 3.35 Å apart (30 layers reach
    /// the bulk value to better than 1e-4 relative: the k-th layer adds
    /// ~k⁻³).
    pub fn graphite(layers: u32) -> Substrate {
        Substrate {
            layers,
            ..Self::graphene()
        }
    }
}

/// The interaction of a shell with a substrate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Adhesion {
    /// The shell.
    pub shell: Shell,
    /// The substrate.
    pub substrate: Substrate,
    /// The carbon–carbon constants.
    pub lj: LjConstants,
}

/// What [`Adhesion::binding`] derives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Binding {
    /// Equilibrium height of the shell's centre above the top layer \[m\].
    pub height: f64,
    /// Gap between the cage and the top layer at equilibrium, height − R \[m\].
    pub gap: f64,
    /// Binding energy `E_b = −U(Z₀)` \[J\].
    pub energy: f64,
    /// Pull-off force `F_a`: the largest attraction on the way out \[N\].
    pub pull_off_force: f64,
    /// Height where the attraction is largest \[m\].
    pub pull_off_height: f64,
    /// Normal stiffness `U″(Z₀)` \[N/m\].
    pub stiffness: f64,
}

impl Adhesion {
    /// C60 on graphene with the default constants.
    pub fn c60_on_graphene() -> Adhesion {
        Adhesion {
            shell: Shell::C60,
            substrate: Substrate::graphene(),
            lj: LjConstants::C60_GRAPHENE,
        }
    }

    /// Check that every parameter lies in its range (below); the error
    /// names the parameter. The ranges keep the continuum integrals within
    /// floating point and the model within its meaning: a cage of atomic to
    /// sub-micron size, carbon-like constants to three decades either side
    /// (`A` = 17.4 eV Å⁶, `B` = 29e3 eV Å¹² for C60 on graphene), sheets of
    /// atomic density and spacing.
    pub fn validate(&self) -> Result<(), Error> {
        let ev6 = EV * 1e-60;
        let ev12 = EV * 1e-120;
        let si = |unit: &str, lo: f64, hi: f64| format!("{lo:.4e} to {hi:.4e} {unit}");
        let checks = [
            (
                "radius",
                self.shell.radius,
                1e-10,
                1e-6,
                si("m", 1e-10, 1e-6),
            ),
            (
                "atoms",
                self.shell.atoms,
                1.0,
                1e8,
                "1 to 1e8 atoms".to_string(),
            ),
            (
                "density",
                self.substrate.density,
                1e17,
                1e21,
                si("atoms/m^2", 1e17, 1e21),
            ),
            (
                "spacing",
                self.substrate.spacing,
                1e-10,
                1e-8,
                si("m", 1e-10, 1e-8),
            ),
            (
                "lj_a",
                self.lj.a,
                1e-2 * ev6,
                1e4 * ev6,
                format!(
                    "1e-2 to 1e4 eV Å^6 = {}",
                    si("J m^6", 1e-2 * ev6, 1e4 * ev6)
                ),
            ),
            (
                "lj_b",
                self.lj.b,
                ev12,
                1e8 * ev12,
                format!("1 to 1e8 eV Å^12 = {}", si("J m^12", ev12, 1e8 * ev12)),
            ),
        ];
        for (key, v, lo, hi, range) in checks {
            if !(lo..=hi).contains(&v) {
                return Err(Error::invalid(key, format!("{v:e} is not allowed"), range));
            }
        }
        if !(1..=100_000).contains(&self.substrate.layers) {
            return Err(Error::invalid(
                "layers",
                format!("{} is not allowed", self.substrate.layers),
                "an integer from 1 to 100000".into(),
            ));
        }
        Ok(())
    }

    fn k(&self) -> f64 {
        std::f64::consts::PI * self.shell.atoms * self.substrate.density / (2.0 * self.shell.radius)
    }

    /// Sum of `f(a, b)` over the layers, `a`, `b` the near and far distances
    /// of the shell from each layer.
    fn over_layers(&self, z: f64, f: impl Fn(f64, f64) -> f64) -> f64 {
        let r = self.shell.radius;
        (0..self.substrate.layers)
            .map(|k| {
                let zk = z + k as f64 * self.substrate.spacing;
                f(zk - r, zk + r)
            })
            .sum()
    }

    /// Interaction energy `U(Z)` with the shell's centre at height `z` above
    /// the top layer \[J\]; `z > R`.
    pub fn energy(&self, z: f64) -> f64 {
        let (a6, b45) = (self.lj.a / 6.0, self.lj.b / 45.0);
        self.k()
            * self.over_layers(z, |a, b| {
                -a6 * (a.powi(-3) - b.powi(-3)) + b45 * (a.powi(-9) - b.powi(-9))
            })
    }

    /// `dU/dZ` \[N\]: positive where the substrate attracts the shell (the
    /// force on the shell is `−dU/dZ`).
    pub fn energy_slope(&self, z: f64) -> f64 {
        let (a2, b5) = (self.lj.a / 2.0, self.lj.b / 5.0);
        self.k()
            * self.over_layers(z, |a, b| {
                a2 * (a.powi(-4) - b.powi(-4)) - b5 * (a.powi(-10) - b.powi(-10))
            })
    }

    /// `d²U/dZ²` \[N/m\].
    pub fn energy_curvature(&self, z: f64) -> f64 {
        let (a2, b2) = (2.0 * self.lj.a, 2.0 * self.lj.b);
        self.k()
            * self.over_layers(z, |a, b| {
                -a2 * (a.powi(-5) - b.powi(-5)) + b2 * (a.powi(-11) - b.powi(-11))
            })
    }

    /// Equilibrium, binding energy, pull-off force and stiffness.
    pub fn binding(&self) -> Result<Binding, Error> {
        self.validate()?;
        let r = self.shell.radius;
        let s = self.lj.sigma();
        // U′ < 0 (repulsion) at a gap of 0.3 σ: there (B/5) a⁻¹⁰ exceeds
        // (A/2) a⁻⁴ by (0.3)⁻⁶ 2/5 = 549 times, far more than all other
        // layers add; U′ > 0 far out (attraction decays like a⁻⁴).
        let lo = r + 0.3 * s;
        let mut hi = r + 2.0 * s;
        while self.energy_slope(hi) <= 0.0 {
            hi = r + 2.0 * (hi - r);
            if hi - r > 1e6 * s {
                return Err(no_well());
            }
        }
        let height = bisect(|z| self.energy_slope(z), lo, hi);
        // The attraction U′ rises from 0 at Z₀ to its maximum at the
        // inflection U″ = 0, then decays: U″ > 0 at Z₀, < 0 far out.
        let mut far = height + s;
        while self.energy_curvature(far) >= 0.0 {
            far = height + 2.0 * (far - height);
            if far - height > 1e6 * s {
                return Err(no_well());
            }
        }
        let pull_off_height = bisect(|z| -self.energy_curvature(z), height, far);
        let b = Binding {
            height,
            gap: height - r,
            energy: -self.energy(height),
            pull_off_force: self.energy_slope(pull_off_height),
            pull_off_height,
            stiffness: self.energy_curvature(height),
        };
        let finite = [
            b.height,
            b.energy,
            b.pull_off_force,
            b.pull_off_height,
            b.stiffness,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !finite || b.energy <= 0.0 || b.pull_off_force <= 0.0 || b.stiffness <= 0.0 {
            return Err(no_well());
        }
        Ok(b)
    }
}

fn no_well() -> Error {
    Error::invalid(
        "lj_a",
        "no attractive well with a finite binding energy, pull-off force and stiffness for these parameters".into(),
        "A and B of an attractive Lennard-Jones pair, with the other parameters in range".into(),
    )
}

/// Root of `f` in `[lo, hi]` with `f(lo) < 0 < f(hi)`, by bisection to the
/// last bit (at most ~1100 halvings of an f64 interval; ~60 here).
pub(crate) fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    // 2200 halvings exhaust any finite f64 interval; the cap guards NaN.
    for _ in 0..2200 {
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            return mid;
        }
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Nodes and weights of n-point Gauss–Legendre on [−1, 1] (Newton on
/// the Legendre recurrence from Tricomi's initial guess; the last iterate
/// after 100 steps if the 1e-15 step criterion is never met).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for iteration in 0.. {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 || iteration == 100 {
                    let w = 2.0 / ((1.0 - x * x) * dp * dp);
                    return (x, w);
                }
            }
            unreachable!("the loop returns by its 100th iteration")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `U(Z)` by direct quadrature, independent of the closed form: the
    /// point–plane potential integrated over the plane (radial quadrature
    /// after `ρ = h tan φ`), then over the shell (Gauss–Legendre in cos α).
    fn energy_by_quadrature(ad: &Adhesion, z: f64) -> f64 {
        let gl = gauss_legendre(400);
        let lj = ad.lj;
        let point_plane = |h: f64| {
            // ∫₀^∞ 2πρ Φ(√(ρ²+h²)) dρ with ρ = h tan φ, φ ∈ [0, π/2).
            let mut s = 0.0;
            for &(x, w) in &gl {
                let phi = 0.25 * std::f64::consts::PI * (x + 1.0);
                let (sp, cp) = phi.sin_cos();
                let rho = h * sp / cp;
                let r2 = rho * rho + h * h;
                let phi_r = -lj.a / r2.powi(3) + lj.b / r2.powi(6);
                let jac = h / (cp * cp);
                s += w
                    * 0.25
                    * std::f64::consts::PI
                    * 2.0
                    * std::f64::consts::PI
                    * rho
                    * phi_r
                    * jac;
            }
            s * ad.substrate.density
        };
        let r = ad.shell.radius;
        let eta_s = ad.shell.atoms / (4.0 * std::f64::consts::PI * r * r);
        let mut total = 0.0;
        for k in 0..ad.substrate.layers {
            let zk = z + k as f64 * ad.substrate.spacing;
            for &(c, w) in &gl {
                // c = cos α; area element 2π R² d(cos α).
                total += w * 2.0 * std::f64::consts::PI * r * r * eta_s * point_plane(zk + r * c);
            }
        }
        total
    }

    #[test]
    fn closed_form_matches_quadrature() {
        for ad in [
            Adhesion::c60_on_graphene(),
            Adhesion {
                substrate: Substrate::graphite(3),
                ..Adhesion::c60_on_graphene()
            },
        ] {
            for z in [6.0, 6.5, 7.5, 10.0] {
                let z = z * ANGSTROM;
                let (u, q) = (ad.energy(z), energy_by_quadrature(&ad, z));
                assert!((u - q).abs() <= 1e-9 * q.abs(), "Z = {z:e}: {u:e} vs {q:e}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let ad = Adhesion {
            substrate: Substrate::graphite(4),
            ..Adhesion::c60_on_graphene()
        };
        for z in [6.2, 6.5, 7.0, 9.0] {
            let z = z * ANGSTROM;
            let h = 1e-4 * ANGSTROM;
            let d1 = (ad.energy(z + h) - ad.energy(z - h)) / (2.0 * h);
            let d2 = (ad.energy_slope(z + h) - ad.energy_slope(z - h)) / (2.0 * h);
            // Central differences: error ~ h² U‴/6, relative ~1e-9 here.
            assert!(
                (ad.energy_slope(z) - d1).abs() <= 1e-6 * d1.abs().max(1e-12),
                "{z:e}"
            );
            assert!(
                (ad.energy_curvature(z) - d2).abs() <= 1e-6 * d2.abs().max(1e-3),
                "{z:e}"
            );
        }
    }

    #[test]
    fn binding_is_a_minimum_and_pull_off_the_largest_attraction() {
        let ad = Adhesion::c60_on_graphene();
        let b = ad.binding().unwrap();
        assert!(ad.energy_slope(b.height).abs() <= 1e-6 * b.pull_off_force);
        assert!(b.stiffness > 0.0);
        for dz in [-0.05, 0.05, 0.5] {
            assert!(ad.energy(b.height + dz * ANGSTROM) > -b.energy);
        }
        // No height beyond Z₀ pulls harder than F_a; a grid of 0.0005 Å
        // finds the maximum to ~(0.00025 Å)² |U‴|/(2 U′) ~ 1e-7 relative.
        assert!(b.pull_off_height - b.height < 1.0 * ANGSTROM);
        let f_max = (1..2000)
            .map(|i| ad.energy_slope(b.height + i as f64 * 0.0005 * ANGSTROM))
            .fold(0.0, f64::max);
        assert!(f_max <= b.pull_off_force * (1.0 + 1e-12));
        assert!(f_max >= b.pull_off_force * (1.0 - 1e-6));
    }

    /// Far from the substrate the shell acts like N atoms at its centre:
    /// U → N π η_g (−A/(2Z⁴)) (the point–plane law), the test of `K`.
    #[test]
    fn far_field_is_n_atoms_at_the_centre() {
        let ad = Adhesion::c60_on_graphene();
        let z = 2000.0 * ANGSTROM;
        let point = ad.shell.atoms
            * std::f64::consts::PI
            * ad.substrate.density
            * (-ad.lj.a / (2.0 * z.powi(4)));
        // (Z − R)⁻³ − (Z + R)⁻³ = 6 R Z⁻⁴ (1 + (10/3)(R/Z)² + O((R/Z)⁴)):
        // with R/Z = 1.8e-3 the next term is ~7e-11 (and the repulsion
        // ~Z⁻¹⁰ nothing).
        let rz = ad.shell.radius / z;
        let expected = 1.0 + 10.0 / 3.0 * rz * rz;
        assert!((ad.energy(z) / point - expected).abs() < 1e-9);
    }

    /// Bad parameters name themselves.
    #[test]
    fn validation_names_the_parameter() {
        let mut ad = Adhesion::c60_on_graphene();
        ad.substrate.layers = 0;
        assert!(
            ad.binding()
                .unwrap_err()
                .to_string()
                .starts_with("layers: ")
        );
        let mut ad = Adhesion::c60_on_graphene();
        ad.lj.a = f64::NAN;
        assert!(ad.binding().unwrap_err().to_string().starts_with("lj_a: "));
    }
}
