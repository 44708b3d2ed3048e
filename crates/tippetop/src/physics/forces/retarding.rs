//! The paper's retarding force `H = (H_x, H_y)` at the contact point
//! (eq. 1.3; docs/physics.md#applied-force): keys `force.K.hx`, `force.K.hy`. The
//! force on the top is `−H`, components in the precessing frame.
//!
//! - Closure: `Q` gains `a (H·w)` (`w = (I⁻¹ e) × r`, §rigid-model; `m a s h H_x/A`
//!   in the Euler angles, §normal-force). While rolling it drops out of the motion and
//!   only changes the friction needed (§coulomb).
//! - Jellett's J: conserved (a force at `P`, §invariants).
//! - Energy: no potential; its work `W_a = ∫ (−H)·v_P dt` is integrated
//!   (zero while rolling).

use super::{Applied, Energy, ForceTerm, Kind, Properties};
use crate::Forcing;
use crate::input::Key;

/// Its keys in a `[[force]]` window, `force.K.hx` and `force.K.hy` (the
/// window's own `kind`, `start` and `stop` are the schedule's, listed with
/// these in `input/scenario.rs`'s `FORCE_KEYS`; their values are checked
/// with the window, `input/forcing.rs`).
pub const KEYS: [Key; 2] = [
    Key::doc(
        "hx",
        "a finite force [N]",
        "0",
        "H_x, the paper's force at the contact point, precessing frame",
    ),
    Key::doc("hy", "a finite force [N]", "0", "H_y, the same along y"),
];

/// The paper's `H` from the force windows.
#[derive(Debug, Clone)]
pub struct Retarding {
    schedule: Forcing,
}

impl Retarding {
    /// The term of a schedule.
    pub fn of(schedule: &Forcing) -> Self {
        Retarding {
            schedule: schedule.clone(),
        }
    }
}

impl ForceTerm for Retarding {
    fn name(&self) -> &'static str {
        "applied force H (force.K.hx, force.K.hy)"
    }
    fn kind(&self) -> Kind {
        Kind::ContactPoint
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "Q += a H·w (docs/physics.md#normal-force, §rigid-model)",
            conserves_jellett: true,
            energy: Energy::Integrated,
        }
    }
    fn add_to(&self, t: f64, acc: &mut Applied) {
        let (hx, hy) = self.schedule.at(t);
        acc.contact_point[0] += hx;
        acc.contact_point[1] += hy;
    }
}
