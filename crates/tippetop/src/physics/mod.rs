//! Physics written once and used by every model (docs/architecture.md):
//! for now the van der Waals adhesion of a fullerene on graphene or
//! graphite.

pub mod adhesion;
