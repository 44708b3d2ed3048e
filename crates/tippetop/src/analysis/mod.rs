//! Analyses built on runs: the friction-law (ε) study,
//! stability of the steady motions (App. B), the asymptotic laws while
//! lying (App. C), and parallel sweeps.

pub mod asymptotics;
pub mod friction;
pub mod regime;
pub mod stability;
pub mod sweep;
