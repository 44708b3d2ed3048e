//! # tippetop
//!
//! Tippe-top dynamics from the 15 g toy to the C60 "nano tippe top" of
//! Chan, Thamwattana & Hill (the paper in `shared/paper`). The physics,
//! derivations and every modelling choice are in `docs/physics.md`.
//!
//! ```no_run
//! let sc = tippetop::Scenario::classical();
//! let traj = tippetop::simulate(&sc).unwrap();
//! println!("theta at 10 s: {}", traj.summary.theta_final);
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod error;
pub mod human;
pub mod input;
pub mod integrate;
pub mod model;
pub(crate) mod numeric;
/// Counter-based random streams (Philox4x32-10) for stochastic runs: see
/// [`random::Stream`].
/// Deterministic elementary functions (`ln`, `sin_cos`) in plain `f64`
/// arithmetic, the same bits everywhere: see [`detmath::ln`].
pub use numeric::detmath;
pub use numeric::random;
pub mod observe;
pub mod physics;
pub(crate) mod sim;
pub mod simulate;
#[doc(hidden)]
pub mod testing;
pub mod trajectory;

pub use error::{Error, Failure};
pub use input::forcing::{ActuatorWindow, BodyActuator, ForceWindow, Forcing};
pub use input::initial::Initial;
pub use input::scenario::{Scenario, limits};
pub use input::solver::{Method, ModelKind, SolverSettings};
pub use input::surface::{ContactMode, FrictionLaw, Surface};
pub use input::thermal::Thermal;
pub use input::top::{Stem, Top};
pub use physics::forces::adhesion::Adhesion;
pub use physics::forces::wells::Well;
pub use simulate::{
    Progress, RunawayWatch, Simulation, Snapshot, simulate, simulate_watching,
    simulate_watching_with_pose, simulate_watching_with_progress, simulate_with_pose,
    simulate_with_progress,
};
pub use trajectory::{EventRecord, NormalIntervals, Sample, StemSummary, Summary, Trajectory};
