//! What the driver shares with the models, with no model in it: the record of a
//! run (running diagnostics, the normal-force sign history, the bounded
//! event list, the summary) and its set-up (sample times, switch times,
//! integrator options), and the messages of run-time failures. The one driver
//! (`simulate`, over the `model::Model` trait every model implements)
//! builds on it; it imports no model, so the import graph has no cycle
//! (docs/architecture.md).

pub mod events;
pub(crate) mod messages;
pub mod record;
pub mod runaway;
pub mod watch;
