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
///
/// The branch is decided from the signs of `q`, `dp`, `dm` and only the
/// chosen quotient is computed (one division on the right-hand side's
/// critical path instead of two). The result is the same as testing the
/// signs of both quotients, except where a quotient is 0 or NaN although
/// `Q` is a nonzero number (underflow below 1e-308, or an infinite `D`).
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
            // q/dp >= 0 (counting −0) and q/dm < 0, from the signs; a NaN
            // makes its quotient NaN, which is neither.
            let okp =
                !q.is_nan() && !dp.is_nan() && dp != 0.0 && (q == 0.0 || (q > 0.0) == (dp > 0.0));
            let okm =
                !q.is_nan() && !dm.is_nan() && dm != 0.0 && q != 0.0 && (q > 0.0) != (dm > 0.0);
            match (okp, okm) {
                (true, false) => Ok(q / dp),
                (false, true) => Ok(q / dm),
                (true, true) => Err(2),
                (false, false) => Err(0),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::normal_force;
    use crate::ContactMode;

    /// The sign rule picks the same branch and value as dividing first and
    /// testing the quotients' signs (the definition), on every sign
    /// combination, zeros of both signs, infinities and NaN.
    #[test]
    fn normal_force_sign_rule_matches_the_quotient_rule() {
        let by_quotients = |q: f64, dp: f64, dm: f64| -> Result<f64, usize> {
            let (np, nm) = (q / dp, q / dm);
            let okp = dp != 0.0 && np >= 0.0;
            let okm = dm != 0.0 && nm < 0.0;
            match (okp, okm) {
                (true, false) => Ok(np),
                (false, true) => Ok(nm),
                (true, true) => Err(2),
                (false, false) => Err(0),
            }
        };
        let vals = [
            -3.0,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            2.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut branches = [0usize; 4];
        for &q in &vals {
            for &dp in &vals {
                for &dm in &vals {
                    let a = normal_force(ContactMode::Bilateral, q, dp, dm);
                    let b = by_quotients(q, dp, dm);
                    // The documented exception: a quotient that is 0 or NaN
                    // while q is a nonzero number (underflow, infinite D).
                    let degenerate = [dp, dm].iter().any(|&d| {
                        let x = q / d;
                        q != 0.0 && !q.is_nan() && !d.is_nan() && (x == 0.0 || x.is_nan())
                    });
                    if degenerate {
                        continue;
                    }
                    match (a, b) {
                        (Ok(x), Ok(y)) => {
                            assert!(x.to_bits() == y.to_bits(), "{q} {dp} {dm}: {x} vs {y}");
                            branches[(x < 0.0) as usize] += 1;
                        }
                        (Err(x), Err(y)) => {
                            assert_eq!(x, y, "{q} {dp} {dm}");
                            branches[2 + (x == 2) as usize] += 1;
                        }
                        _ => panic!("{q} {dp} {dm}: {a:?} vs {b:?}"),
                    }
                }
            }
        }
        // Every outcome was exercised.
        assert!(branches.iter().all(|&n| n > 0), "{branches:?}");
    }
}
