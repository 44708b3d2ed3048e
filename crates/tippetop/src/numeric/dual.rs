//! Forward-mode automatic differentiation: dual numbers `v + d ε` (ε² = 0)
//! and a [`Num`] trait that `f64` and [`Dual`] implement, so one generic
//! right-hand side gives both values and exact directional derivatives
//! (a Jacobian column per seeded component, [`seeded`]).
//!
//! Written here rather than taken from a crate: it is 120 lines, needs only
//! `+ − × ÷ √`, and keeps the linearisation free of a dependency's generic
//! numeric tower; the stability tests check the Jacobians it gives against
//! closed-form characteristic polynomials.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A number type the generic right-hand side computes with: `f64` for values,
/// [`Dual`] for values and one directional derivative.
pub trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `x`.
    fn k(x: f64) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
}

impl Num for f64 {
    fn k(x: f64) -> Self {
        x
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// Dual number `v + d ε`, ε² = 0.
#[derive(Debug, Clone, Copy)]
pub struct Dual {
    /// Value.
    pub v: f64,
    /// Derivative (the ε part).
    pub d: f64,
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual {
            v: self.v / o.v,
            d: (self.d * o.v - self.v * o.d) / (o.v * o.v),
        }
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: -self.d,
        }
    }
}
impl Num for Dual {
    fn k(x: f64) -> Self {
        Dual { v: x, d: 0.0 }
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        Dual {
            v: s,
            d: self.d / (2.0 * s),
        }
    }
}

/// Cross product.
pub fn cross<S: Num>(a: [S; 3], b: [S; 3]) -> [S; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// Dot product.
pub fn dot<S: Num>(a: [S; 3], b: [S; 3]) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// An `f64` vector as constants of `S`.
pub fn lift<S: Num>(a: [f64; 3]) -> [S; 3] {
    [S::k(a[0]), S::k(a[1]), S::k(a[2])]
}

/// The point `x` as duals seeded in direction `j`: `d = 1` in component `j`,
/// 0 elsewhere; the `d` parts of `f(seeded(x, j))` are column `j` of the
/// Jacobian of `f` at `x`.
pub fn seeded<const N: usize>(x: &[f64; N], j: usize) -> [Dual; N] {
    std::array::from_fn(|i| Dual {
        v: x[i],
        d: if i == j { 1.0 } else { 0.0 },
    })
}
