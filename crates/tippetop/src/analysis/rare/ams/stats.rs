//! Intervals over independent replicas: Student's t quantile, the t
//! interval of a mean, Cox's interval of a log-normal mean, and the delta
//! method over replica means.

/// The 97.5 % quantile of Student's t with `nu >= 1` degrees of freedom
/// (the half-width factor of a two-sided 95 % interval): the root of
/// `P(|T| < t) = 0.95`, with `P(|T| < t)` in closed form for integer `nu`
/// (Abramowitz & Stegun 26.7.3–4), by bisection to 1e-13; above 2000
/// degrees of freedom the Cornish–Fisher expansion (error < 1e-12 there).
pub fn t975(nu: u64) -> f64 {
    assert!(nu >= 1, "Student's t needs at least one degree of freedom");
    if nu > 2000 {
        let z = 1.959_963_984_540_054_f64;
        let n = nu as f64;
        let (z3, z5, z7, z9) = (z.powi(3), z.powi(5), z.powi(7), z.powi(9));
        return z
            + (z3 + z) / (4.0 * n)
            + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * n * n)
            + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * n.powi(3))
            + (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z)
                / (92160.0 * n.powi(4));
    }
    let (mut lo, mut hi) = (0.0_f64, 20.0_f64);
    while hi - lo > 1e-13 {
        let mid = 0.5 * (lo + hi);
        if t_central(mid, nu) < 0.95 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// `P(|T| < t)` for Student's t with `nu` degrees of freedom (A & S
/// 26.7.3 for odd `nu`, 26.7.4 for even), `θ = atan(t/sqrt(nu))`.
fn t_central(t: f64, nu: u64) -> f64 {
    let th = (t / (nu as f64).sqrt()).atan();
    let (s, c) = th.sin_cos();
    let c2 = c * c;
    if nu % 2 == 1 {
        // (2/π)[θ + sin θ (cos θ + 2/3 cos³θ + ... + (2·4···(ν−3))/(1·3···(ν−2)) cos^{ν−2}θ)]
        let mut sum = 0.0;
        if nu > 1 {
            let mut term = c;
            sum = term;
            let mut j = 1;
            while 2 * j < nu - 1 {
                term *= c2 * (2 * j) as f64 / (2 * j + 1) as f64;
                sum += term;
                j += 1;
            }
        }
        2.0 / std::f64::consts::PI * (th + s * sum)
    } else {
        // sin θ [1 + 1/2 cos²θ + (1·3)/(2·4) cos⁴θ + ... + (1·3···(ν−3))/(2·4···(ν−2)) cos^{ν−2}θ]
        let mut term = 1.0;
        let mut sum = 1.0;
        let mut j = 1;
        while 2 * j < nu {
            term *= c2 * (2 * j - 1) as f64 / (2 * j) as f64;
            sum += term;
            j += 1;
        }
        s * sum
    }
}

/// Mean and sample standard deviation (`n − 1`), summed in the order
/// given (`None` for fewer than two values).
pub(super) fn mean_sd(x: &[f64]) -> Option<(f64, f64)> {
    let n = x.len();
    if n < 2 {
        return None;
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    Some((mean, var.sqrt()))
}

/// Cox's 95 % interval for the mean of a log-normal law from a sample
/// (all > 0): with `m`, `s²` the mean and variance of the logs, the mean is
/// `exp(m + s²/2)` and the interval
/// `exp(m + s²/2 ± t sqrt(s²/n + s⁴/(2(n − 1))))` (Land 1972; Olsson,
/// J. Stat. Educ. 13 (2005), "modified Cox", with Student's t). Returns the
/// mean estimate and the interval; `None` for fewer than two values or a
/// value <= 0.
pub(super) fn lognormal_mean_ci(x: &[f64]) -> Option<(f64, [f64; 2])> {
    if x.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return None;
    }
    let logs: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let (m, s) = mean_sd(&logs)?;
    let n = x.len() as f64;
    let s2 = s * s;
    let centre = m + 0.5 * s2;
    let half = t975(x.len() as u64 - 1) * (s2 / n + s2 * s2 / (2.0 * (n - 1.0))).sqrt();
    Some((centre.exp(), [(centre - half).exp(), (centre + half).exp()]))
}

/// The variance of a smooth function of replica means by the delta
/// method: `gradᵀ S grad / n`, with `S` the sample covariance (`n − 1`) of
/// the rows `x` (one per replica) and `grad` the function's gradient at the
/// means.
pub(super) fn delta_variance(x: &[Vec<f64>], grad: &[f64]) -> f64 {
    let n = x.len();
    let d = grad.len();
    let mean: Vec<f64> = (0..d)
        .map(|j| x.iter().map(|r| r[j]).sum::<f64>() / n as f64)
        .collect();
    // gᵀ S g = Σ_r (g·(x_r − mean))² / (n − 1)
    let ss: f64 = x
        .iter()
        .map(|r| {
            (0..d)
                .map(|j| grad[j] * (r[j] - mean[j]))
                .sum::<f64>()
                .powi(2)
        })
        .sum();
    ss / (n - 1) as f64 / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Published quantiles (NIST/SEMATECH e-Handbook, table of the t
    /// distribution's upper critical values, 0.025 column; 3 decimals).
    #[test]
    fn t975_matches_the_table() {
        let table = [
            (1, 12.706),
            (2, 4.303),
            (3, 3.182),
            (4, 2.776),
            (5, 2.571),
            (9, 2.262),
            (10, 2.228),
            (19, 2.093),
            (20, 2.086),
            (29, 2.045),
            (30, 2.042),
            (40, 2.021),
            (60, 2.000),
            (100, 1.984),
        ];
        for (nu, want) in table {
            let t = t975(nu);
            assert!((t - want).abs() < 6e-4, "t975({nu}) = {t}, table {want}");
        }
        // Both sides of the switch to the expansion agree.
        assert!((t975(2000) - t975(2001)).abs() < 1e-6);
        assert!((t975(1_000_000) - 1.959_966).abs() < 1e-5);
    }

    /// The closed forms for ν = 1 and 2: `t = tan(0.475 π)` and
    /// `t = sqrt(2) · 0.95/sqrt(1 − 0.95²)`.
    #[test]
    fn t975_closed_forms() {
        let t1 = (0.475 * std::f64::consts::PI).tan();
        assert!((t975(1) - t1).abs() < 1e-9 * t1);
        let t2 = 2f64.sqrt() * 0.95 / (1.0 - 0.95f64 * 0.95).sqrt();
        assert!((t975(2) - t2).abs() < 1e-9 * t2);
    }

    /// The delta method's variance of a linear function is the variance
    /// of that combination of the means, exactly.
    #[test]
    fn delta_variance_of_a_linear_function() {
        let x: Vec<Vec<f64>> = vec![
            vec![1.0, 2.0],
            vec![2.0, 1.0],
            vec![4.0, 0.0],
            vec![3.0, 5.0],
        ];
        let g = [2.0, -1.0];
        let y: Vec<f64> = x.iter().map(|r| 2.0 * r[0] - r[1]).collect();
        let (_, sd) = mean_sd(&y).unwrap();
        let want = sd * sd / 4.0;
        assert!((delta_variance(&x, &g) - want).abs() < 1e-12 * want);
    }
}
