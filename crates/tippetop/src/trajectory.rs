//! The result of a run: samples, diagnostics, events, counters. Every output
//! (CSV, JSON, plots, reports) reads from a [`Trajectory`].

use serde::Serialize;

/// One output row (SI units, radians).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sample {
    /// Time \[s\].
    pub t: f64,
    /// Nutation angle θ \[rad\].
    pub theta: f64,
    /// θ̇ \[rad/s\].
    pub theta_dot: f64,
    /// Precession rate Ω \[rad/s\].
    #[serde(rename = "Omega")]
    pub precession: f64,
    /// Spin ω = n·k \[rad/s\].
    #[serde(rename = "omega")]
    pub spin: f64,
    /// Centre-of-mass velocity, precessing x \[m/s\].
    pub ux: f64,
    /// Centre-of-mass velocity, precessing y \[m/s\].
    pub uy: f64,
    /// Centre-of-mass velocity, vertical \[m/s\].
    pub uz: f64,
    /// Normal force N \[N\].
    #[serde(rename = "N")]
    pub normal: f64,
    /// Slip speed |v_P| \[m/s\].
    pub slip: f64,
    /// Jellett's J = A Ω R sin²θ + C ω (R cos θ − a) \[kg m³/s\].
    #[serde(rename = "J")]
    pub jellett: f64,
    /// Total energy (translational + rotational + potential m g h) \[J\].
    pub energy: f64,
    /// Work done so far by friction \[J\] (<= 0).
    pub work_friction: f64,
    /// Work done so far by the applied force \[J\].
    pub work_applied: f64,
    /// Applied force H_x in effect \[N\].
    pub hx: f64,
    /// Applied force H_y in effect \[N\].
    pub hy: f64,
    /// 1 while rolling (exact Coulomb law, slip held at zero), 0 while sliding.
    pub rolling: u8,
    /// Centre-of-mass position, lab X \[m\]. Lab frame: the plane is
    /// `Z = 0`, `Z` up; the origin is below the centre of mass at `t = 0`
    /// (`x = y = 0` there), and the lab `X` is the initial heading: the
    /// axis `k` tilts towards `+X` at `t = 0` (the precessing frame's `x̂`
    /// starts along `X`, `ŷ = Z × x̂`). docs/physics.md#position.
    pub x: f64,
    /// Centre-of-mass position, lab Y \[m\].
    pub y: f64,
    /// Centre-of-mass height above the plane \[m\] (`R − a cos θ` in contact).
    pub z: f64,
    /// Attitude, unit quaternion body → lab, scalar part `w` (the body's
    /// symmetry axis is its `e3`: `k = q e3 q*`; at `t = 0` the rotation is
    /// by θ about the lab `Y`, so `q = (cos θ/2, 0, sin θ/2, 0)`).
    pub qw: f64,
    /// Attitude quaternion, `x` part.
    pub qx: f64,
    /// Attitude quaternion, `y` part.
    pub qy: f64,
    /// Attitude quaternion, `z` part.
    pub qz: f64,
    /// Contact point (the sphere's lowest point) on the plane, lab X \[m\]:
    /// `x + a k_X`.
    pub xp: f64,
    /// Contact point on the plane, lab Y \[m\]: `y + a k_Y`.
    pub yp: f64,
}

impl Sample {
    /// True if every column is a finite number. A row of a run that
    /// completed always is: the driver fails a run (`non_finite`, or
    /// `output_overflow` for an infinity) at its first row that is not
    /// ([`Sample::first_non_finite`]).
    pub fn is_finite(&self) -> bool {
        self.first_non_finite().is_none()
    }

    /// The first column (in [`COLUMNS`] order) that is not a finite
    /// number, with its value.
    pub fn first_non_finite(&self) -> Option<(&'static str, f64)> {
        let values = self.values();
        // The common case in one pass without the names (the driver asks
        // at every sample).
        if values.iter().all(|v| v.is_finite()) {
            return None;
        }
        COLUMNS
            .iter()
            .zip(self.values())
            .find(|(_, v)| !v.is_finite())
            .map(|(c, v)| (*c, v))
    }
}

impl Sample {
    /// [`Sample::first_non_finite`] over the columns a run computes: all
    /// of them with the pose (`pose`), else all but [`POSE_COLUMNS`] (NaN
    /// in a run without the pose, `simulate::simulate_with_pose`).
    pub fn first_non_finite_of(&self, pose: bool) -> Option<(&'static str, f64)> {
        if pose {
            return self.first_non_finite();
        }
        let values = self.values();
        // The common case in one pass without the names.
        if values
            .iter()
            .zip(POSE_MASK)
            .all(|(v, pose)| pose || v.is_finite())
        {
            return None;
        }
        COLUMNS
            .iter()
            .zip(self.values())
            .find(|(c, v)| !v.is_finite() && !POSE_COLUMNS.contains(c))
            .map(|(c, v)| (*c, v))
    }
}

/// The pose's columns, those after `rolling` in [`COLUMNS`]: the centre of
/// mass's position, the attitude and the contact point. A run without the
/// pose (`simulate::simulate_with_pose`) does not compute them (NaN there),
/// and `tippetop run --no-pose` does not write them.
pub const POSE_COLUMNS: [&str; 9] = ["x", "y", "z", "qw", "qx", "qy", "qz", "xp", "yp"];

/// True at the index (in [`COLUMNS`] order) of each of [`POSE_COLUMNS`].
const POSE_MASK: [bool; 26] = {
    let mut m = [false; 26];
    let mut i = 0;
    while i < 26 {
        let mut j = 0;
        while j < POSE_COLUMNS.len() {
            if eq(COLUMNS[i], POSE_COLUMNS[j]) {
                m[i] = true;
            }
            j += 1;
        }
        i += 1;
    }
    m
};

/// `a == b` in a const context.
const fn eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The CSV column names, in order; the first twelve are fixed by the
/// scenario-file contract, and new columns are appended after `rolling`.
pub const COLUMNS: [&str; 26] = [
    "t",
    "theta",
    "theta_dot",
    "Omega",
    "omega",
    "ux",
    "uy",
    "uz",
    "N",
    "slip",
    "J",
    "energy",
    "work_friction",
    "work_applied",
    "hx",
    "hy",
    "rolling",
    "x",
    "y",
    "z",
    "qw",
    "qx",
    "qy",
    "qz",
    "xp",
    "yp",
];

impl Sample {
    /// The row's values in [`COLUMNS`] order.
    pub fn values(&self) -> [f64; 26] {
        [
            self.t,
            self.theta,
            self.theta_dot,
            self.precession,
            self.spin,
            self.ux,
            self.uy,
            self.uz,
            self.normal,
            self.slip,
            self.jellett,
            self.energy,
            self.work_friction,
            self.work_applied,
            self.hx,
            self.hy,
            self.rolling as f64,
            self.x,
            self.y,
            self.z,
            self.qw,
            self.qx,
            self.qy,
            self.qz,
            self.xp,
            self.yp,
        ]
    }
}

/// Something that happened during the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventRecord {
    /// Time \[s\].
    pub t: f64,
    /// What: "force_switch", "contact_lost", "contact_regained", "stick", "slip",
    /// "theta_above_half_pi", "lift_off", "touchdown", ...
    pub kind: String,
}

/// The normal force of a stochastic run averaged over each output interval
/// (`(t_{i−1}, t_i]`, from its value at every step end weighted by the
/// step): what the contact carries on the output's time scale, where the
/// instantaneous reaction is noise-dominated (docs/physics.md#langevin).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NormalIntervals {
    /// Number of intervals averaged (those the run completed).
    pub intervals: usize,
    /// Mean over those intervals \[N\] (the time average of N; in a
    /// stationary run `m g + F_a` plus the loads: vertical momentum balance).
    pub mean: f64,
    /// Smallest interval mean \[N\] (with adhesion: the pull-off margin on
    /// interval averages).
    pub mean_min: f64,
    /// Largest interval mean \[N\].
    pub mean_max: f64,
    /// Fraction of the intervals whose mean is negative.
    pub negative_fraction: f64,
}

/// The stem's entries of a [`Summary`] (docs/physics.md#stem).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StemSummary {
    /// First time the stem's sphere touched the plane \[s\], if ever.
    pub first_stem_contact_at: Option<f64>,
    /// Fraction of the simulated time with the stem's sphere on the plane.
    pub stem_contact_fraction: f64,
}

/// Scalar summary of a run (the `summary.json` of the CLI, minus wall time).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Time reached \[s\] (the requested end unless the run failed).
    pub t_end: f64,
    /// θ at the end \[rad\].
    pub theta_final: f64,
    /// Largest θ over the run, from the continuous solution \[rad\].
    pub theta_max: f64,
    /// ω at the end \[rad/s\].
    pub omega_final: f64,
    /// Ω at the end \[rad/s\].
    #[serde(rename = "Omega_final")]
    pub precession_final: f64,
    /// Jellett's J at t = 0 \[kg m³/s\].
    #[serde(rename = "J_initial")]
    pub jellett_initial: f64,
    /// max |J − J0| / (C max|ω| R) over all steps and samples.
    #[serde(rename = "J_max_rel_drift")]
    pub jellett_max_rel_drift: f64,
    /// Energy at t = 0 \[J\].
    pub energy_initial: f64,
    /// Energy at the end \[J\].
    pub energy_final: f64,
    /// max |E − E0 − W_friction − W_applied| / max|E| over steps and samples.
    pub energy_balance_max_rel_error: f64,
    /// First time θ exceeds π/2 \[s\] (event), if ever.
    pub first_time_theta_above_half_pi: Option<f64>,
    /// First time N < 0 \[s\] (event), if ever.
    pub contact_lost_at: Option<f64>,
    /// Fraction of the simulated time with N < 0.
    pub negative_normal_fraction: f64,
    /// Fraction of the simulated time spent rolling (exact Coulomb law).
    pub rolling_fraction: f64,
    /// With a stem (`top.stem_radius`, docs/physics.md#stem):
    /// `first_stem_contact_at` \[s\] (null if the stem never touched) and
    /// `stem_contact_fraction`; absent from summary.json without a stem.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub stem: Option<StemSummary>,
    /// Smallest contact reaction `N_c` over the output rows and the final
    /// state \[N\]: how far the run stayed from pulling off (0 in flight);
    /// `None` without adhesion (docs/physics.md#adhesion).
    pub pull_off_margin_min: Option<f64>,
    /// Stochastic runs (`solver.method = "langevin"` or `"brownian"`): the
    /// normal force averaged over each output interval (the instantaneous
    /// reaction carries the noise); `None` (and absent from summary.json)
    /// for deterministic runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_intervals: Option<NormalIntervals>,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// "ok" or the error message.
    pub status: String,
    /// The kind of the run-time failure ([`crate::Failure::as_str`]:
    /// `"painleve"`, `"step_limit"`, ...), `None` for a run that completed.
    pub failure: Option<&'static str>,
}

impl Summary {
    /// `first_stem_contact_at` \[s\]: `None` without a stem or if it never
    /// touched.
    pub fn first_stem_contact_at(&self) -> Option<f64> {
        self.stem.and_then(|s| s.first_stem_contact_at)
    }

    /// `stem_contact_fraction` (0 without a stem).
    pub fn stem_contact_fraction(&self) -> f64 {
        self.stem.map_or(0.0, |s| s.stem_contact_fraction)
    }
}

/// A run: samples, events, summary, and the run-time error if it failed.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Output rows, evenly spaced (up to the failure if the run failed).
    pub samples: Vec<Sample>,
    /// Events in time order.
    pub events: Vec<EventRecord>,
    /// Scalar summary.
    pub summary: Summary,
    /// The run-time failure, if any.
    pub error: Option<crate::Error>,
}
