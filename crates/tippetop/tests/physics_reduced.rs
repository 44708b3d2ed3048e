//! Physics validation of the on-plane models: invariants, closed forms,
//! convergence orders. Every tolerance is justified next to its assertion.
//!
//! These tests run the Euler-angle (`reduced`) model; the same tests run the other on-plane model
//! from the sibling file (the body is `physics/on_plane.rs`).

mod common;

const MODEL: tippetop::ModelKind = tippetop::ModelKind::Reduced;

include!("physics/on_plane.rs");
