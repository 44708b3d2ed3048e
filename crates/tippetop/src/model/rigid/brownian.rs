//! The overdamped (Brownian) rigid top above a hard unilateral wall
//! (`solver.model = "rigid"`, `solver.method = "brownian"`,
//! `surface.contact = "unilateral"`; docs/physics.md#brownian-wall).
//!
//! The top is a free body: one Euler–Maruyama step of the centre (3D,
//! mobility `1/(m γ_t)`) and of the attitude (a rotation by the rotation
//! vector of the angular velocity `(γ_r I)⁻¹ τ + noise`, body axes `A, A,
//! C`), with the generalised force of the model in flight (gravity, the
//! applied force at the lowest point, the adhesion `−U′(gap)` at the
//! lowest point, the wells, the body actuators). The plane is a wall: the
//! admissible set is `gap >= 0`. A step whose end falls below it is
//! mirrored back along the conormal (the displacement of the overdamped
//! body under a vertical push at the lowest point `P`: `Z/(m γ_t)` for
//! the centre, `a (k × Z)/(γ_r A)` for the attitude), to the gap it
//! overshot (the symmetrised reflected Euler scheme of Bossy, Gobet and
//! Talay, J. Appl. Prob. 41 (2004) 877, in the coordinates where the
//! diffusion is isotropic): no mass sticks on the wall and none leaks
//! through it. The stationary density is `e^{−U/kT}` (free-body volume:
//! Lebesgue × Haar) on `gap >= 0`.
//!
//! The on-plane constrained step ([`Rigid::brownian_step`]) is the model of
//! a bilateral (rigid) contact; it is not used here (its stationary density
//! carries the constraint's metric factor `sqrt(1 + m a² sin²θ/A)`, the
//! free body's on the wall does not: Fixman's theorem, docs §brownian-wall).
//!
//! The `N` column is the wall's mean force over the last step, its
//! impulse over the step ([`Wall::force`]).
//!
//! What is recorded: the top is *on the plane* from the start (its gap is
//! 0) until the gap at a step end exceeds the level `ℓ` ([`Wall::level`]),
//! where a `lift_off` is recorded; then *off* until a step's trial end
//! crosses the wall (the scheme's wall hit), where a `touchdown` is
//! recorded. Each record ends the segment at that step's end (a terminal
//! event, [`wall_event`]), where the model writes it into the run log;
//! the grid and the random stream go on unchanged.

use super::{AXIS, DIM, OMEGA, POS, Phase, QUAT, Rigid, RigidError, VEL, WF, quat_of, set3, v3};
use crate::integrate::{Direction, Event, OdeSystem};
use crate::model::Flow;
use crate::model::thermostat::{Bath, modes_basis};
use crate::model::vec3::{add, rotate, scale, turn_quaternion_by};
use crate::sim::events::{Happened, Watch};
use crate::sim::record::RunLog;
use crate::{Error, Failure};

/// The wall's record of a Brownian run with a unilateral contact (see the
/// module doc): scaled units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Wall {
    /// The gap `ℓ` (scaled) above which the top counts as off the plane:
    /// `min(R, E_b/F_a)` with adhesion (its range), `min(R, kT/(m g))`
    /// without (the thermal height), `R` if neither is finite.
    pub level: f64,
    /// True while the top is recorded on the plane.
    pub on: bool,
    /// Records so far (lift-offs plus touchdowns): the event's sign.
    pub changes: u64,
    /// End time (scaled) of the step of the last record.
    pub at: f64,
    /// The wall's mean force over the last step (scaled; the `N` column):
    /// its impulse `λ` over the step, `λ/h` (the centre moved by `λ/(m
    /// γ_t)` is what a force `λ/h` does in the step), 0 without a hit.
    pub force: f64,
}

impl Default for Wall {
    fn default() -> Self {
        Wall {
            level: f64::INFINITY,
            on: true,
            changes: 0,
            at: 0.0,
            force: 0.0,
        }
    }
}

/// How a step that ends below the wall is put back (only the mirror is
/// the model; the others are the wrong schemes the tests measure).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WallRule {
    /// The mirror along the conormal ([`Rigid::mirror`]).
    Mirror,
    /// The projection along the conormal onto `gap = 0` (the projected
    /// Euler scheme).
    #[cfg(test)]
    Project,
    /// Clipping: the centre raised to `gap = 0` (a projection along `Z`).
    #[cfg(test)]
    Clip,
    /// The mirror along `Z` alone (the centre raised by `−2 g₀`, the
    /// attitude not turned): not the conormal when `a sin θ ≠ 0`.
    #[cfg(test)]
    MirrorVertical,
}

/// The terminal event of a record (a lift-off or touchdown at a step's
/// end): a function of time alone, `±1` with the sign flipped at each
/// record and `−` that before the record's time, so the sign changes
/// exactly at the step's end and the root finder returns that end.
pub(super) fn wall_event() -> (Watch, Event<Rigid, DIM>) {
    (
        Watch::Touchdown,
        Event {
            g: Box::new(|m, t, _| {
                let s = if m.wall.changes % 2 == 0 { 1.0 } else { -1.0 };
                if t >= m.wall.at { s } else { -s }
            }),
            direction: Direction::Either,
            terminal: true,
            step_to_event: false,
        },
    )
}

impl Rigid {
    /// True for the overdamped free body with a wall: a Brownian run with
    /// unilateral contact.
    pub(super) fn brownian_wall(&self) -> bool {
        self.brownian
            && self.thermal.is_some()
            && self.contact.contact_mode() == crate::ContactMode::Unilateral
    }

    /// The start of a wall run: a free body (phase `Flight` throughout),
    /// recorded on the plane, with its level `ℓ`.
    pub(super) fn start_wall(&mut self) {
        self.phase = Phase::Flight;
        self.flight_start = 0.0;
        let cv = self.contact.forces().centre_vertical();
        let kt = self.thermal.map_or(0.0, |b| b.kt);
        let scale_len = if cv.force > 0.0 {
            cv.energy / cv.force
        } else if self.g > 0.0 && kt > 0.0 {
            kt / self.g
        } else {
            f64::INFINITY
        };
        self.wall = Wall {
            level: self.rho.min(scale_len),
            ..Wall::default()
        };
    }

    /// One step of the overdamped free body with the wall (module doc):
    /// Euler–Maruyama of the centre and the attitude with the 6 normals
    /// `xi` (`x, y`, the rotational modes along `k̂, ê, f̂`, `z`: the order
    /// of the Langevin flight step), then the mirror at the wall. The
    /// state's velocities are set to the drift part, `W_f` takes the
    /// energy change, and the record is updated at the step's end `t + h`.
    pub(super) fn brownian_free_step(
        &mut self,
        t: f64,
        y: &mut [f64; DIM],
        h: f64,
        xi: &[f64],
    ) -> Result<(), RigidError> {
        self.free_step(t, y, h, xi, WallRule::Mirror)
    }

    /// [`Rigid::brownian_free_step`] with the wall treated by `rule`.
    fn free_step(
        &mut self,
        t: f64,
        y: &mut [f64; DIM],
        h: f64,
        xi: &[f64],
        rule: WallRule,
    ) -> Result<(), RigidError> {
        let Some(b) = self.thermal else { return Ok(()) };
        // A step of zero length is the identity (the noise's amplitude
        // `sqrt(2 kT/(γ h))` would be infinite). The engine no longer takes
        // such steps (its landing slack grows with the step
        // number); this guard stays for direct callers.
        if h.is_nan() || h <= 0.0 {
            return Ok(());
        }
        self.phase = Phase::Flight;
        let en0 = self.energy_scaled(y);
        let mut rest = *y;
        rest[VEL..VEL + 3].fill(0.0);
        rest[OMEGA..OMEGA + 3].fill(0.0);
        let mut dy = [0.0; DIM];
        <Self as OdeSystem<DIM>>::rhs(self, t, &rest, &mut dy)?;
        // Drift: F/(m γ_t) and (γ_r I)⁻¹ τ, the accelerations at rest over
        // the damping rates (m = 1).
        let vd = scale(1.0 / b.gt, v3(&dy, VEL));
        let nd = scale(1.0 / b.gr, v3(&dy, OMEGA));
        let st = (2.0 * b.kt / (b.gt * h)).sqrt();
        let v = [vd[0] + st * xi[0], vd[1] + st * xi[1], vd[2] + st * xi[5]];
        let ([kn, eh, fh], _) = modes_basis(v3(y, AXIS));
        let mut w = nd;
        for (j, (dir, mass)) in [(kn, self.ic), (eh, self.ia), (fh, self.ia)]
            .into_iter()
            .enumerate()
        {
            let amp = (2.0 * b.kt / (b.gr * mass * h)).sqrt();
            w = add(w, scale(amp * xi[2 + j], dir));
        }
        self.turn(y, scale(h, w));
        for i in 0..3 {
            y[POS + i] += h * v[i];
        }
        let impulse = match rule {
            WallRule::Mirror => self.mirror(y, &b, 1.0),
            #[cfg(test)]
            WallRule::Project => self.mirror(y, &b, 0.0),
            #[cfg(test)]
            WallRule::Clip => {
                let g = self.gap(y);
                (g < 0.0).then(|| {
                    y[POS + 2] -= g;
                    -g * b.gt
                })
            }
            #[cfg(test)]
            WallRule::MirrorVertical => {
                let g = self.gap(y);
                (g < 0.0).then(|| {
                    y[POS + 2] -= 2.0 * g;
                    -2.0 * g * b.gt
                })
            }
        };
        let hit = impulse.is_some();
        self.wall.force = impulse.map_or(0.0, |l| l / h);
        set3(y, VEL, vd);
        set3(y, OMEGA, nd);
        y[WF] += self.energy_scaled(y) - en0;
        self.record(t + h, hit, self.gap(y));
        Ok(())
    }

    /// Turn the axis and the attitude by the rotation vector `rv` (the
    /// same rotation: `|k| = 1` and `|q| = 1` to rounding).
    fn turn(&self, y: &mut [f64; DIM], rv: [f64; 3]) {
        let k = rotate(rv, v3(y, AXIS));
        set3(y, AXIS, k);
        let q = turn_quaternion_by(rv, quat_of(y));
        y[QUAT..QUAT + 4].copy_from_slice(&q);
    }

    /// The mirror at the wall: if the gap `g₀` at the trial point is
    /// negative, move along the conormal there, the centre by `λ/γ_t` up
    /// and the attitude by the angle `λ a sin θ/(γ_r A)` about
    /// `ê = k × Z/|k × Z|` (which raises `k_Z`), with `λ` such that the gap
    /// is `−f g₀` (exactly on the path: `gap(λ) = z + λ/γ_t + a cos(θ −
    /// c λ) − ρ`, solved by Newton's method from the linearised `λ`):
    /// `f = 1` is the mirror, `f = 0` the projection (tests only).
    /// Returns the impulse `λ` (scaled, `m = 1`) if the step hit the wall.
    fn mirror(&self, y: &mut [f64; DIM], b: &Bath, f: f64) -> Option<f64> {
        let g0 = self.gap(y);
        if g0 >= 0.0 {
            return None;
        }
        let k = v3(y, AXIS);
        // k × Z = (k_y, −k_x, 0), |k × Z| = sin θ.
        let e = [k[1], -k[0], 0.0];
        let s = e[0].hypot(e[1]);
        let th = s.atan2(k[2]);
        let c = self.a * s / (b.gr * self.ia);
        let z = y[POS + 2];
        let res = |l: f64| z + l / b.gt + self.a * (th - c * l).cos() - self.rho + f * g0;
        let df = |l: f64| 1.0 / b.gt + self.a * c * (th - c * l).sin();
        // Newton's method from the linearised λ, kept in a bracket
        // [lo, hi] of the root (res(0) = (1 + f) g₀ < 0; res >= λ/γ_t +
        // (1 + f) g₀ − 2|a| > 0 at hi), bisecting where a step leaves it.
        let (mut lo, mut hi) = (0.0, b.gt * ((1.0 + f) * -g0 + 2.0 * self.a.abs()));
        let mut l = -(1.0 + f) * g0 / df(0.0);
        if !(l > lo && l < hi) {
            l = 0.5 * (lo + hi);
        }
        for _ in 0..100 {
            let r = res(l);
            if r == 0.0 {
                break;
            }
            if r < 0.0 {
                lo = l;
            } else {
                hi = l;
            }
            let d = df(l);
            let mut next = l - r / d;
            if !(d > 0.0 && next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let done = (next - l).abs() <= 4.0 * f64::EPSILON * l.abs();
            l = next;
            if done {
                break;
            }
        }
        y[POS + 2] += l / b.gt;
        if s > 0.0 {
            self.turn(y, scale(c * l / s, e));
        }
        // Rounding (or a failed Newton step) must not leave it below.
        let g = self.gap(y);
        if g < 0.0 {
            y[POS + 2] -= g;
            l -= g * b.gt;
        }
        Some(l)
    }

    /// Update the record at the step's end `t_end` (module doc): off above
    /// the level, on at a wall hit; at most one record per step.
    fn record(&mut self, t_end: f64, hit: bool, gap: f64) {
        let change = if self.wall.on {
            gap > self.wall.level
        } else {
            hit
        };
        if change {
            self.wall.on = !self.wall.on;
            self.wall.changes += 1;
            self.wall.at = t_end;
        }
    }

    /// The record's terminal event at `t`: write the lift-off or touchdown
    /// into the run log (`lift_off` opens a flight, `touchdown` closes it),
    /// within the run's limit of transitions.
    pub(super) fn wall_terminal(&mut self, t: f64, y: &[f64; DIM], log: &mut RunLog) -> Flow {
        self.transitions += 1;
        if self.transitions > super::MAX_TRANSITIONS {
            return Flow::Stop(Error::runtime(
                t * self.scales.time,
                Failure::SwitchLimit,
                format!(
                    "more than {} lift-offs and touchdowns; {}",
                    super::MAX_TRANSITIONS,
                    super::describe_state(self, y)
                ),
            ));
        }
        if self.wall.on {
            log.push(t, Happened::Touchdown);
            log.land(t);
        } else {
            self.flight_start = t;
            log.lift_off(t);
        }
        Flow::Continue
    }
}

#[cfg(test)]
mod tests {
    //! The wall's treatment measured against the closed form of
    //! docs/physics.md#brownian-wall (test 1 there), with the model's mirror and
    //! two wrong schemes, on the same normals: how many standard errors a
    //! wrong wall is off.
    use super::*;
    use crate::input::thermal::BOLTZMANN;
    use crate::{ContactMode, Forcing, Method, ModelKind, Scenario};

    /// The eccentric nano top (`a = 0.6 R`, `A = C = m a²/2`) at 300 K with
    /// `γ_t = γ_r = γ`, gravity such that `m g R/kT = 1.5` (so `m g a/kT =
    /// 0.9`), unilateral contact, the Brownian method at the rule's limit.
    pub(crate) fn wall_top() -> Scenario {
        let mut sc = Scenario::nano();
        let r = sc.top.radius;
        sc.top.offset = 0.6 * r;
        let ma2 = sc.top.mass * sc.top.offset * sc.top.offset;
        sc.top.inertia_transverse = ma2 / 2.0;
        sc.top.inertia_axial = ma2 / 2.0;
        sc.surface.friction = 0.0;
        sc.surface.contact = ContactMode::Unilateral;
        let kt = BOLTZMANN * 300.0;
        sc.surface.gravity = 1.5 * kt / (sc.top.mass * r);
        sc.forcing = Forcing { windows: vec![] };
        sc.initial.theta = 1.0;
        sc.initial.spin = 0.0;
        sc.solver.model = ModelKind::Rigid;
        sc.solver.method = Method::Brownian;
        let gamma = 1e11;
        sc.thermal.temperature = 300.0;
        sc.thermal.damping_translational = gamma;
        sc.thermal.damping_rotational = gamma;
        sc.thermal.seed = Some(20261124);
        sc
    }

    /// Batch means (40 batches): mean and standard error.
    fn mean_se(v: &[f64]) -> (f64, f64) {
        let nb = 40;
        let per = v.len() / nb;
        let means: Vec<f64> = (0..nb)
            .map(|b| v[b * per..(b + 1) * per].iter().sum::<f64>() / per as f64)
            .collect();
        let m = means.iter().sum::<f64>() / nb as f64;
        let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (nb - 1) as f64;
        (m, (var / nb as f64).sqrt())
    }

    /// Run `steps` steps of the free step with `rule` (the step at the
    /// rule's limit: the binding rate is the tilt's under gravity,
    /// `m g (R + a)/(γ A)`), recording `cos θ` and the gap (in units of
    /// `kT/(m g)`) every 20 steps after 5 %.
    fn run(rule: WallRule, steps: u64) -> (Vec<f64>, Vec<f64>, u64) {
        let sc = wall_top();
        let mut m = Rigid::new(&sc);
        let tu = m.scales.time;
        let (gam, ia) = (sc.thermal.damping_rotational, sc.top.inertia_transverse);
        let load_rate =
            sc.top.mass * sc.surface.gravity * (sc.top.radius + sc.top.offset) / (gam * ia);
        let h = crate::input::thermal::MAX_BROWNIAN_STEP_RATE / load_rate / tu;
        m.latch_force(0.0);
        m.start_wall();
        let mut y = m.scale_state(&sc.initial);
        let stream = crate::random::Stream::new(7, 0);
        let b = m.thermal.unwrap();
        let height = b.kt / m.g;
        let (mut c, mut g, mut below) = (Vec::new(), Vec::new(), 0);
        let mut xi = [0.0; 6];
        for i in 0..steps {
            stream.normals(i, &mut xi);
            m.free_step(i as f64 * h, &mut y, h, &xi, rule).unwrap();
            if i % 20 == 0 && i > steps / 20 {
                let k = v3(&y, AXIS);
                c.push(k[2]);
                let gap = m.gap(&y);
                if gap < 0.0 {
                    below += 1;
                }
                g.push(gap / height);
            }
        }
        (c, g, below)
    }

    /// Test 1 of §brownian-wall on the model's step: `⟨cos θ⟩ = coth b − 1/b` with
    /// `b = m g a/kT = 0.9` (0.28491), the gap exponential with mean
    /// `kT/(m g)` (1 in these units) and `P(gap < 0.05 kT/(m g)) = 1 −
    /// e^{−0.05}` (0.048771). Clipping (a projection onto the wall) puts an
    /// atom at gap 0 (the last probability far too high); the vertical
    /// mirror (not the conormal) biases the tilt. 2 000 000 steps each.
    #[test]
    fn mirror_is_the_wall_and_wrong_walls_fail() {
        let b = 0.9f64;
        let want_cos = 1.0 / b.tanh() - 1.0 / b;
        let want_near = 1.0 - (-0.05f64).exp();
        let steps = 20_000_000;
        let (mut z, mut atoms) = (Vec::new(), Vec::new());
        for rule in [
            WallRule::Mirror,
            WallRule::Project,
            WallRule::Clip,
            WallRule::MirrorVertical,
        ] {
            let n = if rule == WallRule::Mirror {
                steps
            } else {
                steps / 2
            };
            let (c, g, below) = run(rule, n);
            let atom = g.iter().filter(|&&x| x < 1e-9).count() as f64 / g.len() as f64;
            if rule == WallRule::Mirror {
                assert_eq!(below, 0, "{rule:?}: below the wall");
            }
            let near: Vec<f64> = g.iter().map(|&x| f64::from(u8::from(x < 0.05))).collect();
            let sc = |(m, se): (f64, f64), want: f64| (m, se, (m - want) / se);
            let zs = [
                sc(mean_se(&c), want_cos),
                sc(mean_se(&g), 1.0),
                sc(mean_se(&near), want_near),
            ];
            atoms.push(atom);
            eprintln!(
                "{rule:?} ({n} steps, gap < 1e-9 in {atom:.5} of the rows): <cos theta> {:.5} ± {:.5} ({:+.2} SE), <gap> {:.5} ± {:.5} ({:+.2} SE), P(gap < 0.05) {:.5} ± {:.5} ({:+.2} SE)",
                zs[0].0, zs[0].1, zs[0].2, zs[1].0, zs[1].1, zs[1].2, zs[2].0, zs[2].1, zs[2].2
            );
            z.push(zs);
        }
        // The model: every check within 5 SE, the SEs small enough to tell.
        for (m, se, zz) in z[0] {
            assert!(zz.abs() < 5.0, "mirror: {m} ± {se}: {zz} SE");
        }
        assert!(z[0][0].1 < 0.01 && z[0][1].1 < 0.03 && z[0][2].1 < 0.002);
        assert_eq!(atoms[0], 0.0, "the mirror leaves no mass on the wall");
        // The projection: an atom on the wall (sticking), seen by the
        // probability near the wall.
        assert!(atoms[1] > 0.01, "projection: atom {}", atoms[1]);
        assert!(z[1][2].2 > 8.0, "projection not caught: {:?}", z[1]);
        // Clipping and the vertical mirror do not turn the top at the wall:
        // its tilt never feels the wall (gravity has no torque about the
        // centre of mass) and the orientation is uniform.
        for (i, name) in [(2, "clip"), (3, "vertical mirror")] {
            assert!(z[i][0].2.abs() > 8.0, "{name} not caught: {:?}", z[i]);
        }
    }

    /// The weak order of the mirrored step, measured: `E[f(y_T)]` for
    /// `f` = the gap (in `kT/(m g)`) and `cos θ` at `T = 32 H`, from the
    /// top standing on the wall at θ = 1, with steps `H, H/2, H/4, H/8`
    /// (`H` = 16 times the rule's limit, so the tilt relaxes about once by
    /// `T`), each path's coarse normals the scaled sums of its fine ones
    /// (coupled: the differences between step sizes have small variance).
    /// A scheme of weak order `p` has `E_h − E_{h/2} ∝ h^p`, so successive
    /// differences shrink by `2^p`. Bossy, Gobet & Talay (2004) prove order
    /// 1 for the symmetrised reflected Euler scheme in R^d. Measured
    /// (200 000 paths; docs/physics.md#brownian-wall): the gap's
    /// differences 0.00310 ± 0.00019, 0.00104 ± 0.00013, 0.00048 ± 0.00009
    /// (order 1.6, 1.1), but `cos θ`'s 0.00317 ± 0.00013, 0.00227 ± 0.00009,
    /// 0.00166 ± 0.00006 (order 0.48, 0.45): the tilt converges at order
    /// 1/2 at the wall (far from it, the same differences are ~1e-4; with
    /// Bossy–Gobet–Talay's exact symmetric point, `λ = 2 λ₁` along the
    /// conormal, instead of `gap = −g₀`, the gap's differences vanish but
    /// the tilt's stay at order 0.43–0.55: tried, not kept). The assertions
    /// guard what is measured, not the theory's 1 for the tilt.
    /// ~20 s in release:
    /// `cargo test -p tippetop --release --lib weak_order_at_the_wall -- --ignored --nocapture`.
    #[test]
    #[ignore = "200 000 coupled paths at 4 step sizes: ~20 s in release"]
    fn weak_order_at_the_wall() {
        let sc = wall_top();
        let proto = Rigid::new(&sc);
        let tu = proto.scales.time;
        let (gam, ia) = (sc.thermal.damping_rotational, sc.top.inertia_transverse);
        let load_rate =
            sc.top.mass * sc.surface.gravity * (sc.top.radius + sc.top.offset) / (gam * ia);
        let big = 16.0 * crate::input::thermal::MAX_BROWNIAN_STEP_RATE / load_rate / tu;
        let (levels, coarse_steps) = (4usize, 32usize);
        let paths: u64 = 200_000;
        let fine = coarse_steps << (levels - 1);
        let height = proto.thermal.unwrap().kt / proto.g;
        // Sums over paths of f at T for each level (H, H/2, …) and of the
        // differences between neighbouring levels (and their squares).
        let mut mean = [[0.0f64; 2]; 4];
        let mut diff = [[0.0f64; 2]; 3];
        let mut diff2 = [[0.0f64; 2]; 3];
        let mut xi_f = vec![[0.0f64; 6]; fine];
        for path in 0..paths {
            let stream = crate::random::Stream::new(11, path);
            for (i, x) in xi_f.iter_mut().enumerate() {
                stream.normals(i as u64, x);
            }
            let mut out = [[0.0f64; 2]; 4];
            for (l, o) in out.iter_mut().enumerate() {
                // Level l: 2^l steps per coarse step, each of big/2^l, its
                // normals the sums of 2^(3−l) fine ones over sqrt(2^(3−l)).
                let per = 1usize << l;
                let group = 1usize << (levels - 1 - l);
                let h = big / per as f64;
                let mut m = proto.clone();
                m.latch_force(0.0);
                m.start_wall();
                let mut y = m.scale_state(&sc.initial);
                let norm = 1.0 / (group as f64).sqrt();
                for j in 0..coarse_steps * per {
                    let mut xi = [0.0; 6];
                    for g in &xi_f[j * group..(j + 1) * group] {
                        for c in 0..6 {
                            xi[c] += g[c];
                        }
                    }
                    for c in &mut xi {
                        *c *= norm;
                    }
                    m.free_step(j as f64 * h, &mut y, h, &xi, WallRule::Mirror)
                        .unwrap();
                }
                *o = [m.gap(&y) / height, v3(&y, AXIS)[2]];
            }
            for l in 0..4 {
                for q in 0..2 {
                    mean[l][q] += out[l][q];
                    if l < 3 {
                        let d = out[l][q] - out[l + 1][q];
                        diff[l][q] += d;
                        diff2[l][q] += d * d;
                    }
                }
            }
        }
        let n = paths as f64;
        for (q, name) in ["gap", "cos theta"].into_iter().enumerate() {
            let d: Vec<(f64, f64)> = (0..3)
                .map(|l| {
                    let m = diff[l][q] / n;
                    (m, ((diff2[l][q] / n - m * m) / n).sqrt())
                })
                .collect();
            let ratios = [d[0].0 / d[1].0, d[1].0 / d[2].0];
            eprintln!(
                "{name}: E at H..H/8 {:?}; E_h - E_h/2 = {:.5} ± {:.5}, {:.5} ± {:.5}, {:.5} ± {:.5}; ratios {:.2}, {:.2} (order {:.2}, {:.2})",
                (0..4).map(|l| mean[l][q] / n).collect::<Vec<_>>(),
                d[0].0,
                d[0].1,
                d[1].0,
                d[1].1,
                d[2].0,
                d[2].1,
                ratios[0],
                ratios[1],
                ratios[0].log2(),
                ratios[1].log2()
            );
            // Each difference resolved (> 4 SE) and shrinking: the scheme
            // is consistent. The last ratio's order: the gap's (SE ~0.33
            // from the differences' SEs) above 0.3; the tilt's (SE ~0.08)
            // within 0.35 of 1/2, which excludes 1 (a known gap: a scheme
            // that reaches order 1 for the tilt fails here, on purpose, and
            // updates this test and §brownian-wall).
            assert!(
                d[0].0 > 4.0 * d[0].1 && d[2].0 > 4.0 * d[2].1,
                "{name}: {d:?}"
            );
            assert!(d[2].0 < d[0].0, "{name}: not converging: {d:?}");
            let order = ratios[1].log2();
            if q == 0 {
                assert!(order > 0.3, "{name}: order {order}");
            } else {
                assert!((order - 0.5).abs() < 0.35, "{name}: order {order}");
            }
        }
    }
}
