//! Exact (set-valued) Coulomb friction: closed forms for sliding → rolling,
//! rolling conserves energy, the stick limit, cost, invariants across switches.
//!
//! These tests run the Euler-angle (`reduced`) model; the same tests run the other on-plane model
//! from the sibling file (the body is `physics/stick_slip.rs`).

mod common;

const MODEL: tippetop::ModelKind = tippetop::ModelKind::Reduced;

include!("physics/stick_slip.rs");
