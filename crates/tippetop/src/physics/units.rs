//! The unit system of the scaled models: one tolerance means the same for
//! the C60 top and the toy (docs/physics.md#scaling).

/// Units of the scaled variables (a scenario's: `Scales::of`, in
/// input/scenario/limits.rs): lengths by R, masses by m, times by
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
