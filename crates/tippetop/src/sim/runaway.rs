//! The state's watch for a run that runs away: from the [`Progress`]
//! reports of one run (the spin, the steps and the time, so the same run
//! warns at the same place whatever the machine or its load), a warning
//! once per decade by which the spin |ω| has grown, or the mean step size
//! has fallen, since the first report. Such a run ends in a failure (a
//! Painlevé paradox, `solver.max_steps`) unless it recovers; the warning
//! says so before it happens. The CLI's progress display and Python's
//! `tippetop.run` both use it (docs/guide.md#errors). And the state that
//! has run away for good: [`axis_blown`], the blow-up the driver ends a run
//! with (`failure = "blow_up"`), named as such rather than by whatever the
//! blown-up state made fail next (a Painlevé case, a NaN).

use super::record::Progress;
use crate::human;

/// The watch over one run's reports: the first report (time \[s\], spin
/// \[rad/s\], mean step \[s\]), the last one (time, steps) and the decades
/// of spin growth and step fall already reported. Feed it every report of
/// the run, in order ([`RunawayWatch::check`]).
#[derive(Debug, Default, Clone)]
pub struct RunawayWatch {
    first: Option<(f64, f64, f64)>,
    last: (f64, u64),
    spin_decades: i32,
    step_decades: i32,
}

impl RunawayWatch {
    /// The warning (one line, `warning: the state is running away: ...`)
    /// for report `p`, if it crossed a new decade; `None` otherwise and at
    /// the first report (which sets the reference).
    pub fn check(&mut self, p: &Progress) -> Option<String> {
        let (t_last, steps_last) = self.last;
        self.last = (p.t, p.steps);
        if p.steps <= steps_last {
            return None;
        }
        let step = (p.t - t_last) / (p.steps - steps_last) as f64;
        let Some(first) = self.first else {
            self.first = Some((p.t, p.spin.abs(), step));
            return None;
        };
        runaway_warning(
            first,
            (p.t, p.spin.abs(), step),
            &mut self.spin_decades,
            &mut self.step_decades,
        )
    }
}

/// Whole decades by which `now` exceeds `then` (0 when it does not, or
/// when either is not a positive finite number).
fn decades(now: f64, then: f64) -> i32 {
    let r = now / then;
    if r.is_finite() && r > 0.0 && then > 0.0 {
        r.log10().floor().max(0.0) as i32
    } else {
        0
    }
}

/// The warning, once per new decade, that the state is running away:
/// between the first report `first` and this one `now`, each (time \[s\],
/// |spin| \[rad/s\], mean step size over the reports' interval \[s\]), the
/// spin has grown by `10^n` or the step size has fallen by `10^n` for an
/// `n` above the decades already reported (`spin_warned`,
/// `step_warned`, updated).
fn runaway_warning(
    first: (f64, f64, f64),
    now: (f64, f64, f64),
    spin_warned: &mut i32,
    step_warned: &mut i32,
) -> Option<String> {
    let spin_d = decades(now.1, first.1);
    let step_d = decades(first.2, now.2);
    if spin_d <= *spin_warned && step_d <= *step_warned {
        return None;
    }
    *spin_warned = (*spin_warned).max(spin_d);
    *step_warned = (*step_warned).max(step_d);
    let times = |d: i32| format!("{:.0}", 10f64.powi(d));
    let spin = if spin_d >= 1 {
        format!("grown {}x", times(spin_d))
    } else {
        "not grown by a decade".into()
    };
    let step = if step_d >= 1 {
        format!("fallen {}x", times(step_d))
    } else {
        "not fallen by a decade".into()
    };
    Some(format!(
        "warning: the state is running away: at t = {} the spin |omega| = {} has {spin} since t = {} ({}), \
         and the mean step size {} has {step} ({}); such a run ends in a failure (a Painleve paradox, \
         solver.max_steps) unless it recovers: see docs/guide.md#errors",
        human::si(now.0, "s", 3),
        human::si(now.1, "rad/s", 3),
        human::si(first.0, "s", 3),
        human::si(first.1, "rad/s", 3),
        human::si(now.2, "s", 3),
        human::si(first.2, "s", 3),
    ))
}

/// Largest drift of the symmetry axis's length from 1, `| |k| − 1 |`, a
/// state may have. `k̇ = w × k` keeps `|k|` constant, so it drifts only by
/// the integration error, orders of magnitude below this at any tolerance
/// a run meets; a tenth is no integration error but a diverged solution
/// (the room-temperature bit under a 1 µN write reached |k| = 1.3e45).
pub(crate) const AXIS_DRIFT_MAX: f64 = 0.1;

/// True if `norm_sq = |k|²` of a unit axis shows a blow-up: `|k|` off 1 by
/// more than [`AXIS_DRIFT_MAX`], or not a number.
#[inline]
pub(crate) fn axis_blown(norm_sq: f64) -> bool {
    const LO: f64 = (1.0 - AXIS_DRIFT_MAX) * (1.0 - AXIS_DRIFT_MAX);
    const HI: f64 = (1.0 + AXIS_DRIFT_MAX) * (1.0 + AXIS_DRIFT_MAX);
    !(LO..=HI).contains(&norm_sq)
}

/// Why a run of `sc` whose unit axis reached `|k|` = `norm` ended: the
/// state blew up, with what sets the step of its method.
pub(crate) fn blow_up_why(sc: &crate::Scenario, norm: f64) -> String {
    use crate::Method;
    let hint = match sc.solver.method {
        Method::Langevin | Method::Brownian => format!(
            "the fixed step solver.dt = {} is too long for the forces and rates of this motion",
            human::si(sc.solver.dt.unwrap_or(f64::NAN), "s", 3)
        ),
        Method::Rk4 => "the fixed step t_end / steps is too long for this motion".into(),
        Method::Adaptive | Method::Stiff => {
            "the step control lost the solution: lower solver.rtol, or check forces far beyond the top's weight".into()
        }
    };
    format!(
        "the state blew up: the symmetry axis k, a unit vector to the integration error, has |k| = {} \
         (more than {} % off): the integration diverged and the state is no motion of the top; {hint}",
        human::s4(norm),
        AXIS_DRIFT_MAX * 100.0
    )
}

#[cfg(test)]
mod tests {
    use super::runaway_warning;

    /// The blow-up check: a unit axis within a tenth of unit length is
    /// not blown up, one beyond, or NaN, is.
    #[test]
    fn axis_blown_beyond_a_tenth_of_unit_length() {
        use super::axis_blown;
        for n in [1.0, 1.0 + 1e-6, 0.95, 1.0999, 0.9001] {
            assert!(!axis_blown(n * n), "{n}");
        }
        for n in [1.1001, 0.8999, 0.0, 1.3e45, f64::INFINITY, f64::NAN] {
            assert!(axis_blown(n * n), "{n}");
        }
    }

    /// The state's warning: once per new decade of spin growth or step
    /// fall since the first report, saying which; a state that stays
    /// (spin and step within a decade) says nothing.
    #[test]
    fn runaway_warns_once_per_decade_of_spin_or_step() {
        let (mut sw, mut hw) = (0, 0);
        let first = (1e-3, 1e7, 1e-9);
        // 9.9x the spin, 1/9.9 the step: nothing.
        assert!(runaway_warning(first, (2e-3, 9.9e7, 1.01e-10), &mut sw, &mut hw).is_none());
        let w = runaway_warning(first, (3e-3, 1.5e8, 5e-10), &mut sw, &mut hw).unwrap();
        assert!(
            w.starts_with("warning: the state is running away: at t = 3.00 ms"),
            "{w}"
        );
        assert!(
            w.contains("150 Mrad/s has grown 10x since t = 1.00 ms (10.0 Mrad/s)"),
            "{w}"
        );
        assert!(
            w.contains("500 ps has not fallen by a decade (1.00 ns)"),
            "{w}"
        );
        // The same decade again: nothing; the step's first decade: once.
        assert!(runaway_warning(first, (4e-3, 9e8, 2e-10), &mut sw, &mut hw).is_none());
        let w = runaway_warning(first, (5e-3, 9e8, 9e-11), &mut sw, &mut hw).unwrap();
        assert!(w.contains("has fallen 10x (1.00 ns)"), "{w}");
        let w = runaway_warning(first, (6e-3, 2e9, 9e-11), &mut sw, &mut hw).unwrap();
        assert!(w.contains("has grown 100x"), "{w}");
        // A spin that falls (or is zero at first) never warns.
        let (mut sw, mut hw) = (0, 0);
        assert!(runaway_warning(first, (1.0, 1e3, 1e-9), &mut sw, &mut hw).is_none());
        assert!(runaway_warning((0.0, 0.0, 1e-9), (1.0, 1e3, 1e-9), &mut sw, &mut hw).is_none());
    }
}
