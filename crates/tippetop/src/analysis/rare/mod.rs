//! Rare events (issue 27): probabilities far below what brute force can
//! reach (a write that fails once in 1e9) and escape times far beyond a
//! simulation's span (retention over years), computed directly.
//!
//! - [`exact`]: exact answers where the dynamics is a one-dimensional
//!   diffusion in θ (the Brownian mode on the plane): mean first-passage
//!   times and splitting probabilities by quadrature in log space.
//! - [`direct`]: a plain ensemble, each run until the target or the
//!   reset, checked at every step (the cross-check).
//! - [`problem`]: the question (target, reset, horizon, budgets) and the
//!   report of each method (`tippetop rare`, Python's `tt.rare`).
//! - [`ams`]: adaptive multilevel splitting on the full stochastic
//!   dynamics (Langevin and Brownian, every model and force).
//! - [`step_check`]: the same question at `solver.dt / 2` and the
//!   comparison (what `tippetop rare` and `tt.rare` share).

pub mod ams;
pub mod direct;
pub mod exact;
pub mod problem;
pub mod step_check;
