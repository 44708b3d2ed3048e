//! What every model's driver shares, with no model in it: the record of a
//! run (running diagnostics, the normal-force sign history, the bounded
//! event list, the summary) and its set-up (sample times, switch times,
//! integrator options), and the messages of run-time failures. The drivers
//! (`simulate` for the on-plane models, `model::rigid` for the rigid body)
//! build on it; it imports neither, so the import graph has no cycle
//! (docs/architecture.md).

pub mod events;
pub(crate) mod messages;
pub mod record;
