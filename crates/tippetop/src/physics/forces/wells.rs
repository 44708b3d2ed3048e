//! Orientation wells, the `[[well]]` entries (docs/physics.md#wells): each a
//! Gaussian well in the nutation angle θ, `theta` θ_i \[rad\], `depth` d_i
//! \[J\], `width` w_i \[rad\], with the potential
//!
//! ```text
//! U(θ) = −Σ_i d_i exp(−(θ − θ_i)²/(2 w_i²))
//! ```
//!
//! (a stem adhering when the top lies, a corrugation barrier). It acts as a
//! pure torque (a couple: no force, so the centre of mass and the contact
//! force see it only through the motion) about the horizontal axis `ŷ`
//! normal to the symmetry axis `k`, the axis about which θ turns
//! (`ŷ = Z × x̂`, `x̂` the horizontal direction of the tilt, so that
//! `∂k/∂θ = ŷ × k`):
//!
//! ```text
//! τ = τ_y ŷ,   τ_y = −U′(θ) = −Σ_i d_i (θ − θ_i)/w_i² exp(−(θ − θ_i)²/(2 w_i²))
//! ```
//!
//! equivalently `τ = U′(θ) (k × Z)/sin θ`; `τ_y > 0` turns `k` towards larger
//! θ, so the torque drives θ down the potential (`τ·n = τ_y θ̇ = −dU/dt`).
//!
//! - Closure: `ŷ ⊥ k`, so the torque's angular acceleration is `τ/A`; it
//!   enters exactly as the gyroscopic term does, `G ← G + τ_y` in the Euler
//!   angles (`A θ̈ = G + τ_y − a s N − h F_x`), so `Q` gains `a s τ_y/A`
//!   (with `D(σ)` unchanged); the vector and rigid models add `τ/A` to the
//!   torque-free angular acceleration `ẇ₀`, which the closure and the
//!   rolling constraint read (`Q` gains `−a (τ/A)·e`, `e = k × Z`, the same
//!   `a s τ_y/A`). The Ω and ω equations do not change (`τ·Z = τ·k = 0`).
//! - Jellett's J = `−L·r`, `r = a k − R Z`: `dJ/dt` gains `−τ·r = 0`
//!   (`τ ⊥ k`, `τ ⊥ Z`): conserved.
//! - Energy: a potential; the energy includes `U(θ)`, so `E − E0 = W_f + W_a`
//!   holds with the same `W_f`, `W_a`.
//! - Poles: `ŷ` is undefined at θ = 0 and π, and `U′` need not vanish there
//!   (`U′(0) = −Σ d_i θ_i/w_i² exp(−θ_i²/(2w_i²)) <= 0`, `U′(π) >= 0`: each pole
//!   is a conical peak of `U` unless a well is centred on it). The torque is
//!   bounded (`|τ| = |U′|`) and points away from the pole along the current
//!   tilt; at exactly `sin θ = 0` its direction is undefined and the models
//!   apply none (a peak's tip: an equilibrium, unstable). `U` is continuous,
//!   so the energy balance holds through the pole; the reduced model stops
//!   near it anyway (docs/physics.md#failures).
//!
//! # The plug-in
//!
//! The `[[well]]` table is a plug-in of an array of tables: its keys, its
//! validation (the messages `tippetop` has always given), the typed
//! [`Well`] (`tippetop::Well`) and its term are here; one line in
//! [`super::PLUGINS`] registers it. A scenario keeps the entries' numbers
//! with the other plug-ins' ([`PluginTables`]: three per well); the rest of
//! the code reads the typed list through `Scenario::wells()` and writes it
//! with `Scenario::set_wells` (the langevin step check, the stability and
//! rare-event analyses, the device study, the presets), as for
//! `[adhesion]` (physics/forces/adhesion.rs says why). The table stays
//! after `[[force]]` in a scenario's text ([`Plugin::follows`]).

use std::sync::Arc;

use super::{Applied, Energy, ForceTerm, Kind, Plugin, Properties};
use crate::Error;
use crate::input::{Key, PluginTables, TableSpec};

/// The table's name (`[[well]]`).
pub const NAME: &str = "well";

/// Valid range of `well.K.theta`.
pub const THETA_RANGE: &str = "0 <= theta <= pi [rad], the centre of the well";
/// Valid range of `well.K.depth`.
pub const DEPTH_RANGE: &str = "a finite energy, 0 < depth <= 1e300 [J]";
/// Valid range of `well.K.width`.
pub const WIDTH_RANGE: &str =
    "a finite angle, 0 < width <= pi [rad] (the Gaussian's standard deviation)";
/// Wells overlap when their centres are closer than this many times the sum
/// of their widths (then neither is a separate well: at `3 (w_i + w_j)` each
/// Gaussian is below `exp(−4.5) = 1.1 %` of its depth at the other's centre,
/// for equal widths).
pub const OVERLAP_WIDTHS: f64 = 3.0;

const KEYS: &[Key] = &[
    Key::doc(
        "theta",
        THETA_RANGE,
        "required",
        "the well's centre (docs/physics.md#wells)",
    ),
    Key::doc("depth", DEPTH_RANGE, "required", "the well's depth"),
    Key::doc("width", WIDTH_RANGE, "required", "the well's width"),
];

/// One Gaussian well in θ (SI, or scaled when latched:
/// [`super::Forces::wells`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Well {
    /// Centre θ_i \[rad\].
    pub theta: f64,
    /// Depth d_i \[J\] (`U(θ_i) ≈ −d_i`).
    pub depth: f64,
    /// Width w_i \[rad\].
    pub width: f64,
}

/// The wells of a scenario's plug-in tables (none without `[[well]]`).
pub fn of(tables: &PluginTables) -> Vec<Well> {
    tables.get(NAME).map_or_else(Vec::new, from_values)
}

/// Write `wells` into `tables` (no wells: no table).
pub fn store(wells: &[Well], tables: &mut PluginTables) {
    if wells.is_empty() {
        tables.remove(NAME);
    } else {
        tables.set(
            NAME,
            wells
                .iter()
                .flat_map(|w| [w.theta, w.depth, w.width])
                .collect(),
        );
    }
}

/// The wells of the table's numbers (three per entry, in the order of the keys).
fn from_values(v: &[f64]) -> Vec<Well> {
    v.chunks_exact(KEYS.len())
        .map(|c| Well {
            theta: c[0],
            depth: c[1],
            width: c[2],
        })
        .collect()
}

/// Check a list of wells: each key finite and in range, and no two wells
/// overlapping (centres closer than [`OVERLAP_WIDTHS`] times the sum of
/// the widths; the later well's `theta` is named). The error names the key
/// (`well.0.width`).
pub fn validate(wells: &[Well]) -> Result<(), Error> {
    for (k, w) in wells.iter().enumerate() {
        let checks = [
            (
                "theta",
                w.theta,
                THETA_RANGE,
                (0.0..=std::f64::consts::PI).contains(&w.theta),
            ),
            (
                "depth",
                w.depth,
                DEPTH_RANGE,
                w.depth > 0.0 && w.depth <= 1e300,
            ),
            (
                "width",
                w.width,
                WIDTH_RANGE,
                w.width > 0.0 && w.width <= std::f64::consts::PI,
            ),
        ];
        for (key, v, range, ok) in checks {
            if !ok || !v.is_finite() {
                return Err(Error::invalid(
                    &format!("well.{k}.{key}"),
                    format!("{} is not allowed", crate::human::exact(v)),
                    range.into(),
                ));
            }
        }
    }
    for (j, b) in wells.iter().enumerate() {
        for (i, a) in wells.iter().enumerate().take(j) {
            let min = OVERLAP_WIDTHS * (a.width + b.width);
            if (a.theta - b.theta).abs() < min {
                return Err(Error::invalid(
                    &format!("well.{j}.theta"),
                    format!(
                        "{} overlaps well {i} (theta = {}): centres {} rad apart",
                        b.theta,
                        a.theta,
                        (a.theta - b.theta).abs()
                    ),
                    format!(
                        "centres at least 3 (width_{i} + width_{j}) = {min} rad apart (wells must not overlap)"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The `[[well]]` plug-in: an array of tables.
#[derive(Debug, Clone, Copy)]
pub struct WellsPlugin;

impl Plugin for WellsPlugin {
    fn table(&self) -> TableSpec {
        TableSpec {
            name: NAME,
            array: true,
            doc: "orientation wells U = -depth exp(-(theta - centre)^2/(2 width^2)) (none by default)",
            keys: KEYS,
        }
    }
    fn kind(&self) -> Kind {
        Kind::Torque
    }
    fn follows(&self) -> &'static str {
        "force"
    }
    fn entry(&self) -> (&'static str, &'static str) {
        ("well", "wells")
    }
    fn handled_by_name(&self) -> bool {
        true
    }
    fn validate(&self, values: &[f64]) -> Result<(), Error> {
        validate(&from_values(values))
    }
    fn term(&self, values: &[f64]) -> Option<Arc<dyn ForceTerm>> {
        let wells = from_values(values);
        (!wells.is_empty()).then(|| Arc::new(WellsTerm { wells }) as Arc<dyn ForceTerm>)
    }
}

/// `U(θ) = −Σ d_i exp(−(θ − θ_i)²/(2 w_i²))` (units of the depths).
#[inline]
pub fn potential(wells: &[Well], theta: f64) -> f64 {
    wells
        .iter()
        .map(|w| {
            let x = (theta - w.theta) / w.width;
            -w.depth * (-0.5 * x * x).exp()
        })
        .sum()
}

/// `e + U(θ)`; `e` itself without wells (bit for bit): what the models'
/// energies add.
#[inline]
pub fn with_potential(wells: &[Well], e: f64, theta: f64) -> f64 {
    if wells.is_empty() {
        e
    } else {
        e + potential(wells, theta)
    }
}

/// `τ_y = −U′(θ) = −Σ d_i (θ − θ_i)/w_i² exp(−(θ − θ_i)²/(2 w_i²))`: the
/// torque about `ŷ` (units of the depths).
#[inline]
pub fn torque(wells: &[Well], theta: f64) -> f64 {
    wells
        .iter()
        .map(|w| {
            let x = (theta - w.theta) / w.width;
            -w.depth * x / w.width * (-0.5 * x * x).exp()
        })
        .sum()
}

/// `base + τ_y(θ)`, the wells' torque about `ŷ` added to `base` (the
/// reduced model's gyroscopic term of `A θ̈`); `base` itself without wells
/// (bit for bit). The lab-vector models take [`torque_world`]
/// (through [`crate::physics::body::WellsTorque`]).
#[inline(always)]
pub fn with_torque(wells: &[Well], base: f64, theta: f64) -> f64 {
    if wells.is_empty() {
        base
    } else {
        base + torque(wells, theta)
    }
}

/// The torque `τ_y ŷ` in the space frame for the (not necessarily unit)
/// axis `k`: `ŷ = (−k_y, k_x, 0)/|k_h|`, θ = atan2(|k_h|, k_Z); zero where
/// `k_h = 0` (the pole: direction undefined, module doc). `|k_h|` is a
/// plain square root (|k| ≈ 1 in every model: nothing to overflow; it
/// underflows to 0 only for `|k_h| < 1e-154`, then the torque is 0; since
/// 66 instructions less than `hypot` per call). θ and the
/// Gaussians use glibc's `atan2` and `exp`: fdlibm's versions in
/// `detmath` took fewer instructions but more time, their divisions being
/// on the critical path (docs/performance.md#langevin-step).
#[inline]
pub fn torque_world(wells: &[Well], k: [f64; 3]) -> [f64; 3] {
    let kh = (k[0] * k[0] + k[1] * k[1]).sqrt();
    if kh == 0.0 {
        return [0.0; 3];
    }
    let ty = torque(wells, kh.atan2(k[2])) / kh;
    [-k[1] * ty, k[0] * ty, 0.0]
}

/// The wells of a scenario, one force term.
#[derive(Debug, Clone)]
pub struct WellsTerm {
    wells: Vec<Well>,
}

impl ForceTerm for WellsTerm {
    fn name(&self) -> &'static str {
        "orientation wells (well.K.theta, well.K.depth, well.K.width)"
    }
    fn kind(&self) -> Kind {
        Kind::Torque
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "a torque -U'(theta) about y (perpendicular to k and Z): G += tau_y, Q += a s tau_y/A (docs/physics.md#wells)",
            conserves_jellett: true,
            energy: Energy::Potential,
        }
    }
    fn add_to(&self, _t: f64, acc: &mut Applied) {
        acc.wells.extend_from_slice(&self.wells);
    }
}

#[cfg(test)]
mod tests {
    //! The table as a plug-in of an array of tables keeps the scenario text
    //! the file format documents (input/scenario.rs: `[[well]]` entries
    //! after `[[force]]`, absent without wells). The physics is checked in
    //! tests/physics/wells.rs and the messages in tippetop-cli's tests.

    use super::Well;
    use crate::Scenario;

    /// Two wells round-trip through the text, after `[[force]]` and
    /// before `[initial]`, and through `--set well.K.KEY`.
    #[test]
    fn wells_keep_their_place_in_the_text() {
        let list = [
            Well {
                theta: 1.2,
                depth: 1e-33,
                width: 0.2,
            },
            Well {
                theta: 2.5,
                depth: 2e-33,
                width: 0.1,
            },
        ];
        let mut sc = Scenario::nano();
        sc.set_wells(&list);
        assert_eq!(sc.wells(), list);
        let text = sc.to_toml_string();
        let at = |h: &str| text.find(h).unwrap_or_else(|| panic!("{h}: {text}"));
        assert!(at("\n[[force]]\n") < at("\n[[well]]\n"), "{text}");
        assert!(at("\n[[well]]\n") < at("\n[initial]\n"), "{text}");
        assert!(text.contains(
            "\n[[well]]\ntheta = 1.2\ndepth = 1e-33\nwidth = 0.2\n\n[[well]]\ntheta = 2.5\ndepth = 2e-33\nwidth = 0.1\n"
        ));
        assert_eq!(Scenario::from_toml_str(&text).unwrap(), sc);
        let sets: Vec<String> = [
            "well.0.theta=1.2",
            "well.0.depth=1e-33",
            "well.0.width=0.2",
            "well.1.theta=2.5",
            "well.1.depth=2e-33",
            "well.1.width=0.1",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(Scenario::load(Some("nano"), None, &sets).unwrap(), sc);
    }

    /// No wells is no table, and setting none removes the preset's.
    #[test]
    fn no_wells_is_no_table() {
        let mut sc = Scenario::nano_physical();
        assert_eq!(sc.wells().len(), 1);
        sc.set_wells(&[]);
        assert!(sc.wells().is_empty());
        assert!(!sc.to_toml_string().contains("well"));
        // A file's empty list replaces the preset's, as `force = []` does.
        let parsed = Scenario::load(Some("nano-physical"), Some("well = []\n"), &[]).unwrap();
        assert_eq!(parsed, sc);
        assert!(!Scenario::nano().to_toml_string().contains("well"));
    }
}
