//! θ windows watched on the continuous solution (docs/physics.md#bit): for
//! a window `[lo, hi]` of θ and a time interval `[from, to]`, whether θ was
//! ever in the window during the interval, whether it is in at `to`, and
//! when its final unbroken stay began — located by events at the window's
//! edges (`cos(edge) − cos θ` crossing zero — the sign of θ − edge, without
//! θ's `atan2` — on the integrator's dense output) and at
//! the interval's ends (t − from, t − to), not on the output rows.
//!
//! The driver ([`crate::simulate`]) owns a [`Watcher`]: it asks it for the
//! edge levels and time marks to watch, feeds it the crossings in time
//! order ([`Watcher::level_crossed`], [`Watcher::mark_reached`]) and θ at
//! every accepted step's end ([`Watcher::step_end`], which re-synchronises
//! the inside/outside state with θ there, so a crossing the events could
//! not see — θ touching an edge exactly at a step's end — costs at most the
//! time to that step's end). An excursion out of the window and back within
//! one step (two crossings of one edge between step ends) is not seen: the
//! events look for sign changes between step ends, so the resolution of the
//! check is the step (the adaptive steppers' steps follow the dynamics; the
//! Langevin stepper's step is the finest the stochastic solution has, and
//! its dense output is linear).

/// A θ window watched over a time interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThetaWatch {
    /// Start of the interval \[s\].
    pub from: f64,
    /// End of the interval \[s\] (`from <= to`).
    pub to: f64,
    /// The window `[lo, hi]` \[rad\] (closed; `0 <= lo < hi <= π`).
    pub window: [f64; 2],
}

/// What a [`ThetaWatch`] saw.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WindowStay {
    /// The run reached the interval's end `to`.
    pub reached_end: bool,
    /// θ was in the window at some time in `[from, to]` (up to where the
    /// run reached).
    pub ever_inside: bool,
    /// θ is in the window at `to` (`false` if the run did not reach it).
    pub inside_at_end: bool,
    /// Start of the final unbroken stay in the window \[s\], not before
    /// `from` (`Some` only with `inside_at_end`).
    pub stay_from: Option<f64>,
    /// `work_applied` (net work of the applied forces on the top) at `from`
    /// \[J\] (`None` if the run did not reach it).
    pub work_at_from: Option<f64>,
    /// `work_applied` at `to` \[J\] (`None` if the run did not reach it).
    pub work_at_to: Option<f64>,
    /// Crossings of the window's edges inside `[from, to]`.
    pub crossings: u64,
}

/// One watch's running state (scaled times).
#[derive(Debug, Clone)]
struct Track {
    from: f64,
    to: f64,
    window: [f64; 2],
    /// `cos` of the window's edges, `[cos lo, cos hi]` (`+∞` for `lo = 0`,
    /// `−∞` for `hi = π`: a rounded `cos θ` slightly beyond ±1 is inside).
    cos_window: [f64; 2],
    /// θ in the window now.
    inside: bool,
    /// Scaled time of the current stay's start (when `inside`).
    since: f64,
    started: bool,
    ended: bool,
    out: WindowStay,
}

impl Track {
    fn active(&self) -> bool {
        self.started && !self.ended
    }

    fn set_inside(&mut self, inside: bool, t: f64) {
        if inside && !self.inside {
            self.since = t;
        }
        self.inside = inside;
        if self.active() && inside {
            self.out.ever_inside = true;
        }
    }
}

/// The running state of every watch of a run (see the module doc).
#[derive(Debug, Clone)]
pub struct Watcher {
    tracks: Vec<Track>,
    /// Distinct edge levels in (0, π) \[rad\].
    levels: Vec<f64>,
    /// Distinct interval ends (scaled), sorted, with whether processed.
    marks: Vec<(f64, bool)>,
    /// Seconds per scaled time unit.
    tu: f64,
}

impl Watcher {
    /// The watcher of `watches` for a run in scaled time (`tu` seconds per
    /// unit) starting at `t = 0` with θ = `theta0` \[rad\] and
    /// `work_applied` = `work0` \[J\].
    pub fn new(watches: &[ThetaWatch], tu: f64, theta0: f64, work0: f64) -> Self {
        let mut levels: Vec<f64> = watches
            .iter()
            .flat_map(|w| w.window)
            .filter(|&l| l > 0.0 && l < std::f64::consts::PI)
            .collect();
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        let mut marks: Vec<f64> = watches
            .iter()
            .flat_map(|w| [w.from / tu, w.to / tu])
            .collect();
        marks.sort_by(f64::total_cmp);
        marks.dedup();
        let tracks = watches
            .iter()
            .map(|w| Track {
                from: w.from / tu,
                to: w.to / tu,
                window: w.window,
                cos_window: [
                    if w.window[0] == 0.0 {
                        f64::INFINITY
                    } else {
                        w.window[0].cos()
                    },
                    if w.window[1] == std::f64::consts::PI {
                        f64::NEG_INFINITY
                    } else {
                        w.window[1].cos()
                    },
                ],
                inside: w.window[0] <= theta0 && theta0 <= w.window[1],
                since: 0.0,
                started: false,
                ended: false,
                out: WindowStay::default(),
            })
            .collect();
        let mut w = Watcher {
            tracks,
            levels,
            marks: marks.into_iter().map(|m| (m, false)).collect(),
            tu,
        };
        w.pass_marks(0.0, work0);
        w
    }

    /// The edge levels to watch (θ − level through 0, either way) \[rad\].
    pub fn levels(&self) -> &[f64] {
        &self.levels
    }

    /// The time marks (scaled) not yet reached, to watch as `t − mark`
    /// rising through 0, each with its index for [`Watcher::mark_reached`].
    pub fn pending_marks(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.marks
            .iter()
            .enumerate()
            .filter(|(_, m)| !m.1)
            .map(|(i, m)| (i, m.0))
    }

    /// Time mark `i` (scaled).
    pub fn mark(&self, i: usize) -> f64 {
        self.marks[i].0
    }

    /// Process every mark at or before scaled time `t` not yet reached, with
    /// the state there (`work` = `work_applied` \[J\]): for a run that
    /// (re)starts at `t` or ends there.
    pub fn pass_marks(&mut self, t: f64, work: f64) {
        for i in 0..self.marks.len() {
            if !self.marks[i].1 && self.marks[i].0 <= t {
                self.mark_reached(i, work);
            }
        }
    }

    /// θ crossed edge level `levels()[j]` at scaled time `t`, upwards if
    /// `rising`.
    pub fn level_crossed(&mut self, j: usize, t: f64, rising: bool) {
        let level = self.levels[j];
        for tr in &mut self.tracks {
            let [lo, hi] = tr.window;
            if level != lo && level != hi {
                continue;
            }
            if tr.active() {
                tr.out.crossings += 1;
            }
            let entering = (level == lo) == rising;
            tr.set_inside(entering, t);
        }
    }

    /// Mark `i` (from [`Watcher::pending_marks`]) is reached; `work` is
    /// `work_applied` there \[J\].
    pub fn mark_reached(&mut self, i: usize, work: f64) {
        let (t, done) = &mut self.marks[i];
        if *done {
            return;
        }
        *done = true;
        let t = *t;
        let tu = self.tu;
        for tr in &mut self.tracks {
            if !tr.started && tr.from == t {
                tr.started = true;
                tr.out.work_at_from = Some(work);
                if tr.inside {
                    tr.out.ever_inside = true;
                    tr.since = tr.since.max(t);
                }
            }
            if tr.started && !tr.ended && tr.to == t {
                tr.ended = true;
                tr.out.reached_end = true;
                tr.out.work_at_to = Some(work);
                tr.out.inside_at_end = tr.inside;
                tr.out.stay_from = tr.inside.then_some(tr.since.max(tr.from) * tu);
            }
        }
    }

    /// `cos θ` at the end `t` (scaled) of an accepted step, after its
    /// crossings: re-synchronise each watch's inside/outside state with it
    /// (θ in `[lo, hi]` ⇔ `cos hi <= cos θ <= cos lo`: the driver's level
    /// events are `cos(level) − cos θ`, so both read the same function).
    pub fn step_end(&mut self, t: f64, cos_theta: f64) {
        for tr in &mut self.tracks {
            let [c_lo, c_hi] = tr.cos_window;
            let inside = c_hi <= cos_theta && cos_theta <= c_lo;
            if inside != tr.inside {
                tr.set_inside(inside, t);
            }
        }
    }

    /// What each watch saw, in the order given.
    pub fn stays(&self) -> Vec<WindowStay> {
        self.tracks.iter().map(|t| t.out).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: [f64; 2] = [1.0, 2.0];

    fn watcher(from: f64, to: f64, theta0: f64) -> Watcher {
        Watcher::new(
            &[ThetaWatch {
                from,
                to,
                window: W,
            }],
            2.0, // seconds per scaled unit
            theta0,
            0.0,
        )
    }

    fn mark(w: &mut Watcher, t: f64, work: f64) {
        let i = w
            .pending_marks()
            .find(|&(_, m)| m == t)
            .map(|(i, _)| i)
            .unwrap();
        w.mark_reached(i, work);
    }

    #[test]
    fn a_stay_entered_before_the_interval_starts_at_its_start() {
        // Scaled interval [1, 5] = [2 s, 10 s]; θ enters at scaled 0.5.
        let mut w = watcher(2.0, 10.0, 0.5);
        assert_eq!(w.levels(), &[1.0, 2.0]);
        w.level_crossed(0, 0.5, true);
        mark(&mut w, 1.0, 3.0);
        mark(&mut w, 5.0, 7.0);
        let s = w.stays()[0];
        assert!(s.reached_end && s.ever_inside && s.inside_at_end);
        assert_eq!(s.stay_from, Some(2.0));
        assert_eq!((s.work_at_from, s.work_at_to), (Some(3.0), Some(7.0)));
        assert_eq!(s.crossings, 0);
    }

    #[test]
    fn the_final_stay_starts_at_the_last_entry() {
        let mut w = watcher(0.0, 10.0, 0.5);
        w.level_crossed(0, 1.0, true); // in at scaled 1
        w.level_crossed(1, 2.0, true); // out above at 2
        w.level_crossed(1, 3.25, false); // back in at 3.25
        mark(&mut w, 5.0, 0.0);
        let s = w.stays()[0];
        assert!(s.inside_at_end);
        assert_eq!(s.stay_from, Some(6.5));
        assert_eq!(s.crossings, 3);
    }

    #[test]
    fn left_and_never_entered() {
        let mut left = watcher(0.0, 10.0, 0.5);
        left.level_crossed(0, 1.0, true);
        left.level_crossed(0, 2.0, false);
        mark(&mut left, 5.0, 0.0);
        let s = left.stays()[0];
        assert!(s.ever_inside && !s.inside_at_end && s.stay_from.is_none());
        let mut never = watcher(0.0, 10.0, 0.5);
        mark(&mut never, 5.0, 0.0);
        assert!(!never.stays()[0].ever_inside);
        // A stay that ended before the interval does not count.
        let mut before = watcher(4.0, 10.0, 1.5);
        before.level_crossed(0, 1.0, false);
        mark(&mut before, 2.0, 0.0);
        mark(&mut before, 5.0, 0.0);
        assert!(!before.stays()[0].ever_inside);
    }

    #[test]
    fn step_ends_resynchronise_a_missed_crossing() {
        let mut w = watcher(0.0, 10.0, 0.5);
        // θ reached the edge exactly at a step's end: no sign change seen,
        // but θ at the next step's end is inside.
        w.step_end(1.5, 1.2f64.cos());
        mark(&mut w, 5.0, 0.0);
        let s = w.stays()[0];
        assert!(s.inside_at_end);
        assert_eq!(s.stay_from, Some(3.0));
    }

    #[test]
    fn an_unreached_end_is_reported() {
        let mut w = watcher(0.0, 10.0, 1.5);
        w.pass_marks(3.0, 0.0);
        let s = w.stays()[0];
        assert!(!s.reached_end && s.ever_inside && !s.inside_at_end);
        assert_eq!(s.work_at_from, Some(0.0));
        assert_eq!(s.work_at_to, None);
    }
}
