//! Scenarios: everything that defines one run (top, surface, forcing,
//! initial state, solver), parsed from TOML with presets and `--set`
//! overrides, validated with errors that name the key and the valid range.

use crate::{
    ContactMode, Error, Forcing, FrictionLaw, Initial, SolverSettings, Surface, Top,
    state::{Method, ModelKind},
};

/// One complete run description.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The body.
    pub top: Top,
    /// The plane.
    pub surface: Surface,
    /// Applied force schedule.
    pub forcing: Forcing,
    /// Initial state.
    pub initial: Initial,
    /// Solver settings.
    pub solver: SolverSettings,
}

impl Scenario {
    /// The paper's nano preset (Sec. 3): C60 top, μ = 0.13, H_x = H_y = 0.1 zN
    /// from t = 0, g = 9.8, paper initial state, adaptive rtol 1e-10,
    /// 1001 samples over 100 µs.
    pub fn nano() -> Self {
        Scenario {
            top: Top::nano(),
            surface: Surface {
                gravity: 9.8,
                friction: 0.13,
                law: FrictionLaw::Coulomb,
                contact: ContactMode::Bilateral,
                restitution: 0.0,
            },
            forcing: Forcing::constant(1e-22, 1e-22),
            initial: Initial::paper(),
            solver: SolverSettings::new(1e-4),
        }
    }

    /// The paper's classical benchmark (end of App. A): μ = 0.1, no applied
    /// force, paper initial state, adaptive rtol 1e-10, 1001 samples over 10 s.
    pub fn classical() -> Self {
        Scenario {
            top: Top::classical(),
            surface: Surface {
                gravity: 9.8,
                friction: 0.1,
                law: FrictionLaw::Coulomb,
                contact: ContactMode::Bilateral,
                restitution: 0.0,
            },
            forcing: Forcing::none(),
            initial: Initial::paper(),
            solver: SolverSettings::new(10.0),
        }
    }

    /// A preset by name (`"nano"` or `"classical"`).
    pub fn preset(name: &str) -> Result<Self, Error> {
        match name {
            "nano" => Ok(Self::nano()),
            "classical" => Ok(Self::classical()),
            other => Err(Error::invalid(
                "preset",
                format!("unknown preset \"{other}\""),
                "\"nano\" or \"classical\"".into(),
            )),
        }
    }

    /// Validate every part.
    pub fn validate(&self) -> Result<(), Error> {
        self.top.validate()?;
        self.surface.validate()?;
        self.forcing.validate()?;
        self.initial
            .validate(self.solver.model == ModelKind::Reduced)?;
        self.solver.validate()?;
        let _ = Method::Adaptive;
        Ok(())
    }
}
