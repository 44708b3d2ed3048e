//! The [`Model`] of the two models that keep the sphere on the plane
//! (reduced and vector): their events and handlers, written once over
//! [`ContactModel`]. Exact Coulomb law: the slip-zero and stick-limit events
//! end a segment, where the mode switches and the integration restarts;
//! bilateral contact while sliding: `N = 0` ends a segment, where the
//! latched branch flips (docs/physics.md#normal-force).

use crate::integrate::{Direction, Event};
use crate::model::{ContactModel, Flow, Mode, Model, ModelError};
use crate::sim::events::{Happened, Watch};
use crate::sim::messages::painleve_why;
use crate::sim::record::{RunLog, Track, unit};
use crate::{ContactMode, Error, Failure, Sample, Scenario};

/// Decide stick or slip at zero slip (exact law). Returns the state to
/// continue from; sets the model's mode and slip hint.
fn settle_at_zero_slip<M: ContactModel<D>, const D: usize>(
    m: &mut M,
    y: &[f64; D],
) -> ([f64; D], bool) {
    let yr = m.to_rolling(y);
    m.plane_mut().mode = Mode::Rolling;
    let needed = m.contact_forces(&yr).ok().map(|(_, f)| f);
    if needed.is_some() && m.stick_margin(&yr).is_some_and(|s| s >= 0.0) {
        m.plane_mut().stick();
        return (yr, true);
    }
    // Slide off in the direction the needed friction dictates: friction
    // keeps its direction (magnitude μN), the slip grows opposite to it.
    m.plane_mut().slip_off(needed);
    (yr, false)
}

/// Arrive at the Coulomb–Contensou stick (sliding and spinning both
/// stopped, §contensou): the state is put on the stick (an impulse, its work in
/// `W_f`), and the needed wrench decides: stick if it is inside the limit
/// curve, else slide off along it. Returns the state and true if stuck.
fn settle_at_stick<M: ContactModel<D>, const D: usize>(
    m: &mut M,
    y: &[f64; D],
) -> ([f64; D], bool) {
    let ys = m.to_stick(y);
    m.plane_mut().mode = Mode::Rolling;
    let needed = m.contact_wrench(&ys).ok();
    if needed.is_some() && m.stick_margin(&ys).is_some_and(|s| s >= 0.0) {
        m.plane_mut().stick();
        return (ys, true);
    }
    m.plane_mut().slip_off_wrench(needed);
    (ys, false)
}

impl<M: ContactModel<D>, const D: usize> Model<D> for M {
    const HAS_POSE: bool = <M as ContactModel<D>>::HAS_POSE;

    fn time_unit(&self) -> f64 {
        self.scales().time
    }

    fn axial_ratio(&self) -> f64 {
        self.axial()
    }

    fn evaluations(&self) -> u64 {
        self.plane().evaluations
    }

    fn adhesive(&self) -> bool {
        self.plane().adhesive()
    }

    fn has_stem(&self) -> bool {
        self.plane().stem_cos.is_some()
    }

    fn step_hints(&self) -> (f64, bool) {
        (self.dop853_beta(), self.dop853_stability_cap())
    }

    fn start(&mut self, sc: &Scenario, log: &mut RunLog) -> ([f64; D], f64) {
        let mut y = ContactModel::initial_state(self, &sc.initial);
        if self.plane().is_exact() {
            let v = self.slip_of(&y);
            if v[0].hypot(v[1]) == 0.0 {
                let (yn, stuck) = settle_at_zero_slip(self, &y);
                y = yn;
                if stuck {
                    log.start_rolling(0.0);
                    log.push(0.0, Happened::Stick);
                } else {
                    log.push(0.0, Happened::Slip);
                }
            } else {
                self.plane().slip_ref.set(unit(v));
            }
        }
        if self.plane().is_contensou()
            && self
                .plane()
                .contensou_stick_gap(self.slip_of(&y), self.spin_z(&y))
                <= 0.0
        {
            // Starting (to the stick speed) at the Coulomb–Contensou stick.
            let (yn, stuck) = settle_at_stick(self, &y);
            y = yn;
            if stuck {
                log.start_rolling(0.0);
                log.push(0.0, Happened::ContensouStick);
            } else {
                log.push(0.0, Happened::Slip);
            }
        }
        self.plane().start_slip(self.slip_of(&y));
        let n0 = self.contact_forces(&y).map(|(n, _)| n).unwrap_or(f64::NAN);
        (y, n0)
    }

    fn latch_force(&mut self, t: f64) {
        ContactModel::latch_force(self, t);
    }

    fn latch_branch(&mut self, y: &[f64; D]) {
        if !self.plane().latches_normal() {
            self.plane_mut().normal_branch = None;
        } else if self.plane().normal_branch.is_none() {
            // The self-consistent branch at the segment's start.
            if let Ok((n, _)) = self.contact_forces(y) {
                self.plane_mut().normal_branch = Some(n >= 0.0);
            }
        }
    }

    fn events(&self, ev: &mut Vec<(Watch, Event<Self, D>)>) {
        ev.extend([
            (
                Watch::ThetaAboveHalfPi,
                Event {
                    g: Box::new(|m: &M, _, y| m.above_half_pi(y)),
                    direction: Direction::Rising,
                    terminal: false,
                    step_to_event: false,
                },
            ),
            (
                Watch::ThetaMax,
                Event {
                    g: Box::new(|m: &M, _, y| m.theta_rate(y)),
                    direction: Direction::Falling,
                    terminal: false,
                    step_to_event: false,
                },
            ),
            (Watch::NormalZero, {
                // Bilateral contact, sliding: N = 0 ends the segment, where
                // the branch flips; watched only in the direction that
                // leaves the latched sign (a restart a rounding error short
                // of the zero must not fire again).
                let plane = self.plane();
                let (direction, terminal) = match (plane.latches_normal(), plane.normal_branch) {
                    (true, Some(true)) => (Direction::Falling, true),
                    (true, Some(false)) => (Direction::Rising, true),
                    _ => (
                        Direction::Either,
                        plane.contact_mode() == ContactMode::Unilateral,
                    ),
                };
                Event {
                    g: Box::new(|m: &M, _, y| {
                        m.contact_forces(y).map(|(n, _)| n).unwrap_or(f64::NAN)
                    }),
                    direction,
                    terminal,
                    // Latched: smooth through N = 0, so the restart state
                    // can come from a step (docs/physics.md#normal-force).
                    step_to_event: terminal && plane.latches_normal(),
                }
            }),
        ]);
        if self.plane().langevin {
            ev.retain(|(w, _)| *w != Watch::ThetaMax);
        }
        // Rolling or stuck under the exact Coulomb or the Contensou law: the
        // stick margin falls through 0 where the contact starts to slip.
        let stick_limit = || {
            (
                Watch::StickLimit,
                Event {
                    g: Box::new(|m: &M, _, y| m.stick_margin(y).unwrap_or(f64::NAN)),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            )
        };
        if self.plane().is_contensou() {
            // Sliding: the arrival at the stick; stuck: the needed wrench
            // leaving the limit curve (§contensou).
            match self.plane().mode {
                Mode::Sliding => ev.push((
                    Watch::ContensouStick,
                    Event {
                        g: Box::new(|m: &M, _, y| {
                            m.plane().contensou_stick_gap(m.slip_of(y), m.spin_z(y))
                        }),
                        direction: Direction::Falling,
                        terminal: true,
                        step_to_event: false,
                    },
                )),
                Mode::Rolling => ev.push(stick_limit()),
            }
        }
        if let Some(c_td) = self.plane().stem_cos {
            // The stem reaches the plane where θ rises through θ_td (§stem).
            ev.push((
                Watch::StemTouch,
                Event {
                    g: Box::new(move |m: &M, _, y| m.theta(y).cos() - c_td),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            ));
        }
        if self.plane().is_exact() {
            match self.plane().mode {
                Mode::Sliding => ev.push((
                    Watch::SlipZero,
                    Event {
                        g: Box::new(|m: &M, _, y| {
                            let v = m.slip_of(y);
                            let r = m.plane().slip_ref.get();
                            v[0] * r[0] + v[1] * r[1]
                        }),
                        direction: Direction::Falling,
                        terminal: true,
                        step_to_event: false,
                    },
                )),
                Mode::Rolling => ev.push(stick_limit()),
            }
        }
    }

    fn accepted(&self, y: &[f64; D]) {
        self.plane().accepted(|| self.slip_of(y));
    }

    fn track_point(&self, y: &[f64; D]) -> (f64, f64, f64, Option<f64>, f64) {
        (
            self.theta(y),
            self.spin(y),
            self.jellett_scaled(y),
            self.energy_scaled(y),
            self.work_scaled(y),
        )
    }

    fn track_angles(&self, y: &[f64; D]) -> (f64, f64) {
        (self.theta(y), self.spin(y))
    }

    /// `track_point`'s record with θ (an `atan2` in the vector model)
    /// computed only where `cos θ` does not show it below the maximum so
    /// far ([`Track::record_angles_guarded`]): the same maxima.
    fn record_step(&self, track: &mut Track, y: &[f64; D]) {
        track.record_angles_guarded(
            Model::cos_theta(self, y),
            || self.track_angles(y),
            || self.spin(y),
        );
        track.record_rest(
            self.jellett_scaled(y),
            self.energy_scaled(y),
            self.work_scaled(y),
        );
    }

    fn cos_theta(&self, y: &[f64; D]) -> f64 {
        ContactModel::cos_theta(self, y)
    }

    fn track_spin(&self, y: &[f64; D]) -> f64 {
        self.spin(y)
    }

    fn on_force_switch(&mut self, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow {
        // While rolling, check that the contact can still hold the new
        // force. N may jump across zero here, which no event can see:
        // record the crossing at the switch.
        let n_before = self.contact_forces(y).map(|(n, _)| n).ok();
        ContactModel::latch_force(self, t);
        self.plane_mut().normal_branch = None;
        let n_after = self.contact_forces(y).map(|(n, _)| n).ok();
        if let (Some(nb), Some(na)) = (n_before, n_after) {
            if (nb < 0.0) != (na < 0.0) {
                log.cross_normal(t);
                if na < 0.0 && self.plane().contact_mode() == ContactMode::Unilateral {
                    return Flow::Stop(Error::runtime(
                        t * self.time_unit(),
                        Failure::LiftOff,
                        format!(
                            "lift-off at a force switch: the normal force N jumped below zero (contact = \"unilateral\"); the reduced and vector models keep the sphere on the plane and cannot follow a flight, use model = \"rigid\"; {}",
                            ContactModel::describe_state(self, y)
                        ),
                    ));
                }
            }
        }
        if (self.plane().is_exact() || self.plane().is_contensou())
            && self.plane().mode == Mode::Rolling
        {
            if let Ok(w) = self.contact_wrench(y) {
                if self.stick_margin(y).is_some_and(|s| s < 0.0) {
                    self.plane_mut().slip_off_wrench(Some(w));
                    log.stop_rolling(t);
                    log.push(t, Happened::Slip);
                }
            }
        }
        Flow::Continue
    }

    fn on_terminal(&mut self, what: Watch, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow {
        match what {
            Watch::NormalZero if self.plane().latches_normal() => {
                // N = 0 (bilateral): continue on the other branch.
                let b = self.plane().normal_branch;
                self.plane_mut().normal_branch = b.map(|pos| !pos);
                Flow::Continue
            }
            Watch::NormalZero => Flow::Stop(Error::runtime(
                t * self.time_unit(),
                Failure::LiftOff,
                format!(
                    "lift-off: the normal force N fell to zero (contact = \"unilateral\"); the reduced and vector models keep the sphere on the plane and cannot follow a flight, use model = \"rigid\"; {}",
                    ContactModel::describe_state(self, y)
                ),
            )),
            Watch::StemTouch => {
                log.stem_on(t);
                let c_td = self.plane().stem_cos.unwrap_or(f64::NAN);
                Flow::Stop(Error::runtime(
                    t * self.time_unit(),
                    Failure::NotModelled,
                    format!(
                        "the stem touches the plane at theta = theta_td = {} rad (cos theta_td = -(R - r2)/(d2 - a) = {c_td}; docs/physics.md#stem): the reduced and vector models keep the main sphere on the plane and cannot follow the stem's contact, use model = \"rigid\"; {}",
                        c_td.acos(),
                        ContactModel::describe_state(self, y)
                    ),
                ))
            }
            Watch::ContensouStick => {
                self.plane_mut().normal_branch = None;
                let (yn, stuck) = settle_at_stick(self, y);
                *y = yn;
                if stuck {
                    log.start_rolling(t);
                    log.push(t, Happened::ContensouStick);
                }
                Flow::Continue
            }
            Watch::SlipZero | Watch::StickLimit => {
                self.plane_mut().normal_branch = None;
                match self.plane().mode {
                    Mode::Sliding => {
                        let (yn, stuck) = settle_at_zero_slip(self, y);
                        *y = yn;
                        if stuck {
                            log.start_rolling(t);
                            log.push(t, Happened::Stick);
                        }
                    }
                    Mode::Rolling => {
                        let needed = self.contact_wrench(y).ok();
                        *y = self.to_rolling(y);
                        self.plane_mut().slip_off_wrench(needed);
                        log.stop_rolling(t);
                        log.push(t, Happened::Slip);
                    }
                }
                Flow::Continue
            }
            _ => Flow::End,
        }
    }

    fn explain(&self, sc: &Scenario, err: ModelError) -> (Failure, String) {
        match err {
            ModelError::Painleve { theta, solutions } => (
                Failure::Painleve,
                painleve_why(sc, "theta_ddot-N system", theta, solutions),
            ),
            ModelError::Singular { .. } => (Failure::Pole, err.to_string()),
            ModelError::Chattering { .. } => (Failure::Chattering, err.to_string()),
        }
    }

    fn row(&self, t: f64, y: &[f64; D]) -> Sample {
        self.sample(t, y)
    }

    fn normal_force(&self, y: &[f64; D]) -> Option<f64> {
        let f = self.scales().force();
        self.contact_forces(y).ok().map(|(n, _)| n * f)
    }

    fn describe(&self, y: &[f64]) -> String {
        ContactModel::describe_state(self, y)
    }

    fn axis_norm_sq(&self, y: &[f64]) -> Option<f64> {
        ContactModel::axis_norm_sq(self, y)
    }
}
