//! Analyses built on runs: the friction-law (ε) study,
//! stability of the steady motions (App. B), the asymptotic laws while
//! lying (App. C), parallel sweeps, and ensembles of Langevin runs.

pub mod asymptotics;
pub mod bit;
pub mod bitmap;
pub mod desorption;
pub mod device;
pub mod device_rare;
pub mod ensemble;
pub mod friction;
pub mod rare;
pub mod regime;
pub mod retention;
pub mod search;
pub mod stability;
pub mod step_check;
pub mod sweep;
