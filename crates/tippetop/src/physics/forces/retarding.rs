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

use toml::{Table, Value};

use super::{Applied, Energy, ForceTerm, Kind, Properties, Window};
use crate::Error;
use crate::input::Key;
use crate::input::reader::Section;

/// Its keys in a `[[force]]` window of `kind = "contact"` (the default),
/// `force.K.hx` and `force.K.hy`: read here ([`parse`]), checked here
/// ([`check`]) and written here ([`to_table`]); the window's own `kind`,
/// `start` and `stop` are the schedule's (input/forcing.rs, which lists
/// every key of a window in `forcing::KEYS`).
pub const KEYS: [Key; 2] = [
    Key::doc(
        "hx",
        "a finite force [N]",
        "0",
        "H_x, the paper's force at the contact point, precessing frame",
    ),
    Key::doc("hy", "a finite force [N]", "0", "H_y, the same along y"),
];

/// `(H_x, H_y)` \[N\] of a contact window (each 0 when absent): types only,
/// [`check`] checks the values.
pub(crate) fn parse(s: &Section) -> Result<[f64; 2], Error> {
    Ok([s.f64("hx", Some(0.0))?, s.f64("hy", Some(0.0))?])
}

/// Check `(H_x, H_y)` \[N\] of the window at `prefix` (`force.K`): finite;
/// errors name `{prefix}.hx` or `{prefix}.hy` with the key's range.
pub fn check(prefix: &str, h: [f64; 2]) -> Result<(), Error> {
    for (k, v) in KEYS.iter().zip(h) {
        if !v.is_finite() {
            return Err(Error::invalid(
                &format!("{prefix}.{}", k.name),
                format!("{} is not allowed", crate::human::exact(v)),
                k.range.into(),
            ));
        }
    }
    Ok(())
}

/// Write `hx`, `hy` into a window's table (always, zeros included).
pub(crate) fn to_table(h: [f64; 2], t: &mut Table) {
    for (k, v) in KEYS.iter().zip(h) {
        t.insert(k.name.into(), Value::Float(v));
    }
}

/// The paper's `H` from the force windows.
#[derive(Debug, Clone)]
pub struct Retarding {
    windows: Vec<Window<[f64; 2]>>,
}

impl Retarding {
    /// The term of the schedule's windows: `(H_x, H_y)` \[N\] on each
    /// window's `[start, stop)`, in the schedule's order.
    pub fn new(windows: Vec<Window<[f64; 2]>>) -> Self {
        Retarding { windows }
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
        // Summed over the windows in effect first, then added: the
        // arithmetic of `Forcing::at`, bit for bit.
        let mut h = (0.0, 0.0);
        for w in self.windows.iter().filter(|w| w.active(t)) {
            h.0 += w.value[0];
            h.1 += w.value[1];
        }
        acc.contact_point[0] += h.0;
        acc.contact_point[1] += h.1;
    }
}
