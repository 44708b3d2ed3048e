//! Applied physics as data: a list of force terms, each of one [`Kind`].
//!
//! A *term* is one physical effect with its scenario keys (the paper's
//! retarding force `H`, a vertical load `h_z`, ...). A *kind* is how a term
//! enters the equations of motion; every model implements each kind once,
//! so a new term of an implemented kind is one file here (a type
//! implementing [`ForceTerm`]) plus its scenario keys and one line in
//! [`Forces::of`]. Each term states, in code ([`ForceTerm::properties`])
//! and in its doc, how it enters the normal-force closure `N D(σ) = Q`
//! (docs/physics.md §4), whether it conserves Jellett's J (§7) and whether
//! it has a potential or its work is integrated (like `W_a`).
//!
//! Wired today: [`Kind::ContactPoint`], with the terms [`retarding::Retarding`]
//! (the paper's `H`) and [`vertical_load::VerticalLoad`] (`force.K.hz`,
//! §17). The other kinds are declared so that their place is fixed; no
//! model applies them yet, and [`Applied`] has no slot for them (a term of
//! such a kind cannot be built until its kind is wired). docs/architecture.md
//! ("Forces as data") describes the seam.

pub mod retarding;
pub mod vertical_load;

use std::sync::Arc;

use crate::Scenario;

/// How a kind of term enters the models.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A force at the contact point `P`, components in the precessing frame
    /// `(x̂, ŷ, Z)` (docs/physics.md §1); the force on the top is
    /// `−(h_x x̂ + h_y ŷ + h_z Z)` (the paper's sign). Closure: it changes
    /// the gap's acceleration by `(K F)_Z` (`K` the contact matrix of §11),
    /// so `Q` gains `a (H·w)` for the horizontal part and `h_z D₀` for the
    /// vertical part, `D₀ = D(σ)` without friction (§17). Conserves J (its
    /// moment about the centre of mass is `r × F`, §7). No potential: its
    /// work `∫ F·v_P dt` is integrated in `W_a` (zero while rolling; the
    /// vertical part does work only in flight). Wired in every model.
    ContactPoint,
    /// Not yet wired (issue #14, adhesion): a force along the vertical
    /// through the sphere's centre that depends on the contact state: in
    /// contact a load that adds to `N` directly (no torque about `P`, no
    /// work), in flight a potential `U(gap)`. Conserves J.
    CentreVertical,
    /// Not yet wired: a force at a body point, lab frame (tips, field
    /// gradients). Enters `Q` through its torque's share; does not conserve
    /// J in general; work integrated.
    BodyPoint,
    /// Not yet wired: a pure torque (field torques, drilling, rolling
    /// resistance). Enters `Q` through `ṅ`; J not conserved in general;
    /// work integrated.
    Torque,
    /// Not yet wired: linear damping with a hook for its noise (the thermal
    /// issue fills it). Dissipative; J not conserved in general; work
    /// integrated.
    Damping,
}

/// What a term's energy does, for the energy balance `E − E0 = W_f + W_a`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Energy {
    /// No potential: the work is integrated into `W_a`.
    Integrated,
    /// A potential that the energy `E` includes.
    Potential,
}

/// What a term states about itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Properties {
    /// How the term enters the normal-force closure `N D(σ) = Q`.
    pub closure: &'static str,
    /// True if Jellett's `J` is conserved under the term.
    pub conserves_jellett: bool,
    /// Potential or integrated work.
    pub energy: Energy,
}

/// The applied physics in effect at one time, summed by kind (SI).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Applied {
    /// `(h_x, h_y, h_z)` \[N\] at the contact point, precessing frame; the
    /// force on the top is `−(h_x x̂ + h_y ŷ + h_z Z)` ([`Kind::ContactPoint`]).
    pub contact_point: [f64; 3],
}

/// One applied-force term.
pub trait ForceTerm: std::fmt::Debug + Send + Sync {
    /// A short name, for messages.
    fn name(&self) -> &'static str;
    /// How it enters the models.
    fn kind(&self) -> Kind;
    /// How it enters the closure, whether it conserves J, its energy.
    fn properties(&self) -> Properties;
    /// Add the term's value at time `t` \[s\] to `acc` (SI). Constant
    /// between the scenario's force switch times.
    fn add_to(&self, t: f64, acc: &mut Applied);
}

/// The latched contact-point force of a segment, scaled (force unit of
/// [`crate::physics::units::Scales`]): what the models read.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactPointForce {
    /// `(h_x, h_y)`: the paper's `H` (the force on the top is `−H`).
    pub h: [f64; 2],
    /// `h_z`: the vertical load (the force on the top is `−h_z Z`); `+0`
    /// when there is none.
    pub hz: f64,
}

impl ContactPointForce {
    /// `Q` of the closure `N D(σ) = Q` with the load: `Q + h_z D₀`, `D₀`
    /// the closure's `D(σ)` without friction (docs/physics.md §17). `Q`
    /// itself when there is no load (bit for bit).
    #[inline(always)]
    pub fn closure_q(&self, q: f64, d0: f64) -> f64 {
        if self.hz == 0.0 { q } else { q + self.hz * d0 }
    }

    /// The total vertical force at `P` on the top, `N − h_z`, from the
    /// plane's reaction `N` (`N` itself when there is no load: `hz` is `+0`).
    #[inline(always)]
    pub fn vertical_total(&self, normal: f64) -> f64 {
        normal - self.hz
    }

    /// The plane's reaction `N = F_Z + h_z` from the total vertical contact
    /// force `F_Z` (rolling's constraint force); `F_Z` itself when there is
    /// no load (bit for bit).
    #[inline(always)]
    pub fn reaction(&self, fz: f64) -> f64 {
        if self.hz == 0.0 { fz } else { fz + self.hz }
    }
}

/// Relative distance within which a latch time is read as a switch time
/// ([`Forces::latch`]): a few roundings of the scaled time's round trip.
pub const SWITCH_SNAP: f64 = 8.0 * f64::EPSILON;

/// A scenario's force terms and the value latched for the current segment.
#[derive(Debug, Clone)]
pub struct Forces {
    terms: Vec<Arc<dyn ForceTerm>>,
    /// The schedule's switch times \[s\], sorted.
    switch_times: Vec<f64>,
    latched: ContactPointForce,
}

impl Forces {
    /// The terms of `sc` (nothing latched: zero force). A new term is one
    /// line here.
    pub fn of(sc: &Scenario) -> Self {
        let mut terms: Vec<Arc<dyn ForceTerm>> =
            vec![Arc::new(retarding::Retarding::of(&sc.forcing))];
        if sc.forcing.has_load() {
            terms.push(Arc::new(vertical_load::VerticalLoad::of(&sc.forcing)));
        }
        Forces {
            terms,
            switch_times: sc.forcing.switch_times(),
            latched: ContactPointForce::default(),
        }
    }

    /// The terms.
    pub fn terms(&self) -> &[Arc<dyn ForceTerm>] {
        &self.terms
    }

    /// The sum of every term at time `t` \[s\] (SI).
    pub fn at(&self, t: f64) -> Applied {
        let mut acc = Applied::default();
        for term in &self.terms {
            term.add_to(t, &mut acc);
        }
        acc
    }

    /// Latch the force in effect at `t` \[s\], scaled by `force_unit` \[N\].
    ///
    /// The models latch at a segment's start, a switch time `s` that went
    /// through the scaled time `s/T` and back (`t = (s/T)·T`), which can land
    /// an ulp below `s`, where the schedule still has the old force (a
    /// window ending at `0.1 + 0.02` stayed on for the rest of the run with
    /// `T = 0.02 s`). A `t` within [`SWITCH_SNAP`] (relative) of a switch
    /// time is therefore read at the switch time itself: the force that
    /// starts there.
    pub fn latch(&mut self, t: f64, force_unit: f64) {
        let i = self.switch_times.partition_point(|&s| s < t);
        let near = |s: f64| (s - t).abs() <= SWITCH_SNAP * s.abs();
        let t = [i.checked_sub(1), Some(i)]
            .into_iter()
            .flatten()
            .filter_map(|j| self.switch_times.get(j).copied())
            .find(|&s| near(s))
            .unwrap_or(t);
        let [hx, hy, hz] = self.at(t).contact_point;
        self.latched = ContactPointForce {
            h: [hx / force_unit, hy / force_unit],
            hz: hz / force_unit,
        };
    }

    /// The latched contact-point force (scaled).
    #[inline(always)]
    pub fn contact_point(&self) -> ContactPointForce {
        self.latched
    }
}
