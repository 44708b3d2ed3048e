//! Analyses built on runs: stability, asymptotics, sweeps. (work in progress)
