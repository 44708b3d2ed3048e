//! Small 3-vector helpers shared by the body's dynamics
//! ([`crate::physics::body`]) and the models written in the space frame
//! ([`crate::model::rigid`], [`crate::model::vector`]): plain `[f64; 3]` arithmetic, kept
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

/// A rotation about the lab Z axis by an angle φ (the initial heading).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RotZ {
    s: f64,
    c: f64,
    /// sin, cos of φ/2 (for quaternions).
    hs: f64,
    hc: f64,
}

impl RotZ {
    /// The rotation by `phi` \[rad\].
    pub(crate) fn new(phi: f64) -> Self {
        let (s, c) = phi.sin_cos();
        let (hs, hc) = (0.5 * phi).sin_cos();
        RotZ { s, c, hs, hc }
    }

    /// `R_Z(φ) v`.
    pub(crate) fn apply(&self, v: V3) -> V3 {
        [
            self.c * v[0] - self.s * v[1],
            self.s * v[0] + self.c * v[1],
            v[2],
        ]
    }

    /// `q_Z(φ) ⊗ q` for a quaternion `(w, x, y, z)`: the attitude turned by
    /// φ about the lab Z axis.
    pub(crate) fn turn_quaternion(&self, q: [f64; 4]) -> [f64; 4] {
        let (w1, z1) = (self.hc, self.hs);
        [
            w1 * q[0] - z1 * q[3],
            w1 * q[1] - z1 * q[2],
            w1 * q[2] + z1 * q[1],
            w1 * q[3] + z1 * q[0],
        ]
    }
}

/// `v` turned by the rotation vector `rv` (axis `rv/|rv|`, angle `|rv|`
/// \[rad\]): Rodrigues' formula, `|v|` kept to rounding.
pub(crate) fn rotate(rv: V3, v: V3) -> V3 {
    let th = dot(rv, rv).sqrt();
    if th == 0.0 {
        return v;
    }
    let n = scale(1.0 / th, rv);
    let (s, c) = th.sin_cos();
    add(
        add(scale(c, v), scale(s, cross(n, v))),
        scale((1.0 - c) * dot(n, v), n),
    )
}

/// The lab-frame rotation by the rotation vector `rv` applied to an
/// attitude carried as `p ⊗ q_Z(ψ)` (`p` body → lab with its axis along
/// `k`, not turning about it; docs/physics.md#position): the rotation split into
/// its swing (about an axis normal to `k̂ = k/|k|`) and its twist about `k̂`,
/// `r = s ⊗ t` (`t = (r_w, (r⃗·k̂) k̂)` normalised, `s = r ⊗ t*`), so that
/// `r ⊗ p ⊗ q_Z(ψ) = (s ⊗ p) ⊗ q_Z(ψ + α)`. Returns `s ⊗ p` (renormalised)
/// and the twist angle `α = 2 atan2(r⃗·k̂, r_w)` \[rad\].
pub(crate) fn swing_twist_turn(rv: V3, k: V3, p: [f64; 4]) -> ([f64; 4], f64) {
    let th = dot(rv, rv).sqrt();
    if th == 0.0 {
        return (p, 0.0);
    }
    let (s, c) = (0.5 * th).sin_cos();
    let u = scale(s / th, rv);
    let kh = scale(1.0 / dot(k, k).sqrt(), k);
    let uk = dot(u, kh);
    let nt = c.hypot(uk);
    if nt == 0.0 {
        // A half turn about an axis normal to k: all swing.
        return (turn_quaternion_by(rv, p), 0.0);
    }
    // s = r ⊗ t*, t* = (c, −uk k̂)/nt.
    let (tw, tv) = (c / nt, scale(-uk / nt, kh));
    let sw = [
        c * tw - dot(u, tv),
        c * tv[0] + tw * u[0] + (u[1] * tv[2] - u[2] * tv[1]),
        c * tv[1] + tw * u[1] + (u[2] * tv[0] - u[0] * tv[2]),
        c * tv[2] + tw * u[2] + (u[0] * tv[1] - u[1] * tv[0]),
    ];
    let r = [
        sw[0] * p[0] - sw[1] * p[1] - sw[2] * p[2] - sw[3] * p[3],
        sw[0] * p[1] + sw[1] * p[0] + sw[2] * p[3] - sw[3] * p[2],
        sw[0] * p[2] + sw[2] * p[0] + sw[3] * p[1] - sw[1] * p[3],
        sw[0] * p[3] + sw[3] * p[0] + sw[1] * p[2] - sw[2] * p[1],
    ];
    let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]).sqrt();
    ([r[0] / n, r[1] / n, r[2] / n, r[3] / n], 2.0 * uk.atan2(c))
}

/// The attitude `q` (body → lab, `(w, x, y, z)`) after the lab-frame
/// rotation by the rotation vector `rv`: `(cos(|rv|/2), sin(|rv|/2) rv/|rv|)
/// ⊗ q`, renormalised.
pub(crate) fn turn_quaternion_by(rv: V3, q: [f64; 4]) -> [f64; 4] {
    let th = dot(rv, rv).sqrt();
    if th == 0.0 {
        return q;
    }
    let (s, c) = (0.5 * th).sin_cos();
    let u = scale(s / th, rv);
    let r = [
        c * q[0] - u[0] * q[1] - u[1] * q[2] - u[2] * q[3],
        c * q[1] + u[0] * q[0] + u[1] * q[3] - u[2] * q[2],
        c * q[2] + u[1] * q[0] + u[2] * q[1] - u[0] * q[3],
        c * q[3] + u[2] * q[0] + u[0] * q[2] - u[1] * q[1],
    ];
    let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]).sqrt();
    [r[0] / n, r[1] / n, r[2] / n, r[3] / n]
}
