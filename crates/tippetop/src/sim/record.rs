//! The record of a run and its set-up, shared by every model's driver.

use crate::{
    Error, EventRecord, Method, Sample, Scenario, Summary,
    integrate::{self, Options, Stepper},
    sim::events::Happened,
};

/// Accepted steps between two calls of the progress callback of
/// [`crate::simulate::simulate_with_progress`].
pub const PROGRESS_EVERY: u64 = 1 << 14;

/// What the progress callback of
/// [`crate::simulate::simulate_with_progress`] is told: how far the run
/// is, and enough of its state to see it running away (a spin growing by
/// decades, the step size falling by decades) before it fails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// The fraction `t / t_end` of the run done, in `[0, 1]`.
    pub fraction: f64,
    /// The time reached \[s\] (the end of the last accepted step).
    pub t: f64,
    /// Accepted steps so far.
    pub steps: u64,
    /// The spin ω = n·k there \[rad/s\] (the output row's `omega`).
    pub spin: f64,
}

/// Largest number of stick/slip switches of one run before it is stopped.
pub const MAX_SWITCHES: usize = 200_000;

/// The events a run records: at most [`crate::limits::MAX_EVENTS`], then one
/// `"event_limit_reached"` record (see there).
#[derive(Debug, Default, Clone)]
pub(crate) struct EventList {
    list: Vec<EventRecord>,
    dropped: u64,
    /// Record nothing (the paths of `analysis::rare`, which read no
    /// events and are copied at every branching).
    pub(crate) off: bool,
}

impl EventList {
    /// Record that `what` happened at `t` \[s\] (or count it if the list is
    /// full).
    pub(crate) fn push(&mut self, t: f64, what: Happened) {
        if self.off {
            return;
        }
        if self.list.len() < crate::limits::MAX_EVENTS {
            self.list.push(EventRecord {
                t,
                kind: what.as_str().into(),
            });
        } else {
            if self.dropped == 0 {
                self.list.push(EventRecord {
                    t,
                    kind: Happened::EventLimitReached.as_str().into(),
                });
            }
            self.dropped += 1;
        }
    }

    /// The records in time order.
    pub(crate) fn into_sorted(mut self) -> Vec<EventRecord> {
        self.list.sort_by(|a, b| a.t.total_cmp(&b.t));
        self.list
    }
}

pub(crate) fn unit(v: [f64; 2]) -> [f64; 2] {
    let n = v[0].hypot(v[1]);
    if n > 0.0 {
        [v[0] / n, v[1] / n]
    } else {
        [0.0, 0.0]
    }
}

/// Running diagnostics of a run (scaled units), updated at every accepted
/// step, sample and event by the driver for every model.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Track {
    j0: f64,
    j_dev_max: f64,
    omega_abs_max: f64,
    e0: f64,
    e_abs_max: f64,
    balance_max: f64,
    theta_max: f64,
    /// `cos(theta_max) + COS_GUARD_MARGIN` at the last rise of
    /// `theta_max` through [`Track::record_angles_guarded`] (NaN before:
    /// nothing skipped); a state with `cos θ` above it has a smaller θ.
    cos_guard: f64,
}

/// How far above `cos(θ_max)` a state's `cos θ` must be for θ to be
/// skipped: `|d cos θ/dθ| <= 1`, so `θ < θ_max − 1e-12`, far more than the
/// few ulps (< 1e-15) by which `cos θ`, `cos(θ_max)` and `atan2` are
/// rounded: the skipped θ would not have changed the maximum.
const COS_GUARD_MARGIN: f64 = 1e-12;

impl Track {
    /// Start from θ, ω, J and the energy E (if it could be evaluated) at t = 0.
    pub(crate) fn new(theta: f64, omega: f64, j: f64, energy: Option<f64>) -> Self {
        let e0 = energy.unwrap_or(0.0);
        Track {
            j0: j,
            j_dev_max: 0.0,
            omega_abs_max: omega.abs(),
            e0,
            e_abs_max: e0.abs(),
            balance_max: 0.0,
            theta_max: theta,
            cos_guard: f64::NAN,
        }
    }

    /// The largest |spin| recorded so far, scaled: in units of the run's
    /// fastest initial rate `1 / T_ref` (the models' time unit).
    pub(crate) fn spin_abs_max(&self) -> f64 {
        self.omega_abs_max
    }

    /// The largest energy-balance error so far relative to max |E| (NaN-safe:
    /// infinite if the balance is not finite).
    pub(crate) fn balance_rel(&self) -> f64 {
        let r = if self.e_abs_max > 0.0 {
            self.balance_max / self.e_abs_max
        } else {
            self.balance_max
        };
        if r.is_nan() { f64::INFINITY } else { r }
    }

    /// Take the maxima of `other` (a track of the same run) too.
    pub(crate) fn merge(&mut self, other: &Track) {
        self.j_dev_max = self.j_dev_max.max(other.j_dev_max);
        self.omega_abs_max = self.omega_abs_max.max(other.omega_abs_max);
        self.e_abs_max = self.e_abs_max.max(other.e_abs_max);
        self.balance_max = self.balance_max.max(other.balance_max);
        self.theta_max = self.theta_max.max(other.theta_max);
    }

    /// Record θ and ω only (an ensemble's run: `simulate_for_row`), with
    /// θ computed (`angles()`: θ, an `atan2`, and the spin; else `spin()`)
    /// only where `cos_theta` (the state's `cos θ` to a few ulps, NaN if
    /// unknown) does not show that θ is below the maximum so far: the same
    /// `theta_max` bits as recording every θ.
    pub(crate) fn record_angles_guarded(
        &mut self,
        cos_theta: f64,
        angles: impl FnOnce() -> (f64, f64),
        spin: impl FnOnce() -> f64,
    ) {
        let omega = if cos_theta > self.cos_guard {
            spin()
        } else {
            let (theta, omega) = angles();
            let new = self.theta_max.max(theta);
            if new.to_bits() != self.theta_max.to_bits() {
                self.cos_guard = new.cos() + COS_GUARD_MARGIN;
            }
            self.theta_max = new;
            omega
        };
        self.omega_abs_max = self.omega_abs_max.max(omega.abs());
    }

    /// Record a state: θ, ω, J, the energy E (if it could be evaluated) and
    /// the work done so far `W_f + W_a`.
    pub(crate) fn record(
        &mut self,
        theta: f64,
        omega: f64,
        j: f64,
        energy: Option<f64>,
        work: f64,
    ) {
        self.theta_max = self.theta_max.max(theta);
        self.omega_abs_max = self.omega_abs_max.max(omega.abs());
        self.record_rest(j, energy, work);
    }

    /// Record J, the energy E (if it could be evaluated) and the work done
    /// so far `W_f + W_a`: [`Track::record`] without θ and ω (with
    /// [`Track::record_angles_guarded`], the same record as `record`).
    pub(crate) fn record_rest(&mut self, j: f64, energy: Option<f64>, work: f64) {
        self.j_dev_max = self.j_dev_max.max((j - self.j0).abs());
        if let Some(en) = energy {
            self.e_abs_max = self.e_abs_max.max(en.abs());
            self.balance_max = self.balance_max.max((en - self.e0 - work).abs());
        }
    }
}

/// What a driver knows at the end of a run, besides its [`Track`].
pub(crate) struct RunEnd<'a> {
    /// Time reached (scaled).
    pub t: f64,
    /// Time unit \[s\].
    pub time_unit: f64,
    /// C/(m R²): the J drift is relative to C max|ω| R.
    pub axial: f64,
    /// The final output row and θ there.
    pub last: &'a Sample,
    /// All output rows.
    pub samples: &'a [Sample],
    /// First time θ > π/2 \[s\].
    pub first_above: Option<f64>,
    /// First time N < 0 \[s\] and fraction of the time with N < 0.
    pub contact: (Option<f64>, f64),
    /// Time spent rolling (scaled).
    pub rolling_time: f64,
    /// Work counters.
    pub stats: integrate::Stats,
    /// The run-time failure, if any.
    pub error: Option<&'a Error>,
    /// True when the scenario has adhesion (`pull_off_margin_min` is then
    /// reported).
    pub adhesive: bool,
    /// With a stem (docs/physics.md#stem): the first time the stem touched
    /// \[s\] and the fraction of the time on the stem; `None` without one.
    pub stem: Option<(Option<f64>, f64)>,
    /// Stochastic runs: `∫ N dt` \[N, scaled time\] over each output
    /// interval `(s_{i−1}, s_i]` (index `i`, from 1) and the sample times.
    pub normal_buckets: Option<(&'a [f64], &'a [f64])>,
}

/// The run's [`Summary`] from its [`Track`] and its end.
pub(crate) fn summarize(track: &Track, end: RunEnd<'_>) -> Summary {
    let ratio = |num: f64, den: f64| if den > 0.0 { num / den } else { num };
    let t = end.t;
    Summary {
        t_end: t * end.time_unit,
        theta_final: end.last.theta,
        theta_max: track.theta_max,
        omega_final: end.last.spin,
        precession_final: end.last.precession,
        jellett_initial: end.samples.first().map(|s| s.jellett).unwrap_or(f64::NAN),
        jellett_max_rel_drift: ratio(track.j_dev_max, end.axial * track.omega_abs_max),
        energy_initial: end.samples.first().map(|s| s.energy).unwrap_or(f64::NAN),
        energy_final: end.last.energy,
        energy_balance_max_rel_error: ratio(track.balance_max, track.e_abs_max),
        first_time_theta_above_half_pi: end.first_above,
        contact_lost_at: end.contact.0,
        negative_normal_fraction: end.contact.1,
        rolling_fraction: if t > 0.0 { end.rolling_time / t } else { 0.0 },
        stem: end
            .stem
            .map(|(first, fraction)| crate::trajectory::StemSummary {
                first_stem_contact_at: first,
                stem_contact_fraction: fraction,
            }),
        pull_off_margin_min: end.adhesive.then(|| {
            end.samples
                .iter()
                .map(|s| s.normal)
                .fold(end.last.normal, f64::min)
        }),
        normal_intervals: end.normal_buckets.map(|(sums, times)| {
            let mut acc = crate::trajectory::NormalIntervals {
                intervals: 0,
                mean: 0.0,
                mean_min: f64::INFINITY,
                mean_max: f64::NEG_INFINITY,
                negative_fraction: 0.0,
            };
            let mut negative = 0usize;
            for i in 1..times.len() {
                if times[i] > t {
                    break;
                }
                let mean = sums[i] / (times[i] - times[i - 1]);
                acc.intervals += 1;
                acc.mean_min = acc.mean_min.min(mean);
                acc.mean_max = acc.mean_max.max(mean);
                acc.mean += mean;
                negative += usize::from(mean < 0.0);
            }
            if acc.intervals > 0 {
                acc.negative_fraction = negative as f64 / acc.intervals as f64;
                acc.mean /= acc.intervals as f64;
            } else {
                acc.mean = f64::NAN;
                acc.mean_min = f64::NAN;
                acc.mean_max = f64::NAN;
            }
            acc
        }),
        steps: end.stats.steps,
        rejected_steps: end.stats.rejected,
        rhs_evaluations: end.stats.rhs_evals,
        status: match end.error {
            None => "ok".into(),
            Some(e) => e.to_string(),
        },
        failure: end.error.and_then(|e| e.failure()).map(|f| f.as_str()),
    }
}

/// The sign history of the normal force N: its sign at t = 0 and the
/// (scaled) times it crossed zero, from events or from jumps at force
/// switches. Shared by the driver for every model. Constant memory: the
/// first crossing, the number of crossings and the time with N < 0 so far.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalLog {
    negative_at_start: bool,
    first: Option<f64>,
    count: u64,
    last: f64,
    neg_time: f64,
}

impl NormalLog {
    /// Start with N(0) = `n_initial` (NaN counts as non-negative).
    pub fn new(n_initial: f64) -> Self {
        NormalLog {
            negative_at_start: n_initial < 0.0,
            first: None,
            count: 0,
            last: 0.0,
            neg_time: 0.0,
        }
    }

    /// Record a crossing at scaled time `t`; returns what happened:
    /// contact lost (N now < 0) or regained.
    pub fn cross(&mut self, t: f64) -> Happened {
        if self.negative_now() {
            self.neg_time += t - self.last;
        }
        self.last = t;
        self.first.get_or_insert(t);
        self.count += 1;
        if self.negative_now() {
            Happened::ContactLost
        } else {
            Happened::ContactRegained
        }
    }

    /// Whether N is negative after the crossings recorded so far.
    pub fn negative_now(&self) -> bool {
        self.negative_at_start != (self.count % 2 == 1)
    }

    /// First time N < 0 (scaled), if ever.
    pub fn first_negative(&self) -> Option<f64> {
        if self.negative_at_start {
            Some(0.0)
        } else {
            self.first
        }
    }

    /// Fraction of `[0, t_final]` with N < 0 (`t_final` not before the
    /// last crossing).
    pub fn negative_fraction(&self, t_final: f64) -> f64 {
        if t_final <= 0.0 {
            return 0.0;
        }
        let mut neg_time = self.neg_time;
        if self.negative_now() {
            neg_time += t_final - self.last;
        }
        neg_time / t_final
    }
}

/// What every model's driver needs from a scenario, in scaled time: the
/// end time, the sample times, the force-switch times inside the run, and
/// the integrator options.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSetup {
    /// End time (scaled).
    pub t_end: f64,
    /// Evenly spaced sample times on `[0, t_end]`, the last exactly `t_end`.
    pub sample_times: Vec<f64>,
    /// Switch times of the force schedule strictly inside `(0, t_end)`.
    pub tstops: Vec<f64>,
    /// Integrator options from `[solver]`.
    pub opts: Options,
}

/// Number of steps of a Langevin run of `sc` (`solver.dt` set).
fn langevin_steps(sc: &Scenario) -> u64 {
    crate::input::thermal::langevin_steps(sc.solver.t_end, sc.solver.dt.unwrap_or(sc.solver.t_end))
}

impl RunSetup {
    /// The setup of `sc` with time unit `time_unit` \[s\].
    pub fn new(sc: &Scenario, time_unit: f64) -> Self {
        let t_end = sc.solver.t_end / time_unit;
        let ns = sc.solver.samples;
        let sample_times = (0..ns)
            .map(|i| {
                if i + 1 == ns {
                    t_end
                } else {
                    t_end * i as f64 / (ns - 1) as f64
                }
            })
            .collect();
        let tstops = sc
            .switch_times()
            .into_iter()
            .map(|t| t / time_unit)
            .filter(|&t| t > 0.0 && t < t_end)
            .collect();
        let opts = Options {
            stepper: match sc.solver.method {
                Method::Adaptive => Stepper::Dop853 {
                    rtol: sc.solver.rtol,
                    atol: sc.solver.rtol,
                    beta: 0.0,
                    stability_cap: false,
                },
                Method::Stiff => Stepper::Rodas4P {
                    rtol: sc.solver.rtol,
                    atol: sc.solver.rtol,
                },
                Method::Rk4 => Stepper::Rk4 {
                    h: t_end / sc.solver.steps as f64,
                },
                Method::Langevin => Stepper::Langevin {
                    h: t_end / langevin_steps(sc) as f64,
                    seed: sc.thermal.seed.unwrap_or(0),
                    run: sc.thermal.run,
                    first_step: 0,
                },
                Method::Brownian => Stepper::Brownian {
                    h: t_end / langevin_steps(sc) as f64,
                    seed: sc.thermal.seed.unwrap_or(0),
                    run: sc.thermal.run,
                    first_step: 0,
                },
            },
            max_steps: sc.solver.step_limit(),
            h0: None,
            // Samples and events are read from the dense output, whose error
            // the step-size control does not see: with steps much longer than
            // the time scale of the motion (a tiny nutation on a steady
            // precession lets DOP853 take steps of a whole period) the
            // interpolant is far less accurate than the step ends. No step
            // longer than the sample spacing keeps the dense output at the
            // step-error level.
            h_max: Some(t_end / (ns - 1) as f64),
        };
        // Langevin: samples on the nearest step end (the engine's grid `k h`;
        // the last one is `t_end`, where the last step lands).
        let sample_times = match opts.stepper {
            Stepper::Langevin { h, .. } | Stepper::Brownian { h, .. } => {
                let mut st: Vec<f64> = sample_times;
                let last = st.len() - 1;
                for (i, t) in st.iter_mut().enumerate() {
                    if i < last {
                        *t = crate::integrate::nearest_grid(*t, h).min(t_end);
                    }
                }
                st
            }
            _ => sample_times,
        };
        RunSetup {
            t_end,
            sample_times,
            tstops,
            opts,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{EventList, NormalLog, Track};
    use crate::limits::MAX_EVENTS;
    use crate::sim::events::Happened;

    /// At most MAX_EVENTS records, then one marker; memory stays bounded
    /// however many events a run has.
    #[test]
    fn event_list_is_capped() {
        let mut l = EventList::default();
        for k in 0..MAX_EVENTS + 1000 {
            l.push(k as f64, Happened::ContactLost);
        }
        assert_eq!(l.dropped, 1000);
        let v = l.into_sorted();
        assert_eq!(v.len(), MAX_EVENTS + 1);
        assert_eq!(v[MAX_EVENTS].kind, "event_limit_reached");
        assert_eq!(v[MAX_EVENTS].t, MAX_EVENTS as f64);
        assert_eq!(v[MAX_EVENTS - 1].kind, "contact_lost");
    }

    #[test]
    fn normal_log_fraction_and_first_time() {
        let mut l = NormalLog::new(1.0);
        assert_eq!(l.first_negative(), None);
        assert_eq!(l.cross(2.0), Happened::ContactLost);
        assert_eq!(l.cross(3.0), Happened::ContactRegained);
        assert_eq!(l.cross(8.0), Happened::ContactLost);
        assert_eq!(l.first_negative(), Some(2.0));
        // Negative on [2, 3) and [8, 10]: 3 of 10.
        assert_eq!(l.negative_fraction(10.0), 0.3);
        let mut l = NormalLog::new(-1.0);
        assert_eq!(l.first_negative(), Some(0.0));
        assert_eq!(l.cross(4.0), Happened::ContactRegained);
        assert_eq!(l.negative_fraction(8.0), 0.5);
    }

    /// The guarded maximum of θ (`atan2` skipped where `cos θ` shows θ
    /// below the maximum) is the plain maximum of every θ, bit for bit,
    /// over 400 000 axes of a random walk in θ and φ whose steps range
    /// from 1e-2 rad down to single ulps (so many θ lie within ulps of the
    /// maximum) and whose length drifts off 1 by up to 1e-9 (|k| = 1 holds
    /// only to the integration error); and it does skip most of them.
    #[test]
    fn guarded_theta_max_is_the_plain_maximum() {
        let mut uniform = crate::testing::uniform_sequence(0x2545_f491_4f6c_dd1d);
        let angles = |k: [f64; 3]| ((k[0] * k[0] + k[1] * k[1]).sqrt().atan2(k[2]), k[2]);
        let cos = |k: [f64; 3]| k[2] / (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
        for theta0 in [0.1, std::f64::consts::FRAC_PI_2, 3.0] {
            let (mut th, mut ph): (f64, f64) = (theta0, 0.3);
            let mut k = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let mut plain = Track::new(angles(k).0, k[2], 0.0, None);
            let mut guarded = plain.clone();
            let mut calls = 0usize;
            let n = 400_000;
            for i in 0..n {
                let scale = [1e-2, 1e-6, 1e-12, 1e-15, 3e-16][i % 5];
                th = (th + scale * (uniform() - 0.5)).clamp(0.0, std::f64::consts::PI);
                ph += 1e-3 * (uniform() - 0.5);
                let len = 1.0 + 1e-9 * (uniform() - 0.5);
                k = [
                    len * th.sin() * ph.cos(),
                    len * th.sin() * ph.sin(),
                    len * th.cos(),
                ];
                let (theta, spin) = angles(k);
                plain.theta_max = plain.theta_max.max(theta);
                plain.omega_abs_max = plain.omega_abs_max.max(spin.abs());
                guarded.record_angles_guarded(
                    cos(k),
                    || {
                        calls += 1;
                        angles(k)
                    },
                    || k[2],
                );
                assert_eq!(guarded.theta_max.to_bits(), plain.theta_max.to_bits());
                assert_eq!(
                    guarded.omega_abs_max.to_bits(),
                    plain.omega_abs_max.to_bits()
                );
            }
            assert!(calls < n / 2, "θ computed {calls} times of {n}");
        }
    }
}

/// The bookkeeping of a run's discrete history that the driver owns and the
/// models' event handlers write to: the event list, the normal force's
/// sign history, and the intervals spent rolling and (rigid model,
/// unilateral contact) in flight. Times are scaled; `time_unit` \[s\]
/// converts them for the event records.
#[derive(Debug, Clone)]
pub(crate) struct RunLog {
    /// The events recorded so far (SI times).
    pub events: EventList,
    /// Sign history of N.
    pub normal: NormalLog,
    /// Seconds per scaled time unit.
    pub time_unit: f64,
    rolling_since: Option<f64>,
    rolling_time: f64,
    flight_since: Option<f64>,
    flight_time: f64,
    first_lift_off: Option<f64>,
    stem_since: Option<f64>,
    stem_time: f64,
    first_stem: Option<f64>,
}

impl RunLog {
    /// An empty log; `n_initial` is N at t = 0 (scaled).
    pub(crate) fn new(time_unit: f64, n_initial: f64) -> Self {
        RunLog {
            events: EventList::default(),
            normal: NormalLog::new(n_initial),
            time_unit,
            rolling_since: None,
            rolling_time: 0.0,
            flight_since: None,
            flight_time: 0.0,
            first_lift_off: None,
            stem_since: None,
            stem_time: 0.0,
            first_stem: None,
        }
    }

    /// Record that `what` happened at scaled time `t`.
    pub(crate) fn push(&mut self, t: f64, what: Happened) {
        self.events.push(t * self.time_unit, what);
    }

    /// Record a zero crossing of N at scaled time `t` (contact lost or
    /// regained).
    pub(crate) fn cross_normal(&mut self, t: f64) {
        let what = self.normal.cross(t);
        self.push(t, what);
    }

    /// The top starts rolling at `t` (an interval, no event record).
    pub(crate) fn start_rolling(&mut self, t: f64) {
        self.rolling_since = Some(t);
    }

    /// The top stops rolling at `t`, if it rolled.
    pub(crate) fn stop_rolling(&mut self, t: f64) {
        if let Some(s0) = self.rolling_since.take() {
            self.rolling_time += t - s0;
        }
    }

    /// The top lifts off at `t`: records `"lift_off"` and starts a flight.
    pub(crate) fn lift_off(&mut self, t: f64) {
        self.flight_since = Some(t);
        self.first_lift_off.get_or_insert(t);
        self.push(t, Happened::LiftOff);
    }

    /// True while a flight is open (between [`RunLog::lift_off`] and
    /// [`RunLog::land`]).
    pub(crate) fn in_flight(&self) -> bool {
        self.flight_since.is_some()
    }

    /// A flight ends at `t` (the top settles in contact), if it flew.
    pub(crate) fn land(&mut self, t: f64) {
        if let Some(s0) = self.flight_since.take() {
            self.flight_time += t - s0;
        }
    }

    /// The stem's sphere lands at `t` (docs/physics.md#stem): records
    /// `"stem_touchdown"` and starts an interval on the stem.
    pub(crate) fn stem_on(&mut self, t: f64) {
        self.push(t, Happened::StemTouchdown);
        self.first_stem.get_or_insert(t);
        self.stem_since.get_or_insert(t);
    }

    /// The stem's sphere leaves the plane at `t`: records `"stem_liftoff"`
    /// and closes the interval on the stem.
    pub(crate) fn stem_off(&mut self, t: f64) {
        self.push(t, Happened::StemLiftoff);
        self.close_stem(t);
    }

    fn close_stem(&mut self, t: f64) {
        if let Some(s0) = self.stem_since.take() {
            self.stem_time += t - s0;
        }
    }

    /// The first stem touchdown and the fraction of `[0, t]` on the stem
    /// (scaled; call after [`RunLog::finish`]).
    pub(crate) fn stem(&self, t: f64) -> (Option<f64>, f64) {
        (
            self.first_stem,
            if t > 0.0 { self.stem_time / t } else { 0.0 },
        )
    }

    /// Close the open intervals at the final time `t`; returns the time
    /// spent rolling (scaled).
    pub(crate) fn finish(&mut self, t: f64) -> f64 {
        self.close_stem(t);
        self.land(t);
        self.stop_rolling(t);
        self.rolling_time
    }

    /// The first lift-off and the fraction of `[0, t]` in flight (scaled).
    pub(crate) fn flights(&self, t: f64) -> (Option<f64>, f64) {
        (
            self.first_lift_off,
            if t > 0.0 { self.flight_time / t } else { 0.0 },
        )
    }
}
