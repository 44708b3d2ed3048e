//! Rare events (issue 27): probabilities far below what brute force can
//! reach (a write that fails once in 1e9) and escape times far beyond a
//! simulation's span (retention over years), computed directly.
//!
//! - [`exact`]: exact answers where the dynamics is a one-dimensional
//!   diffusion in θ (the Brownian mode on the plane): mean first-passage
//!   times and splitting probabilities by quadrature in log space.
//! - [`ams`]: adaptive multilevel splitting on the full stochastic
//!   dynamics (Langevin and Brownian, every model and force).

pub mod ams;
pub mod exact;
