//! General numerics with no physics in them: dual numbers for exact
//! Jacobians, eigenvalues of small dense matrices and counter-based random
//! streams, and deterministic elementary functions (`detmath`).

pub mod detmath;
pub mod dual;
pub mod eigen;
pub mod random;
pub(crate) mod vec3;
