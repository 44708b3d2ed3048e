//! Orientation wells, the scenario's `[[well]]` entries: the data and its
//! validation (the physics is `physics::forces::wells`, docs/physics.md#wells).

use crate::Error;

/// Valid range of `well.K.theta`.
pub const THETA_RANGE: &str = "0 <= theta <= pi [rad], the centre of the well";
/// Valid range of `well.K.depth`.
pub const DEPTH_RANGE: &str = "a finite energy, 0 < depth <= 1e300 [J]";
/// Valid range of `well.K.width`.
pub const WIDTH_RANGE: &str =
    "a finite angle, 0 < width <= pi [rad] (the Gaussian's standard deviation)";
/// Wells overlap when their centres are closer than this many times the sum
/// of their widths (then neither is a separate well: at `3 (w_i + w_j)` each
/// Gaussian is below `exp(−4.5) = 1.1 %` of its depth at the other's centre,
/// for equal widths).
pub const OVERLAP_WIDTHS: f64 = 3.0;

/// One Gaussian well in θ (SI, or scaled when latched:
/// `physics::forces::Forces::wells`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Well {
    /// Centre θ_i \[rad\].
    pub theta: f64,
    /// Depth d_i \[J\] (`U(θ_i) ≈ −d_i`).
    pub depth: f64,
    /// Width w_i \[rad\].
    pub width: f64,
}

/// Check a list of wells: each key finite and in range, and no two wells
/// overlapping (centres closer than [`OVERLAP_WIDTHS`] times the sum of
/// the widths; the later well's `theta` is named). The error names the key
/// (`well.0.width`).
pub fn validate(wells: &[Well]) -> Result<(), Error> {
    for (k, w) in wells.iter().enumerate() {
        let checks = [
            (
                "theta",
                w.theta,
                THETA_RANGE,
                (0.0..=std::f64::consts::PI).contains(&w.theta),
            ),
            (
                "depth",
                w.depth,
                DEPTH_RANGE,
                w.depth > 0.0 && w.depth <= 1e300,
            ),
            (
                "width",
                w.width,
                WIDTH_RANGE,
                w.width > 0.0 && w.width <= std::f64::consts::PI,
            ),
        ];
        for (key, v, range, ok) in checks {
            if !ok || !v.is_finite() {
                return Err(Error::invalid(
                    &format!("well.{k}.{key}"),
                    format!("{v} is not allowed"),
                    range.into(),
                ));
            }
        }
    }
    for (j, b) in wells.iter().enumerate() {
        for (i, a) in wells.iter().enumerate().take(j) {
            let min = OVERLAP_WIDTHS * (a.width + b.width);
            if (a.theta - b.theta).abs() < min {
                return Err(Error::invalid(
                    &format!("well.{j}.theta"),
                    format!(
                        "{} overlaps well {i} (theta = {}): centres {} rad apart",
                        b.theta,
                        a.theta,
                        (a.theta - b.theta).abs()
                    ),
                    format!(
                        "centres at least 3 (width_{i} + width_{j}) = {min} rad apart (wells must not overlap)"
                    ),
                ));
            }
        }
    }
    Ok(())
}
