//! The scene of the animation: the top's geometry in the lab frame, the
//! camera, and the colour of a point of the sphere (the same rules as the
//! viewer's JavaScript, `viewer.html`).
//!
//! Geometry (docs/physics.md#geometry, §position): `O` the centre of mass (`x, y, z`),
//! `k = q e3 q*` the symmetry axis, the sphere's centre `C = O + a k`, its
//! radius `R`; the contact point below `C`.
//!
//! Camera: orthographic, looking from azimuth [`CAMERA_AZIMUTH`] (from the
//! lab `X` axis, counter-clockwise seen from above) and elevation
//! [`CAMERA_ELEVATION`] above the floor, at the point `(C_x, C_y, R)`
//! (it follows the top across the floor), `R` drawn as [`RADIUS_FRACTION`]
//! of the smaller image side. Light: a distant lamp up and to the left of
//! the camera; Lambert shading (ambient 0.3, diffuse 0.7) and a small
//! specular highlight.

/// A vector in the lab frame.
pub type V3 = [f64; 3];

/// Camera azimuth \[rad\]: the camera lies towards
/// `(cos az, sin az, ·)` from the point it looks at.
pub const CAMERA_AZIMUTH: f64 = -65.0 * std::f64::consts::PI / 180.0;
/// Camera elevation above the floor \[rad\].
pub const CAMERA_ELEVATION: f64 = 25.0 * std::f64::consts::PI / 180.0;
/// The sphere's radius on screen as a fraction of the smaller image side.
pub const RADIUS_FRACTION: f64 = 0.2;
/// Half-width of the painted meridian band \[rad of body azimuth\].
pub const BAND_HALF_WIDTH: f64 = 0.28;
/// The cap around `+k` is painted where `b·e3 >` this (body frame).
pub const CAP_COS: f64 = 0.88;

/// `a · b`.
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// `a × b`.
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// `a + s b`.
pub fn axpy(a: V3, s: f64, b: V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}
/// `v / |v|`.
pub fn unit(v: V3) -> V3 {
    let n = dot(v, v).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// The rotation matrix (rows) of the unit quaternion `q = (w, x, y, z)`,
/// body → lab: `v_lab = M v_body`.
pub fn rotation(q: [f64; 4]) -> [V3; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// The body's pose at one frame.
#[derive(Debug, Clone, Copy)]
pub struct Pose {
    /// Rotation body → lab (rows).
    pub m: [V3; 3],
    /// Symmetry axis `k` (unit, lab).
    pub k: V3,
    /// Centre of mass `O` \[m\].
    pub com: V3,
    /// Sphere's centre `C = O + a k` \[m\].
    pub centre: V3,
}

impl Pose {
    /// The pose of centre of mass `com` \[m\], attitude `q`, offset `a` \[m\].
    pub fn new(com: V3, q: [f64; 4], a: f64) -> Pose {
        let m = rotation(q);
        let k = [m[0][2], m[1][2], m[2][2]];
        Pose {
            m,
            k,
            com,
            centre: axpy(com, a, k),
        }
    }
    /// The body-frame components of the lab vector `v` (`Mᵀ v`).
    pub fn to_body(&self, v: V3) -> V3 {
        let m = &self.m;
        [
            m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
            m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
            m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
        ]
    }
}

/// An orthographic camera.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    /// Unit vector from the target towards the camera.
    pub d: V3,
    /// Screen right (unit, lab).
    pub r: V3,
    /// Screen up (unit, lab).
    pub u: V3,
    /// The lab point drawn at `(cx, cy)` \[m\].
    pub target: V3,
    /// Pixels per metre.
    pub scale: f64,
    /// Screen position of the target \[px\].
    pub cx: f64,
    /// Screen position of the target \[px\] (y down).
    pub cy: f64,
}

impl Camera {
    /// A camera at azimuth `az` and elevation `el` \[rad\] looking at
    /// `target`, `scale` px/m, the target drawn at `(cx, cy)` px.
    pub fn new(az: f64, el: f64, target: V3, scale: f64, cx: f64, cy: f64) -> Camera {
        let d = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
        let r = unit(cross([-d[0], -d[1], -d[2]], [0.0, 0.0, 1.0]));
        let u = cross(r, [-d[0], -d[1], -d[2]]);
        Camera {
            d,
            r,
            u,
            target,
            scale,
            cx,
            cy,
        }
    }

    /// The default camera of a `width × height` image for a top of radius
    /// `radius` \[m\] with its centre at `centre`.
    pub fn standard(width: u32, height: u32, radius: f64, centre: V3) -> Camera {
        let side = width.min(height) as f64;
        Camera::new(
            CAMERA_AZIMUTH,
            CAMERA_ELEVATION,
            [centre[0], centre[1], radius],
            RADIUS_FRACTION * side / radius,
            0.5 * width as f64,
            0.56 * height as f64,
        )
    }

    /// Screen position \[px\] and depth (towards the camera \[m\]) of `p`.
    pub fn project(&self, p: V3) -> (f64, f64, f64) {
        let w = axpy(p, -1.0, self.target);
        (
            self.cx + self.scale * dot(w, self.r),
            self.cy - self.scale * dot(w, self.u),
            dot(w, self.d),
        )
    }

    /// The lab point on the screen plane through the target at pixel
    /// `(px, py)`.
    pub fn unproject(&self, px: f64, py: f64) -> V3 {
        let a = (px - self.cx) / self.scale;
        let b = -(py - self.cy) / self.scale;
        axpy(axpy(self.target, a, self.r), b, self.u)
    }

    /// The direction of the light (unit, lab): up and left of the camera.
    pub fn light(&self) -> V3 {
        unit(axpy(
            axpy([0.0; 3], -0.45, self.r),
            1.0,
            axpy(axpy([0.0; 3], 0.75, self.u), 0.8, self.d),
        ))
    }

    /// Whether the point `p` is hidden by the sphere of centre `c`, radius
    /// `radius` (behind its front surface, seen from the camera).
    pub fn hidden_by_sphere(&self, p: V3, c: V3, radius: f64) -> bool {
        let w = axpy(p, -1.0, c);
        let along = dot(w, self.d);
        let perp2 = dot(w, w) - along * along;
        if perp2 >= radius * radius {
            return false;
        }
        along < (radius * radius - perp2).sqrt() - 1e-9 * radius
    }
}

/// Measure of `[-h, h]` (repeated every 2π) within `(-∞, x]`, up to a
/// constant: the antiderivative of the band's indicator.
fn band_measure(x: f64, h: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let y = x + std::f64::consts::PI;
    let periods = (y / tau).floor();
    let rest = y - periods * tau - std::f64::consts::PI;
    periods * 2.0 * h + (rest + h).clamp(0.0, 2.0 * h)
}

/// Fraction of the time the band of half-width `h` \[rad\] covers the body
/// azimuth `alpha` \[rad\] while the body turns through `sweep` \[rad\]
/// about its axis (centred on the frame's time): 0 or 1 for no sweep,
/// `h/π` once `sweep` is a whole turn.
pub fn band_coverage(alpha: f64, h: f64, sweep: f64) -> f64 {
    if sweep < 1e-9 {
        let a =
            (alpha + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        return if a.abs() < h { 1.0 } else { 0.0 };
    }
    ((band_measure(alpha + 0.5 * sweep, h) - band_measure(alpha - 0.5 * sweep, h)) / sweep)
        .clamp(0.0, 1.0)
}

/// Base colour of the sphere.
pub const BODY: V3 = [0.84, 0.27, 0.25];
/// Colour of the meridian band.
pub const BAND: V3 = [0.98, 0.84, 0.27];
/// Colour of the cap around `+k`.
pub const CAP: V3 = [0.95, 0.95, 0.92];
/// Colour of the equator line.
pub const EQUATOR: V3 = [0.25, 0.12, 0.12];

/// The colour (RGB in \[0, 1\]) of the sphere's surface point with lab
/// normal `n` (unit), body-frame normal `b`, lit from `light`, seen along
/// `view` (unit, towards the camera), the band smeared over `sweep` \[rad\].
pub fn surface_colour(n: V3, b: V3, light: V3, view: V3, sweep: f64) -> V3 {
    let alpha = b[1].atan2(b[0]);
    // Smallest smear: about a pixel's worth, so the band's edges are smooth.
    let cov = band_coverage(alpha, BAND_HALF_WIDTH, sweep.max(0.03));
    let mut c: V3 = std::array::from_fn(|i| BODY[i] + cov * (BAND[i] - BODY[i]));
    if b[2] > CAP_COS {
        c = CAP;
    }
    let eq = (1.0 - b[2].abs() / 0.035).clamp(0.0, 1.0);
    c = std::array::from_fn(|i| c[i] + eq * (EQUATOR[i] - c[i]));
    let diffuse = dot(n, light).max(0.0);
    let half = unit(axpy(light, 1.0, view));
    let spec = 0.35 * dot(n, half).max(0.0).powi(40);
    std::array::from_fn(|i| (c[i] * (0.3 + 0.7 * diffuse) + spec).min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn rotation_of_the_initial_attitude() {
        let th: f64 = 0.3;
        let p = Pose::new(
            [0.0, 0.0, 1.0],
            [(th / 2.0).cos(), 0.0, (th / 2.0).sin(), 0.0],
            0.1,
        );
        assert!((p.k[0] - th.sin()).abs() < 1e-15 && (p.k[2] - th.cos()).abs() < 1e-15);
        let b = p.to_body(p.k);
        assert!((b[2] - 1.0).abs() < 1e-15);
        assert!((p.centre[2] - (1.0 + 0.1 * th.cos())).abs() < 1e-15);
    }

    #[test]
    fn camera_basis_and_projection() {
        let c = Camera::new(-FRAC_PI_2, 0.0, [0.0; 3], 10.0, 50.0, 50.0);
        // Looking along +Y from -Y: right is +X, up is +Z.
        assert!((c.r[0] - 1.0).abs() < 1e-12 && (c.u[2] - 1.0).abs() < 1e-12);
        let (x, y, _) = c.project([1.0, 0.0, 2.0]);
        assert!((x - 60.0).abs() < 1e-9 && (y - 30.0).abs() < 1e-9);
        let q = c.unproject(60.0, 30.0);
        assert!((q[0] - 1.0).abs() < 1e-12 && (q[2] - 2.0).abs() < 1e-12);
        // The far side of a sphere is hidden, the near side is not.
        assert!(c.hidden_by_sphere([0.0, 0.9, 0.0], [0.0; 3], 1.0));
        assert!(!c.hidden_by_sphere([0.0, -1.0, 0.0], [0.0; 3], 1.0));
        assert!(!c.hidden_by_sphere([1.5, 0.0, 0.0], [0.0; 3], 1.0));
    }

    #[test]
    fn band_coverage_limits() {
        let h = 0.3;
        assert_eq!(band_coverage(0.0, h, 0.0), 1.0);
        assert_eq!(band_coverage(1.0, h, 0.0), 0.0);
        assert_eq!(band_coverage(2.0 * PI + 0.1, h, 0.0), 1.0);
        for sweep in [2.0 * PI, 4.0 * PI, 20.0 * PI] {
            for a in [-3.0, 0.0, 1.0, 2.5] {
                assert!((band_coverage(a, h, sweep) - h / PI).abs() < 1e-12);
            }
        }
        // Half in: the edge at h, a small sweep centred on it.
        assert!((band_coverage(h, h, 0.1) - 0.5).abs() < 1e-12);
    }
}
