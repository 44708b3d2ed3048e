//! A vertical load at the contact point, `force.K.hz` \[N\] (docs/physics.md
//! §vertical-load): positive pushes the top onto the plane, so the force on the top is
//! `−h_z Z` at `P`. `N` stays the plane's reaction; the total vertical force
//! at `P` is `N − h_z`.
//!
//! - Closure: `N D(σ) = Q + h_z D₀`, `D₀` the closure's `D` without friction
//!   (`1 + m a² s²/A` in the Euler angles). Without friction `N − h_z` and the
//!   motion are those without the load: the load acts along the constraint's
//!   own line and the plane takes it up; it changes the motion only through
//!   the friction, which sees `N`. A sphere (`a = 0`) has `N = m g + h_z`.
//!   Rolling: the constraint force is unchanged, `N = F_Z + h_z`.
//! - Jellett's J: conserved (a force at `P`, §invariants).
//! - Energy: no potential. It does no work in contact (`v_Pz = 0`); in
//!   flight (rigid model) its work `−h_z v_Pz` is integrated in `W_a`.

use super::{Applied, Energy, ForceTerm, Kind, Properties};
use crate::Forcing;
use crate::input::Key;

/// Its key in a `[[force]]` window, `force.K.hz` (listed with the window's
/// other keys in `input/scenario.rs`'s `FORCE_KEYS`; its value is checked
/// with the window, `input/forcing.rs`).
pub const KEY: Key = Key::doc(
    "hz",
    "a finite force [N] (vertical load at the contact point, > 0 pushes onto the plane)",
    "0",
    "vertical load at the contact point (docs/physics.md#vertical-load)",
);

/// The vertical load from the force windows.
#[derive(Debug, Clone)]
pub struct VerticalLoad {
    schedule: Forcing,
}

impl VerticalLoad {
    /// The term of a schedule.
    pub fn of(schedule: &Forcing) -> Self {
        VerticalLoad {
            schedule: schedule.clone(),
        }
    }
}

impl ForceTerm for VerticalLoad {
    fn name(&self) -> &'static str {
        "vertical load (force.K.hz)"
    }
    fn kind(&self) -> Kind {
        Kind::ContactPoint
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "Q += hz D0, D0 = D without friction (docs/physics.md#vertical-load)",
            conserves_jellett: true,
            energy: Energy::Integrated,
        }
    }
    fn add_to(&self, t: f64, acc: &mut Applied) {
        acc.contact_point[2] += self.schedule.load_at(t);
    }
}
