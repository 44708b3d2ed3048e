//! Equations of motion, one file per formulation.

pub mod reduced;
pub mod rigid;
