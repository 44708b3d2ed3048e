//! Analyses built on runs: the paper's claims, the friction-law (ε) study,
//! stability, asymptotics, sweeps.

pub mod asymptotics;
pub mod friction;
pub mod paper;
pub mod stability;
