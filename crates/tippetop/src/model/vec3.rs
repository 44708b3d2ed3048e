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
    let det = dot(c[0], cross(c[1], c[2]));
    [
        dot(b, cross(c[1], c[2])) / det,
        dot(c[0], cross(b, c[2])) / det,
        dot(c[0], cross(c[1], b)) / det,
    ]
}
