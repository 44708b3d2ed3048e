//! What the splitting returns: a replica's result ([`Replica`], which
//! shards write and merges read) and the combined [`Estimate`].

use serde::{Deserialize, Serialize};

/// What an estimate is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// `P(target before reset [and before T])`.
    Probability,
    /// The mean first-passage time to the target \[s\].
    MeanFirstPassageTime,
}

/// One splitting level of a replica: the level `Z_j` (ξ's units) and
/// `log10 Π_{i <= j} (1 − K_i/n)` after it (the estimate of
/// `P(score > Z_j)`): the picture of the levels.
pub type Level = [f64; 2];

/// A replica's direct run (mean first-passage time).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct DirectPhase {
    /// Steps it took.
    pub steps: u64,
    /// Crossings of the interface recorded (the AMS's starting states).
    pub crossings: u64,
    /// Times it met the target (it then restarts from the initial state).
    pub hits: u64,
    /// Sum of the times from a start to its first crossing \[s\] and their
    /// number.
    pub first_crossing_sum: f64,
    /// Number of first crossings.
    pub first_crossing_count: u64,
    /// Sum of the times between consecutive crossings whose excursion fell
    /// back into the basin \[s\].
    pub cycle_sum: f64,
    /// Number of such cycles.
    pub cycle_count: u64,
}

/// One replica's result ([`Ams::run`](super::Ams::run); serialisable, so that shards can be
/// combined later).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Replica {
    /// Position in the ensemble of replicas (0-based).
    pub index: usize,
    /// Its stream's run word (`thermal.run + index`).
    pub run: u64,
    /// `"ok"`, or why it has no estimate (budget, failure, panic).
    pub status: String,
    /// Its particles `n`.
    pub particles: usize,
    /// Its estimate `p̂` (0 if extinct).
    pub estimate: f64,
    /// `Π (1 − K_j/n) × Σ_{at target} (duration from the root) / n` \[s\]:
    /// the estimate of `E[duration; target]` (mean first-passage time).
    pub weighted_duration: f64,
    /// Particles at the target at the end.
    pub hits: u64,
    /// Every particle was killed at some level.
    pub extinct: bool,
    /// Iterations (levels).
    pub iterations: u64,
    /// Paths run (roots and branches).
    pub trajectories: u64,
    /// Steps integrated (replays and the direct run included).
    pub steps: u64,
    /// Paths cut by the step budget.
    pub truncated: u64,
    /// Paths that failed (a run-time error of the simulation).
    pub failed: u64,
    /// The first failure's message.
    pub first_failure: Option<String>,
    /// The levels ([`Level`]), for the picture of the staircase: every
    /// level of the replica while they are at most
    /// [`super::MAX_STORED_LEVELS`], else every 2nd (4th, ...) one and the
    /// last (the estimate does not use them).
    pub levels: Vec<Level>,
    /// The direct run (mean first-passage time).
    pub direct: Option<DirectPhase>,
}

/// The mean first-passage time's parts (the flux relation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Flux {
    /// The basin's level `z_A` (ξ's units).
    pub basin: f64,
    /// The interface's level `z_Σ`.
    pub interface: f64,
    /// `p`: P(target before the basin) from a crossing state (replica
    /// mean), and its standard error.
    pub probability: f64,
    /// Standard error of `probability`.
    pub probability_se: f64,
    /// `T₁`: mean time from the initial state to the first crossing \[s\].
    pub first_crossing_time: f64,
    /// `C`: mean time between crossings whose excursion failed \[s\].
    pub cycle_time: f64,
    /// `S`: mean duration of a successful excursion \[s\] (`None` if no
    /// particle met the target).
    pub transit_time: Option<f64>,
    /// Failed cycles measured, over all replicas.
    pub cycles: u64,
    /// Times the direct runs met the target.
    pub direct_hits: u64,
    /// The escape rate `1/τ` \[1/s\].
    pub rate: f64,
}

/// An estimate with its 95 % interval ([`Ams::combine`](super::Ams::combine), [`Ams::direct`](super::Ams::direct)).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// What it is of.
    pub quantity: Quantity,
    /// `"ams"` or `"direct"`.
    pub method: &'static str,
    /// The estimate (probability, or seconds). Finite: 0 for a probability
    /// no replica reached; for a time no replica reached, the lower end of
    /// `ci95`.
    pub estimate: f64,
    /// The 95 % interval (`interval` says how). Its upper end is infinite
    /// only for a mean time that no replica could bound.
    pub ci95: [f64; 2],
    /// Standard error of `estimate`.
    pub standard_error: f64,
    /// How `ci95` was made: `"student_t"` (mean of replicas ± t SE),
    /// `"rule_of_three"` (nothing reached: `[0, 1 − 0.05^{1/N}]`),
    /// `"lognormal_delta"` (the flux relation: `τ exp(± t SE/τ)`),
    /// `"wilson"` (direct probability), `"bound"` (a time bounded below).
    pub interval: &'static str,
    /// Cox's log-normal interval of the mean of the replicas (probability,
    /// every replica > 0).
    pub ci95_lognormal: Option<[f64; 2]>,
    /// Every replica extinct (no particle ever met the target).
    pub extinct: bool,
    /// Replicas (AMS) or runs (direct).
    pub replicas: usize,
    /// Particles per replica (1 for direct runs).
    pub particles: usize,
    /// Iterations over all replicas.
    pub iterations: u64,
    /// Paths run.
    pub trajectories: u64,
    /// Steps integrated.
    pub steps: u64,
    /// Paths cut by the step budget (the estimate is then of the event
    /// within the budget).
    pub truncated: u64,
    /// Paths that failed.
    pub failed: u64,
    /// The first failure's message.
    pub first_failure: Option<String>,
    /// The flux relation's parts (mean first-passage time by AMS).
    pub flux: Option<Flux>,
}
