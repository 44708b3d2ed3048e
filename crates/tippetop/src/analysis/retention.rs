//! Retention: how long a state holds at a target temperature, from escape
//! rates measured at raised temperatures (or lowered barriers), where the
//! escape is fast enough to simulate, extrapolated by the Arrhenius law
//! (docs/physics.md#retention).
//!
//! Escape over a barrier of many kT, after the top has settled in its
//! well, is a Poisson process (Kramers): its rate `k` is measured by an
//! ensemble with a first-passage criterion
//! ([`crate::analysis::ensemble::escape_rate`]: `passages / exposure`, the
//! standard error of `ln k` is `1/sqrt(passages)`). Kramers' rate is
//! `k = ν e^{−E/kT}` with a prefactor `ν` that depends on the damping and
//! the well's and barrier's curvatures, and only weakly (a power) on T;
//! the Arrhenius fit `ln k = ln ν − E/(k_B T)` treats `ν` as constant, so
//! the fitted `E` is the barrier up to that power (a few kT at the
//! measured temperatures), and the extrapolation's error bar covers the
//! statistics, not that model error: measure at temperatures close to the
//! target and check that the fitted barrier matches the potential's.

use serde::Serialize;

use crate::Error;
use crate::error::num;
use crate::input::thermal::BOLTZMANN;

/// One measured escape rate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RatePoint {
    /// Temperature \[K\].
    pub temperature: f64,
    /// Escape rate \[1/s\].
    pub rate: f64,
    /// Standard error of `ln rate`.
    pub ln_rate_se: f64,
}

/// The weighted least-squares fit of `ln k = ln ν − E/(k_B T)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArrheniusFit {
    /// `ln ν` (ν in 1/s).
    pub ln_prefactor: f64,
    /// The barrier `E` \[J\].
    pub barrier: f64,
    /// The barrier in eV.
    pub barrier_ev: f64,
    /// Standard error of `E` \[J\].
    pub barrier_se: f64,
    /// Covariance of `(ln ν, −E)` (the intercept and slope in `1/(k_B T)`
    /// \[1/J\]), scaled by the Birge ratio `chi2/dof` when that exceeds 1.
    pub covariance: [[f64; 2]; 2],
    /// Weighted sum of squared residuals.
    pub chi2: f64,
    /// Degrees of freedom (points − 2).
    pub dof: usize,
    /// The points fitted.
    pub points: Vec<RatePoint>,
}

/// The fit's prediction at one temperature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extrapolation {
    /// Temperature \[K\].
    pub temperature: f64,
    /// Predicted escape rate \[1/s\] (`0` where it underflows f64: see
    /// [`Extrapolation::ln_rate`]).
    pub rate: f64,
    /// `ln` of the predicted rate in 1/s: finite where `rate` and
    /// `mean_time` are not (far extrapolations).
    pub ln_rate: f64,
    /// Its 95 % interval (normal on `ln k`) \[1/s\].
    pub rate_ci95: [f64; 2],
    /// Standard error of `ln k`.
    pub ln_rate_se: f64,
    /// Mean retention time `1/k` \[s\].
    pub mean_time: f64,
    /// Its 95 % interval \[s\].
    pub time_ci95: [f64; 2],
}

/// Smallest temperature of a fitted point or of the target \[K\].
pub const MIN_TEMPERATURE: f64 = 1e-3;
/// Largest temperature of a fitted point or of the target \[K\] (as
/// `tippetop regime`'s).
pub const MAX_TEMPERATURE: f64 = 1e5;
/// Smallest escape rate of a fitted point \[1/s\].
pub const MIN_RATE: f64 = 1e-300;
/// Largest escape rate of a fitted point \[1/s\].
pub const MAX_RATE: f64 = 1e300;

/// Valid range of a temperature (of a point or of the target).
pub const TEMPERATURE_RANGE: &str = "1e-3 <= temperature <= 1e5 [K]";
/// Valid range of a point's escape rate.
pub const RATE_RANGE: &str = "1e-300 <= rate <= 1e300 [1/s]";
/// Valid range of a point's standard error of `ln rate` (`1/sqrt(passages)`
/// with at least one passage).
pub const SE_RANGE: &str = "0 < ln_rate_se <= 1 (1/sqrt(passages))";

/// Check a temperature \[K\] against [`TEMPERATURE_RANGE`] (error key `key`).
pub fn check_temperature(key: &str, t: f64) -> Result<(), Error> {
    if (MIN_TEMPERATURE..=MAX_TEMPERATURE).contains(&t) {
        Ok(())
    } else {
        Err(Error::invalid(
            key,
            format!("{} K is out of range", num(t)),
            TEMPERATURE_RANGE.into(),
        ))
    }
}

impl RatePoint {
    /// Check the point's values against [`TEMPERATURE_RANGE`],
    /// [`RATE_RANGE`] and [`SE_RANGE`]; the error's key is the field
    /// (`temperature`, `rate`, `ln_rate_se`).
    pub fn check(&self) -> Result<(), Error> {
        check_temperature("temperature", self.temperature)?;
        if !(MIN_RATE..=MAX_RATE).contains(&self.rate) {
            return Err(Error::invalid(
                "rate",
                format!("{} 1/s is out of range", num(self.rate)),
                RATE_RANGE.into(),
            ));
        }
        if !(self.ln_rate_se > 0.0 && self.ln_rate_se <= 1.0) {
            return Err(Error::invalid(
                "ln_rate_se",
                format!("{} is out of range", num(self.ln_rate_se)),
                SE_RANGE.into(),
            ));
        }
        Ok(())
    }
}

/// Fit the Arrhenius law to `points` (weights `1/se²` on `ln k`). Needs at
/// least two distinct temperatures and every point within its ranges
/// ([`RatePoint::check`]); error key `points` (the message names the
/// point, 0-based, and its field). An error too if the fit is not finite
/// (temperatures too close to tell a slope).
pub fn fit_arrhenius(points: &[RatePoint]) -> Result<ArrheniusFit, Error> {
    let bad = |what: String| {
        Error::invalid(
            "points",
            what,
            "escape rates at two or more distinct temperatures".into(),
        )
    };
    for (i, p) in points.iter().enumerate() {
        if let Err(Error::Invalid { key, what, range }) = p.check() {
            return Err(Error::invalid(
                "points",
                format!("point {i}: {key}: {what}"),
                range,
            ));
        }
    }
    let (mut s, mut sx, mut sxx, mut sy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in points {
        let w = 1.0 / (p.ln_rate_se * p.ln_rate_se);
        let x = 1.0 / (BOLTZMANN * p.temperature);
        let y = p.rate.ln();
        s += w;
        sx += w * x;
        sxx += w * x * x;
        sy += w * y;
        sxy += w * x * y;
    }
    let delta = s * sxx - sx * sx;
    let distinct = points
        .iter()
        .any(|p| p.temperature != points[0].temperature);
    if points.len() < 2 || !distinct || delta.is_nan() || delta <= 0.0 {
        return Err(bad(format!(
            "{} rates at {} distinct temperatures",
            points.len(),
            if distinct { "two or more" } else { "one" }
        )));
    }
    let slope = (s * sxy - sx * sy) / delta;
    let intercept = (sxx * sy - sx * sxy) / delta;
    let chi2: f64 = points
        .iter()
        .map(|p| {
            let x = 1.0 / (BOLTZMANN * p.temperature);
            let r = p.rate.ln() - intercept - slope * x;
            r * r / (p.ln_rate_se * p.ln_rate_se)
        })
        .sum();
    let dof = points.len() - 2;
    let birge = if dof > 0 {
        (chi2 / dof as f64).max(1.0)
    } else {
        1.0
    };
    let covariance = [
        [birge * sxx / delta, -birge * sx / delta],
        [-birge * sx / delta, birge * s / delta],
    ];
    let barrier = -slope;
    if !(slope.is_finite()
        && intercept.is_finite()
        && covariance.iter().flatten().all(|c| c.is_finite()))
    {
        return Err(bad(format!(
            "the fit is not finite (ln k = {} - {} / (k_B T)): temperatures too close together",
            num(intercept),
            num(barrier)
        )));
    }
    Ok(ArrheniusFit {
        ln_prefactor: intercept,
        barrier,
        barrier_ev: barrier / 1.602176634e-19,
        barrier_se: covariance[1][1].sqrt(),
        covariance,
        chi2,
        dof,
        points: points.to_vec(),
    })
}

impl ArrheniusFit {
    /// [`ArrheniusFit::extrapolate`], checked: `temperature` within
    /// [`TEMPERATURE_RANGE`] and the rate, the time and their intervals
    /// finite and non-zero in `f64` (error key `key`, the target's name).
    pub fn extrapolate_checked(&self, key: &str, temperature: f64) -> Result<Extrapolation, Error> {
        check_temperature(key, temperature)?;
        let at = self.extrapolate(temperature);
        let fine = |x: f64| x.is_finite() && x > 0.0;
        if !([at.rate, at.mean_time]
            .into_iter()
            .chain(at.rate_ci95)
            .chain(at.time_ci95))
        .all(fine)
        {
            let ln_k = self.ln_prefactor - self.barrier / (BOLTZMANN * temperature);
            return Err(Error::invalid(
                key,
                format!(
                    "at {} K the extrapolated rate exp({:.4e}) 1/s (95 % CI a factor exp(+-{:.4e}) either way) is beyond f64",
                    num(temperature),
                    ln_k,
                    1.96 * at.ln_rate_se
                ),
                "a target temperature nearer the measured ones".into(),
            ));
        }
        Ok(at)
    }

    /// The predicted rate and retention time at `temperature` \[K\], with
    /// the fit's statistical 95 % interval (unchecked: see
    /// [`ArrheniusFit::extrapolate_checked`]).
    pub fn extrapolate(&self, temperature: f64) -> Extrapolation {
        let x = 1.0 / (BOLTZMANN * temperature);
        let y = self.ln_prefactor - self.barrier * x;
        let c = &self.covariance;
        let var = c[0][0] + 2.0 * x * c[0][1] + x * x * c[1][1];
        let se = var.max(0.0).sqrt();
        let rate = y.exp();
        let lo = (y - 1.96 * se).exp();
        let hi = (y + 1.96 * se).exp();
        Extrapolation {
            temperature,
            rate,
            ln_rate: y,
            rate_ci95: [lo, hi],
            ln_rate_se: se,
            mean_time: 1.0 / rate,
            time_ci95: [1.0 / hi, 1.0 / lo],
        }
    }
}
