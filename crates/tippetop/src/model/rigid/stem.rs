//! The stem (docs/physics.md#stem): a second contact sphere of radius `r2`
//! (scaled `r2/R`) centred on the symmetry axis at `S = O + d2 k`.
//!
//! The rigid model's contact geometry is that of its *active* sphere (the
//! fields `a`, `rho`: centre offset along `k` and radius, scaled): the
//! contact vector `r = a k − rho Z`, the gap `z_O + a k_Z − rho`, the
//! constraint `z_O = rho − a k_Z`, and everything built on them (closure,
//! rolling, impact, Jellett's `J = −L·r`). The main sphere is `(a/R, 1)`, the
//! stem's `(d2/R, r2/R)`; the top starts on the main sphere.
//!
//! The sphere that is not active is watched by its gap (event
//! [`Watch::SphereTouchdown`], in contact and in flight). When it reaches
//! the plane it becomes the active sphere and lands with the rigid model's
//! impact law (`Rigid::touch_down`: Newton restitution, Coulomb impulse);
//! the previously active sphere is released. If that impulse would drive the
//! released sphere into the plane (its contact point's normal velocity after
//! the impact negative), both spheres stay on the plane: a two-contact
//! frictional problem, which is not modelled; the run stops there
//! (`not_modelled`).

use super::{
    AXIS, DIM, Eval, MAX_TRANSITIONS, OMEGA, PENETRATION_GUARD, POS, Phase, QUAT, Rigid,
    RigidError, V3, VEL, WA, WF, Z, describe_state, enter_contact, quat_of, set3, v3,
};
use crate::integrate::{Direction, Event};
use crate::model::vec3::{add, cross, dot, scale, sub};
use crate::model::{Flow, Mode};
use crate::sim::events::{Happened, Watch};
use crate::sim::record::RunLog;
use crate::{Error, Failure};

impl Rigid {
    /// `(centre offset, radius)` (scaled) of the sphere that is not active;
    /// `None` without a stem.
    fn other_sphere(&self) -> Option<(f64, f64)> {
        let stem = self.spheres.1?;
        Some(if self.on_stem { self.spheres.0 } else { stem })
    }

    /// Gap between the non-active sphere and the plane (scaled): with the
    /// constraint's height in contact, `rho − rho' + (a' − a) k_Z`, and the
    /// state's in flight, `z_O + a' k_Z − rho'` (`a'`, `rho'` that sphere's);
    /// +∞ without a stem.
    pub fn other_gap(&self, y: &[f64; DIM]) -> f64 {
        let Some((c, rho)) = self.other_sphere() else {
            return f64::INFINITY;
        };
        let kz = y[AXIS + 2];
        match self.phase {
            Phase::Contact => self.rho - rho + (c - self.a) * kz,
            Phase::Flight => y[POS + 2] + c * kz - rho,
        }
    }

    /// Rate of [`Rigid::other_gap`] (scaled).
    fn other_gap_rate(&self, y: &[f64; DIM]) -> f64 {
        let Some((c, _)) = self.other_sphere() else {
            return 0.0;
        };
        let kin = self.kin(y);
        let kdz = cross(kin.n, kin.k)[2];
        match self.phase {
            Phase::Contact => (c - self.a) * kdz,
            Phase::Flight => y[VEL + 2] + c * kdz,
        }
    }

    /// The non-active sphere's touchdown event function: its gap over the
    /// time since the last switch of spheres, and the gap's rate at the
    /// switch itself (where that sphere has just left the plane, gap 0), as
    /// [`Rigid::touchdown_function`].
    pub fn other_touchdown_function(&self, t: f64, y: &[f64; DIM]) -> f64 {
        let dt = t - self.switch_start;
        if dt > 0.0 {
            self.other_gap(y) / dt
        } else {
            self.other_gap_rate(y)
        }
    }

    /// The stem's events (none without a stem): the non-active sphere
    /// reaches the plane, and in flight its penetration guard.
    pub(super) fn stem_events(&self, ev: &mut Vec<(Watch, Event<Rigid, DIM>)>) {
        if self.spheres.1.is_none() {
            return;
        }
        if self.both {
            // Two-contact phase: θ is held (k_Z fixed); either normal force
            // through zero ends it.
            ev.retain(|(w, _)| !matches!(w, Watch::NormalZero | Watch::ThetaMax));
            for i in 0..2 {
                ev.push((
                    Watch::SphereLiftoff,
                    Event {
                        g: Box::new(move |m, _, y| {
                            m.two_normals(y)
                                .map(|n| if i == 0 { n.0 } else { n.1 })
                                .unwrap_or(f64::NAN)
                        }),
                        direction: Direction::Falling,
                        terminal: true,
                        step_to_event: false,
                    },
                ));
            }
            return;
        }
        ev.push((
            Watch::SphereTouchdown,
            Event {
                g: Box::new(|m, t, y| m.other_touchdown_function(t, y)),
                direction: Direction::Falling,
                terminal: true,
                step_to_event: false,
            },
        ));
        if self.phase == Phase::Flight {
            ev.push((
                Watch::SphereTouchdown,
                Event {
                    g: Box::new(|m, _, y| m.other_gap(y) + PENETRATION_GUARD),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            ));
        }
    }

    /// The non-active sphere reached the plane at `t`: it becomes the
    /// active one and lands with the impact law (`touch_down`); the other
    /// is released (module doc). Stops with `not_modelled` where the
    /// impact would push the released sphere into the plane.
    pub(super) fn switch_sphere(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        let tu = self.scales.time;
        let Some(new) = self.other_sphere() else {
            return Flow::Continue;
        };
        self.transitions += 1;
        if self.transitions > MAX_TRANSITIONS {
            return Flow::Stop(Error::runtime(
                t * tu,
                Failure::SwitchLimit,
                format!(
                    "more than {MAX_TRANSITIONS} lift-offs, touchdowns and switches between the main sphere and the stem; {}",
                    describe_state(self, y)
                ),
            ));
        }
        let was_contact = self.phase == Phase::Contact;
        let old = (self.a, self.rho);
        if was_contact {
            // The state onto the old sphere's constraint (and the rolling
            // velocity while rolling): its stored z_O, v then give the
            // energy the contact phase had.
            if self.contact.mode == Mode::Rolling {
                self.project_rolling(y);
                self.contact.mode = Mode::Sliding;
                self.contact.slip_hint = [0.0; 2];
                log.stop_rolling(t);
            } else {
                self.project_contact(y);
            }
        }
        (self.a, self.rho) = new;
        self.on_stem = !self.on_stem;
        self.switch_start = t;
        if was_contact {
            // The new sphere's impact must release the old one: the old
            // contact point's normal velocity after it must be positive.
            // Where it is not (zero to `ZENO` of the speed, or negative),
            // both spheres stay on the plane: the two-contact phase.
            let (yn, _, _) = match self.impact(y) {
                Ok(v) => v,
                Err(err) => {
                    return Flow::Stop(Error::runtime(
                        t * tu,
                        Failure::Painleve,
                        format!("{err}; {}", describe_state(self, y)),
                    ));
                }
            };
            let kin = self.kin(&yn);
            let v_old = yn[VEL + 2] + old.0 * cross(kin.n, kin.k)[2];
            let v = v3(&yn, VEL);
            let size = dot(v, v).sqrt() + dot(kin.n, kin.n).sqrt() * (old.0 + old.1);
            if v_old <= ZENO * size {
                return self.enter_two(t, y, log, old);
            }
            if !self.on_stem {
                log.stem_off(t);
            }
        }
        // The impact law is the touchdown's (from flight).
        self.phase = Phase::Flight;
        self.flight_start = t;
        let flow = self.touch_down(t, y, log);
        if was_contact && self.phase == Phase::Flight && !log.in_flight() {
            // The new sphere rebounds: the top is in flight.
            log.lift_off(t);
        }
        flow
    }

    /// Enter the two-contact phase at a switch from contact on `old`
    /// (`(a, rho)` of the sphere that was active) to the sphere now active:
    /// the active sphere's impact (the touchdown law), then frictionless
    /// normal impulses at both contact points that zero both normal
    /// velocities (the energy they remove is booked into `W_f`), then
    /// [`Rigid::settle_two`]. Stops (`not_modelled`) with restitution > 0,
    /// the exact Coulomb law (its stick at two contacts is not modelled), or
    /// where the impulses would pull.
    fn enter_two(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog, old: (f64, f64)) -> Flow {
        let tu = self.scales.time;
        let at_once = |m: &Rigid, y: &[f64; DIM], why: &str| {
            Flow::Stop(Error::runtime(
                t * tu,
                Failure::NotModelled,
                format!(
                    "the main sphere and the stem touch the plane at once at t = {:e} s ({why}): this two-contact problem is not modelled (docs/physics.md#stem); {}",
                    t * tu,
                    describe_state(m, y)
                ),
            ))
        };
        if self.restitution != 0.0 {
            return at_once(self, y, "with restitution > 0");
        }
        if self.contact.is_exact() {
            return at_once(
                self,
                y,
                "with the exact Coulomb law, whose stick at two contacts is not modelled; a smooth law such as friction_law = \"contensou\" is",
            );
        }
        let before = self.energy_raw(y);
        let (mut yn, _, _) = match self.impact(y) {
            Ok(v) => v,
            Err(_) => return at_once(self, y, "the impact has no solution"),
        };
        // Frictionless normal impulses P at both points: the normal
        // velocity of point i changes by Σ_j K_ij P_j,
        // K_ij = 1/m + (r_i × Z)·I⁻¹(r_j × Z).
        let kin = self.kin(&yn);
        let k = kin.k;
        let rs = [kin.r, sub(scale(old.0, k), scale(old.1, Z))];
        let kij =
            |i: usize, j: usize| 1.0 + dot(cross(rs[i], Z), self.inv_inertia(k, cross(rs[j], Z)));
        let vn = |yy: &[f64; DIM], r: V3| {
            let n = v3(yy, OMEGA);
            add(v3(yy, VEL), cross(n, r))[2]
        };
        let b = [-vn(&yn, rs[0]), -vn(&yn, rs[1])];
        let (k00, k01, k10, k11) = (kij(0, 0), kij(0, 1), kij(1, 0), kij(1, 1));
        let det = k00 * k11 - k01 * k10;
        if det.is_nan() || det <= 0.0 {
            return at_once(self, y, "the two normal impulses have no unique solution");
        }
        let p = [
            (b[0] * k11 - k01 * b[1]) / det,
            (k00 * b[1] - k10 * b[0]) / det,
        ];
        // A slightly separating old point (normal speed up to ZENO of the
        // speed scale) takes a small pulling impulse; more is a pull.
        let v = v3(&yn, VEL);
        let size = dot(v, v).sqrt() + dot(kin.n, kin.n).sqrt() * (old.0 + old.1);
        let pull = p.iter().any(|&pi| pi < -10.0 * ZENO * size);
        if pull {
            return at_once(self, y, "the normal impulses would pull");
        }
        let imp = scale(p[0] + p[1], Z);
        let v_new = add(v3(&yn, VEL), imp);
        set3(&mut yn, VEL, v_new);
        let dn = add(cross(rs[0], scale(p[0], Z)), cross(rs[1], scale(p[1], Z)));
        let n_new = add(v3(&yn, OMEGA), self.inv_inertia(k, dn));
        set3(&mut yn, OMEGA, n_new);
        yn[POS + 2] = self.rho - self.a * k[2];
        *y = yn;
        y[WF] += self.energy_raw(y) - before;
        if self.on_stem {
            log.stem_on(t);
        } else {
            log.push(t, Happened::Touchdown);
        }
        self.bounces = 0;
        self.phase = Phase::Contact;
        self.flight_start = t;
        self.settle_two(t, y, log)
    }

    /// In contact on both spheres (just entered): keep both where both
    /// normal forces are positive; else release the one whose force is
    /// negative (both negative: the top flies).
    fn settle_two(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        self.both = true;
        self.project_contact(y);
        let (na, no) = self.two_normals(y).unwrap_or((f64::NAN, f64::NAN));
        if na >= 0.0 && no >= 0.0 {
            return Flow::Continue;
        }
        self.split_two(t, y, log, if na < no { 0 } else { 1 })
    }

    /// Leave the two-contact phase: sphere `lifting` (0 the active, 1 the
    /// other) leaves the plane; the other carries on alone (or the top flies
    /// if its normal force is negative too).
    fn split_two(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog, lifting: usize) -> Flow {
        self.both = false;
        self.switch_start = t;
        if lifting == 0 {
            if let Some(o) = self.other_sphere() {
                (self.a, self.rho) = o;
                self.on_stem = !self.on_stem;
            }
        }
        // The stem lifts: it is now the non-active sphere.
        if !self.on_stem {
            log.stem_off(t);
        }
        if enter_contact(self, t, y) == Phase::Flight {
            log.lift_off(t);
            if self.on_stem {
                log.stem_off(t);
            }
        }
        Flow::Continue
    }

    /// The event `N = 0` of one sphere in the two-contact phase.
    pub(super) fn leave_two(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        self.transitions += 1;
        let (na, no) = self.two_normals(y).unwrap_or((0.0, 1.0));
        self.split_two(t, y, log, if na <= no { 0 } else { 1 })
    }

    /// The normal forces `(N_active, N_other)` of the two-contact phase
    /// (scaled).
    pub fn two_normals(&self, y: &[f64; DIM]) -> Result<(f64, f64), RigidError> {
        self.two_contact(y).map(|(_, n)| (n[0], n[1]))
    }

    /// Evaluate the two-contact phase (the right-hand side of
    /// [`Rigid::eval`] there): `normal` is the sum of both normal forces
    /// (the plane's whole reaction), `friction` the sum of both friction
    /// forces.
    pub(super) fn eval_two(&self, y: &[f64; DIM]) -> Result<Eval, RigidError> {
        self.two_contact(y).map(|(e, _)| e)
    }

    /// The two-contact phase (§stem): the main sphere and the stem both on the
    /// plane, sliding. With `r_j = c_j k − rho_j Z`, the friction
    /// coefficient vector `f_j` of each contact's slip `v + n × r_j` (and the
    /// drilling `τ_j`, Contensou), `F_j = N_j (Z − f_j)`, both constraints
    /// `z_O + c_i k_Z = rho_i` twice differentiated give the 2 × 2 system
    /// `Σ_j N_j (1 + c_i (Z − f_j)·w_j) = Q_i`, `w_j = (I⁻¹ e) × r_j`,
    /// `e = k × Z`, `Q_i = g − c_i (ṅ₀·e + n_Z (n·k) − k_Z |n|²)` (the
    /// one-contact closure of the module doc for each sphere). No applied
    /// forces (validation).
    fn two_contact(&self, y: &[f64; DIM]) -> Result<(Eval, [f64; 2]), RigidError> {
        let kin = self.kin(y);
        let (k, n) = (kin.k, kin.n);
        let Some((co, rho_o)) = self.other_sphere() else {
            return Err(RigidError::Painleve {
                theta: kin.kh.atan2(k[2]),
                solutions: 0,
            });
        };
        let c = [self.a, co];
        let rs = [kin.r, sub(scale(co, k), scale(rho_o, Z))];
        let v = v3(y, VEL);
        let wk = dot(n, k);
        let nn = dot(n, n);
        let ndot0 = scale(-1.0, self.inv_inertia(k, cross(n, self.inertia(k, n))));
        let e = cross(k, Z);
        let ie = self.inv_inertia(k, e);
        let mut f = [[0.0; 3]; 2];
        let mut tau = [0.0; 2];
        let mut vp = [[0.0; 3]; 2];
        let mut w = [[0.0; 3]; 2];
        for j in 0..2 {
            vp[j] = add(v, cross(n, rs[j]));
            let v2 = [vp[j][0], vp[j][1]];
            let (f2, t) = match self.contact.drilling(v2, n[2]) {
                Some((f2, t)) => (f2, t),
                None => (self.contact.coefficient(v2), 0.0),
            };
            f[j] = [f2[0], f2[1], 0.0];
            tau[j] = t;
            w[j] = cross(ie, rs[j]);
        }
        let base = -dot(ndot0, e) - n[2] * wk + k[2] * nn;
        let q = [self.g + c[0] * base, self.g + c[1] * base];
        let m = |i: usize, j: usize| 1.0 + c[i] * (w[j][2] - dot(f[j], w[j]));
        let (m00, m01, m10, m11) = (m(0, 0), m(0, 1), m(1, 0), m(1, 1));
        let det = m00 * m11 - m01 * m10;
        let floor = 1e-12 * (m00.abs() * m11.abs() + m01.abs() * m10.abs());
        if det.is_nan() || det.abs() <= floor {
            return Err(RigidError::Painleve {
                theta: kin.kh.atan2(k[2]),
                solutions: 0,
            });
        }
        let normals = [
            (q[0] * m11 - m01 * q[1]) / det,
            (m00 * q[1] - m10 * q[0]) / det,
        ];
        let mut force = [0.0; 3];
        let mut torque = [0.0; 3];
        let mut friction = [0.0; 3];
        let mut power = 0.0;
        for j in 0..2 {
            let ff = scale(-normals[j], f[j]);
            let fj = add(scale(normals[j], Z), ff);
            force = add(force, fj);
            friction = add(friction, ff);
            let mz = -normals[j] * tau[j];
            torque = add(torque, add(cross(rs[j], fj), [0.0, 0.0, mz]));
            power += dot(ff, vp[j]) + mz * n[2];
        }
        let kdot = cross(n, k);
        let torque = sub(torque, scale((self.ic - self.ia) * wk, kdot));
        let mut dy = [0.0; DIM];
        set3(&mut dy, POS, v);
        set3(&mut dy, VEL, sub(force, scale(self.g, Z)));
        set3(&mut dy, OMEGA, self.inv_inertia(k, torque));
        dy[QUAT..QUAT + 4].copy_from_slice(&super::attitude_rate(quat_of(y), n));
        set3(&mut dy, super::AXIS, kdot);
        dy[WF] = power;
        dy[WA] = 0.0;
        Ok((
            Eval {
                dy,
                // The plane's whole reaction (the output's N column).
                normal: normals[0] + normals[1],
                friction,
                kin,
                q_free: q[0],
                // Both contacts' drilling torques about Z (§contensou).
                torque: -normals[0] * tau[0] - normals[1] * tau[1],
            },
            normals,
        ))
    }
}

/// Relative normal speed below which a switch of spheres keeps both on the
/// plane (the limit of a sequence of ever shorter rocking switches, which
/// the two-contact phase replaces).
pub const ZENO: f64 = 1e-6;
