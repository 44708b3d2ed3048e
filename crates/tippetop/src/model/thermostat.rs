//! The heat bath of the Langevin method for a top on the plane: the exact
//! Ornstein–Uhlenbeck step of its generalised velocities `(v_x, v_y, w)` at
//! fixed axis `k` (docs/physics.md §21), written over plain vectors so the
//! models that keep the sphere on the plane share it (the rigid model in
//! contact; the vector model has the same step inline, bit for bit).

use super::vec3::{V3, add, cross, dot, scale};
use crate::Scenario;
use crate::physics::units::Scales;

/// The heat bath in scaled units (m = R = 1, the model's time unit): kT,
/// γ_t, γ_r and the contact damping c/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bath {
    pub kt: f64,
    pub gt: f64,
    pub gr: f64,
    pub c: f64,
}

impl Bath {
    /// The bath of a scenario with a stochastic method, in `scales`.
    pub fn of(sc: &Scenario, scales: &Scales) -> Option<Bath> {
        sc.solver.method.is_stochastic().then(|| {
            let th = &sc.thermal;
            Bath {
                kt: th.kt() / scales.energy(),
                gt: th.damping_translational * scales.time,
                gr: th.damping_rotational * scales.time,
                c: th.damping_contact * scales.time / scales.mass,
            }
        })
    }
}

/// The orthonormal basis `(k̂, ê, f̂)` of the rotational modes for the axis
/// `k` (`ê = k × Z/|k × Z|`, any horizontal unit vector at the poles,
/// `f̂ = k̂ × ê`) and `sin²θ`.
pub(crate) fn modes_basis(kr: V3) -> ([V3; 3], f64) {
    let kn = scale(1.0 / dot(kr, kr).sqrt(), kr);
    let e = [kn[1], -kn[0], 0.0];
    let s2 = e[0] * e[0] + e[1] * e[1];
    let eh = if s2 > 0.0 {
        scale(1.0 / s2.sqrt(), e)
    } else {
        [1.0, 0.0, 0.0]
    };
    ([kn, eh, cross(kn, eh)], s2)
}

/// The body's scaled constants: offset `a`, moments `A`, `C`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Body {
    pub a: f64,
    pub ia: f64,
    pub ic: f64,
}

/// The exact Ornstein–Uhlenbeck step over `h` of `(v_h, w)` on the plane
/// at axis `k`, with 5 standard normals `xi` (docs/physics.md §21). Without
/// contact damping `M` and `Γ` are diagonal in `(X, Y | k̂, ê, f̂)`; with it,
/// the 5×5 problem is solved in the eigenbasis of `M^{−1/2} Γ M^{−1/2}`.
pub(crate) fn ou_on_plane(
    b: &Bath,
    body: &Body,
    k: V3,
    vh: &mut [f64; 2],
    w: &mut V3,
    h: f64,
    xi: &[f64],
) {
    if b.c > 0.0 {
        return ou_on_plane_coupled(b, body, k, vh, w, h, xi);
    }
    let mode = |x: f64, rate: f64, mass: f64, z: f64| {
        let decay = (-rate * h).exp();
        let var = -(b.kt / mass) * (-2.0 * rate * h).exp_m1();
        decay * x + var.sqrt() * z
    };
    for j in 0..2 {
        vh[j] = mode(vh[j], b.gt, 1.0, xi[j]);
    }
    let ([kn, eh, fh], s2) = modes_basis(k);
    let beta = body.a * body.a * s2;
    let modes = [
        (kn, b.gr, body.ic),
        (
            eh,
            (b.gr * body.ia + b.gt * beta) / (body.ia + beta),
            body.ia + beta,
        ),
        (fh, b.gr, body.ia),
    ];
    let mut wn = *w;
    for (j, (dir, rate, mass)) in modes.into_iter().enumerate() {
        let x = dot(wn, dir);
        let dx = mode(x, rate, mass, xi[2 + j]) - x;
        wn = add(wn, scale(dx, dir));
    }
    *w = wn;
}

/// [`ou_on_plane`] with the contact damping (`Γ` gains `c Pᵀ P`).
fn ou_on_plane_coupled(
    b: &Bath,
    body: &Body,
    k: V3,
    vh: &mut [f64; 2],
    w: &mut V3,
    h: f64,
    xi: &[f64],
) {
    use nalgebra::{Matrix5, SymmetricEigen, Vector5};
    let ([kn, eh, fh], s2) = modes_basis(k);
    let (a, ia, ic) = (body.a, body.ia, body.ic);
    let beta = a * a * s2;
    let m = [1.0, 1.0, ic, ia + beta, ia];
    let g = [b.gt, b.gt, b.gr * ic, b.gr * ia + b.gt * beta, b.gr * ia];
    let r = [a * kn[0], a * kn[1], a * kn[2] - 1.0];
    let cols: [[f64; 2]; 5] = {
        let c = |d: V3| {
            let x = cross(d, r);
            [x[0], x[1]]
        };
        [[1.0, 0.0], [0.0, 1.0], c(kn), c(eh), c(fh)]
    };
    let sq: [f64; 5] = m.map(f64::sqrt);
    let smat = Matrix5::from_fn(|i, j| {
        let pp = cols[i][0] * cols[j][0] + cols[i][1] * cols[j][1];
        let gij = if i == j { g[i] } else { 0.0 } + b.c * pp;
        gij / (sq[i] * sq[j])
    });
    let eig = SymmetricEigen::new(smat);
    let dirs = [kn, eh, fh];
    let p = [vh[0], vh[1], dot(*w, kn), dot(*w, eh), dot(*w, fh)];
    let z = Vector5::from_fn(|i, _| sq[i] * p[i]);
    let mut q = eig.eigenvectors.transpose() * z;
    for j in 0..5 {
        let lam = eig.eigenvalues[j].max(0.0);
        let decay = (-lam * h).exp();
        let var = -b.kt * (-2.0 * lam * h).exp_m1();
        q[j] = decay * q[j] + var.sqrt() * xi[j];
    }
    let z = eig.eigenvectors * q;
    vh[0] = z[0] / sq[0];
    vh[1] = z[1] / sq[1];
    let mut wn = *w;
    for j in 0..3 {
        wn = add(wn, scale(z[2 + j] / sq[2 + j] - p[2 + j], dirs[j]));
    }
    *w = wn;
}

/// The exact Ornstein–Uhlenbeck step over `h` of a free body (in flight):
/// the centre's velocity `v` (3 modes of mass 1 at γ_t) and the angular
/// velocity `w` in the basis `(k̂, ê, f̂)` (masses `C, A, A`, each at γ_r),
/// with 6 standard normals `xi` (`v_x, v_y`, the three rotational modes,
/// `v_z`: the first five in the order the contact step uses them). No
/// contact damping (no contact).
pub(crate) fn ou_free(b: &Bath, body: &Body, k: V3, v: &mut V3, w: &mut V3, h: f64, xi: &[f64]) {
    let mode = |x: f64, rate: f64, mass: f64, z: f64| {
        let decay = (-rate * h).exp();
        let var = -(b.kt / mass) * (-2.0 * rate * h).exp_m1();
        decay * x + var.sqrt() * z
    };
    v[0] = mode(v[0], b.gt, 1.0, xi[0]);
    v[1] = mode(v[1], b.gt, 1.0, xi[1]);
    v[2] = mode(v[2], b.gt, 1.0, xi[5]);
    let ([kn, eh, fh], _) = modes_basis(k);
    let mut wn = *w;
    for (j, (dir, mass)) in [(kn, body.ic), (eh, body.ia), (fh, body.ia)]
        .into_iter()
        .enumerate()
    {
        let x = dot(wn, dir);
        let dx = mode(x, b.gr, mass, xi[2 + j]) - x;
        wn = add(wn, scale(dx, dir));
    }
    *w = wn;
}
