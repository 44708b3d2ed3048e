//! The reaction coordinate ξ of the splitting ([`Coordinate`]).

use crate::Error;
use crate::Scenario;
use crate::analysis::ensemble::Exit;
use crate::trajectory::COLUMNS;

/// A reaction coordinate ξ: the splitting's levels are levels of ξ, which
/// should grow towards the target (any function of the state gives an
/// unbiased estimate; a good one gives a small variance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coordinate {
    /// A trajectory.csv column (index into [`COLUMNS`]), negated if
    /// `negated`: `theta`, `-theta`, `omega`.
    Column {
        /// Index into [`COLUMNS`].
        column: usize,
        /// ξ = −value.
        negated: bool,
    },
    /// `|column − centre|` (centre in the column's SI unit):
    /// `|theta-1.5707963267948966|`, the distance from a well's centre.
    Distance {
        /// Index into [`COLUMNS`].
        column: usize,
        /// The centre.
        centre: f64,
    },
    /// `tilt_energy` \[J\]: the energy of the tilt mode,
    /// `½ (A + m a² sin²θ) θ̇² + U_wells(θ) − m g a cos θ` (its kinetic
    /// energy on the plane, the wells and gravity's share of the potential):
    /// in the Langevin mode, where the tilt oscillates in its well, the
    /// committor of an escape depends on θ̇ as much as on θ, and this is the
    /// coordinate that follows it (docs/physics.md#ams). It needs the
    /// scenario ([`Coordinate::value_in`]).
    TiltEnergy,
}

/// Valid form of `--coordinate`.
pub const COORDINATE_RANGE: &str = "a trajectory.csv column (theta, omega, ...), -COLUMN (decreasing towards the target), |COLUMN-C| (distance from C, SI units, e.g. |theta-1.5707963267948966|) or tilt_energy";

impl Coordinate {
    /// θ itself.
    pub const THETA: Coordinate = Coordinate::Column {
        column: 1,
        negated: false,
    };

    /// Parse `theta`, `-theta`, `|theta-1.57|` (error key `--coordinate`).
    pub fn parse(spec: &str) -> Result<Coordinate, Error> {
        let bad = |what: String| Error::invalid("--coordinate", what, COORDINATE_RANGE.into());
        let column = |name: &str| {
            COLUMNS
                .iter()
                .position(|c| *c == name.trim())
                .ok_or_else(|| bad(format!("{:?} is not a trajectory.csv column", name.trim())))
        };
        let s = spec.trim();
        if s == "tilt_energy" {
            return Ok(Coordinate::TiltEnergy);
        }
        if let Some(inner) = s.strip_prefix('|').and_then(|r| r.strip_suffix('|')) {
            let Some((name, c)) = inner.split_once('-') else {
                return Err(bad(format!("{s:?} is not |COLUMN-C|")));
            };
            let centre: f64 = c
                .trim()
                .parse()
                .map_err(|_| bad(format!("{:?} is not a number", c.trim())))?;
            if !centre.is_finite() {
                return Err(bad(format!("{centre} is not a finite centre")));
            }
            return Ok(Coordinate::Distance {
                column: column(name)?,
                centre,
            });
        }
        match s.strip_prefix('-') {
            Some(name) => Ok(Coordinate::Column {
                column: column(name)?,
                negated: true,
            }),
            None => Ok(Coordinate::Column {
                column: column(s)?,
                negated: false,
            }),
        }
    }

    /// The default coordinate for a target: θ oriented towards it when the
    /// target reads θ only (`theta>b`: θ; `theta<a`: −θ; both: the distance
    /// `|θ − c|` from the middle `c` of the window they leave), θ
    /// otherwise.
    pub fn toward(target: &Exit) -> Coordinate {
        let terms = target.terms();
        if terms.is_empty() || terms.iter().any(|t| t.0 != 1) {
            return Coordinate::THETA;
        }
        let above = terms.iter().filter(|t| t.1).map(|t| t.2).reduce(f64::min);
        let below = terms.iter().filter(|t| !t.1).map(|t| t.2).reduce(f64::max);
        match (below, above) {
            (Some(a), Some(b)) => Coordinate::Distance {
                column: 1,
                centre: 0.5 * (a + b),
            },
            (Some(_), None) => Coordinate::Column {
                column: 1,
                negated: true,
            },
            _ => Coordinate::THETA,
        }
    }

    /// The default coordinate of a problem: [`Coordinate::toward`] the
    /// target, except in the Langevin mode for a target that leaves a θ
    /// window on both sides (a state's escape): [`Coordinate::TiltEnergy`],
    /// whose levels follow an oscillating tilt's chance to escape (with
    /// `|θ − c|` the replicas' estimates of `nano-physical`'s escape spread
    /// over seven decades, with the tilt energy over one and a half:
    /// docs/physics.md#ams).
    pub fn default_for(sc: &Scenario, target: &Exit) -> Coordinate {
        match Coordinate::toward(target) {
            Coordinate::Distance { column: 1, .. }
                if sc.solver.method == crate::Method::Langevin =>
            {
                Coordinate::TiltEnergy
            }
            other => other,
        }
    }

    /// The columns it reads (indices into [`COLUMNS`]).
    pub fn columns(&self) -> Vec<usize> {
        match *self {
            Coordinate::Column { column, .. } | Coordinate::Distance { column, .. } => vec![column],
            Coordinate::TiltEnergy => vec![1, 2],
        }
    }

    /// ξ from the row's values (`get(column)`, SI); NaN for
    /// [`Coordinate::TiltEnergy`], which needs the scenario
    /// ([`Coordinate::value_in`]).
    pub fn value(&self, get: &dyn Fn(usize) -> f64) -> f64 {
        match *self {
            Coordinate::Column { column, negated } => {
                let v = get(column);
                if negated { -v } else { v }
            }
            Coordinate::Distance { column, centre } => (get(column) - centre).abs(),
            Coordinate::TiltEnergy => f64::NAN,
        }
    }

    /// ξ from the row's values for the scenario `sc`.
    pub fn value_in(&self, sc: &Scenario, get: &dyn Fn(usize) -> f64) -> f64 {
        match self {
            Coordinate::TiltEnergy => TiltEnergy::of(sc).value(get(1), get(2)),
            other => other.value(get),
        }
    }
}

/// The tilt mode's energy ([`Coordinate::TiltEnergy`]) of one scenario.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TiltEnergy {
    inertia: f64,
    ma2: f64,
    mga: f64,
    wells: Vec<crate::Well>,
}

impl TiltEnergy {
    pub(crate) fn of(sc: &Scenario) -> TiltEnergy {
        let t = &sc.top;
        TiltEnergy {
            inertia: t.inertia_transverse,
            ma2: t.mass * t.offset * t.offset,
            mga: t.mass * sc.surface.gravity * t.offset,
            wells: sc.wells(),
        }
    }

    /// The energy \[J\] at θ \[rad\], θ̇ \[rad/s\].
    pub(crate) fn value(&self, theta: f64, theta_dot: f64) -> f64 {
        let s = theta.sin();
        let wells: f64 = self
            .wells
            .iter()
            .map(|w| -w.depth * (-(theta - w.theta).powi(2) / (2.0 * w.width * w.width)).exp())
            .sum();
        0.5 * (self.inertia + self.ma2 * s * s) * theta_dot * theta_dot + wells
            - self.mga * theta.cos()
    }
}

impl std::fmt::Display for Coordinate {
    /// The canonical spec (shortest round-trip floats).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Coordinate::Column { column, negated } => {
                write!(f, "{}{}", if negated { "-" } else { "" }, COLUMNS[column])
            }
            Coordinate::Distance { column, centre } => {
                write!(f, "|{}-{centre:?}|", COLUMNS[column])
            }
            Coordinate::TiltEnergy => f.write_str("tilt_energy"),
        }
    }
}
