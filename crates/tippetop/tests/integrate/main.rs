//! The integrators (`tippetop::integrate`): RK4, DOP853 and Rodas4P on
//! shared test problems with exact solutions (`problems`: the harmonic
//! oscillator, a Kepler orbit, exp(−t²), a blow-up, two stiff problems, a
//! latched switch).
//!
//! - `engines`: what every engine must do, each property written once and
//!   run over the engines: order, tolerance proportionality, dense output,
//!   evaluation count, clean failures;
//! - `driver`: the shared `solve` driver (events, tstops, samples,
//!   determinism, limits) over every engine;
//! - `dop853`: DOP853's own step-size control at the stability limit;
//! - `random`: the counter-based random stream the fixed-step (Langevin)
//!   engines draw from: known answers, purity, statistics;
//! - `langevin`: the Langevin engine's weak order on the thermostatted
//!   harmonic oscillator (closed-form moments).

mod dop853;
mod driver;
mod engines;
mod langevin;
mod problems;
mod random;
