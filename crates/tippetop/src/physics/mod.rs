//! Physics written once and used by every model (docs/architecture.md):
//! the body's contact dynamics in lab vectors (`body`), the unit system of
//! the scaled models, the applied force terms, and the van der Waals
//! adhesion of a fullerene on graphene or graphite and inside a carbon
//! nanotube.

pub mod adhesion;
pub mod body;
pub mod contensou;
pub mod forces;
pub mod nanotube;
pub mod units;
