//! The unit system of the scaled models: one tolerance means the same for
//! the C60 top and the toy (docs/physics.md §8).

use crate::Scenario;

/// Units of the scaled variables: lengths by R, masses by m, times by
/// `1/rate` with `rate` the largest of |ω0|, |Ω0|, |θ̇0|, sqrt(g/R),
/// sqrt(|H|max/(m R)) and 1/t_end, so that the scale exists for g = 0 and
/// ω0 = 0 and one tolerance means the same for the C60 top and the toy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Length unit \[m\] (= R).
    pub length: f64,
    /// Mass unit \[kg\] (= m).
    pub mass: f64,
    /// Time unit \[s\].
    pub time: f64,
}

impl Scales {
    /// The scales of a scenario.
    pub fn of(sc: &Scenario) -> Self {
        let top = &sc.top;
        let i = &sc.initial;
        let rate = [
            i.spin.abs(),
            i.precession.abs(),
            i.theta_dot.abs(),
            (sc.surface.gravity / top.radius).sqrt(),
            (sc.forcing.max_magnitude() / (top.mass * top.radius)).sqrt(),
            1.0 / sc.solver.t_end,
        ]
        .into_iter()
        .fold(0.0, f64::max);
        Scales {
            length: top.radius,
            mass: top.mass,
            time: 1.0 / rate,
        }
    }
    /// Velocity unit \[m/s\].
    pub fn velocity(&self) -> f64 {
        self.length / self.time
    }
    /// Force unit \[N\].
    pub fn force(&self) -> f64 {
        self.mass * self.length / (self.time * self.time)
    }
    /// Energy unit \[J\].
    pub fn energy(&self) -> f64 {
        self.mass * self.length * self.length / (self.time * self.time)
    }
    /// Moment-of-inertia unit \[kg m²\].
    pub fn inertia(&self) -> f64 {
        self.mass * self.length * self.length
    }
}
