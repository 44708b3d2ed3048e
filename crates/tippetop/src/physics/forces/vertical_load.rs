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

use toml::{Table, Value};

use super::{Applied, Energy, ForceTerm, Kind, Properties, Window};
use crate::Error;
use crate::input::Key;
use crate::input::reader::Section;

/// Its key in a `[[force]]` window of `kind = "contact"`, `force.K.hz`:
/// read ([`parse`]), checked ([`check`]) and written ([`to_table`]) here;
/// listed with the window's other keys in `input/forcing.rs`'s `KEYS`.
pub const KEY: Key = Key::doc(
    "hz",
    "a finite force [N] (vertical load at the contact point, > 0 pushes onto the plane)",
    "0",
    "vertical load at the contact point (docs/physics.md#vertical-load)",
);

/// `h_z` \[N\] of a contact window (0 when absent): type only, [`check`]
/// checks the value.
pub(crate) fn parse(s: &Section) -> Result<f64, Error> {
    s.f64(KEY.name, Some(0.0))
}

/// Check `h_z` \[N\] of the window at `prefix` (`force.K`): finite; the
/// error names `{prefix}.hz` with the key's range.
pub fn check(prefix: &str, hz: f64) -> Result<(), Error> {
    if hz.is_finite() {
        return Ok(());
    }
    Err(Error::invalid(
        &format!("{prefix}.{}", KEY.name),
        format!("{} is not allowed", crate::human::exact(hz)),
        KEY.range.into(),
    ))
}

/// Write `hz` into a window's table, only when set: scenarios without a
/// load keep their text (scenario.toml, summary.json) unchanged.
pub(crate) fn to_table(hz: f64, t: &mut Table) {
    if hz != 0.0 {
        t.insert(KEY.name.into(), Value::Float(hz));
    }
}

/// The vertical load from the force windows.
#[derive(Debug, Clone)]
pub struct VerticalLoad {
    windows: Vec<Window<f64>>,
}

impl VerticalLoad {
    /// The term of the schedule's windows: `h_z` \[N\] on each window's
    /// `[start, stop)`, in the schedule's order.
    pub fn new(windows: Vec<Window<f64>>) -> Self {
        VerticalLoad { windows }
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
        // Summed first, then added: `Forcing::load_at`'s arithmetic.
        let mut hz = 0.0;
        for w in self.windows.iter().filter(|w| w.active(t)) {
            hz += w.value;
        }
        acc.contact_point[2] += hz;
    }
}
