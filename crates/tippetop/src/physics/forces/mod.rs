//! Applied physics as data: a list of force terms, each of one [`Kind`].
//!
//! A *term* is one physical effect with its scenario keys (the paper's
//! retarding force `H`, a vertical load `h_z`, ...). A *kind* is how a term
//! enters the equations of motion; every model implements each kind once,
//! so a new term of an implemented kind is one file here (a [`Plugin`]:
//! its scenario table, validation, doc and a type implementing
//! [`ForceTerm`]) plus one line in [`PLUGINS`] (docs/extending.md; the
//! example is [`wind`]; [`adhesion`] and [`wells`] are too). The older terms (the
//! `[[force]]` schedule's retarding force and vertical load and body
//! actuators) are windows of that schedule, each in its file with its keys,
//! their parse, checks and rendering ([`retarding::KEYS`],
//! [`vertical_load::KEY`], [`actuators::KEYS`]) and its term, which keeps
//! its values as [`Window`]s; the schedule (input/forcing.rs) reads a
//! window's `kind`, `start`, `stop` and hands the rest to its term's file,
//! and the terms are built in `Forces::of` (input/scenario/plugins.rs). Each term states, in code ([`ForceTerm::properties`])
//! and in its doc, how it enters the normal-force closure `N D(σ) = Q`
//! (docs/physics.md#normal-force), whether it conserves Jellett's J (§invariants) and whether
//! it has a potential or its work is integrated (like `W_a`).
//!
//! Wired today: [`Kind::ContactPoint`], with the terms [`retarding::Retarding`]
//! (the paper's `H`) and [`vertical_load::VerticalLoad`] (`force.K.hz`,
//! §vertical-load), and [`Kind::CentreVertical`], with the plug-in [`adhesion::AdhesionPlugin`]
//! (van der Waals adhesion, §adhesion), [`Kind::Torque`], with the term
//! the plug-in [`wells::WellsPlugin`] (orientation wells, §wells), and [`Kind::BodyPoint`], with
//! the terms [`actuators::Actuators`] (tips and magnetic dipoles, §actuators;
//! vector and rigid models). The other kinds are declared so that their place is fixed; no
//! model applies them yet, and [`Applied`] has no slot for them (a term of
//! such a kind cannot be built until its kind is wired). docs/architecture.md
//! ("Where to add") describes the seam.

pub mod actuators;
pub mod adhesion;
pub mod retarding;
pub mod vertical_load;
pub mod wells;
pub mod wind;

use std::sync::Arc;

use crate::Error;
use crate::input::TableSpec;

/// A force plug-in: a term with a scenario table of its own, in one file
/// (its keys with their ranges, defaults and docs; their validation; its
/// doc; its physics), listed once in [`PLUGINS`]. The scenario parser,
/// `--set`, `to_toml`, the validation messages and `tippetop keys` learn
/// its table from there (docs/extending.md). Its values are numbers, one
/// per key, in the order of its keys (a key left out has its default); for
/// an array of tables (`[[well]]`), each entry's numbers in turn
/// (`values.chunks(keys.len())`).
pub trait Plugin: Sync {
    /// Its scenario table (name, one-line doc, keys).
    fn table(&self) -> TableSpec;
    /// How it enters the models. The reduced model applies only
    /// [`Kind::ContactPoint`], [`Kind::CentreVertical`] and [`Kind::Torque`]
    /// terms; a scenario with a plug-in of another kind and
    /// `model = "reduced"` is refused, naming the table.
    fn kind(&self) -> Kind;
    /// The scenario table its table follows in a scenario's text, the
    /// listing of `tippetop keys` and docs/keys.md (one of the scenario's
    /// own tables: `top`, `surface`, `force`, `well`, `initial`, `solver`,
    /// `thermal`). Default: `thermal`, the end. The older terms keep the
    /// place their tables had (`[adhesion]` after `[surface]`), so that
    /// scenario texts did not change when they became plug-ins.
    fn follows(&self) -> &'static str {
        "thermal"
    }
    /// Whether a table with these values stays in the scenario (is written
    /// by `to_toml`, refused where plug-ins are). Default: always. The
    /// `[adhesion]` table with both numbers zero is dropped, as it always was.
    fn keeps(&self, _values: &[f64]) -> bool {
        true
    }
    /// True for the older terms that the code handles by name: the
    /// stability and exact rare-event analyses model or refuse
    /// `[adhesion]` themselves, and the stem's and the tube's refusals name
    /// it. False (the default) for a new term, which they refuse as "a
    /// force plug-in's table" (`input::scenario::plugins::first_key`).
    fn handled_by_name(&self) -> bool {
        false
    }
    /// For an array of tables ([`TableSpec::array`], `[[well]]`): what one
    /// entry is called in messages, singular and plural (`"well"`,
    /// `"wells"`). Default: `"entry"`, `"entries"`.
    fn entry(&self) -> (&'static str, &'static str) {
        ("entry", "entries")
    }
    /// Checks beyond each key's bounds ([`crate::input::Key::bounds`],
    /// checked before); `values` in the order of the keys.
    fn validate(&self, _values: &[f64]) -> Result<(), Error> {
        Ok(())
    }
    /// The term of `values`, or `None` when it applies nothing (the run is
    /// then that without the table, bit for bit).
    fn term(&self, values: &[f64]) -> Option<Arc<dyn ForceTerm>>;
    /// The fastest rate \[1/s\] the term sets for a top of mass `mass`
    /// \[kg\], radius `radius` \[m\] and transverse inertia `inertia`
    /// \[kg m²\], with its formula: it joins the rates of the time unit
    /// (`scenario::limits::time_unit`) and of the Langevin step check
    /// (`scenario::langevin::step_rates`). Default: none.
    fn rate(
        &self,
        _values: &[f64],
        _mass: f64,
        _radius: f64,
        _inertia: f64,
    ) -> Option<(f64, &'static str)> {
        None
    }
}

/// The force plug-ins: a new one is its file plus one line here.
pub static PLUGINS: &[&dyn Plugin] = &[&adhesion::AdhesionPlugin, &wells::WellsPlugin, &wind::Wind];

/// The plug-in whose table is `name`.
pub fn plugin(name: &str) -> Option<&'static dyn Plugin> {
    PLUGINS.iter().copied().find(|p| p.table().name == name)
}

/// How a kind of term enters the models.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A force at the contact point `P`, components in the precessing frame
    /// `(x̂, ŷ, Z)` (docs/physics.md#geometry); the force on the top is
    /// `−(h_x x̂ + h_y ŷ + h_z Z)` (the paper's sign). Closure: it changes
    /// the gap's acceleration by `(K F)_Z` (`K` the contact matrix of §rigid-model),
    /// so `Q` gains `a (H·w)` for the horizontal part and `h_z D₀` for the
    /// vertical part, `D₀ = D(σ)` without friction (§vertical-load). Conserves J (its
    /// moment about the centre of mass is `r × F`, §invariants). No potential: its
    /// work `∫ F·v_P dt` is integrated in `W_a` (zero while rolling; the
    /// vertical part does work only in flight). Wired in every model.
    ContactPoint,
    /// A force along the vertical through the sphere's centre that depends
    /// on the contact state (docs/physics.md#adhesion): in contact a load `F_a`
    /// that adds to the plane's reaction (`N_c = F_a + N`, where `N − F_a`
    /// is what the closure gives the motion; no torque about `P`, no
    /// work), in flight (rigid model) the force `−U′(gap)` of a potential
    /// `U(gap)` that the energy includes. Its line passes through `P`, so
    /// the models apply it as a vertical load at `P` ([`ContactPointForce::with_load`]).
    /// Conserves J. Wired in every model.
    CentreVertical,
    /// A wrench from the body: a force `F` at the centre of mass and a
    /// torque `τ` about it, lab frame (a tip at a body point: `F` and
    /// `ρ × F`; a magnetic dipole: `μ k × B` and `∇(μ k·B)`;
    /// [`actuators`], docs/physics.md#actuators). It adds to the free
    /// accelerations, `v̇ += F/m`, `ẇ₀ += I⁻¹ τ`, so `Q` gains
    /// `−F_Z/m − a (I⁻¹ τ)·e` and the rolling constraint's right-hand side
    /// `−F/m`. J: `dJ/dt = −τ·r`, conserved only if the line of a tip's
    /// force passes through `P` (or a field is vertical). Work integrated
    /// (`F·v_O + τ·w`, rolling or not). Wired in the vector and rigid
    /// models (contact and flight); the reduced model refuses it. Terms:
    /// [`actuators::Actuators`] and the plug-in [`wind::Wind`].
    BodyPoint,
    /// A pure torque (a couple). Wired for torques about the horizontal
    /// axis `ŷ ⊥ k` that derive from a potential in θ
    /// ([`wells::WellsPlugin`], docs/physics.md#wells): it adds `τ/A` to the
    /// torque-free angular acceleration, so it enters `Q` through `ṅ`
    /// (`Q += a s τ_y/A`); J conserved (`τ ⊥ k`, `τ ⊥ Z`); potential `U(θ)`
    /// in the energy. A magnetic field's torque `μ k × B` is applied as
    /// a [`Kind::BodyPoint`] wrench (with its gradient force, §actuators). Other
    /// torques (drilling, rolling resistance) are not wired: in general J
    /// is not conserved and the work is integrated.
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
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Applied {
    /// `(h_x, h_y, h_z)` \[N\] at the contact point, precessing frame; the
    /// force on the top is `−(h_x x̂ + h_y ŷ + h_z Z)` ([`Kind::ContactPoint`]).
    pub contact_point: [f64; 3],
    /// The centre-vertical term ([`Kind::CentreVertical`]): pull-off force
    /// `F_a` \[N\] and binding energy `E_b` \[J\]; zero without adhesion.
    pub centre_vertical: CentreVertical,
    /// The orientation wells ([`Kind::Torque`]), SI; empty without wells.
    pub wells: Vec<wells::Well>,
    /// The body actuators in effect ([`Kind::BodyPoint`]), SI; zero without.
    pub body: actuators::BodyLoad,
}

/// A value in effect on `[start, stop)` \[s\]: one window of the
/// `[[force]]` schedule (input/forcing.rs) as a windowed term keeps it
/// ([`retarding::Retarding`], [`vertical_load::VerticalLoad`],
/// [`actuators::Actuators`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window<T> {
    /// Switch-on time \[s\].
    pub start: f64,
    /// Switch-off time \[s\]; `f64::INFINITY` for never.
    pub stop: f64,
    /// What the window applies.
    pub value: T,
}

impl<T> Window<T> {
    /// `value` on `[start, stop)` \[s\].
    pub fn at((start, stop): (f64, f64), value: T) -> Self {
        Window { start, stop, value }
    }

    /// True if it acts at `t` \[s\]: `start <= t < stop`.
    #[inline(always)]
    pub fn active(&self, t: f64) -> bool {
        self.start <= t && t < self.stop
    }
}

/// A centre-vertical force: the pull-off force `F_a` and the binding
/// energy `E_b` of the gap potential `U(z) = −E_b exp(−F_a z/E_b)` (so
/// `U(0) = −E_b`, `−U′(0) = F_a`). SI in [`Applied`]; scaled (force unit,
/// energy unit = force unit × R) when latched ([`Forces::centre_vertical`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CentreVertical {
    /// `F_a`: the load in contact, and the attraction at zero gap.
    pub force: f64,
    /// `E_b`: the separation work (`U(∞) − U(0)`).
    pub energy: f64,
}

impl CentreVertical {
    /// The load in contact, `F_a` (`+0` without adhesion).
    #[inline(always)]
    pub fn in_contact(&self) -> f64 {
        self.force
    }

    /// The attraction at gap `z >= 0`: `−U′(z) = F_a exp(−F_a z/E_b)`
    /// (`0` without adhesion; continuous with [`Self::in_contact`] at `z = 0`).
    #[inline(always)]
    pub fn at_gap(&self, z: f64) -> f64 {
        if self.force == 0.0 {
            0.0
        } else {
            self.force * (-self.force * z / self.energy).exp()
        }
    }

    /// The potential relative to contact, `U(z) − U(0) = E_b (1 − exp(−F_a z/E_b))`:
    /// what the energy adds in flight (`0` in contact and without adhesion).
    #[inline(always)]
    pub fn potential(&self, z: f64) -> f64 {
        if self.force == 0.0 {
            0.0
        } else {
            -self.energy * (-self.force * z / self.energy).exp_m1()
        }
    }
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
    /// The same force with `load` added to the vertical load `h_z`: how
    /// the models apply a centre-vertical force `load` (its line passes
    /// through `P`, §adhesion). `self` itself when `load` is zero (bit for bit).
    #[inline(always)]
    pub fn with_load(self, load: f64) -> Self {
        if load == 0.0 {
            self
        } else {
            ContactPointForce {
                hz: self.hz + load,
                ..self
            }
        }
    }

    /// `Q` of the closure `N D(σ) = Q` with the load: `Q + h_z D₀`, `D₀`
    /// the closure's `D(σ)` without friction (docs/physics.md#vertical-load). `Q`
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
    /// The centre-vertical force, scaled ([`Forces::latch`]).
    centre: CentreVertical,
    /// `latched` with the centre-vertical force in contact folded into its
    /// vertical load ([`Forces::contact_point_in_contact`]), kept at the
    /// latch: the models ask at every evaluation.
    in_contact: ContactPointForce,
    /// The top's radius \[m\]: the length unit, for the energy unit.
    radius: f64,
    /// The orientation wells, depths scaled ([`Forces::scale_wells`]);
    /// empty without wells.
    wells: Vec<wells::Well>,
    /// The body actuators' load, scaled ([`Forces::latch`]).
    body: actuators::BodyLoad,
    /// `body.is_zero()`, kept at the latch: the models ask at every
    /// evaluation, and comparing the load's 24 numbers cost ~77
    /// instructions an evaluation (docs/performance.md#langevin-step).
    body_zero: bool,
    /// Latches that changed the latched values so far: what the models'
    /// evaluation caches key on (the latched values change only there).
    generation: u64,
    /// Where the last latch read the schedule: the number of switch times
    /// below the time it read, that time's bits if it was one of them, and
    /// the force unit's bits ([`Forces::latch`]).
    latched_at: Option<(usize, Option<u64>, u64)>,
    /// What the latched segment applies ([`Forces::applied`]), kept at the
    /// latch and when the wells are set.
    applied: AppliedClass,
}

/// What a latched segment applies, in the classes the models' right-hand
/// sides are specialised on ([`Forces::applied`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AppliedClass {
    /// Anything: wells, body actuators, a vertical load, adhesion, `H`.
    General,
    /// At most the horizontal force `H` at the contact point
    /// ([`Forces::only_horizontal`]).
    OnlyHorizontal,
    /// Nothing ([`Forces::nothing_applied`]).
    Nothing,
}

impl Forces {
    /// The force of `terms` (nothing latched: zero force), switching at
    /// `switch_times` \[s\] (sorted), for a top of radius `radius` \[m\]
    /// (the length unit). A scenario's: `Forces::of` (input/scenario/plugins.rs).
    pub fn new(terms: Vec<Arc<dyn ForceTerm>>, switch_times: Vec<f64>, radius: f64) -> Self {
        Forces {
            terms,
            switch_times,
            latched: ContactPointForce::default(),
            centre: CentreVertical::default(),
            in_contact: ContactPointForce::default(),
            radius,
            wells: Vec::new(),
            body: actuators::BodyLoad::default(),
            body_zero: true,
            generation: 0,
            latched_at: None,
            applied: AppliedClass::Nothing,
        }
    }

    /// True if the latched segment applies nothing: no wells, no body
    /// actuators, and the contact-point force and the centre-vertical load
    /// `+0` exactly (the values a scenario without force terms latches).
    /// The models' right-hand sides then take a path with these terms
    /// known to be absent: the same arithmetic on the same values, without
    /// the tests and loads that find each absent (issue #28, "forces as
    /// data should cost nothing when a term is absent").
    #[inline(always)]
    pub fn nothing_applied(&self) -> bool {
        self.applied == AppliedClass::Nothing
    }

    /// True if the latched segment applies at most the horizontal force
    /// `H` at the contact point: no wells, no body actuators, the vertical
    /// load and the centre-vertical load `+0` exactly ([`Forces::nothing_applied`]
    /// with `H` allowed).
    #[inline(always)]
    pub fn only_horizontal(&self) -> bool {
        self.applied != AppliedClass::General
    }

    /// [`Forces::nothing_applied`] and [`Forces::only_horizontal`] as one
    /// value, kept at the latch: the models' right-hand sides pick their
    /// specialised path with one load.
    #[inline(always)]
    pub fn applied(&self) -> AppliedClass {
        self.applied
    }

    /// Recompute [`Forces::applied`] and [`Forces::contact_point_in_contact`].
    fn update_nothing(&mut self) {
        self.in_contact = self.latched.with_load(self.centre.in_contact());
        let zero = 0.0f64.to_bits();
        let ContactPointForce { h, hz } = self.latched;
        let only_h = self.wells.is_empty()
            && self.body_zero
            && hz.to_bits() == zero
            && self.centre.force.to_bits() == zero;
        self.applied = if only_h && h[0].to_bits() == zero && h[1].to_bits() == zero {
            AppliedClass::Nothing
        } else if only_h {
            AppliedClass::OnlyHorizontal
        } else {
            AppliedClass::General
        };
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
        // The terms are constant between switch times (`ForceTerm::add_to`):
        // a latch inside the interval (or at the switch time) the last one
        // read latches the same values, which are kept, generation and all
        // (a nano run latches at every stick/slip and normal-force switch).
        let k = self.switch_times.partition_point(|&s| s < t);
        let exact = (self.switch_times.get(k) == Some(&t)).then_some(t.to_bits());
        let at = (k, exact, force_unit.to_bits());
        if self.latched_at == Some(at) {
            return;
        }
        self.latched_at = Some(at);
        let applied = self.at(t);
        let [hx, hy, hz] = applied.contact_point;
        self.latched = ContactPointForce {
            h: [hx / force_unit, hy / force_unit],
            hz: hz / force_unit,
        };
        let cv = applied.centre_vertical;
        self.centre = CentreVertical {
            force: cv.force / force_unit,
            energy: cv.energy / (force_unit * self.radius),
        };
        self.body = applied.body.scaled(force_unit, self.radius);
        self.body_zero = self.body.is_zero();
        self.generation += 1;
        self.update_nothing();
    }

    /// The latched body actuators' load (scaled; zero without actuators).
    #[inline(always)]
    pub fn body(&self) -> &actuators::BodyLoad {
        &self.body
    }

    /// True if the latched body actuators apply nothing
    /// ([`actuators::BodyLoad::is_zero`] of [`Forces::body`], kept at the
    /// latch).
    #[inline(always)]
    pub fn body_is_zero(&self) -> bool {
        self.body_zero
    }

    /// The number of latches so far (a cache key: the latched values
    /// change only at a latch).
    #[inline(always)]
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Scale the wells' depths by `energy_unit` \[J\] (once, when the model
    /// is built: the wells do not change during a run).
    pub fn scale_wells(&mut self, energy_unit: f64) {
        self.wells = self
            .at(0.0)
            .wells
            .iter()
            .map(|w| wells::Well {
                depth: w.depth / energy_unit,
                ..*w
            })
            .collect();
        self.update_nothing();
    }

    /// The latched orientation wells (depths scaled; empty without wells).
    #[inline(always)]
    pub fn wells(&self) -> &[wells::Well] {
        &self.wells
    }

    /// The latched centre-vertical force (scaled; zero without adhesion).
    #[inline(always)]
    pub fn centre_vertical(&self) -> CentreVertical {
        self.centre
    }

    /// The latched contact-point force (scaled).
    #[inline(always)]
    pub fn contact_point(&self) -> ContactPointForce {
        self.latched
    }

    /// The latched contact-point force with the centre-vertical force in
    /// contact added to its vertical load (scaled; kept at the latch, the
    /// same bits as `contact_point().with_load(centre_vertical().in_contact())`).
    #[inline(always)]
    pub fn contact_point_in_contact(&self) -> ContactPointForce {
        self.in_contact
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scenario;

    /// `Forces::latch` keeps its values and generation inside the open
    /// interval, or at the switch time, the last latch read, and reads the
    /// schedule again elsewhere: a schedule of H on [0, 1) and −H/2 from 1 s, latched
    /// as a run's segments would (every value compared with a fresh
    /// `Forces` latched once at the same time). Fails if the latch kept a
    /// value across a switch, or bumped the generation without a change.
    #[test]
    fn latch_rereads_the_schedule_only_across_a_switch() {
        let text = "preset = \"classical\"\n\
            [[force]]\nhx = 2e-3\nhy = -1e-3\nstart = 0.0\nstop = 1.0\n\
            [[force]]\nhx = -1e-3\nhy = 5e-4\nstart = 1.0\n";
        let sc = Scenario::from_toml_str(text).unwrap();
        let unit = 0.5;
        let fresh = |t: f64| {
            let mut f = Forces::of(&sc);
            f.latch(t, unit);
            f.contact_point()
        };
        let mut f = Forces::of(&sc);
        // (time, whether the values must be re-read there)
        let steps = [
            (0.0, true),
            (0.25, true), // a switch time and the interval after it: read apart
            (0.999, false),
            (1.0, true),
            (1.0, false),
            (1.0 - 1e-18, false), // snapped to the switch time 1.0
            (1.5, true),
            (2.0, false),
            // Across a switch with no latch at it.
            (0.5, true),
            (1.5, true),
        ];
        let mut generation = f.generation();
        for (t, rereads) in steps {
            f.latch(t, unit);
            assert_eq!(f.contact_point(), fresh(t), "t = {t}");
            assert_eq!(f.generation() != generation, rereads, "t = {t}");
            generation = f.generation();
        }
        assert_eq!(fresh(0.5).h, [2e-3 / unit, -1e-3 / unit]);
        assert_eq!(fresh(1.0).h, [-1e-3 / unit, 5e-4 / unit]);
    }
}
