//! Equations of motion, one file per formulation.

pub mod reduced;
pub mod rigid;
pub(crate) mod vec3;
pub mod vector;

use crate::{ContactMode, FrictionLaw, contact::SlidingLaw};

/// The friction coefficient vector `f(v)` (`|f| <= μ`) of the models that
/// keep the sphere on the plane, in sliding mode: the law's
/// [`SlidingLaw::coefficient`], and for the exact law (`exact`) the slip
/// hint at exactly zero slip and the smooth continuation through zero.
///
/// Exact law, sliding: the slip-zero event is located on the dense output
/// of the step that crosses zero. Continuing the friction smoothly through
/// the crossing (keep its direction, i.e. flip `v/|v|` once `v·d < 0`, `d`
/// the approach direction `slip_ref`) keeps that step smooth, so the event
/// time is as accurate as the step; the stages past zero are discarded at
/// the event.
#[inline]
pub(crate) fn sliding_coefficient(
    law: &FrictionLaw,
    exact: bool,
    mu: f64,
    v: [f64; 2],
    slip_hint: [f64; 2],
    slip_ref: [f64; 2],
) -> [f64; 2] {
    if !exact {
        return law.coefficient(mu, v);
    }
    if v[0] == 0.0 && v[1] == 0.0 {
        return [mu * slip_hint[0], mu * slip_hint[1]];
    }
    let f = law.coefficient(mu, v);
    if v[0] * slip_ref[0] + v[1] * slip_ref[1] < 0.0 {
        [-f[0], -f[1]]
    } else {
        f
    }
}

/// The normal force `N` from the contact closure `N D(σ) = Q`, where
/// `D(σ) = dp` for the friction that `N >= 0` gives and `dm` for `N < 0`
/// (the friction sees `|N|`): `"paper"` contact takes `Q/dp` with its sign
/// (no solution if `dp <= 0`); bilateral and unilateral contact take the one
/// self-consistent branch. `Err(n)`: the Painlevé case, with `n` (0 or 2)
/// consistent solutions.
#[inline]
pub(crate) fn normal_force(contact: ContactMode, q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
    match contact {
        ContactMode::Paper => {
            if dp <= 0.0 {
                return Err(0);
            }
            Ok(q / dp)
        }
        ContactMode::Bilateral | ContactMode::Unilateral => {
            let np = q / dp;
            let nm = q / dm;
            let okp = dp != 0.0 && np >= 0.0;
            let okm = dm != 0.0 && nm < 0.0;
            match (okp, okm) {
                (true, false) => Ok(np),
                (false, true) => Ok(nm),
                (true, true) => Err(2),
                (false, false) => Err(0),
            }
        }
    }
}
