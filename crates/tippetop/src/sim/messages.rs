//! The messages of run-time failures: what stopped a run and what to do.

use crate::{Failure, Method, Scenario, sim::record::Track};

/// How many times the fastest initial rate (`1 / T_ref`) a run's spin may
/// reach for its steps to count as steady: beyond it the steps shrink with
/// the spin, and the mean step so far says nothing of the steps left.
const SPEEDUP_STEADY: f64 = 10.0;

/// Why a run of `sc` stopped at its step limit `cap` at time `reached`
/// \[s\], `track` its record so far. A run whose spin stayed within
/// [`SPEEDUP_STEADY`] times its fastest initial rate and that needs, at
/// its mean step so far, no more than [`crate::limits::STEP_LIMIT_MAX`]
/// steps for all of `t_end` is advancing: the message names the limit as
/// the cause and the value of `solver.max_steps` that lets it finish. Any
/// other cannot make progress: the message says why it may not.
pub(crate) fn step_limit_why(sc: &Scenario, track: &Track, cap: u64, reached: f64) -> String {
    let t_end = sc.solver.t_end;
    let needed = cap as f64 * t_end / reached;
    let which = if sc.solver.max_steps.is_some() {
        "solver.max_steps"
    } else {
        "solver.max_steps, the default"
    };
    // The track holds scaled rates: |spin| in units of 1 / T_ref.
    let speedup = track.spin_abs_max();
    let spin = speedup / crate::limits::time_unit(sc);
    if needed <= crate::limits::STEP_LIMIT_MAX as f64 && speedup <= SPEEDUP_STEADY {
        // A tenth more than the mean step needs, up to two figures.
        let ask = round_up_2(needed * 1.1).min(crate::limits::STEP_LIMIT_MAX);
        return format!(
            "step limit {cap} reached ({which}): the run was advancing, {} per step on average over {} s of t_end = {} s, and needs about {} steps in all; raise the limit, e.g. --set solver.max_steps={ask} (at most {}), or shorten solver.t_end",
            crate::human::si(reached / cap as f64, "s", 4),
            crate::human::sig(reached, 4),
            crate::human::exact(t_end),
            crate::human::sig(needed, 3),
            crate::limits::STEP_LIMIT_MAX
        );
    }
    let mean = t_end / cap as f64;
    let hint = match (sc.surface.law, sc.solver.method) {
        (crate::FrictionLaw::Coulomb, _) => {
            "stick/slip switches or N = 0 crossings that follow each other ever faster, or a rate far faster than t_end"
        }
        (crate::FrictionLaw::CoulombSliding, _) => {
            "a slip that chatters around zero: try friction_law = \"coulomb\" (exact stick/slip)"
        }
        (_, Method::Stiff) => "a stiff friction law near rolling: try a larger friction_eps",
        _ => "a stiff friction law near rolling: try method = \"stiff\" or a larger friction_eps",
    };
    let periods = sc.solver.t_end / crate::limits::time_unit(sc);
    let so_far = if speedup > SPEEDUP_STEADY {
        format!(
            "; the spin has grown to {} rad/s, {} times the fastest initial rate, and the steps shrink with it",
            crate::human::sig(spin, 4),
            crate::human::sig(speedup, 3)
        )
    } else if needed.is_finite() {
        format!(
            "; about {} steps at its mean step so far",
            crate::human::sig(needed, 3)
        )
    } else {
        String::new()
    };
    format!(
        "step limit {cap} reached ({which}; the run cannot make progress: the motion needs steps far shorter than t_end / {cap} = {}{so_far}; {hint}; t_end is {} time units T_ref of the fastest initial rate; solver.max_steps sets the limit, at most {})",
        crate::human::si(mean, "s", 4),
        crate::human::sig(periods, 4),
        crate::limits::STEP_LIMIT_MAX
    )
}

/// `x` > 0 rounded up to two significant figures, as an integer.
fn round_up_2(x: f64) -> u64 {
    let p = 10f64.powi(x.log10().floor() as i32 - 1).max(1.0);
    ((x / p).ceil() * p) as u64
}

/// Why a run whose output row has `value` in `column`, not a finite
/// number, fails: an infinity is a value that overflows f64 in SI units
/// (`output_overflow`), a NaN a value that is not defined (`non_finite`).
pub(crate) fn nonfinite_output_why(column: &str, value: f64) -> (Failure, String) {
    if value.is_nan() {
        (
            Failure::NonFinite,
            format!("the output row became NaN in column {column}"),
        )
    } else {
        (
            Failure::OutputOverflow,
            format!(
                "the output row became infinite in column {column} (the value overflows f64 in SI units)"
            ),
        )
    }
}

/// The friction law as a phrase for messages.
pub(crate) fn law_phrase(law: crate::FrictionLaw) -> String {
    match law {
        crate::FrictionLaw::Coulomb => "Coulomb friction (friction_law = \"coulomb\")".into(),
        crate::FrictionLaw::CoulombSliding => {
            "sliding Coulomb friction (friction_law = \"coulomb_sliding\")".into()
        }
        crate::FrictionLaw::Regularized { eps } => {
            format!(
                "regularized friction (friction_law = \"regularized\", friction_eps = {eps} m/s)"
            )
        }
        crate::FrictionLaw::Viscous { eps } => {
            format!("viscous friction (friction_law = \"viscous\", friction_eps = {eps} m/s)")
        }
        crate::FrictionLaw::Contensou {
            radius, pressure, ..
        } => format!(
            "Coulomb-Contensou friction (friction_law = \"{}\", contact_radius = {radius} m, contact_pressure = \"{}\")",
            law.name(),
            pressure.name()
        ),
    }
}

/// Why a run of `sc` failed with the Painlevé case at `theta` \[rad\]
/// (`solutions` consistent normal forces, 0 or 2, of the model's `system`
/// of equations), naming the run's law.
pub(crate) fn painleve_why(sc: &Scenario, system: &str, theta: f64, solutions: usize) -> String {
    format!(
        "Painleve paradox at theta = {} rad: the {system} with {} has {solutions} consistent solutions (m a h mu sin(theta)/A too large); no unique motion exists",
        crate::human::s4(theta),
        law_phrase(sc.surface.law)
    )
}

/// Relative energy-balance error beyond which a failed fixed-step (RK4) run
/// is reported as unstable rather than by the failure that ended it.
pub(crate) const RK4_UNSTABLE_BALANCE: f64 = 1e-2;

/// A failed RK4 run whose energy balance was already off by more than
/// [`RK4_UNSTABLE_BALANCE`]: the fixed step made the solution unstable, and
/// `why` (a Painlevé case, a NaN) is a consequence, not the physics. Any
/// other failure of an RK4 run says that its fixed step may be the cause.
/// Returns the failure's kind (`kind`, or [`Failure::Unstable`]) and message.
pub(crate) fn unstable_rk4(
    sc: &Scenario,
    track: &Track,
    kind: Failure,
    why: String,
) -> (Failure, String) {
    let rel = track.balance_rel();
    if sc.solver.method == Method::Rk4 && (rel.is_nan() || rel > RK4_UNSTABLE_BALANCE) {
        let msg = format!(
            "the RK4 solution became unstable (energy balance error {rel:.1e} of max |E|): the fixed step t_end / steps = {} s is too long for this motion, raise solver.steps or use method = \"adaptive\"; it ended with: {why}",
            crate::human::s4(sc.solver.t_end / sc.solver.steps as f64)
        );
        (Failure::Unstable, msg)
    } else if sc.solver.method == Method::Rk4 {
        let msg = format!(
            "{why} (method = \"rk4\" with a fixed step t_end / steps = {:e} s: check that it persists with more steps or method = \"adaptive\")",
            sc.solver.t_end / sc.solver.steps as f64
        );
        (kind, msg)
    } else {
        (kind, why)
    }
}
