//! The keys of the body actuators (`kind = "tip"` and `kind = "magnetic"`,
//! docs/physics.md#actuators) in a window of `[[force]]`, `[[write]]` or
//! `[[erase]]`: one parser for the three lists.
//!
//! ```toml
//! [[force]]
//! kind = "tip"                 # default "contact" (hx, hy, hz)
//! point = [0.0, 0.0, 1e-9]     # [m], body frame: origin at the centre of mass, z along k
//! force = [1e-22, 0.0, 0.0]    # [N], lab frame (Z up), the force on the top
//! start = 0.0
//! stop = 1e-5
//! [[force]]
//! kind = "magnetic"
//! moment = 9.2740100783e-24    # [A m^2] along k: one Bohr magneton
//! field = [0.0, 0.0, 1.0]      # [T], uniform, lab frame (default 0)
//! gradient = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]  # [T/m], G_ij = dB_i/dx_j (default 0)
//! ```
//!
//! A key of another kind (`point` in a contact window, `hx` in a tip
//! window, ...) is an error naming it; `point`, `force` and `moment` are
//! required by their kind.

use toml::Value;

use crate::input::Key;
use crate::input::forcing::{
    BodyActuator, MAGNETIC_FIELD_RANGE, MAGNETIC_GRADIENT_RANGE, MAGNETIC_MOMENT_RANGE,
    TIP_FORCE_RANGE, TIP_POINT_RANGE,
};
use crate::input::reader::Section;
use crate::input::solver::ModelKind;
use crate::{ActuatorWindow, Error};

/// The valid values of `kind`.
pub const KIND_RANGE: &str = "\"contact\" (hx, hy, hz: the paper's force at the contact point), \"tip\" (point, force) or \"magnetic\" (moment, field, gradient)";

/// The body actuators' keys with their ranges (`kind` is the caller's).
pub const KEYS: [Key; 5] = [
    Key::doc(
        "point",
        TIP_POINT_RANGE,
        "required by tip",
        "the tip's point on the body",
    ),
    Key::doc(
        "force",
        TIP_FORCE_RANGE,
        "required by tip",
        "the tip's force on the top",
    ),
    Key::doc(
        "moment",
        MAGNETIC_MOMENT_RANGE,
        "required by magnetic",
        "the magnetic moment along the axis",
    ),
    Key::doc(
        "field",
        MAGNETIC_FIELD_RANGE,
        "[0, 0, 0]",
        "the uniform field B0",
    ),
    Key::doc(
        "gradient",
        MAGNETIC_GRADIENT_RANGE,
        "zero",
        "the field's gradient G",
    ),
];

/// The keys of the contact force (a `[[force]]` window's own).
const CONTACT_KEYS: [&str; 3] = ["hx", "hy", "hz"];

/// A window's kind: `None` for `"contact"` (or no `kind`), else the body
/// actuator its keys give. Keys of another kind are errors naming them.
pub(super) fn parse(s: &Section) -> Result<Option<BodyActuator>, Error> {
    let kind = match s.get("kind") {
        None => "contact",
        Some(Value::String(v)) if matches!(v.as_str(), "contact" | "tip" | "magnetic") => {
            v.as_str()
        }
        Some(Value::String(v)) => {
            return Err(Error::invalid(
                &s.full("kind"),
                format!("unknown value {v:?}"),
                KIND_RANGE.into(),
            ));
        }
        Some(v) => return Err(s.wrong_type("kind", "a string", v)),
    };
    let own: &[&str] = match kind {
        "contact" => &CONTACT_KEYS,
        "tip" => &["point", "force"],
        _ => &["moment", "field", "gradient"],
    };
    let others = CONTACT_KEYS.iter().chain(KEYS.iter().map(|k| &k.name));
    if let Some(k) = others
        .filter(|k| !own.contains(k))
        .find(|k| s.get(k).is_some())
    {
        return Err(Error::invalid(
            &s.full(k),
            format!("not a key of kind = \"{kind}\""),
            format!("{kind} windows take {}", own.join(", ")),
        ));
    }
    let required = |key: &str| -> Result<(), Error> {
        match s.get(key) {
            Some(_) => Ok(()),
            None => Err(Error::invalid(
                &s.full(key),
                "missing".into(),
                format!("required with kind = \"{kind}\": {}", range(key)),
            )),
        }
    };
    match kind {
        "contact" => Ok(None),
        "tip" => {
            required("point")?;
            required("force")?;
            Ok(Some(BodyActuator::Tip {
                point: s.f64s("point", None)?,
                force: s.f64s("force", None)?,
            }))
        }
        _ => {
            required("moment")?;
            Ok(Some(BodyActuator::Magnetic {
                moment: s.f64("moment", None)?,
                field: s.f64s("field", Some([0.0; 3]))?,
                gradient: gradient(s)?,
            }))
        }
    }
}

fn range(key: &str) -> &'static str {
    KEYS.iter()
        .find(|k| k.name == key)
        .map(|k| k.range)
        .unwrap_or("")
}

/// `gradient`: a 3x3 array of finite numbers (default zero).
fn gradient(s: &Section) -> Result<[[f64; 3]; 3], Error> {
    let Some(v) = s.get("gradient") else {
        return Ok([[0.0; 3]; 3]);
    };
    let bad = || s.wrong_type("gradient", "a 3x3 array of numbers", v);
    let Value::Array(rows) = v else {
        return Err(bad());
    };
    if rows.len() != 3 {
        return Err(bad());
    }
    let mut g = [[0.0; 3]; 3];
    for (gi, row) in g.iter_mut().zip(rows) {
        let Value::Array(row) = row else {
            return Err(bad());
        };
        if row.len() != 3 {
            return Err(bad());
        }
        for (gij, x) in gi.iter_mut().zip(row) {
            *gij = match x {
                Value::Float(f) => *f,
                Value::Integer(i) => *i as f64,
                _ => return Err(bad()),
            };
            if !gij.is_finite() {
                return Err(Error::invalid(
                    &s.full("gradient"),
                    format!("{gij} is not allowed"),
                    MAGNETIC_GRADIENT_RANGE.into(),
                ));
            }
        }
    }
    Ok(g)
}

/// The TOML keys of a body actuator (with `kind`), for rendering.
pub(super) fn to_table(a: &BodyActuator, t: &mut toml::Table) {
    let arr = |v: &[f64; 3]| Value::Array(v.iter().map(|x| Value::Float(*x)).collect());
    t.insert("kind".into(), Value::String(a.name().into()));
    match a {
        BodyActuator::Tip { point, force } => {
            t.insert("point".into(), arr(point));
            t.insert("force".into(), arr(force));
        }
        BodyActuator::Magnetic {
            moment,
            field,
            gradient,
        } => {
            t.insert("moment".into(), Value::Float(*moment));
            t.insert("field".into(), arr(field));
            t.insert(
                "gradient".into(),
                Value::Array(gradient.iter().map(arr).collect()),
            );
        }
    }
}

/// What the models cannot apply: the reduced model none of the body
/// actuators, the vector model a tip off the symmetry axis (its dynamics
/// read only the axis `k`, not the spin angle). Errors name `{prefix}.KEY`.
pub fn check_model(w: &ActuatorWindow, prefix: &str, model: ModelKind) -> Result<(), Error> {
    let kind = w.actuator.name();
    match model {
        ModelKind::Reduced => Err(Error::invalid(
            &format!("{prefix}.kind"),
            format!("\"{kind}\" is not available in model = \"reduced\""),
            "kind = \"tip\" and \"magnetic\" need model = \"vector\" (the default) or \"rigid\""
                .into(),
        )),
        ModelKind::Vector if w.actuator.off_axis() => Err(Error::invalid(
            &format!("{prefix}.point"),
            "is off the symmetry axis, which model = \"vector\" cannot apply (its dynamics read only the axis k, not the spin angle)".into(),
            "point = [0, 0, z] with model = \"vector\"; any point with model = \"rigid\"".into(),
        )),
        _ => Ok(()),
    }
}
