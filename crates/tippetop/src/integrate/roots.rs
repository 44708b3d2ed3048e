//! Bracketed root finding for event location.

/// Find a zero of `g` in `[a, b]` given `ga = g(a)` and `gb = g(b)` of
/// opposite signs (or `gb == 0`), to a bracket width `<= tol`.
///
/// Illinois variant of regula falsi (the retained end's value is halved when
/// the same end is kept twice in a row), with a bisection step whenever two
/// iterations fail to halve the bracket. Returns the bracket end on the side
/// of `b` (where `g` has the sign of `gb`), or a point where `g == 0`.
pub(super) fn illinois(
    mut g: impl FnMut(f64) -> f64,
    mut a: f64,
    mut b: f64,
    mut ga: f64,
    mut gb: f64,
    tol: f64,
) -> f64 {
    if gb == 0.0 {
        return b;
    }
    // Which end was replaced last: -1 = a, +1 = b, 0 = none yet.
    let mut side = 0i32;
    let mut width_2_ago = f64::INFINITY;
    let mut width_1_ago = f64::INFINITY;
    // Bisection alone needs < 64 halvings from any f64 interval down to a few
    // ulps; the cap only guards against a pathological g (NaN values).
    for _ in 0..200 {
        let width = b - a;
        if width <= tol {
            break;
        }
        let bisect = width > 0.5 * width_2_ago;
        width_2_ago = width_1_ago;
        width_1_ago = width;
        let mut c = if bisect {
            a + 0.5 * width
        } else {
            b - gb * (b - a) / (gb - ga)
        };
        if !(c > a && c < b) {
            c = a + 0.5 * width;
            if !(c > a && c < b) {
                break;
            }
        }
        let gc = g(c);
        if gc == 0.0 {
            return c;
        }
        if gc.is_nan() {
            // Cannot tell the side: return the current far end.
            break;
        }
        if (gc > 0.0) == (gb > 0.0) {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::illinois;

    const TOL: f64 = 4.0 * f64::EPSILON;

    #[test]
    fn simple_root() {
        let r = illinois(|t| t * t - 0.5, 0.0, 1.0, -0.5, 0.5, TOL);
        assert!((r - 0.5f64.sqrt()).abs() <= TOL, "{r}");
    }

    /// A flat (triple) root stalls plain regula falsi; the bisection
    /// safeguard still closes the bracket.
    #[test]
    fn flat_root() {
        let mut n = 0;
        let g = |t: f64| (t - 0.3).powi(3);
        let r = illinois(
            |t| {
                n += 1;
                g(t)
            },
            0.0,
            1.0,
            g(0.0),
            g(1.0),
            TOL,
        );
        assert!((r - 0.3).abs() <= TOL, "{r}");
        assert!(n < 200, "{n} evaluations");
    }

    /// A sign jump (no zero): converges to the jump by the safeguard, and
    /// returns the end past the crossing.
    #[test]
    fn jump() {
        let r = illinois(
            |t| if t < 0.3 { -1.0 } else { 1.0 },
            0.0,
            1.0,
            -1.0,
            1.0,
            TOL,
        );
        assert!(r >= 0.3 && r - 0.3 <= TOL, "{r}");
    }

    /// Decreasing g, root at b exactly.
    #[test]
    fn root_at_end() {
        let r = illinois(|t| 1.0 - t, 0.0, 1.0, 1.0, 0.0, TOL);
        assert_eq!(r, 1.0);
    }
}
