//! Full 3D rigid-body model: centre-of-mass position and velocity, the
//! symmetry axis and the angular velocity in the world frame, and a unit
//! quaternion for the full attitude, with the contact at the sphere's lowest
//! point. It cross-checks the reduced (Euler-angle) model and handles what
//! that one cannot: `θ = 0` or `π` exactly, and lift-off (free flight,
//! touchdown).
//!
//! # State and units
//!
//! Scaled units as the reduced model ([`Scales`]: lengths by R, masses by m,
//! times by the same `Scales::of`), so tolerances mean the same.
//! The state (`DIM = 18`) is
//! `[x_O (3), v_O (3), q (4: w, x, y, z; body → world), n (3), W_f, W_a, k (3)]`:
//! the centre-of-mass position and velocity, the attitude quaternion, the
//! angular velocity, the work done so far by friction and by the applied
//! force, and the symmetry axis (unit vector `k = q e3 q*`; body principal
//! axes `e1, e2, e3`, `I = diag(A, A, C)`). Vectors are in the space frame.
//!
//! The dynamics of a symmetric body depend on its attitude only through `k`
//! (the inertia tensor is `I = A 1 + (C − A) k kᵀ`), so the right-hand side
//! reads `k` and `n` and never the quaternion: `q` carries the rotation
//! about the axis (the spin angle) along, and `k = q e3 q*` holds to the
//! integration error. Integrating `k` and the world-frame `n` rather than `q`
//! and the body-frame rates is what keeps Jellett's `J` (docs/physics.md
//! §rigid-model): `k` and `n` turn only at the precession and nutation rates, while
//! `q` and the body-frame rates turn with the spin, and an error in the spin
//! phase of `q` that `n_b` does not share rotates the world `n` about `k`,
//! which changes `J`.
//!
//! # Equations
//!
//! Geometric centre `C = O + a k`, lowest point `P = C − R Z`,
//! `r = P − O = a k − R Z`. With the contact force `F` at `P`:
//!
//! - Newton: `m v̇ = F − m g Z`, `ẋ = v`.
//! - Euler (world frame): `d(I n)/dt = r × F`, with
//!   `İ n = (C − A)(n·k) k̇`: `I ṅ = r × F − (C − A)(n·k) k̇`.
//! - Axis: `k̇ = n × k` (keeps `|k|` constant exactly, so it drifts only by
//!   the integration error, as in the vector form; `k` is normalised at
//!   every restart).
//! - Attitude: `q̇ = ½ (0, n) ⊗ q − κ (|q|² − 1) q` with `κ = 1` (per
//!   time unit): the second term makes `|q| = 1` attracting.
//! - `Ẇ_f = F_f · v_P`, `Ẇ_a = (−H) · v_P`, `v_P = v + n × r`.
//!
//! `F = N Z + F_f − H − h_z Z`: the vertical load `h_z` (force terms,
//! [`crate::physics::forces`]) adds `h_z (1/m + a w_Z)` to the closure's `Q`
//! below and `h_z` to the rolling `N`; `N` is the plane's reaction
//! (docs/physics.md#vertical-load). `H = h_x x̂ + h_y ŷ` is the paper's retarding force
//! (the force on the top is `−H`), `x̂` the horizontal unit vector along the
//! horizontal projection of `k`, `ŷ = Z × x̂` (world `X`, `Y` when `k` is
//! exactly vertical). `(h_x, h_y)` is latched per segment in
//! `begin_segment`. Friction `F_f = −N_f f(v_P)` with the horizontal slip
//! `v_P` and `f` from the law while sliding; `"coulomb"` is the exact
//! stick/slip law (below), `"coulomb_sliding"` has `f = 0` at exactly zero
//! slip and stops with the chattering error when the slip keeps reversing.
//!
//! # Normal force (contact)
//!
//! Contact holds the height of `C` at `R`: `z_O + a k_Z = R`. Twice
//! differentiated, with `k̈ = ṅ × k + n (n·k) − k |n|²` and
//! `ṅ = ṅ₀ + I⁻¹ (r × F)`, `ṅ₀ = −I⁻¹ (n × I n)` (world frame,
//! `I⁻¹ v = v/A + (1/C − 1/A)(v·k) k`), the constraint is linear in `N` for a
//! given friction direction:
//!
//! ```text
//! N D(σ) = Q,   e = k × Z,  w = (I⁻¹ e) × r,
//! D(σ) = m⁻¹ + a (w_Z − σ f·w),
//! Q    = g + a (H·w − ṅ₀·e − n_Z (n·k) + k_Z |n|²),
//! ```
//!
//! with `N_f = σ N` (per unit mass; `m = 1` in scaled units). For
//! `k = (s, 0, c)` this is exactly the reduced model's
//! `D = 1 + m a s (a s − σ h f_x)/A`. The branches are the on-plane models'
//! (the contact state's `ContactState::closure`): bilateral takes the self-consistent
//! sign (Painlevé error for 0 or 2 solutions) and, while sliding, latches it
//! per segment with N = 0 a terminal event where it flips; paper uses `N`
//! with its sign; unilateral flies when `N` falls through 0.
//!
//! The vertical position and velocity stay in the state: in contact
//! `v̇_z = N/m − g` is the constraint acceleration, so the constraint
//! `z_C = R`, `v_Cz = 0` drifts only by the integration error. In contact
//! they do not enter the dynamics at all (`r`, `v_P`'s horizontal part, `N`
//! depend on the attitude, `n` and horizontal `v` only); the energy and the
//! output `u_z` use the constraint values `z_O = R − a k_Z`,
//! `v_z = −a (n × k)_Z`. The state is projected back onto `z_C = R`,
//! `v_Cz = 0` (and `q`, `k` normalised) at every restart: lift-off, touchdown,
//! and the force schedule's switch times. The driver integrates from switch
//! to switch itself (one `solve` per segment, `begin_segment` latching the
//! force at the segment's start) instead of passing the switch times as
//! `tstops`, so that it can project there and, for unilateral contact, let
//! the top fly at once when the new force makes `N` negative (a jump of `N`
//! at a switch is not a zero crossing the event finder could see).
//!
//! # Exact Coulomb friction: rolling and switching
//!
//! [`Mode::Rolling`] (contact only) holds the horizontal slip at zero. The
//! velocity of the material point at the contact, `V(t) = v + n × r(t)`,
//! must stay zero, with `r = a k − R Z` the *current* contact point: it moves
//! over the body (`ṙ = a k̇ = a n × k`, not `n × r`). So the constraint is
//! `dV/dt = v̇ + ṅ × r + n × (a n × k) = 0` in all three components (the
//! vertical one is the contact closure above, since `(n × Z)_Z = 0`). This
//! differs from the material acceleration of P,
//! `v̇ + ṅ × r + n × (n × r)`, by `n × (n × R Z)`, whose horizontal part
//! `R n_Z n_h` is nonzero for any spinning rolling sphere. With
//! `m v̇ = F − m g Z` and `ṅ = ṅ₀ + I⁻¹ (r × F)` the total contact force `F`
//! (normal, friction and the applied `−H`) solves
//!
//! ```text
//! K F = b,  K F = F/m − r × I⁻¹ (r × F),
//!           b   = g Z − ṅ₀ × r − a n × (n × k)
//! ```
//!
//! (`K` symmetric positive definite: no Painlevé case while rolling). Then
//! `N = F_Z`, the friction needed is `F_f = F_h + H`, and `H` drops out of
//! the motion. `Ẇ_f = Ẇ_a = 0`. The rolling right-hand side does not read
//! the state's `v` (it is integrated, and reset to `−n × r` at every
//! restart); outputs and the energy use `v = −n × r`, and `slip` is 0.
//!
//! While sliding (exact law), `μ v/|v|` is continued smoothly through zero
//! (its sign flips once `v·d < 0`, `d` the slip direction at the last
//! accepted step, as in the reduced model), so the step crossing zero slip
//! is smooth and the event `v_P·d = 0` (falling) is located accurately.
//! There the state is projected onto rolling (`v = −n × r`; the tiny
//! kinetic-energy change is booked into `W_f`) and the needed friction
//! computed: roll if `|F_f| ≤ μ|N|`, else keep sliding with
//! `f = μ · (−F_f/|F_f|)` at exactly zero slip ([`ContactState::slip_hint`]).
//! Rolling ends at the event `μ|N| − |F_f| = 0` (falling), sliding off with
//! the friction continuous in direction; it is also re-checked at every
//! force switch (the needed friction jumps with `H`). Zero slip at `t = 0`
//! (to rounding, [`Rigid::slip_is_zero`]) or after a sticking touchdown
//! impulse is decided the same way. Under unilateral contact the `N = 0`
//! event also ends rolling (the flight starts from the rolling velocity),
//! though generically the stick margin reaches zero first, since
//! `μ|N| → 0` while the needed friction does not.
//!
//! # Chattering of the sliding-only law
//!
//! The on-plane models' detection, in `ContactState::accepted`: for
//! `"coulomb_sliding"`, every accepted step in contact whose slip reverses
//! direction (`v_P · v_P,prev < 0`) is counted; after [`CHATTER_REVERSALS`]
//! the next evaluation fails with [`RigidError::Chattering`], whose message
//! is the reduced model's.
//!
//! # The contact state
//!
//! The friction law, μ, the contact mode, the latched force terms,
//! sliding/rolling, the slip hint and reference, the latched `N = 0` branch
//! and the chatter detection are the [`ContactState`] the on-plane models
//! hold ([`Rigid::contact`]); its horizontal vectors are the world `X, Y`
//! components of this model's 3D vectors (z = 0). The friction coefficient
//! is the on-plane models' `ContactState::coefficient` (the law `f(v)`
//! written once), and the contact dynamics in one-sphere contact and in
//! flight are [`crate::physics::body`]'s, written once for this model and
//! the vector model.
//!
//! # Outputs
//!
//! `θ = atan2(|k_h|, k_Z)`; `θ̇ = n·ŷ`; `Ω = ((k_h × k̇_h)·Z)/|k_h|²` (reported
//! as 0 where `|k_h| < 1e-12`, where it is undefined); `ω = n·k`;
//! `u_x, u_y = v·x̂, v·ŷ`; `J = −L·r` from `L = I n` and `r` in 3D; `E` as
//! above; `rolling` is 1 while rolling (then `slip` is exactly 0 and `u`
//! the rolling velocity), and `summary.rolling_fraction` the fraction of
//! time rolling. Events: as the reduced driver (`theta_above_half_pi`,
//! `force_switch`, `contact_lost`/`contact_regained` for bilateral/paper
//! contact, `stick`/`slip`), plus `lift_off`/`touchdown`.
//!
//! # Flight and touchdown (contact = "unilateral")
//!
//! Lift-off is the event `N = 0` (falling). In flight `N = 0`, no friction;
//! gravity acts, and the applied force acts at the sphere's lowest point `P`.
//! Touchdown is the event `z_C − R = 0` (falling), written as
//! `(z_C − R)/(t − t_flight_start)` (and `v_Cz` at the flight's start) so
//! that it is positive at the start of a rebound, where the gap is 0: a
//! short bounce inside one step is still a sign change. A guard event at a
//! penetration of `1e-10 R` catches anything that is missed anyway (e.g. a
//! top that barely leaves the plane after a lift-off). The impact law:
//!
//! - impulse `Π` at `P`; the velocity of the material point at `P` jumps by
//!   `K Π` with `K Π = Π/m − r × (I⁻¹ (r × Π))` (symmetric positive definite);
//! - try sticking: `Π` such that the tangential velocity of `P` after the
//!   impact is zero and the normal one is `−e v_n⁻` (Newton restitution,
//!   `e = surface.restitution`). Accept if `|Π_t| ≤ μ Π_n`;
//! - otherwise sliding: `Π = Π_n (Z − μ t̂)`, `t̂` the pre-impact tangential
//!   slip direction (or, with no slip, minus the sticking impulse's
//!   tangential direction), `Π_n` from the normal restitution condition.
//!   A non-positive effective mass along that direction stops the run.
//! - the energy the impact removes is added to `W_f` (so `work_friction`
//!   includes impact losses and `E − E0 = W_f + W_a` holds across impacts).
//! - if the rebound would give a flight shorter than `1e-9` time units
//!   (`2 v_n⁺/Q`, `Q` the gap's downward acceleration), or `v_n⁺ = 0`
//!   (`e = 0`), the top is put in contact (projected onto the constraint);
//!   if then `N < 0` it lifts off at once. After [`MAX_BOUNCES`] bounces
//!   without a contact phase, a bounce whose flight would be shorter than
//!   1e-6 time units also ends in contact (Zeno guard).
//!
//! Every lift-off and touchdown is an [`crate::EventRecord`] (`Happened::LiftOff`,
//! `Happened::Touchdown`). For unilateral contact, `contact_lost_at` is the first
//! lift-off and `negative_normal_fraction` the fraction of time in flight.

mod brownian;
mod stem;

use super::vec3::{V3, Z, add, cross, dot, scale, solve3, sub};
use crate::physics::body;
use crate::sim::events::{Happened, Watch};
use crate::sim::messages::painleve_why;
use crate::sim::record::RunLog;
use crate::{
    ContactMode, Error, Failure, Sample, Scenario, Top,
    integrate::{Direction, Event, OdeSystem},
    model::reduced::{CHATTER_REVERSALS, ModelError, Scales},
    model::{ContactState, Flow, Model},
    sim::record::unit,
};

pub use crate::model::reduced::Mode;

/// Number of state components.
pub const DIM: usize = 18;
/// Index of the centre-of-mass position (3 components).
pub const POS: usize = 0;
/// Index of the centre-of-mass velocity (3 components).
pub const VEL: usize = 3;
/// Index of the attitude quaternion (w, x, y, z).
pub const QUAT: usize = 6;
/// Index of the angular velocity n (world frame, 3 components).
pub const OMEGA: usize = 10;
/// Index of the friction work.
pub const WF: usize = 13;
/// Index of the applied-force work.
pub const WA: usize = 14;
/// Index of the symmetry axis k (world frame, 3 components).
pub const AXIS: usize = 15;

/// Quaternion-norm stabilisation rate κ \[1/time unit\].
pub const KAPPA: f64 = 1.0;
/// Bounces without a contact phase after which short bounces end in contact.
pub const MAX_BOUNCES: usize = 1000;
/// Largest number of lift-offs plus touchdowns of one run before it stops.
pub const MAX_TRANSITIONS: usize = 200_000;
/// Flight time \[time units\] below which a rebound is treated as contact.
pub const MIN_FLIGHT: f64 = 1e-9;

/// Rotate `v` by the unit quaternion `q` (body → world).
#[inline]
fn rotate(q: [f64; 4], v: V3) -> V3 {
    let u = [q[1], q[2], q[3]];
    let t = scale(2.0, cross(u, v));
    add(add(v, scale(q[0], t)), cross(u, t))
}

fn quat_of(y: &[f64; DIM]) -> [f64; 4] {
    [y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3]]
}

/// The state's rate in one-sphere contact (plane or tube) from the
/// contact solution `c`: `ẋ = v`, `v̇ = F − (g Z − F_b)` (`gv`), `ẇ`, the
/// attitude's rate at `n`, `k̇` and `Ẇ_f`; `Ẇ_a` and the rest are zero.
#[inline(always)]
fn contact_rates(y: &[f64; DIM], c: &body::Contact, gv: V3, n: V3, kd: V3) -> [f64; DIM] {
    let mut dy = [0.0; DIM];
    set3(&mut dy, POS, v3(y, VEL));
    set3(&mut dy, VEL, sub(c.force, gv));
    set3(&mut dy, OMEGA, c.wd);
    dy[QUAT..QUAT + 4].copy_from_slice(&attitude_rate(quat_of(y), n));
    set3(&mut dy, AXIS, kd);
    dy[WF] = c.wf;
    dy
}

/// `q̇ = ½ (0, n) ⊗ q − κ (|q|² − 1) q`.
#[inline(always)]
fn attitude_rate(qs: [f64; 4], n: V3) -> [f64; 4] {
    let q2 = qs[0] * qs[0] + qs[1] * qs[1] + qs[2] * qs[2] + qs[3] * qs[3];
    let st = KAPPA * (q2 - 1.0);
    let (qw, qv) = (qs[0], [qs[1], qs[2], qs[3]]);
    let qdw = -0.5 * dot(n, qv);
    let qdv = scale(0.5, add(scale(qw, n), cross(n, qv)));
    [
        qdw - st * qw,
        qdv[0] - st * qv[0],
        qdv[1] - st * qv[1],
        qdv[2] - st * qv[2],
    ]
}

fn normalized(q: [f64; 4]) -> [f64; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

fn v3(y: &[f64; DIM], i: usize) -> V3 {
    [y[i], y[i + 1], y[i + 2]]
}

fn set3(y: &mut [f64; DIM], i: usize, v: V3) {
    y[i..i + 3].copy_from_slice(&v);
}

/// Contact or flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// On the plane: `z_C = R` held, `N` from the constraint.
    Contact,
    /// Free flight (unilateral contact only): `N = 0`, no friction.
    Flight,
}

/// Why the right-hand side (or an impact) cannot be evaluated.
#[derive(Debug, Clone, PartialEq)]
pub enum RigidError {
    /// The N equation with friction has 0 or 2 consistent solutions.
    Painleve {
        /// θ \[rad\].
        theta: f64,
        /// Number of consistent solutions found (0 or 2).
        solutions: usize,
    },
    /// The sliding impact impulse has a non-positive effective mass.
    ImpactJam {
        /// θ \[rad\].
        theta: f64,
    },
    /// The sliding-only Coulomb law reversed the slip direction at step
    /// after step (same criterion and message as the reduced model's
    /// [`ModelError::Chattering`]).
    Chattering {
        /// Slip reversals counted.
        reversals: u32,
    },
    /// The top left the tube's wall (`N < 0` under unilateral contact):
    /// flight in the tube is not modelled (docs/physics.md#tube-dynamics).
    TubeFlight,
}

impl std::fmt::Display for RigidError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RigidError::Painleve { theta, solutions } => write!(
                f,
                "Painleve paradox at theta = {} rad: the N equation with friction has {solutions} consistent solutions (m a h mu sin(theta)/A too large); no unique motion exists",
                crate::human::s4(*theta)
            ),
            RigidError::ImpactJam { theta } => write!(
                f,
                "touchdown at theta = {} rad: the sliding friction impulse has a non-positive effective mass (impact Painleve case); no impulse satisfies the impact law",
                crate::human::s4(*theta)
            ),
            RigidError::Chattering { reversals } => write!(
                f,
                "{}",
                ModelError::Chattering {
                    reversals: *reversals
                }
            ),
            RigidError::TubeFlight => write!(f, "{TUBE_FLIGHT}"),
        }
    }
}

/// Why a run in the tube stops at lift-off.
const TUBE_FLIGHT: &str = "the top lifts off the tube's wall (N falls through 0, contact = \"unilateral\"): flight inside the tube is not modelled (docs/physics.md#tube-dynamics); contact = \"bilateral\" holds it on the wall";

/// Kinematic quantities at one state (scaled units, world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kin {
    /// Normalised attitude quaternion.
    pub q: [f64; 4],
    /// Symmetry axis k (the state's, unit to the integration error).
    pub k: V3,
    /// Angular velocity n (world).
    pub n: V3,
    /// r = OP = a k − Z.
    pub r: V3,
    /// Velocity of the material point at P, v + n × r.
    pub vp: V3,
    /// Precessing-frame x̂ (horizontal, along k's projection; X if k vertical).
    pub xh: V3,
    /// ŷ = Z × x̂.
    pub yh: V3,
    /// |k_h| = sin θ.
    pub kh: f64,
}

/// Everything the right-hand side computes at one state (scaled units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eval {
    /// State derivative.
    pub dy: [f64; DIM],
    /// Normal force N (0 in flight).
    pub normal: f64,
    /// Friction force on the top (world, horizontal).
    pub friction: V3,
    /// Kinematics.
    pub kin: Kin,
    /// `Q`: the normal force per unit `D`; `−Q` is the gap's acceleration in flight.
    pub q_free: f64,
    /// Drilling torque about Z (Coulomb–Contensou friction: the law's
    /// while sliding, the constraint torque in the stick; 0 otherwise).
    pub torque: f64,
}

/// The rigid-body model as an ODE system in scaled units.
#[derive(Debug, Clone)]
pub struct Rigid {
    /// Unit system.
    pub scales: Scales,
    /// Centre offset of the active contact sphere along `k` (scaled): `a/R`
    /// for the main sphere, `d2/R` for the stem's (§stem).
    a: f64,
    /// Radius of the active contact sphere (scaled): 1 for the main sphere,
    /// `r2/R` for the stem's (§stem).
    rho: f64,
    /// The main sphere's `(a/R, 1)` and the stem's `(d2/R, r2/R)` (`None`
    /// without a stem): the active one is in `a`, `rho`.
    spheres: ((f64, f64), Option<(f64, f64)>),
    /// True while the stem's sphere is the active contact sphere.
    pub on_stem: bool,
    /// True in the two-contact phase: the main sphere and the stem both on
    /// the plane (§stem; `phase` is then `Contact`).
    pub both: bool,
    /// Time of the last switch of the active sphere (scaled): the other
    /// sphere's gap is 0 there ([`Rigid::other_touchdown_function`]).
    switch_start: f64,
    ia: f64,
    ic: f64,
    /// The inertia (scaled), `A` and `C`.
    inertia: body::Inertia,
    /// The wells' torque at the last axis ([`body::WellsTorque`]).
    wells_torque: body::WellsTorque,
    g: f64,
    restitution: f64,
    /// The contact state (shared with the on-plane models): friction law,
    /// μ, contact mode, the applied force terms latched for the segment,
    /// sliding or rolling (always sliding in flight), the slip hint and
    /// reference (world X, Y), the latched `N = 0` branch (bilateral
    /// contact, sliding, in contact), chatter detection and the evaluation
    /// count.
    pub contact: ContactState,
    /// Current phase.
    pub phase: Phase,
    /// Lift-offs and touchdowns so far (bounded by [`MAX_TRANSITIONS`]).
    transitions: usize,
    /// Bounces since the last contact phase (Zeno guard, [`MAX_BOUNCES`]).
    bounces: usize,
    /// Time the current flight started (scaled).
    pub flight_start: f64,
    /// The SI top.
    pub top: Top,
    /// g \[m/s²\].
    pub gravity_si: f64,
    /// The Langevin heat bath (scaled), `None` unless `method = "langevin"`
    /// or `"brownian"` (Langevin on the plane and in the tube; Brownian on
    /// the plane only, the validation refuses it in the tube).
    thermal: Option<super::thermostat::Bath>,
    /// The Ornstein–Uhlenbeck step's coefficients from the last call.
    ou: super::thermostat::OuCache,
    /// `solver.method = "brownian"`: with unilateral contact the top is the
    /// overdamped free body above a wall (`rigid/brownian.rs`).
    brownian: bool,
    /// The wall's record of such a run (`rigid/brownian.rs`).
    wall: brownian::Wall,
    /// The inside of a tube (scaled radius; `surface.shape = "tube"`,
    /// docs/physics.md#tube-dynamics), `None` on the plane.
    tube: Option<body::Tube>,
    /// The initial contact point's angle about the tube's axis \[rad\].
    tube_angle: f64,
}

impl Rigid {
    /// Build the scaled model of a scenario.
    pub fn new(sc: &Scenario) -> Self {
        let scales = Scales::of(sc);
        let main = (sc.top.offset / scales.length, 1.0);
        let stem = sc
            .top
            .stem
            .map(|st| (st.distance / scales.length, st.radius / scales.length));
        Rigid {
            scales,
            a: main.0,
            rho: main.1,
            spheres: (main, stem),
            on_stem: false,
            both: false,
            switch_start: 0.0,
            ia: sc.top.inertia_transverse / scales.inertia(),
            ic: sc.top.inertia_axial / scales.inertia(),
            inertia: body::Inertia::new(
                sc.top.inertia_transverse / scales.inertia(),
                sc.top.inertia_axial / scales.inertia(),
            ),
            wells_torque: body::WellsTorque::default(),
            g: sc.surface.gravity * scales.time * scales.time / scales.length,
            restitution: sc.surface.restitution,
            contact: ContactState::new(sc, &scales),
            phase: Phase::Contact,
            transitions: 0,
            bounces: 0,
            flight_start: 0.0,
            top: sc.top,
            gravity_si: sc.surface.gravity,
            thermal: super::thermostat::Bath::of(sc, &scales),
            ou: super::thermostat::OuCache::default(),
            brownian: sc.solver.method == crate::Method::Brownian,
            wall: brownian::Wall::default(),
            tube: sc.surface.shape.tube().map(|(b, _)| body::Tube {
                radius: b / scales.length,
            }),
            tube_angle: sc.surface.shape.tube().map_or(0.0, |(_, angle)| angle),
        }
    }

    /// Gravity in scaled units.
    pub fn gravity(&self) -> f64 {
        self.g
    }

    /// Latch the applied force in effect at scaled time `t`.
    pub fn latch_force(&mut self, t: f64) {
        self.contact.latch_force(t, &self.scales);
    }

    /// Scaled state (in contact) from the SI initial values, with the
    /// precessing x along world X: `k = (s, 0, c)`,
    /// `n = ((ω − Ω c) s, θ̇, Ω s² + ω c)`, `v = (u_x, u_y, a s θ̇)`,
    /// `z_O = R − a c`, `x_O = y_O = 0`.
    pub fn scale_state(&self, i: &crate::Initial) -> [f64; DIM] {
        let t = self.scales.time;
        let vu = self.scales.velocity();
        let (s, c) = i.theta.sin_cos();
        let (thd, om, w) = (i.theta_dot * t, i.precession * t, i.spin * t);
        let (hs, hc) = (0.5 * i.theta).sin_cos();
        let q = [hc, 0.0, hs, 0.0];
        let n_w = [(w - om * c) * s, thd, om * s * s + w * c];
        let mut y = [0.0; DIM];
        set3(&mut y, POS, [0.0, 0.0, 1.0 - self.a * c]);
        set3(&mut y, VEL, [i.ux / vu, i.uy / vu, self.a * s * thd]);
        y[QUAT..QUAT + 4].copy_from_slice(&q);
        set3(&mut y, OMEGA, n_w);
        set3(&mut y, AXIS, rotate(q, Z));
        if i.heading != 0.0 {
            // Turned by the heading about Z (the dynamics are the same;
            // docs/physics.md#position): v, n, k, and the attitude q_Z(φ₀) ⊗ q.
            let rz = super::vec3::RotZ::new(i.heading);
            for at in [VEL, OMEGA, AXIS] {
                let v = rz.apply(v3(&y, at));
                set3(&mut y, at, v);
            }
            let q = rz.turn_quaternion(quat_of(&y));
            y[QUAT..QUAT + 4].copy_from_slice(&q);
        }
        if let Some(tube) = self.tube {
            // The tube: the state on the tangent plane at the lowest line,
            // turned by the initial angle about the tube's axis (x along X
            // through (0, 0, b)).
            let rv = [self.tube_angle, 0.0, 0.0];
            let axis = [0.0, 0.0, tube.radius];
            let p = add(super::vec3::rotate(rv, sub(v3(&y, POS), axis)), axis);
            set3(&mut y, POS, p);
            for at in [VEL, OMEGA, AXIS] {
                let v = super::vec3::rotate(rv, v3(&y, at));
                set3(&mut y, at, v);
            }
            let q = super::vec3::turn_quaternion_by(rv, quat_of(&y));
            y[QUAT..QUAT + 4].copy_from_slice(&q);
        }
        y
    }

    /// I⁻¹ v in the world frame for the symmetry axis k.
    #[inline(always)]
    fn inv_inertia(&self, k: V3, v: V3) -> V3 {
        self.inertia.inverse(k, v)
    }

    /// I v in the world frame for the symmetry axis k.
    #[inline(always)]
    fn inertia(&self, k: V3, v: V3) -> V3 {
        self.inertia.apply(k, v)
    }

    /// Kinematics at a state (inlined, as it was before the tube's branch
    /// made it larger: out of line it costs 8 % of a rigid run).
    #[inline(always)]
    pub fn kin(&self, y: &[f64; DIM]) -> Kin {
        let q = normalized(quat_of(y));
        let k = v3(y, AXIS);
        let n = v3(y, OMEGA);
        let r = match self.tube {
            None => [self.a * k[0], self.a * k[1], self.a * k[2] - self.rho],
            Some(_) => self.tube_offset(y),
        };
        let vp = add(v3(y, VEL), cross(n, r));
        let kh = k[0].hypot(k[1]);
        let xh = if kh > 0.0 {
            [k[0] / kh, k[1] / kh, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        let yh = [-xh[1], xh[0], 0.0];
        Kin {
            q,
            k,
            n,
            r,
            vp,
            xh,
            yh,
            kh,
        }
    }

    /// The tube at the contact of the state's sphere (`None` on the plane).
    pub fn tube_at(&self, y: &[f64; DIM]) -> Option<body::TubeAt> {
        self.tube
            .map(|tube| tube.at(add(v3(y, POS), scale(self.a, v3(y, AXIS)))))
    }

    /// `r = a k − ρ n` in the tube (kept out of line: the plane's
    /// [`Rigid::kin`] stays what it was).
    #[inline(never)]
    fn tube_offset(&self, y: &[f64; DIM]) -> V3 {
        let n = self.tube_at(y).map_or(Z, |t| t.n);
        sub(scale(self.a, v3(y, AXIS)), scale(self.rho, n))
    }

    /// The slip `v_P` in the contact state's 2D components: the horizontal
    /// `(x, y)` on the plane, the tangent `(e₁, e₂)` in the tube.
    fn slip_2d(&self, y: &[f64; DIM], kin: &Kin) -> [f64; 2] {
        match self.tube_at(y) {
            None => [kin.vp[0], kin.vp[1]],
            Some(t) => t.components(kin.vp),
        }
    }

    /// Evaluate the model at a state in the current phase: the body's
    /// contact dynamics ([`crate::physics::body`]) in one-sphere contact
    /// and in flight, the two-contact phase of the stem (§stem) otherwise.
    pub fn eval(&self, y: &[f64; DIM]) -> Result<Eval, RigidError> {
        if self.both {
            return self.eval_two(y);
        }
        if self.tube.is_some() {
            return self.eval_tube(y);
        }
        let kin = self.kin(y);
        let body = self.body();
        let at = body::At::new(&body::Plane, self.a, self.rho, kin.k, kin.n);
        let hw = body::applied_world(self.contact.applied(), kin.k);
        // Adhesion (§adhesion), along the vertical through P: the load F_a in
        // contact, −U′(gap) in flight; applied as a load at P, no work in W_a
        // (its potential is in the energy). `cp` itself without adhesion.
        let cv = self.contact.forces().centre_vertical();
        let cp = self
            .contact
            .forces()
            .contact_point()
            .with_load(match self.phase {
                Phase::Contact => cv.in_contact(),
                Phase::Flight => cv.at_gap(self.gap(y)),
            });
        let wrench = body::wrench(self.contact.forces(), kin.k, || {
            crate::physics::forces::actuators::material_axes(quat_of(y), kin.k)
        });
        let free = body.free(
            &at,
            self.wells_torque.at(self.contact.wells(), kin.k),
            wrench,
        );
        let (q_free, _) = body.closure_q(&at, &free, hw, &cp);
        let c = match (self.phase, self.contact.mode) {
            (Phase::Flight, _) => self.flight(&body, &at, &free, hw, &cp, kin.vp),
            (Phase::Contact, Mode::Rolling) => body.roll(&self.contact, &at, &free, hw, &cp),
            (Phase::Contact, Mode::Sliding) => body
                .slide(&self.contact, &at, &free, hw, &cp, [kin.vp[0], kin.vp[1]])
                .map_err(|solutions| RigidError::Painleve {
                    theta: kin.kh.atan2(kin.k[2]),
                    solutions,
                })?,
        };
        let mut dy = contact_rates(y, &c, free.gv, kin.n, at.kd);
        dy[WA] = c.wa;
        if let Some(wr) = free.wrench {
            // The actuators' power F·v_O + τ·n (§actuators), rolling or not, with
            // the velocity the energy uses.
            dy[WA] += body::power(wr, self.output_velocity(y, &kin), kin.n);
        }
        Ok(Eval {
            dy,
            normal: c.normal,
            friction: [c.friction[0], c.friction[1], 0.0],
            kin,
            q_free,
            torque: c.torque,
        })
    }

    /// [`Rigid::eval`] in the tube (docs/physics.md#tube-dynamics): the
    /// body's tube path ([`body::Body::slide_tube`], [`body::Body::roll_tube`])
    /// with gravity, the point friction laws, the `[[force]]` schedule
    /// (`H` in the contact's frame, [`body::TubeAt::applied`], the load
    /// `h_z` along `−n`) and adhesion's load `F_a` along `−n` in contact;
    /// the friction in `Eval` is in the contact's
    /// tangent components (`e₁ = X`, `e₂ = n × X`).
    #[inline(never)]
    fn eval_tube(&self, y: &[f64; DIM]) -> Result<Eval, RigidError> {
        if self.phase == Phase::Flight {
            return Err(RigidError::TubeFlight);
        }
        let kin = self.kin(y);
        let Some(tube) = self.tube_at(y) else {
            unreachable!("eval_tube on the plane")
        };
        let body = self.body();
        let at = body::At::new(&tube, self.a, self.rho, kin.k, kin.n);
        let free = body.free(&at, None, None);
        let hw = tube.applied(self.contact.applied(), kin.k);
        // Adhesion in the tube (`[adhesion]` with shape = "tube"): the load
        // F_a along −n at P in contact (the tube's pull-off force,
        // docs/physics.md#tube-dynamics); flight is not modelled.
        let cp = self.contact.forces().contact_point_in_contact();
        let cd = add(v3(y, VEL), scale(self.a, at.kd));
        let c = match self.contact.mode {
            Mode::Rolling => body.roll_tube(&at, &free, &tube, self.rho, hw, &cp),
            Mode::Sliding => body
                .slide_tube(
                    &self.contact,
                    &at,
                    &free,
                    &tube,
                    hw,
                    &cp,
                    cd,
                    tube.components(kin.vp),
                )
                .map_err(|solutions| RigidError::Painleve {
                    theta: kin.kh.atan2(kin.k[2]),
                    solutions,
                })?,
        };
        let mut dy = contact_rates(y, &c, free.gv, kin.n, at.kd);
        if hw != [0.0; 3] {
            dy[WA] = c.wa;
        }
        Ok(Eval {
            dy,
            normal: c.normal,
            friction: [c.friction[0], c.friction[1], 0.0],
            kin,
            q_free: 0.0,
            torque: 0.0,
        })
    }

    /// The body's constants for the active contact sphere.
    #[inline(always)]
    fn body(&self) -> body::Body {
        body::Body {
            a: self.a,
            inertia: self.inertia,
            g: self.g,
        }
    }

    /// Flight: no contact force; the applied force at `P` (`−H` and the
    /// vertical load with adhesion's pull) acts, and does work at the
    /// velocity `vp` of the material point at `P`.
    fn flight(
        &self,
        body: &body::Body,
        at: &body::At,
        free: &body::Free,
        hw: V3,
        cp: &crate::physics::forces::ContactPointForce,
        vp: V3,
    ) -> body::Contact {
        let force = [-hw[0], -hw[1], cp.vertical_total(0.0)];
        // The work of the applied force at P less adhesion's (its potential
        // is in the energy).
        let fa = [
            -hw[0],
            -hw[1],
            self.contact.forces().contact_point().vertical_total(0.0),
        ];
        body::Contact {
            normal: 0.0,
            friction: [0.0; 2],
            force,
            wd: body.angular(at, free, force),
            wf: 0.0,
            wa: dot(fa, vp),
            torque: 0.0,
        }
    }

    /// Columns of the contact matrix `K`, `K F = F/m − r × I⁻¹ (r × F)`:
    /// the change of the contact point's velocity per unit impulse at P
    /// (symmetric positive definite).
    fn k_columns(&self, k: V3, r: V3) -> [V3; 3] {
        let kmul = |p: V3| sub(p, cross(r, self.inv_inertia(k, cross(r, p))));
        [
            kmul([1.0, 0.0, 0.0]),
            kmul([0.0, 1.0, 0.0]),
            kmul([0.0, 0.0, 1.0]),
        ]
    }

    /// True where the driver latches the normal-force branch
    /// ([`ContactState::normal_branch`]): in contact, and where the contact
    /// state latches it ([`ContactState::latches_normal`]).
    pub fn latches_normal(&self) -> bool {
        self.phase == Phase::Contact && self.contact.latches_normal()
    }

    /// Stick margin while rolling, `μ |N| − |F_f|` (scaled force), of an
    /// evaluation ([`ContactState::stick_margin`]).
    fn stick_margin(&self, e: &Eval) -> f64 {
        self.contact
            .stick_margin_wrench(e.normal, horizontal(e.friction), e.torque)
    }

    /// Project onto the Coulomb–Contensou stick (§contensou): onto the contact
    /// constraint, then the impulse at P with the torque about Z
    /// ([`body::stick_solve`], `b = −v_P`, `β = −n_Z`) that
    /// brings the slip and the spin about Z to zero, and `v = −n × r`.
    pub fn project_stick(&self, y: &mut [f64; DIM]) {
        self.project_contact(y);
        let kin = self.kin(y);
        let vp = [kin.vp[0], kin.vp[1], 0.0];
        let (imp, m) = body::stick_solve(&self.inertia, kin.k, kin.r, scale(-1.0, vp), -kin.n[2]);
        let n = add(
            kin.n,
            self.inv_inertia(kin.k, add(cross(kin.r, imp), [0.0, 0.0, m])),
        );
        // n_Z is zero by construction: held so exactly, not to rounding.
        set3(y, OMEGA, [n[0], n[1], 0.0]);
        self.project_rolling(y);
    }

    /// Horizontal slip velocity `v_P` (world, scaled) from the state's `v`.
    /// In the tube, the tangent components (along `e₁ = X`, `e₂ = n × X`).
    pub fn slip_of(&self, y: &[f64; DIM]) -> V3 {
        let kin = self.kin(y);
        let s = self.slip_2d(y, &kin);
        [s[0], s[1], 0.0]
    }

    /// True if the horizontal slip is zero to rounding:
    /// `|v_P| ≤ 16 ε (|v| + |n| |r|)` (ε the machine epsilon), the accuracy
    /// to which `v + n × r` can be computed. Initial states given as rolling
    /// (e.g. `u_y = −R ω sin θ` for a sphere) only reach this, not 0.
    pub fn slip_is_zero(&self, y: &[f64; DIM]) -> bool {
        let kin = self.kin(y);
        let v = v3(y, VEL);
        let size = dot(v, v).sqrt() + dot(kin.n, kin.n).sqrt() * dot(kin.r, kin.r).sqrt();
        let s = self.slip_2d(y, &kin);
        s[0].hypot(s[1]) <= 16.0 * f64::EPSILON * size
    }

    /// Centre-of-mass velocity of rolling contact at this attitude and
    /// angular velocity: `v = −n × r` (all three components; its vertical
    /// part is the contact constraint's `−a (n × k)_Z`).
    fn rolling_velocity(&self, kin: &Kin) -> V3 {
        scale(-1.0, cross(kin.n, kin.r))
    }

    /// Project onto rolling contact: normalise q and k, `z_C = R`, `v = −n × r`
    /// (zero slip).
    pub fn project_rolling(&self, y: &mut [f64; DIM]) {
        self.project_contact(y);
        let kin = self.kin(y);
        set3(y, VEL, self.rolling_velocity(&kin));
    }

    /// Centre-of-mass velocity used for outputs and the energy: the rolling
    /// constraint value while rolling, the state's otherwise (with the
    /// contact constraint's vertical part in contact).
    fn output_velocity(&self, y: &[f64; DIM], kin: &Kin) -> V3 {
        if self.phase == Phase::Contact && self.contact.mode == Mode::Rolling {
            self.rolling_velocity(kin)
        } else if self.tube.is_some() {
            v3(y, VEL)
        } else {
            let (_, vz) = self.vertical(y, kin);
            [y[VEL], y[VEL + 1], vz]
        }
    }

    /// Gap between the sphere and the plane, `z_C − R` (scaled).
    /// In the tube, `b − |c⊥| − ρ`.
    pub fn gap(&self, y: &[f64; DIM]) -> f64 {
        if let Some(tube) = self.tube {
            return tube.gap(add(v3(y, POS), scale(self.a, v3(y, AXIS))), self.rho);
        }
        y[POS + 2] + self.a * y[AXIS + 2] - self.rho
    }

    /// Rate of change of the gap, `v_Cz` (scaled).
    pub fn gap_rate(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        if let Some(t) = self.tube_at(y) {
            return dot(t.n, add(v3(y, VEL), scale(self.a, cross(kin.n, kin.k))));
        }
        y[VEL + 2] + self.a * cross(kin.n, kin.k)[2]
    }

    /// The touchdown event function: `gap/(t − t_flight_start)`, and the
    /// gap rate at the flight's start. Same sign as the gap for `t` after the
    /// start, but positive at the start of a rebound (where the gap is 0), so
    /// that a touchdown within the first step is still a sign change.
    pub fn touchdown_function(&self, t: f64, y: &[f64; DIM]) -> f64 {
        let dt = t - self.flight_start;
        if dt > 0.0 {
            self.gap(y) / dt
        } else {
            self.gap_rate(y)
        }
    }

    /// One Euler–Maruyama step of the overdamped dynamics in contact
    /// (`solver.method = "brownian"`, docs/physics.md#langevin): the vector
    /// model's step ([`super::thermostat::overdamped`]: the same basis,
    /// mobility, drift and normals, with or without the contact damping)
    /// with the generalised force at
    /// rest from this model's right-hand side, the constraint's height and
    /// vertical velocity. The state's velocities are set to the drift part,
    /// `W_f` takes the energy change.
    fn brownian_step(
        &mut self,
        t: f64,
        y: &mut [f64; DIM],
        h: f64,
        xi: &[f64],
    ) -> Result<(), RigidError> {
        let Some(b) = self.thermal else { return Ok(()) };
        // Only bilateral and paper contact come here (`overdamped_step`
        // sends unilateral contact to the free body above the wall), and
        // they never fly.
        if self.phase != Phase::Contact {
            return Ok(());
        }
        let en0 = self.energy_scaled(y);
        let mut rest = *y;
        rest[VEL..VEL + 3].fill(0.0);
        rest[OMEGA..OMEGA + 3].fill(0.0);
        let mut dy = [0.0; DIM];
        <Self as OdeSystem<DIM>>::rhs(self, t, &rest, &mut dy)?;
        let ([kn, eh, fh], s2) = super::thermostat::modes_basis(v3(y, AXIS));
        let body = super::thermostat::Body {
            a: self.a,
            ia: self.ia,
            ic: self.ic,
        };
        let nd = v3(&dy, OMEGA);
        let acc = [dy[VEL], dy[VEL + 1], dot(nd, kn), dot(nd, eh), dot(nd, fh)];
        let (p, drift) = super::thermostat::overdamped(&b, &body, [kn, eh, fh], s2, acc, h, xi);
        let w = add(add(scale(p[2], kn), scale(p[3], eh)), scale(p[4], fh));
        let rv = scale(h, w);
        let k = super::vec3::rotate(rv, v3(y, AXIS));
        set3(y, AXIS, k);
        let q = super::vec3::turn_quaternion_by(rv, quat_of(y));
        y[QUAT..QUAT + 4].copy_from_slice(&q);
        y[POS] += h * p[0];
        y[POS + 1] += h * p[1];
        let wdrift = add(
            add(scale(drift[2], kn), scale(drift[3], eh)),
            scale(drift[4], fh),
        );
        set3(y, OMEGA, wdrift);
        y[VEL] = drift[0];
        y[VEL + 1] = drift[1];
        y[POS + 2] = 1.0 - self.a * k[2];
        y[VEL + 2] = -self.a * cross(wdrift, k)[2];
        y[WF] += self.energy_scaled(y) - en0;
        Ok(())
    }

    /// Project onto the contact constraint: normalise q and k, `z_C = R`, `v_Cz = 0`.
    pub fn project_contact(&self, y: &mut [f64; DIM]) {
        let q = normalized(quat_of(y));
        y[QUAT..QUAT + 4].copy_from_slice(&q);
        let kq = v3(y, AXIS);
        let k = scale(1.0 / dot(kq, kq).sqrt(), kq);
        set3(y, AXIS, k);
        let n = v3(y, OMEGA);
        if let Some(tube) = self.tube {
            // The centre onto |c⊥| = b − ρ, its normal velocity removed.
            let c = tube.onto(add(v3(y, POS), scale(self.a, k)), self.rho);
            set3(y, POS, sub(c, scale(self.a, k)));
            let nt = tube.at(c).n;
            let v = v3(y, VEL);
            let vn = dot(nt, add(v, scale(self.a, cross(n, k))));
            set3(y, VEL, sub(v, scale(vn, nt)));
            return;
        }
        y[POS + 2] = self.rho - self.a * k[2];
        y[VEL + 2] = -self.a * cross(n, k)[2];
    }

    /// Angular momentum about the centre of mass (world, scaled).
    pub fn angular_momentum(&self, y: &[f64; DIM]) -> V3 {
        let kin = self.kin(y);
        self.inertia(kin.k, kin.n)
    }

    /// Jellett's `J = −L·r_OP` computed in 3D (scaled, m R³/T).
    pub fn jellett_scaled(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        -dot(self.inertia(kin.k, kin.n), kin.r)
    }

    /// Centre-of-mass height and velocity used for the energy and `u_z`:
    /// the constraint values in contact, the state in flight.
    fn vertical(&self, y: &[f64; DIM], kin: &Kin) -> (f64, f64) {
        match self.phase {
            // The tube: the state's (projected at every restart).
            Phase::Contact if self.tube.is_some() => (y[POS + 2], y[VEL + 2]),
            Phase::Contact => (
                self.rho - self.a * kin.k[2],
                -self.a * cross(kin.n, kin.k)[2],
            ),
            Phase::Flight => (y[POS + 2], y[VEL + 2]),
        }
    }

    /// Total energy `½ m |v|² + ½ n·I n + m g z_O`, plus in flight the
    /// adhesion's potential counted from contact, `E_b (1 − exp(−F_a z/E_b))`
    /// at the gap `z` (§adhesion; zero in contact and without adhesion) (scaled).
    pub fn energy_scaled(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        let (z, _) = self.vertical(y, &kin);
        let v = self.output_velocity(y, &kin);
        let e = 0.5 * dot(v, v) + 0.5 * dot(kin.n, self.inertia(kin.k, kin.n)) + self.g * z;
        self.with_gap_potential(e, y)
    }

    /// Energy from the state as stored (scaled), with the adhesion's
    /// potential in flight as [`Rigid::energy_scaled`].
    fn energy_raw(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        let v = v3(y, VEL);
        let e =
            0.5 * dot(v, v) + 0.5 * dot(kin.n, self.inertia(kin.k, kin.n)) + self.g * y[POS + 2];
        self.with_gap_potential(e, y)
    }

    /// `e` plus, in flight with adhesion, the potential `U(gap) − U(0)`
    /// (`e` itself otherwise, bit for bit).
    /// Also adds the wells' potential `U(θ)` (§wells; nothing without wells).
    fn with_gap_potential(&self, e: f64, y: &[f64; DIM]) -> f64 {
        let cv = self.contact.forces().centre_vertical();
        let e = if self.phase == Phase::Flight && cv.force > 0.0 {
            e + cv.potential(self.gap(y))
        } else {
            e
        };
        let wells = self.contact.wells();
        if wells.is_empty() {
            e
        } else {
            crate::physics::forces::wells::with_potential(wells, e, self.theta(y))
        }
    }

    /// Spin ω = n·k (scaled).
    pub fn spin_scaled(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        dot(kin.n, kin.k)
    }

    /// [`Rigid::theta`] from the state's axis alone (the same bits: `kin`'s
    /// `kh` is the same `hypot`), without the rest of [`Rigid::kin`].
    fn theta_of_axis(&self, y: &[f64; DIM]) -> f64 {
        let k = v3(y, AXIS);
        k[0].hypot(k[1]).atan2(k[2])
    }

    /// [`Rigid::spin_scaled`] from the state alone (the same bits).
    fn spin_of_axis(&self, y: &[f64; DIM]) -> f64 {
        dot(v3(y, OMEGA), v3(y, AXIS))
    }

    /// θ = angle between k and Z \[rad\].
    pub fn theta(&self, y: &[f64; DIM]) -> f64 {
        let kin = self.kin(y);
        kin.kh.atan2(kin.k[2])
    }

    /// Touchdown impulse (see the module doc). Returns the post-impact state,
    /// the rebound normal speed of P, and whether the impulse was the
    /// sticking one (zero tangential velocity of P after the impact).
    pub fn impact(&self, y: &[f64; DIM]) -> Result<([f64; DIM], f64, bool), RigidError> {
        let kin = self.kin(y);
        let (k, r) = (kin.k, kin.r);
        let vp = kin.vp;
        let vn = vp[2].min(0.0);
        let e = self.restitution;
        // Columns of K.
        let kmul = |p: V3| sub(p, cross(r, self.inv_inertia(k, cross(r, p))));
        let cols = self.k_columns(k, r);
        let target = [-vp[0], -vp[1], -(1.0 + e) * vn];
        if let Some(cp) = self.contact.contensou_params() {
            return self.impact_contensou(y, &kin, target, cp);
        }
        let stick = solve3(cols, target);
        let pt = stick[0].hypot(stick[1]);
        let mu = self.contact.mu();
        let stuck = pt <= mu * stick[2];
        let imp = if stuck {
            stick
        } else {
            let vt = vp[0].hypot(vp[1]);
            let d = if vt > 0.0 {
                [-vp[0] / vt, -vp[1] / vt, 0.0]
            } else if pt > 0.0 {
                [stick[0] / pt, stick[1] / pt, 0.0]
            } else {
                [0.0; 3]
            };
            let dir = add(Z, scale(mu, d));
            let kn = kmul(dir)[2];
            if kn <= 0.0 {
                return Err(RigidError::ImpactJam {
                    theta: kin.kh.atan2(k[2]),
                });
            }
            scale(-(1.0 + e) * vn / kn, dir)
        };
        let mut yn = *y;
        y_normalize(&mut yn, kin.q);
        set3(&mut yn, VEL, add(v3(y, VEL), imp));
        let n_new = add(kin.n, self.inv_inertia(k, cross(r, imp)));
        set3(&mut yn, OMEGA, n_new);
        let vpn = add(v3(&yn, VEL), cross(n_new, r))[2];
        Ok((yn, vpn.max(0.0), stuck))
    }
}

impl Rigid {
    /// The touchdown impulse under Coulomb–Contensou friction (§contensou): the
    /// module doc's law with the drilling torque. Try sticking: the impulse
    /// `Π` at P and the angular impulse `Π_M` about Z
    /// ([`body::stick_solve`], `b` the stick target: zero
    /// tangential velocity, `−e v_n⁻` normal; `β = −n_Z`) that leave no slip
    /// and no spin about Z; accept it if `Π_n >= 0` and
    /// `(|Π_t|/(μ Π_n), |Π_M|/(μ Π_n r_c))` is inside the law's limit curve
    /// (the gauge `<= 1`). Otherwise sliding with the law frozen at the
    /// pre-impact ratio `d = |v_t|/(r_c |n_Z|)` (as the point law freezes
    /// the slip direction): `Π = Π_n (Z − μ f(d) t̂)`,
    /// `Π_M = −Π_n μ r_c m(d) sign n_Z`, `Π_n` from the normal restitution
    /// (the torque about Z does not move P vertically: `(I⁻¹Z × r)·Z = 0`);
    /// at zero slip and spin the point of the limit curve on the ray of the
    /// sticking impulse. With `r_c → 0` it is the point law's impact.
    fn impact_contensou(
        &self,
        y: &[f64; DIM],
        kin: &Kin,
        target: V3,
        (rc, p, pade): (f64, crate::input::surface::Pressure, bool),
    ) -> Result<([f64; DIM], f64, bool), RigidError> {
        let (k, r, vp, n) = (kin.k, kin.r, kin.vp, kin.n);
        let mu = self.contact.mu();
        let (stick, sm) = body::stick_solve(&self.inertia, k, r, target, -n[2]);
        let pt = stick[0].hypot(stick[1]);
        let gauge = |pn: f64, ft: f64, mt: f64| {
            crate::physics::contensou::gauge(p, pade, ft / (mu * pn), mt / (mu * pn * rc))
        };
        let stuck = stick[2] > 0.0 && mu > 0.0 && gauge(stick[2], pt, sm.abs()).0 <= 1.0
            || (pt == 0.0 && sm == 0.0 && stick[2] >= 0.0);
        let (imp, m_imp) = if stuck {
            (stick, sm)
        } else {
            let vt = vp[0].hypot(vp[1]);
            let spin = rc * n[2].abs();
            // The direction of the force, the sign of the torque and d.
            let (t_hat, sgn, d) = if vt > 0.0 || spin > 0.0 {
                (
                    if vt > 0.0 {
                        [vp[0] / vt, vp[1] / vt, 0.0]
                    } else {
                        [0.0; 3]
                    },
                    if spin > 0.0 { n[2].signum() } else { 0.0 },
                    if spin > 0.0 { vt / spin } else { f64::INFINITY },
                )
            } else {
                let d = if stick[2] > 0.0 && mu > 0.0 {
                    gauge(stick[2], pt, sm.abs()).1
                } else {
                    f64::INFINITY
                };
                (
                    if pt > 0.0 {
                        [-stick[0] / pt, -stick[1] / pt, 0.0]
                    } else {
                        [0.0; 3]
                    },
                    if sm == 0.0 { 0.0 } else { -sm.signum() },
                    d,
                )
            };
            let (fd, md) = crate::physics::contensou::law(p, pade, d);
            let dir = add(Z, scale(-mu * fd, t_hat));
            let kn = self.k_columns(k, r);
            let kn = dir[0] * kn[0][2] + dir[1] * kn[1][2] + dir[2] * kn[2][2];
            if kn <= 0.0 {
                return Err(RigidError::ImpactJam {
                    theta: kin.kh.atan2(k[2]),
                });
            }
            let pn = target[2] / kn;
            (scale(pn, dir), -pn * mu * rc * md * sgn)
        };
        let mut yn = *y;
        y_normalize(&mut yn, kin.q);
        set3(&mut yn, VEL, add(v3(y, VEL), imp));
        let n_new = add(
            n,
            self.inv_inertia(k, add(cross(r, imp), [0.0, 0.0, m_imp])),
        );
        set3(&mut yn, OMEGA, n_new);
        let vpn = add(v3(&yn, VEL), cross(n_new, r))[2];
        Ok((yn, vpn.max(0.0), stuck))
    }
}

fn y_normalize(y: &mut [f64; DIM], q: [f64; 4]) {
    y[QUAT..QUAT + 4].copy_from_slice(&q);
}

impl OdeSystem<DIM> for Rigid {
    type Error = RigidError;

    /// Five normals per half step in contact (`v_x, v_y` and the three
    /// rotational modes: the vector model's), one more in flight (`v_z`).
    const NOISE: usize = 5;
    const NOISE_EXTRA: usize = 1;

    /// The exact Ornstein–Uhlenbeck step: in contact
    /// ([`super::thermostat::ou_in_contact`], the vector model's step, in
    /// the contact's frame: the lab on the plane, `(e₁, e₂, n)` in the tube,
    /// docs/physics.md#tube-langevin) the tangent velocity and `n` relax
    /// with their noise at fixed configuration and the normal velocity is
    /// the constraint's; in flight
    /// ([`super::thermostat::ou_free`]) all six velocities relax. `W_f`
    /// takes the kinetic energy's change (the bath's work).
    fn thermostat(&mut self, y: &mut [f64; DIM], h: f64, xi: &[f64]) {
        let Some(b) = self.thermal else { return };
        let body = super::thermostat::Body {
            a: self.a,
            ia: self.ia,
            ic: self.ic,
        };
        if self.phase == Phase::Flight {
            let free = |y: &[f64; DIM]| {
                let (v, k, n) = (v3(y, VEL), v3(y, AXIS), v3(y, OMEGA));
                0.5 * dot(v, v) + 0.5 * dot(n, self.inertia(k, n))
            };
            let e0 = free(y);
            let (k, mut v, mut w) = (v3(y, AXIS), v3(y, VEL), v3(y, OMEGA));
            super::thermostat::ou_free(&b, &body, k, &mut v, &mut w, h, xi);
            set3(y, VEL, v);
            set3(y, OMEGA, w);
            y[WF] += free(y) - e0;
            return;
        }
        // In contact: the shared step in the contact's frame (the normal
        // along Z; the lab frame on the plane, the tube's (e₁, e₂, n) in the
        // tube: docs/physics.md#tube-langevin), the normal velocity the
        // constraint's.
        if let Some(tube) = self.tube {
            // The centre back onto the wall (RK4's drift off it, ~1e-15 R
            // per step, would otherwise add up over a long run).
            let ka = scale(self.a, v3(y, AXIS));
            let c = tube.onto(add(v3(y, POS), ka), self.rho);
            set3(y, POS, sub(c, ka));
        }
        let frame = self.tube_at(y);
        let into = |x: V3| frame.map_or(x, |f| f.into_frame(x));
        let (k, v, mut w) = (into(v3(y, AXIS)), into(v3(y, VEL)), into(v3(y, OMEGA)));
        let mut vt = [v[0], v[1]];
        let (vn, work) = super::thermostat::ou_in_contact(
            &b,
            &body,
            &self.inertia,
            &mut self.ou,
            k,
            &mut vt,
            &mut w,
            h,
            xi,
        );
        let back = |x: V3| frame.map_or(x, |f| f.from_frame(x));
        set3(y, VEL, back([vt[0], vt[1], vn]));
        set3(y, OMEGA, back(w));
        y[WF] += work;
    }

    fn overdamped_step(
        &mut self,
        t: f64,
        y: &mut [f64; DIM],
        h: f64,
        xi: &[f64],
    ) -> Result<(), RigidError> {
        // Unilateral contact: the free body above the wall (its own step,
        // `rigid/brownian.rs`); bilateral and paper contact: on the plane.
        if self.brownian_wall() {
            return self.brownian_free_step(t, y, h, xi);
        }
        self.brownian_step(t, y, h, xi)
    }

    fn begin_segment(&mut self, t: f64, _y: &[f64; DIM]) {
        self.latch_force(t);
    }

    fn rhs(&mut self, _t: f64, y: &[f64; DIM], dy: &mut [f64; DIM]) -> Result<(), RigidError> {
        self.contact
            .start_evaluation()
            .map_err(|_| RigidError::Chattering {
                reversals: CHATTER_REVERSALS,
            })?;
        *dy = self.eval(y)?.dy;
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// The driver.

/// Penetration \[R\] at which the guard event declares a touchdown.
pub const PENETRATION_GUARD: f64 = 1e-10;

/// The events of the current phase and mode, each with what it watches
/// for (in flight: touchdown and its guard; in contact: N = 0 and, under
/// the exact law, the stick/slip switch).
fn events_for(m: &Rigid, ev: &mut Vec<(Watch, Event<Rigid, DIM>)>) {
    ev.extend([
        // θ rises through π/2 ⇔ k_Z falls through 0.
        (
            Watch::ThetaAboveHalfPi,
            Event {
                g: Box::new(|m: &Rigid, _, y| -m.kin(y).k[2]),
                direction: Direction::Rising,
                terminal: false,
                step_to_event: false,
            },
        ),
        // θ̇ ∝ −(n × k)_Z falls through 0 at a local maximum of θ.
        (
            Watch::ThetaMax,
            Event {
                g: Box::new(|m: &Rigid, _, y| {
                    let kin = m.kin(y);
                    -cross(kin.n, kin.k)[2]
                }),
                direction: Direction::Falling,
                terminal: false,
                step_to_event: false,
            },
        ),
    ]);
    if m.contact.langevin {
        // θ's maxima are the step ends' (the noise reverses θ̇ at almost
        // every step).
        ev.retain(|(w, _)| *w != Watch::ThetaMax);
    }
    match (m.phase, m.contact.contact_mode()) {
        // The Brownian free body above the wall: its records at step ends.
        (Phase::Flight, _) if m.brownian_wall() => ev.push(brownian::wall_event()),
        (Phase::Flight, _) => {
            ev.push((
                Watch::Touchdown,
                Event {
                    g: Box::new(|m, t, y| m.touchdown_function(t, y)),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            ));
            // Guard: a touchdown the first event missed (gap back below 0
            // within the flight's first step) is caught at a penetration of
            // 1e-10 R.
            ev.push((
                Watch::PenetrationGuard,
                Event {
                    g: Box::new(|m, _, y| m.gap(y) + PENETRATION_GUARD),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            ));
        }
        (Phase::Contact, ContactMode::Unilateral) => ev.push((
            Watch::NormalZero,
            Event {
                g: Box::new(|m, _, y| m.eval(y).map(|e| e.normal).unwrap_or(f64::NAN)),
                direction: Direction::Falling,
                terminal: true,
                step_to_event: false,
            },
        )),
        (Phase::Contact, _) => {
            // Bilateral contact, sliding: N = 0 ends the segment, where the
            // driver flips the latched branch; watched only in the direction
            // that leaves the latched sign, and the restart state comes from
            // a step to the event (the right-hand side is smooth through the
            // zero on the latched branch).
            let (direction, terminal) = match (m.latches_normal(), m.contact.normal_branch) {
                (true, Some(true)) => (Direction::Falling, true),
                (true, Some(false)) => (Direction::Rising, true),
                _ => (Direction::Either, false),
            };
            ev.push((
                Watch::NormalZero,
                Event {
                    g: Box::new(|m, _, y| m.eval(y).map(|e| e.normal).unwrap_or(f64::NAN)),
                    direction,
                    terminal,
                    step_to_event: terminal,
                },
            ))
        }
    }
    m.stem_events(ev);
    if m.phase == Phase::Contact && m.contact.is_contensou() && m.contact.mode == Mode::Sliding {
        ev.push((
            Watch::ContensouStick,
            Event {
                g: Box::new(|m, _, y| {
                    let v = m.slip_of(y);
                    m.contact.contensou_stick_gap([v[0], v[1]], y[OMEGA + 2])
                }),
                direction: Direction::Falling,
                terminal: true,
                step_to_event: false,
            },
        ));
    }
    if m.phase == Phase::Contact && (m.contact.is_exact() || m.contact.is_contensou()) {
        match m.contact.mode {
            // Coulomb–Contensou sliding: the arrival at the stick (above).
            Mode::Sliding if m.contact.is_contensou() => {}
            // v_P · d falls through zero, d the slip direction at the last
            // accepted step: the slip vector passes through zero along d.
            Mode::Sliding => ev.push((
                Watch::SlipZero,
                Event {
                    g: Box::new(|m, _, y| {
                        let d = m.contact.slip_ref.get();
                        dot(m.slip_of(y), [d[0], d[1], 0.0])
                    }),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            )),
            Mode::Rolling => ev.push((
                Watch::StickLimit,
                Event {
                    g: Box::new(|m, _, y| {
                        m.eval(y).map(|e| m.stick_margin(&e)).unwrap_or(f64::NAN)
                    }),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            )),
        }
    }
}

/// The horizontal components `(x, y)` of a world vector, for the contact
/// state's 2D slip and friction.
fn horizontal(v: V3) -> [f64; 2] {
    [v[0], v[1]]
}

/// Decide stick or slip at zero slip (exact law, in contact): project the
/// state onto rolling contact (the projection's energy change is booked into
/// `W_f`), compute the friction rolling needs and roll if `|F_f| ≤ μ|N|`;
/// otherwise slide off with the friction `μ|N|` along the needed friction's
/// direction (the slip grows opposite to it). Returns true if it rolls.
fn settle_at_zero_slip(m: &mut Rigid, y: &mut [f64; DIM]) -> bool {
    m.contact.mode = Mode::Sliding;
    let before = m.energy_scaled(y);
    m.project_rolling(y);
    y[WF] += m.energy_scaled(y) - before;
    m.contact.mode = Mode::Rolling;
    let mut needed = None;
    if let Ok(e) = m.eval(y) {
        if m.stick_margin(&e) >= 0.0 {
            m.contact.stick();
            return true;
        }
        needed = Some(horizontal(e.friction));
    }
    m.contact.slip_off(needed);
    false
}

/// Leave rolling (stick margin through zero, or a force switch the contact
/// cannot hold, or lift-off): put the state on the rolling constraint and
/// slide off with the friction continuous in direction.
fn slide_off(m: &mut Rigid, y: &mut [f64; DIM]) {
    let needed = m
        .eval(y)
        .ok()
        .map(|e| (e.normal, horizontal(e.friction), e.torque));
    m.project_rolling(y);
    m.contact.slip_off_wrench(needed);
}

/// Arrive at the Coulomb–Contensou stick (sliding and spinning both
/// stopped, in contact; §contensou): project onto the stick (the projection's
/// energy change is booked into `W_f`) and stick if the needed wrench is
/// inside the limit curve, else slide off along it. Returns true if stuck.
fn settle_at_stick(m: &mut Rigid, y: &mut [f64; DIM]) -> bool {
    m.contact.mode = Mode::Sliding;
    let before = m.energy_scaled(y);
    m.project_stick(y);
    m.contact.mode = Mode::Rolling;
    y[WF] += m.energy_scaled(y) - before;
    let mut needed = None;
    if let Ok(e) = m.eval(y) {
        if m.stick_margin(&e) >= 0.0 {
            m.contact.stick();
            return true;
        }
        needed = Some((e.normal, horizontal(e.friction), e.torque));
    }
    m.contact.slip_off_wrench(needed);
    false
}

/// One output row from a scaled state.
pub fn sample_of(m: &Rigid, t: f64, y: &[f64; DIM]) -> Sample {
    let sc = m.scales;
    let (tu, vu) = (sc.time, sc.velocity());
    let ev = m.eval(y).ok();
    let kin = m.kin(y);
    let (k, n) = (kin.k, kin.n);
    let kdot = cross(n, k);
    let theta = kin.kh.atan2(k[2]);
    let om = if kin.kh > 1e-12 {
        (k[0] * kdot[1] - k[1] * kdot[0]) / (kin.kh * kin.kh)
    } else {
        0.0
    };
    let v = m.output_velocity(y, &kin);
    let rolling = m.phase == Phase::Contact && m.contact.mode == Mode::Rolling;
    let h = m.contact.applied();
    let normal = if m.brownian_wall() {
        // The wall's mean force over the last step (rigid/brownian.rs).
        m.wall.force
    } else {
        ev.map(|e| e.normal).unwrap_or(f64::NAN)
    };
    // Position and attitude (docs/physics.md#position): the state's x_O (its
    // height the contact constraint's value in contact, the state's in
    // flight);
    // the quaternion turned onto the integrated axis k, which the dynamics,
    // θ and every other column use.
    let l = sc.length;
    // The unit axis (|k| = 1 holds only to the integration error between
    // restarts), as θ.
    let nk = dot(k, k).sqrt();
    let ku = [k[0] / nk, k[1] / nk, k[2] / nk];
    let z = match m.phase {
        Phase::Contact if m.tube.is_some() => y[POS + 2],
        Phase::Contact => m.rho - m.a * ku[2],
        Phase::Flight => y[POS + 2],
    };
    let q = crate::observe::attitude_with_axis(quat_of(y), k);
    let (x, yy) = (y[POS] * l, y[POS + 1] * l);
    Sample {
        t: t * tu,
        theta,
        theta_dot: dot(n, kin.yh) / tu,
        precession: om / tu,
        spin: dot(n, k) / tu,
        ux: dot(v, kin.xh) * vu,
        uy: dot(v, kin.yh) * vu,
        uz: v[2] * vu,
        normal: normal * sc.force(),
        slip: if rolling {
            0.0
        } else {
            let s = m.slip_2d(y, &kin);
            s[0].hypot(s[1]) * vu
        },
        jellett: m.jellett_scaled(y) * sc.mass * sc.length.powi(3) / tu,
        energy: m.energy_scaled(y) * sc.energy(),
        work_friction: y[WF] * sc.energy(),
        work_applied: y[WA] * sc.energy(),
        hx: h[0] * sc.force(),
        hy: h[1] * sc.force(),
        rolling: rolling as u8,
        x,
        y: yy,
        z: z * l,
        qw: q[0],
        qx: q[1],
        qy: q[2],
        qz: q[3],
        xp: x + m.a * ku[0] * l,
        yp: yy + m.a * ku[1] * l,
    }
}

fn describe_state(m: &Rigid, y: &[f64]) -> String {
    if y.len() != DIM {
        return "state unavailable".into();
    }
    let mut a = [0.0; DIM];
    a.copy_from_slice(y);
    let s = sample_of(m, 0.0, &a);
    let h = crate::human::s4;
    format!(
        "state: theta = {} rad, theta_dot = {} rad/s, Omega = {} rad/s, omega = {} rad/s, ux = {} m/s, uy = {} m/s, uz = {} m/s, gap = {} m ({:?})",
        h(s.theta),
        h(s.theta_dot),
        h(s.precession),
        h(s.spin),
        h(s.ux),
        h(s.uy),
        h(s.uz),
        h(m.gap(&a) * m.scales.length),
        m.phase
    )
}

/// Put the top in contact at `y` (projected); for unilateral contact, if
/// `N < 0` there it flies at once. Returns the phase chosen. The projection's
/// kinetic-energy change is booked into `W_f`.
fn enter_contact(m: &mut Rigid, t: f64, y: &mut [f64; DIM]) -> Phase {
    let before = m.energy_raw(y);
    m.project_contact(y);
    y[WF] += m.energy_raw(y) - before;
    m.phase = Phase::Contact;
    if m.contact.contact_mode() == ContactMode::Unilateral {
        if let Ok(e) = m.eval(y) {
            if e.normal < 0.0 {
                m.phase = Phase::Flight;
                m.flight_start = t;
            }
        }
    }
    m.phase
}

impl Model<DIM> for Rigid {
    fn time_unit(&self) -> f64 {
        self.scales.time
    }

    fn axial_ratio(&self) -> f64 {
        self.ic
    }

    fn evaluations(&self) -> u64 {
        self.contact.evaluations
    }

    fn start(&mut self, sc: &Scenario, log: &mut RunLog) -> ([f64; DIM], f64) {
        let mut y = self.scale_state(&sc.initial);
        let n_initial = self.eval(&y).map(|e| e.normal).unwrap_or(f64::NAN);
        if self.brownian_wall() {
            // A free body from the start, recorded on the plane.
            self.start_wall();
            return (y, n_initial);
        }
        if self.contact.contact_mode() == ContactMode::Unilateral && n_initial < 0.0 {
            self.phase = Phase::Flight;
            self.flight_start = 0.0;
            log.lift_off(0.0);
        }
        if self.contact.is_exact() && self.phase == Phase::Contact {
            let v = self.slip_of(&y);
            if self.slip_is_zero(&y) {
                let stuck = settle_at_zero_slip(self, &mut y);
                if stuck {
                    log.start_rolling(0.0);
                }
                log.push(
                    0.0,
                    if stuck {
                        Happened::Stick
                    } else {
                        Happened::Slip
                    },
                );
            } else {
                self.contact.slip_ref.set(unit(horizontal(v)));
            }
        }
        if self.contact.is_contensou() && self.phase == Phase::Contact {
            let v = self.slip_of(&y);
            if self
                .contact
                .contensou_stick_gap(horizontal(v), y[OMEGA + 2])
                <= 0.0
            {
                // Starting (to the stick speed) at the Coulomb–Contensou
                // stick.
                let stuck = settle_at_stick(self, &mut y);
                if stuck {
                    log.start_rolling(0.0);
                }
                log.push(
                    0.0,
                    if stuck {
                        Happened::ContensouStick
                    } else {
                        Happened::Slip
                    },
                );
            }
        }
        self.contact.start_slip(horizontal(self.slip_of(&y)));
        (y, n_initial)
    }

    fn latch_force(&mut self, t: f64) {
        Rigid::latch_force(self, t);
    }

    fn latch_branch(&mut self, y: &[f64; DIM]) {
        if !self.latches_normal() {
            self.contact.normal_branch = None;
        } else if self.contact.normal_branch.is_none() {
            // The self-consistent branch at the segment's start.
            if let Ok(e) = self.eval(y) {
                self.contact.normal_branch = Some(e.normal >= 0.0);
            }
        }
    }

    fn events(&self, ev: &mut Vec<(Watch, Event<Self, DIM>)>) {
        events_for(self, ev)
    }

    fn accepted(&self, y: &[f64; DIM]) {
        if self.phase != Phase::Contact {
            return;
        }
        self.contact.accepted(|| horizontal(self.slip_of(y)));
    }

    fn track_point(&self, y: &[f64; DIM]) -> (f64, f64, f64, Option<f64>, f64) {
        (
            self.theta(y),
            self.spin_scaled(y),
            self.jellett_scaled(y),
            Some(self.energy_scaled(y)),
            y[WF] + y[WA],
        )
    }

    fn track_angles(&self, y: &[f64; DIM]) -> (f64, f64) {
        // θ and the spin of `track_point`, the same bits, without J and the
        // energy (an ensemble run records these two at every step).
        (self.theta_of_axis(y), self.spin_of_axis(y))
    }

    fn cos_theta(&self, y: &[f64; DIM]) -> f64 {
        // k_Z/|k|: a few ulps from the cosine of `theta`'s angle.
        let k = v3(y, AXIS);
        k[2] / dot(k, k).sqrt()
    }

    fn track_spin(&self, y: &[f64; DIM]) -> f64 {
        self.spin_of_axis(y)
    }

    fn flies(&self) -> bool {
        self.contact.contact_mode() == ContactMode::Unilateral
    }

    fn has_stem(&self) -> bool {
        self.spheres.1.is_some()
    }

    fn adhesive(&self) -> bool {
        self.contact.adhesive()
    }

    fn on_force_switch(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        // Latch the new force (solve does it again in begin_segment),
        // project onto the contact constraint, and fly if N < 0 now
        // (unilateral). N may jump across zero here, which no event can
        // see: without flight (bilateral, paper contact) the jump is
        // recorded as a crossing at the switch, as the on-plane models do.
        let n_before = (self.phase == Phase::Contact)
            .then(|| self.eval(y).map(|e| e.normal).ok())
            .flatten();
        Rigid::latch_force(self, t);
        self.contact.normal_branch = None;
        if self.phase == Phase::Contact && self.contact.mode == Mode::Rolling {
            // Re-check stick with the new force (N does not depend on H
            // while rolling, the friction does).
            self.project_rolling(y);
            if let Ok(e) = self.eval(y) {
                if self.stick_margin(&e) < 0.0 {
                    slide_off(self, y);
                    log.stop_rolling(t);
                    log.push(t, Happened::Slip);
                }
            }
        }
        if self.phase == Phase::Contact {
            if self.contact.mode == Mode::Sliding {
                self.project_contact(y);
            }
            let n_after = self.eval(y).map(|e| e.normal).ok();
            if let (Some(nb), Some(na), false) = (n_before, n_after, self.flies()) {
                if (nb < 0.0) != (na < 0.0) {
                    log.cross_normal(t);
                }
            }
            let n = n_after.unwrap_or(0.0);
            if self.contact.contact_mode() == ContactMode::Unilateral && n < 0.0 {
                self.phase = Phase::Flight;
                self.flight_start = t;
                log.lift_off(t);
            }
        }
        Flow::Continue
    }

    fn on_terminal(&mut self, what: Watch, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        let tu = self.scales.time;
        if what == Watch::Touchdown && self.brownian_wall() {
            return self.wall_terminal(t, y, log);
        }
        match what {
            Watch::NormalZero if self.latches_normal() => {
                // N = 0 (bilateral): continue on the other branch.
                self.contact.normal_branch = self.contact.normal_branch.map(|pos| !pos);
                Flow::Continue
            }
            Watch::NormalZero | Watch::Touchdown | Watch::PenetrationGuard => {
                self.transitions += 1;
                if self.transitions > MAX_TRANSITIONS {
                    return Flow::Stop(Error::runtime(
                        t * tu,
                        Failure::SwitchLimit,
                        format!(
                            "more than {MAX_TRANSITIONS} lift-offs and touchdowns; {}",
                            describe_state(self, y)
                        ),
                    ));
                }
                match self.phase {
                    Phase::Contact if self.tube.is_some() => Flow::Stop(Error::runtime(
                        t * tu,
                        Failure::NotModelled,
                        format!("{TUBE_FLIGHT}; {}", describe_state(self, y)),
                    )),
                    Phase::Contact => {
                        // Lift-off: N fell through 0 (from sliding or
                        // rolling: the flight starts from the rolling
                        // velocity).
                        if self.contact.mode == Mode::Rolling {
                            self.project_rolling(y);
                            self.contact.unstick();
                            log.stop_rolling(t);
                        } else {
                            self.project_contact(y);
                        }
                        self.phase = Phase::Flight;
                        self.flight_start = t;
                        log.lift_off(t);
                        if self.on_stem {
                            log.stem_off(t);
                        }
                        Flow::Continue
                    }
                    Phase::Flight => self.touch_down(t, y, log),
                }
            }
            Watch::SphereTouchdown => self.switch_sphere(t, y, log),
            Watch::SphereLiftoff => self.leave_two(t, y, log),
            Watch::ContensouStick if self.both => Flow::Stop(Error::runtime(
                t * tu,
                Failure::NotModelled,
                format!(
                    "sliding and spinning both stopped while the main sphere and the stem both touch the plane: the Coulomb-Contensou stick at two contacts is not modelled (docs/physics.md#contensou, §stem); {}",
                    describe_state(self, y)
                ),
            )),
            Watch::ContensouStick => {
                self.contact.normal_branch = None;
                if settle_at_stick(self, y) {
                    log.start_rolling(t);
                    log.push(t, Happened::ContensouStick);
                }
                Flow::Continue
            }
            Watch::SlipZero | Watch::StickLimit => {
                match self.contact.mode {
                    Mode::Sliding => {
                        if settle_at_zero_slip(self, y) {
                            log.start_rolling(t);
                            log.push(t, Happened::Stick);
                        }
                    }
                    Mode::Rolling => {
                        slide_off(self, y);
                        log.stop_rolling(t);
                        log.push(t, Happened::Slip);
                    }
                }
                Flow::Continue
            }
            _ => Flow::End,
        }
    }

    fn explain(&self, sc: &Scenario, err: RigidError) -> (Failure, String) {
        match err {
            RigidError::Painleve { theta, solutions } => (
                Failure::Painleve,
                painleve_why(sc, "N equation", theta, solutions),
            ),
            RigidError::ImpactJam { .. } => (Failure::Painleve, err.to_string()),
            RigidError::Chattering { .. } => (Failure::Chattering, err.to_string()),
            RigidError::TubeFlight => (Failure::NotModelled, err.to_string()),
        }
    }

    fn normal_force(&self, y: &[f64; DIM]) -> Option<f64> {
        match self.phase {
            Phase::Flight if self.brownian_wall() => Some(self.wall.force * self.scales.force()),
            Phase::Flight => Some(0.0),
            Phase::Contact => self.eval(y).ok().map(|e| e.normal * self.scales.force()),
        }
    }

    fn row(&self, t: f64, y: &[f64; DIM]) -> Sample {
        sample_of(self, t, y)
    }

    fn describe(&self, y: &[f64]) -> String {
        describe_state(self, y)
    }

    fn axis_norm_sq(&self, y: &[f64]) -> Option<f64> {
        let k = y.get(AXIS..AXIS + 3)?;
        Some(k[0] * k[0] + k[1] * k[1] + k[2] * k[2])
    }
}

impl Rigid {
    /// Touchdown at `t` (flight, the touchdown or guard event): put `C`
    /// exactly on the plane, apply the impact, and settle into contact
    /// when the rebound is too short to follow.
    fn touch_down(&mut self, t: f64, y: &mut [f64; DIM], log: &mut RunLog) -> Flow {
        if self.on_stem {
            log.stem_on(t);
        } else {
            log.push(t, Happened::Touchdown);
        }
        let kz = self.kin(y).k[2];
        let before = self.energy_scaled(y);
        y[POS + 2] = self.rho - self.a * kz;
        let (yn, vn_plus, stuck) = match self.impact(y) {
            Ok(v) => v,
            Err(err) => {
                return Flow::Stop(Error::runtime(
                    t * self.scales.time,
                    Failure::Painleve,
                    format!("{err}; {}", describe_state(self, y)),
                ));
            }
        };
        // Book the impact's energy change (position unchanged) into W_f.
        let after = self.energy_scaled(&yn);
        *y = yn;
        y[WF] += after - before;
        self.bounces += 1;
        let qf = self.eval(y).map(|e| e.q_free).unwrap_or(0.0);
        let t_fl = if qf > 0.0 {
            2.0 * vn_plus / qf
        } else {
            f64::INFINITY
        };
        let settle = vn_plus <= 0.0
            || t_fl < MIN_FLIGHT
            || (self.bounces > MAX_BOUNCES && t_fl < 1e3 * MIN_FLIGHT);
        self.flight_start = t;
        if settle {
            log.land(t);
            self.bounces = 0;
            if enter_contact(self, t, y) == Phase::Flight {
                log.lift_off(t);
                if self.on_stem {
                    log.stem_off(t);
                }
            } else if self.contact.is_contensou() {
                // A sticking impulse (slip and spin about Z zero) leaves the
                // contact at the Coulomb–Contensou stick, decided there.
                if stuck && settle_at_stick(self, y) {
                    log.start_rolling(t);
                    log.push(t, Happened::ContensouStick);
                }
            } else if self.contact.is_exact() {
                // Exact law: a sticking impulse leaves zero slip, where
                // stick/slip is decided as at a slip-zero event.
                self.contact.slip_hint = [0.0; 2];
                let v = self.slip_of(y);
                if stuck || self.slip_is_zero(y) {
                    if settle_at_zero_slip(self, y) {
                        log.start_rolling(t);
                        log.push(t, Happened::Stick);
                    }
                } else {
                    self.contact.slip_ref.set(unit(horizontal(v)));
                }
            }
        } else if self.on_stem {
            // A bounce of the stem's sphere.
            log.stem_off(t);
        }
        Flow::Continue
    }
}
