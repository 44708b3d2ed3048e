//! Analyses built on runs: the paper's claims, stability, asymptotics, sweeps.

pub mod paper;
