//! Run a scenario: the driver that turns a [`Scenario`] into a [`Trajectory`].

use crate::{Error, Scenario, Trajectory};

/// Run `scenario`. `Err` only for bad input; a run that fails while
/// integrating returns `Ok` with `trajectory.error` set and the samples up to
/// the failure.
pub fn simulate(scenario: &Scenario) -> Result<Trajectory, Error> {
    scenario.validate()?;
    todo!("simulate")
}
