//! The physics spec: every invariant and closed form written once, as a
//! function of the model (`solver.model` = reduced, vector, rigid), and run
//! on every model it applies to. A model is left out only by a filter that
//! says why ([`spec::cannot`]: the model cannot do this by construction;
//! [`spec::known_gap`]: it should and does not yet, with the measured
//! number). A failing check names the model. Every tolerance is justified
//! next to its assertion.
//!
//! - `invariants`: Jellett's J, energy conservation and balance, the
//!   normal-force closure, determinism, negative N reported;
//! - `closed_forms`: steady precession, nutation frequency, the inverted
//!   top's n_Z, Painlevé, N jumping below zero at a force switch, the poles;
//! - `stick_slip`: the exact Coulomb law (sliding → rolling closed forms,
//!   rolling dissipates nothing, the stick limit, cost, chattering);
//! - `convergence`: RK4's order, rtol scaling, the stiff method, the kink
//!   of μ|N| where N changes sign;
//! - `crosscheck`: the models against each other;
//! - `forces`: the applied force terms (the vertical load `force.K.hz`);
//! - `actuators`: the body actuators (a tip at a body point, a magnetic
//!   dipole in a field; §actuators): closed forms in flight, the contact-point
//!   force through P, the energy balance, Jellett's J;
//! - `adhesion`: van der Waals adhesion (`[adhesion]`, a centre-vertical term);
//! - `wells`: orientation wells (`[[well]]`, a torque about `ŷ ⊥ k`):
//!   small-oscillation period, energy with the potential, J, a barrier;
//! - `position`: where the top is (position, attitude, contact point);
//! - `initial`: the lab-frame initial state and the heading (isotropy);
//! - `rigid`: what only the rigid model has (attitude, flight, impacts);
//! - `stem`: the stem's second contact sphere (§stem): θ_td, the energy
//!   balance across its touchdowns, its Jellett integral, the on-plane stop;
//! - `first_passage`: the Brownian escape time against the exact mean
//!   first-passage time (the retention machinery's closed-form check);
//! - `thermal`: Langevin dynamics (vector model): equipartition, the
//!   orientation density, diffusion, the damped energy, replay.

mod actuators;
mod adhesion;
mod brownian_wall;
mod closed_forms;
mod contensou;
mod convergence;
mod crosscheck;
mod first_passage;
mod forces;
mod initial;
mod invariants;
mod position;
mod rigid;
mod spec;
mod stem;
mod stick_slip;
mod thermal;
mod wells;
