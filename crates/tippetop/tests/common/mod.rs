//! Scenarios shared by several test files.

use tippetop::{FrictionLaw, Scenario, Top};

/// A uniform sphere (a = 0, A = C = 2/5 m R², the classical preset's R and
/// m) with its axis tilted by `theta`, spinning at `spin` about it, on a
/// plane with friction `mu` under the exact Coulomb law; 0.4 s, 401 samples.
pub fn uniform_sphere(theta: f64, spin: f64, mu: f64) -> Scenario {
    let mut sc = Scenario::classical();
    let (m, r) = (sc.top.mass, sc.top.radius);
    sc.top = Top {
        radius: r,
        offset: 0.0,
        mass: m,
        inertia_transverse: 0.4 * m * r * r,
        inertia_axial: 0.4 * m * r * r,
    };
    sc.surface.friction = mu;
    sc.surface.law = FrictionLaw::Coulomb;
    sc.initial.theta = theta;
    sc.initial.spin = spin;
    sc.solver.t_end = 0.4;
    sc.solver.samples = 401;
    sc
}
