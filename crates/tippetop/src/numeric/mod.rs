//! General numerics with no physics in them: dual numbers for exact
//! Jacobians and eigenvalues of small dense matrices.

pub mod dual;
pub mod eigen;
