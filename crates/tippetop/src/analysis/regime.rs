//! The regime a scenario is in: dimensionless ratios, computed from its
//! parameters and initial state, that say which physics matters (issue
//! #14): whether the load is the weight or adhesion, whether friction can
//! hold the applied force, and, at a temperature, whether the spin and the
//! orientation survive thermal motion. Each entry is a number, or `None`
//! where it is undefined (no adhesion, no temperature, zero weight).
//!
//! Constants (docs/physics.md#regime): Boltzmann's `k_B = 1.380649e-23 J/K`
//! and `ħ = 1.054571817e-34 J s` (exact and CODATA 2018); the
//! reorientational correlation time of C60 `τ = 9.1 ps` (solid C60 at
//! 283 K, NMR, Johnson et al.; 15.5 ps in solution), the scale on which
//! thermal motion randomises a C60's orientation at room temperature.

use serde::Serialize;

use crate::{Error, Scenario};

/// Boltzmann's constant \[J/K\] (exact, SI 2019).
pub const K_B: f64 = 1.380649e-23;
/// Reduced Planck constant \[J s\] (CODATA 2018).
pub const HBAR: f64 = 1.054571817e-34;
/// Reorientational correlation time of C60 near room temperature \[s\]
/// (solid C60 at 283 K, NMR).
pub const C60_ORIENTATION_CORRELATION_TIME: f64 = 9.1e-12;
/// Below this many quanta of angular momentum (`C|ω0|/ħ`) a classical
/// rigid-body rotation is questionable.
pub const MIN_QUANTA: f64 = 10.0;
/// Largest temperature accepted \[K\].
pub const MAX_TEMPERATURE: f64 = 1e5;

/// The ratios (see the module doc); `None` where undefined.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Regime {
    /// Temperature the thermal ratios use \[K\]; `None`: no temperature.
    pub temperature: Option<f64>,
    /// Pull-off force over weight, `F_a/(m g)`; `None` without adhesion
    /// or with g = 0.
    pub adhesion_over_weight: Option<f64>,
    /// Largest applied force over the weight, `max_t |H(t)|/(m g)`; `None`
    /// with g = 0.
    pub applied_over_weight: Option<f64>,
    /// Largest applied force over what friction can hold,
    /// `max_t |H(t)| / (μ (m g + F_a))`; `None` when `μ (m g + F_a) = 0`.
    pub applied_over_friction_capacity: Option<f64>,
    /// Spin energy over the thermal energy, `½ C ω0² / (k_B T)`.
    #[serde(rename = "rotational_energy_over_kT")]
    pub rotational_energy_over_kt: Option<f64>,
    /// `|ω0| / √(k_B T / C)`, the spin against the thermal spin.
    pub spin_over_thermal_spin: Option<f64>,
    /// `C |ω0| / ħ`, the spin's angular momentum in quanta (defined for
    /// every scenario).
    pub angular_momentum_over_hbar: f64,
    /// `t_end / τ` with τ the C60 orientation correlation time (a thermal
    /// time: `None` without temperature).
    pub window_over_orientation_correlation_time: Option<f64>,
}

/// Largest |H(t)| the scenario's force schedule reaches on `[0, t_end)`
/// \[N\] (exact: the force is constant between switch times).
pub fn max_applied_force(sc: &Scenario) -> f64 {
    std::iter::once(0.0)
        .chain(sc.forcing.switch_times())
        .filter(|&t| (0.0..sc.solver.t_end).contains(&t))
        .map(|t| {
            let (hx, hy) = sc.forcing.at(t);
            hx.hypot(hy)
        })
        .fold(0.0, f64::max)
}

/// The regime of `sc` at `temperature` \[K\] (`None`: no thermal ratios).
/// Errors: a temperature that is not finite or outside `0..=1e5` K.
pub fn regime(sc: &Scenario, temperature: Option<f64>) -> Result<Regime, Error> {
    if let Some(t) = temperature {
        if !(0.0..=MAX_TEMPERATURE).contains(&t) {
            return Err(Error::invalid(
                "temperature",
                format!("{} is not allowed", crate::human::exact(t)),
                format!("0 <= temperature <= {MAX_TEMPERATURE:e} [K]"),
            ));
        }
    }
    Ok(at(sc, temperature))
}

/// [`regime`] without the range check of the temperature.
fn at(sc: &Scenario, temperature: Option<f64>) -> Regime {
    let top = &sc.top;
    let weight = top.mass * sc.surface.gravity;
    let h = max_applied_force(sc);
    let positive = |x: f64| (x > 0.0 && x.is_finite()).then_some(x);
    let ratio = |num: f64, den: f64| positive(den).map(|d| num / d);
    // The scenario's pull-off force F_a (0 without adhesion).
    let adhesion = sc.adhesion().force;
    let kt = temperature.map(|t| K_B * t).and_then(positive);
    let spin = sc.initial.spin;
    let c = top.inertia_axial;
    Regime {
        temperature,
        adhesion_over_weight: sc
            .adhesion()
            .is_on()
            .then(|| ratio(adhesion, weight))
            .flatten(),
        applied_over_weight: ratio(h, weight),
        applied_over_friction_capacity: ratio(h, sc.surface.friction * (weight + adhesion)),
        rotational_energy_over_kt: kt.map(|kt| 0.5 * c * spin * spin / kt),
        spin_over_thermal_spin: kt.map(|kt| spin.abs() / (kt / c).sqrt()),
        angular_momentum_over_hbar: c * spin.abs() / HBAR,
        window_over_orientation_correlation_time: kt
            .map(|_| sc.solver.t_end / C60_ORIENTATION_CORRELATION_TIME),
    }
}

/// The regime of a run of `sc` at its own temperature: the scenario's
/// `thermal.temperature` when it is above 0 (a Langevin or Brownian run),
/// else none (the thermal ratios `None`). What `summary.json` carries and
/// what `tippetop regime` reports without `--temperature`. (A scenario's
/// temperature is any finite `T >= 0`: no range to check here.)
pub fn of_run(sc: &Scenario) -> Regime {
    let t = sc.thermal.temperature;
    at(sc, (t > 0.0).then_some(t))
}

/// One line of the regime table: the key, its value, and what it means.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// The `summary.json` key.
    pub key: &'static str,
    /// The value (`None`: undefined).
    pub value: Option<f64>,
    /// What the value means for this scenario.
    pub verdict: String,
}

/// Radius below which a top counts as molecular \[m\] (the verdicts then
/// point at the nanoscale physics the model lacks).
pub const MOLECULAR_RADIUS: f64 = 1e-8;

/// The regime of `sc` as a table with a verdict per line.
pub fn lines(sc: &Scenario, r: &Regime) -> Vec<Line> {
    let molecular = sc.top.radius < MOLECULAR_RADIUS;
    let no_t = "no temperature given (tippetop regime --temperature K)";
    let line = |key, value: Option<f64>, verdict: String| Line {
        key,
        value,
        verdict,
    };
    vec![
        line(
            "adhesion_over_weight",
            r.adhesion_over_weight,
            match r.adhesion_over_weight {
                Some(x) if x > 1.0 => "adhesion dominates the weight: the load is the pull-off \
                                       force, and a pull must exceed F_a + m g to lift the top off"
                    .into(),
                Some(_) => "adhesion is on but the weight dominates it".into(),
                None if sc.adhesion().is_on() => {
                    "adhesion is on; no weight (g = 0): the load is the pull-off force".into()
                }
                None if molecular => {
                    "no adhesion in the model: the load is the weight (van der Waals adhesion \
                     holds a C60 on graphene with ~5e13 m g: tippetop adhesion, [adhesion])"
                        .into()
                }
                None => "no adhesion in the model: the load is the weight".into(),
            },
        ),
        line(
            "applied_over_weight",
            r.applied_over_weight,
            match r.applied_over_weight {
                None => "no weight (g = 0): only the applied force loads the contact".into(),
                Some(0.0) => "no applied force".into(),
                Some(x) if x > 1.0 => "the applied force exceeds the weight: with nothing else \
                                       holding the top down, N can go negative (lift-off)"
                    .into(),
                Some(_) => "the weight dominates the applied force".into(),
            },
        ),
        line(
            "applied_over_friction_capacity",
            r.applied_over_friction_capacity,
            match r.applied_over_friction_capacity {
                None => "no friction capacity (mu = 0 or no load)".into(),
                Some(0.0) => "no applied force".into(),
                Some(x) if x > 1.0 => {
                    "friction cannot hold the applied force: the contact slides".into()
                }
                Some(_) => "friction can hold the applied force (the contact may stick)".into(),
            },
        ),
        line(
            "rotational_energy_over_kT",
            r.rotational_energy_over_kt,
            match r.rotational_energy_over_kt {
                None => no_t.into(),
                Some(x) if x < 1.0 => {
                    "the spin's energy is below kT: thermal motion buries the spin".into()
                }
                Some(_) => "the spin's energy exceeds kT".into(),
            },
        ),
        line(
            "spin_over_thermal_spin",
            r.spin_over_thermal_spin,
            match r.spin_over_thermal_spin {
                None => no_t.into(),
                Some(x) if x < 1.0 => "the spin is slower than the thermal spin sqrt(kT/C)".into(),
                Some(_) => "the spin is faster than the thermal spin".into(),
            },
        ),
        line(
            "angular_momentum_over_hbar",
            Some(r.angular_momentum_over_hbar),
            if r.angular_momentum_over_hbar < MIN_QUANTA {
                format!(
                    "below {MIN_QUANTA} quanta of angular momentum: classical rotation is questionable"
                )
            } else {
                "many quanta: classical rotation is fine".into()
            },
        ),
        line(
            "window_over_orientation_correlation_time",
            r.window_over_orientation_correlation_time,
            match r.window_over_orientation_correlation_time {
                None => no_t.into(),
                Some(x) if x > 1.0 => format!(
                    "a C60's orientation decorrelates ~{x:.1e} times during the run (tau = 9.1 ps near room temperature)"
                ),
                Some(_) => "the run is shorter than the C60 orientation correlation time".into(),
            },
        ),
    ]
}
