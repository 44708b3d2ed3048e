//! Small 3-vector helpers shared by the models written in the space frame
//! ([`super::rigid`], [`super::vector`]): plain `[f64; 3]` arithmetic, kept
//! inline so the right-hand sides stay free of heap traffic and calls.

/// A 3-vector (components in whatever frame the caller uses).
pub(crate) type V3 = [f64; 3];

/// The vertical unit vector Z (space frame).
pub(crate) const Z: V3 = [0.0, 0.0, 1.0];

/// `a + b`.
#[inline]
pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline]
pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `s a`.
#[inline]
pub(crate) fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

/// `a · b`.
#[inline]
pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
#[inline]
pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Solve the 3×3 system whose matrix has columns `c` by Cramer's rule (for
/// the small symmetric positive definite contact matrices of the models).
pub(crate) fn solve3(c: [V3; 3], b: V3) -> V3 {
    let c12 = cross(c[1], c[2]);
    let inv_det = 1.0 / dot(c[0], c12);
    [
        dot(b, c12) * inv_det,
        dot(c[0], cross(b, c[2])) * inv_det,
        dot(c[0], cross(c[1], b)) * inv_det,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cramer's rule recovers x from K x for a symmetric positive definite
    /// K of the contact kind (identity plus rank-one terms) to rounding.
    #[test]
    fn solve3_inverts_a_contact_matrix() {
        let r = [0.03, -0.02, -0.9];
        let c = cross([0.1, 0.2, 0.97], r);
        let col = |e: V3| {
            add(
                sub(scale(1.0 + 2.5 * dot(r, r), e), scale(2.5 * dot(r, e), r)),
                scale(-0.7 * dot(c, e), c),
            )
        };
        let k = [col([1.0, 0.0, 0.0]), col([0.0, 1.0, 0.0]), col(Z)];
        let x = [0.3, -1.7, 9.8];
        let b = add(add(scale(x[0], k[0]), scale(x[1], k[1])), scale(x[2], k[2]));
        let got = solve3(k, b);
        for i in 0..3 {
            assert!((got[i] - x[i]).abs() <= 1e-14 * 9.8, "{got:?} vs {x:?}");
        }
    }
}
