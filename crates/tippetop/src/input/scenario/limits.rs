//! Limits of one run, checked before it starts ([`check_run`], called by
//! [`Scenario::validate`]): what the solver needs to be representable in
//! `f64` (finite units, finite scaled times, finite initial energy), how long
//! a run may be in its own time unit, how many samples it may keep, and the
//! caps that bound a run that cannot make progress (steps, recorded events).
//!
//! Every value a scenario can hold passes through the scaled model of
//! docs/physics.md: lengths by `R`, masses by `m`, times by `T_ref`, the
//! inverse of the fastest initial rate ([`time_unit`]). A scenario whose
//! units or scaled values overflow or underflow is bad input (exit code 2),
//! not a run that fails.
//!
//! Files a user hands in (scenario files, an ensemble's `summary.json` for
//! `tippetop retention`, a shard's `shard.json`) are read with
//! [`read_file`], at most [`MAX_FILE_BYTES`].

use std::io::Read as _;
use std::path::Path;

use crate::error::num;
use crate::{Error, Scenario, SolverSettings, observe};

/// Largest file a command reads as input text \[bytes\]: 16 MiB (a scenario
/// file is a few kB; a `summary.json` a few kB plus its events, at most
/// 100 000 of them: ~5 MB).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The text of the input file `path`, read up to [`MAX_FILE_BYTES`] + 1
/// bytes (so a pipe or a device such as `/dev/zero` is caught too, without
/// reading it to the end). Errors ([`Error::Invalid`] with the path as the
/// key): unreadable, larger than the limit, not UTF-8.
pub fn read_file(path: &Path) -> Result<String, Error> {
    let key = path.display().to_string();
    let bad = |what: String, range: &str| Error::invalid(&key, what, range.into());
    let unreadable = |e: std::io::Error| bad(format!("cannot read it: {e}"), "a readable file");
    let file = std::fs::File::open(path).map_err(unreadable)?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(unreadable)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(bad(
            "larger than the 16 MiB limit of input files".into(),
            "at most 16777216 bytes",
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        bad(
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
            "a UTF-8 text file",
        )
    })
}

/// The bounds of the solver settings live with them (`state`).
pub use crate::input::solver::{
    BYTES_PER_SAMPLE, MAX_SAMPLES, MAX_STEPS, STEP_LIMIT_MAX, max_steps_for,
};

/// Largest `t_end / T_ref`, the run's length in its own time unit `T_ref`
/// (the inverse of the fastest initial rate: spin, precession, nutation
/// rate, `sqrt(g/R)`, `sqrt(|(H, h_z)|/(m R))`).
///
/// Why 1e9: near `t = 1e9 T_ref` consecutive `f64` times are `1.2e-7 T_ref`
/// apart, so the phase of the fastest motion can no longer be resolved to
/// the tolerances the solver offers (`rtol >= 1e-14`); and the fastest motion
/// turns `1e9 / (2 pi) = 1.6e8` times, which at several steps per turn is
/// beyond the largest step limit [`STEP_LIMIT_MAX`] anyway.
pub const MAX_SCALED_T_END: f64 = 1e9;

/// Largest number of events a run records (`Trajectory::events`); further
/// events still enter the summary (first times, the fraction of the time
/// with N < 0) but are not listed, and a single `"event_limit_reached"`
/// record marks where the list stops. A run
/// whose motion chatters can cross `N = 0` millions of times; the list
/// would otherwise grow with the steps taken, not with the samples kept.
pub const MAX_EVENTS: usize = 100_000;

/// Largest memory one run may need for the rows and events it keeps
/// \[bytes\]: 1.5 GiB (the largest run, [`crate::input::solver::MAX_SAMPLES`] rows of
/// [`BYTES_PER_SAMPLE`] = 224 bytes, needs 1.12 GB). [`run_memory_bytes`]
/// of a valid scenario stays below it.
pub const MAX_RUN_BYTES: u64 = 3 << 29;

/// The memory bound of one command \[bytes\]: 3 GiB for the runs it keeps at
/// once and the results it gathers (rows, histograms, arrays). Every
/// documented limit stays within it: a single run at [`MAX_SAMPLES`] needs
/// 1.12 GB; a command that runs several runs at once runs no more of them
/// than fit ([`fit_threads`]); what grows with the number of runs or cases
/// has a limit of its own. The whole process adds its code, the plots and
/// the allocator's slack: the peaks measured at the limits (docs/guide.md,
/// "Limits") stay below 4 GB.
pub const MEMORY_BUDGET: u64 = 3 << 30;

/// A memory size for a message (`1.12 GB`, `162 MB`).
pub fn fmt_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.3} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.3} MB", b / 1e6)
    } else {
        format!("{:.3} kB", b / 1e3)
    }
}

/// How many jobs a command may run at once within [`MEMORY_BUDGET`]: at
/// most `threads`, each keeping `per_job` bytes while it runs, beside the
/// `fixed` bytes the command keeps anyway (its histograms, the rows that
/// wait to be written in order). Err (key `key`, the setting to lower) if
/// not even one job fits.
pub fn fit_threads(key: &str, threads: usize, per_job: u64, fixed: u64) -> Result<usize, Error> {
    let need = fixed.saturating_add(per_job);
    if need > MEMORY_BUDGET {
        return Err(Error::invalid(
            key,
            format!(
                "needs {} of memory ({} per run at once, {} besides)",
                fmt_bytes(need),
                fmt_bytes(per_job),
                fmt_bytes(fixed)
            ),
            format!("at most {} per command", fmt_bytes(MEMORY_BUDGET)),
        ));
    }
    let fit = (MEMORY_BUDGET - fixed) / per_job.max(1);
    Ok(threads
        .min(usize::try_from(fit).unwrap_or(usize::MAX))
        .max(1))
}

/// The memory a run of `solver` keeps while it runs \[bytes\]: its samples
/// (rows and sample times) and at most [`MAX_EVENTS`] events. The
/// integrator's own state is a few kB and independent of the run's length.
pub fn run_memory_bytes(solver: &SolverSettings) -> u64 {
    run_memory_bytes_for(solver.samples)
}

/// [`run_memory_bytes`] of a run of `samples` output rows \[bytes\].
pub fn run_memory_bytes_for(samples: usize) -> u64 {
    let event = (std::mem::size_of::<crate::EventRecord>() + 32) as u64;
    (samples as u64)
        .saturating_mul(BYTES_PER_SAMPLE)
        .saturating_add(MAX_EVENTS as u64 * event)
}

/// The rates that define the time unit `T_ref` \[1/s\], each with the scenario
/// key it comes from and a description.
fn rates(sc: &Scenario) -> [(f64, String, &'static str); 10] {
    let top = &sc.top;
    let i = &sc.initial;
    // The force window with the largest applied force names the key.
    let (force_key, _) = sc
        .forcing
        .windows
        .iter()
        .enumerate()
        .flat_map(|(k, w)| {
            [
                (format!("force.{k}.hx"), w.hx),
                (format!("force.{k}.hy"), w.hy),
                (format!("force.{k}.hz"), w.hz),
            ]
        })
        .fold((String::from("force.0.hx"), -1.0), |best, (k, v)| {
            if v.abs() > best.1 { (k, v.abs()) } else { best }
        });
    // The body actuators (docs/physics.md#actuators): the sum of each window's
    // largest rate bounds what any combination of them sets (zero without).
    let nf = sc.forcing.windows.len();
    let (act_key, act_rate) = sc
        .actuators
        .iter()
        .enumerate()
        .map(|(j, w)| {
            let r = w
                .actuator
                .rate(top.mass, top.radius, top.inertia_transverse);
            (format!("force.{}", nf + j), r)
        })
        .fold((String::from("force"), 0.0), |(bk, br), (k, r)| {
            (if r > br { k } else { bk }, br + r)
        });
    // The force plug-ins' body forces join the actuators' rate (nothing
    // changes without their tables).
    let (act_key, act_rate) = super::plugins::rates(sc)
        .into_iter()
        .fold((act_key, act_rate), |(bk, br), (r, name, _)| {
            (if r > br { name.to_string() } else { bk }, br + r)
        });
    [
        (i.spin.abs(), "initial.spin".into(), "|spin|"),
        (
            act_rate,
            act_key,
            "sqrt(|F| / (mass radius)), sqrt(|F| |point| / inertia_transverse), sqrt(|moment| |field| / inertia_transverse), sqrt(|moment| |gradient| / (mass radius)) (tips, magnets; a force plug-in's rate, e.g. wind sqrt(|(fx, fy)| / (mass radius)))",
        ),
        (
            i.precession.abs(),
            "initial.precession".into(),
            "|precession|",
        ),
        (i.theta_dot.abs(), "initial.theta_dot".into(), "|theta_dot|"),
        (
            (sc.surface.gravity / top.radius).sqrt(),
            "surface.gravity".into(),
            "sqrt(gravity / radius)",
        ),
        (
            (sc.forcing.max_contact_force() / (top.mass * top.radius)).sqrt(),
            force_key,
            "sqrt(|(H, hz)| / (mass radius))",
        ),
        (1.0 / sc.solver.t_end, "solver.t_end".into(), "1 / t_end"),
        // The thermal rates (zero without `[thermal]`: nothing changes).
        (
            (sc.thermal.kt() / top.inertia_transverse).sqrt(),
            "thermal.temperature".into(),
            "sqrt(kT / inertia_transverse)",
        ),
        (
            sc.thermal.damping_translational,
            "thermal.damping_translational".into(),
            "damping_translational",
        ),
        (
            sc.thermal.damping_rotational,
            "thermal.damping_rotational".into(),
            "damping_rotational",
        ),
    ]
}

/// The time unit `T_ref` of a scenario \[s\]: the inverse of its fastest
/// initial rate (see [`MAX_SCALED_T_END`]); the same as the models' `Scales::of`.
pub fn time_unit(sc: &Scenario) -> f64 {
    1.0 / rates(sc).iter().map(|r| r.0).fold(0.0, f64::max)
}

/// `log10 |x|` (`-inf` for 0).
fn log10(x: f64) -> f64 {
    x.abs().log10()
}

/// Which of the factors of a product that left `f64` caused it: the
/// factors as `(key, log10 of the factor's contribution)`, `value` the
/// product. Overflow (or NaN): the largest contribution; underflow: the
/// smallest.
fn blame<'a>(factors: &[(&'a str, f64)], value: f64) -> &'a str {
    let under = value.abs() < 1.0;
    factors
        .iter()
        .copied()
        .filter(|f| !f.1.is_nan())
        .reduce(|a, b| {
            let b_worse = if under { b.1 < a.1 } else { b.1 > a.1 };
            if b_worse { b } else { a }
        })
        .map_or(factors[0].0, |f| f.0)
}

/// The key to name when rate `index` of [`rates`] (its own key `key`) is
/// not finite: for the rates made of several keys, the one whose factor
/// is furthest out of range (`top.mass = 1e-320` overflows the rate of the
/// applied force, `sqrt(|H| / (m R))`, but the mass is the cause).
fn rate_cause(sc: &Scenario, index: usize, key: &str) -> String {
    let top = &sc.top;
    let (m, r) = (log10(top.mass), log10(top.radius));
    let factors: Vec<(&str, f64)> = match index {
        RATE_GRAVITY => vec![
            ("surface.gravity", log10(sc.surface.gravity)),
            ("top.radius", -r),
        ],
        RATE_FORCE => vec![
            (key, log10(sc.forcing.max_contact_force())),
            ("top.mass", -m),
            ("top.radius", -r),
        ],
        RATE_THERMAL => vec![
            ("thermal.temperature", log10(sc.thermal.kt())),
            ("top.inertia_transverse", -log10(top.inertia_transverse)),
        ],
        // The actuators' rates: the top's keys if one of them is beyond
        // 1e150 either way, else the window.
        RATE_ACTUATOR => {
            let a = log10(top.inertia_transverse);
            let worst = [
                ("top.mass", m),
                ("top.radius", r),
                ("top.inertia_transverse", a),
            ]
            .into_iter()
            .filter(|f| f.1.abs() > 150.0)
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
            return worst.map_or(key, |f| f.0).to_string();
        }
        _ => return key.to_string(),
    };
    blame(&factors, f64::INFINITY).to_string()
}

/// Positions in [`rates`] of the rates made of several keys.
const RATE_ACTUATOR: usize = 1;
const RATE_GRAVITY: usize = 4;
const RATE_FORCE: usize = 5;
const RATE_THERMAL: usize = 7;

fn bad<T>(key: &str, what: String, range: String) -> Result<T, Error> {
    Err(Error::invalid(key, what, range))
}

/// Check what a run of `sc` needs beyond each key's own range (the keys are
/// assumed to be in range already): finite units and scaled parameters,
/// `t_end / T_ref <= MAX_SCALED_T_END`, a finite initial energy, the sample
/// count and memory, and the RK4 step count. Errors name the key to change.
pub fn check_run(sc: &Scenario) -> Result<(), Error> {
    check_memory(&sc.solver)?;
    let (tu, rate_key) = check_time_unit(sc)?;
    check_units(sc, tu, &rate_key)?;
    check_initial(sc, tu)?;
    check_adhesive_friction(sc)
}

/// The sample count and the run's memory ([`check_run`]'s first step).
fn check_memory(so: &crate::input::solver::SolverSettings) -> Result<(), Error> {
    if so.samples > MAX_SAMPLES {
        return bad(
            "solver.samples",
            format!("{} is too many", so.samples),
            format!(
                "2 <= samples <= {MAX_SAMPLES}: each row keeps {BYTES_PER_SAMPLE} bytes in memory"
            ),
        );
    }
    let bytes = run_memory_bytes(so);
    if bytes > MAX_RUN_BYTES {
        return bad(
            "solver.samples",
            format!("{} rows would need {bytes} bytes of memory", so.samples),
            format!("at most {MAX_RUN_BYTES} bytes per run"),
        );
    }
    Ok(())
}

/// Every rate finite and `t_end / T_ref <= MAX_SCALED_T_END`: the time unit
/// `T_ref` \[s\] and the key that sets it ([`check_run`]'s second step).
fn check_time_unit(sc: &Scenario) -> Result<(f64, String), Error> {
    let so = &sc.solver;
    // Every rate finite: each one is a candidate for 1/T_ref.
    let rates = rates(sc);
    for (index, (r, key, what)) in rates.iter().enumerate() {
        if !r.is_finite() {
            return bad(
                &rate_cause(sc, index, key),
                format!("{what} = {} s^-1 overflows", num(*r)),
                "a value whose rate (1/s) is finite in f64; see the key's own range too".into(),
            );
        }
    }
    let (rate, rate_key, which) = rates
        .iter()
        .fold((0.0, String::new(), ""), |best, (r, k, w)| {
            if *r > best.0 {
                (*r, k.clone(), *w)
            } else {
                best
            }
        });
    let tu = 1.0 / rate;
    let scaled_end = so.t_end / tu;
    if scaled_end.is_nan() || scaled_end > MAX_SCALED_T_END {
        return bad(
            "solver.t_end",
            format!(
                "{} s is {} time units T_ref = 1/({which}) = {} s",
                num(so.t_end),
                num(scaled_end),
                num(tu)
            ),
            format!(
                "t_end <= {MAX_SCALED_T_END:e} T_ref = {} s: a longer run cannot resolve the fastest motion (lower the rate or t_end)",
                num(MAX_SCALED_T_END * tu)
            ),
        );
    }

    Ok((tu, rate_key))
}

/// The units of the scaled model and the scaled parameters: finite and
/// non-zero, for the time unit `tu` \[s\] set by `rate_key`.
fn check_units(sc: &Scenario, tu: f64, rate_key: &str) -> Result<(), Error> {
    let top = &sc.top;
    let length = top.radius;
    let mass = top.mass;
    let inertia = mass * length * length;
    let velocity = length / tu;
    let force = mass * length / (tu * tu);
    let energy = inertia / (tu * tu);
    let unit_range =
        "mass and radius such that the scaled model's units are finite and non-zero in f64";
    // Each unit is mass^a radius^b T_ref^c: the key to blame is the one
    // whose factor pushes it furthest out of range.
    for (v, what, [a, b, c]) in [
        (inertia, "the inertia unit mass radius^2", [1.0, 2.0, 0.0]),
        (
            velocity,
            "the velocity unit radius / T_ref",
            [0.0, 1.0, -1.0],
        ),
        (
            force,
            "the force unit mass radius / T_ref^2",
            [1.0, 1.0, -2.0],
        ),
        (
            energy,
            "the energy unit mass radius^2 / T_ref^2",
            [1.0, 2.0, -2.0],
        ),
    ] {
        if !(v.is_finite() && v >= f64::MIN_POSITIVE) {
            let key = blame(
                &[
                    ("top.mass", a * log10(mass)),
                    ("top.radius", b * log10(length)),
                    (rate_key, c * log10(tu)),
                ],
                v,
            );
            return bad(
                key,
                format!(
                    "{what} is {v:e} [SI] (mass {mass:e} kg, radius {length:e} m, T_ref {tu:e} s)"
                ),
                unit_range.into(),
            );
        }
    }
    for (key, v) in [
        ("top.inertia_transverse", top.inertia_transverse / inertia),
        ("top.inertia_axial", top.inertia_axial / inertia),
    ] {
        if !(v.is_finite() && v >= f64::MIN_POSITIVE && 1.0 / v < f64::MAX) {
            return bad(
                key,
                format!("divided by mass radius^2 = {inertia:e} kg m^2 it is {v:e}"),
                "a moment of inertia whose ratio to mass radius^2 is finite and non-zero in f64"
                    .into(),
            );
        }
    }
    if let Some(eps) = sc.surface.law.eps() {
        let v = eps / velocity;
        if !(v.is_finite() && v >= f64::MIN_POSITIVE) {
            return bad(
                "surface.friction_eps",
                format!("divided by the velocity unit {velocity:e} m/s it is {v:e}"),
                "a speed whose ratio to radius / T_ref is finite and non-zero in f64".into(),
            );
        }
    }
    if sc.adhesion().is_on() {
        for (key, v, unit, what) in [
            ("adhesion.force", sc.adhesion().force, force, "force"),
            ("adhesion.energy", sc.adhesion().energy, energy, "energy"),
        ] {
            let x = v / unit;
            if !(x.is_finite() && x >= f64::MIN_POSITIVE) {
                return bad(
                    key,
                    format!("divided by the {what} unit {unit:e} it is {x:e}"),
                    format!(
                        "a {what} whose ratio to the scaled model's unit is finite and non-zero in f64"
                    ),
                );
            }
        }
    }
    Ok(())
}

/// The initial velocities in velocity units and the initial energy finite,
/// for the time unit `tu` \[s\].
fn check_initial(sc: &Scenario, tu: f64) -> Result<(), Error> {
    let top = &sc.top;
    let mass = top.mass;
    let velocity = top.radius / tu;
    let i = &sc.initial;
    for (key, v) in [("initial.ux", i.ux), ("initial.uy", i.uy)] {
        if !(v / velocity).is_finite() {
            return bad(
                key,
                format!(
                    "{} m/s is {:e} velocity units radius / T_ref",
                    num(v),
                    v / velocity
                ),
                "a velocity whose ratio to radius / T_ref is finite in f64".into(),
            );
        }
    }

    // The initial energy, with room to grow (the energy is computed in SI
    // for every output row).
    let e0 = observe::energy(
        top,
        sc.surface.gravity,
        i.theta,
        i.theta_dot,
        i.precession,
        i.spin,
        [i.ux, i.uy, 0.0],
    );
    const MAX_ENERGY: f64 = 1e300;
    if e0.is_nan() || e0.abs() > MAX_ENERGY {
        // Blame the velocity whose own energy is largest.
        let terms = [
            ("initial.ux", 0.5 * mass * i.ux * i.ux),
            ("initial.uy", 0.5 * mass * i.uy * i.uy),
            (
                "initial.theta_dot",
                0.5 * top.inertia_transverse * i.theta_dot * i.theta_dot,
            ),
            (
                "initial.precession",
                0.5 * top.inertia_transverse * i.precession * i.precession,
            ),
            ("initial.spin", 0.5 * top.inertia_axial * i.spin * i.spin),
            ("surface.gravity", mass * sc.surface.gravity * top.radius),
        ];
        let key = terms
            .iter()
            .fold(("initial.spin", -1.0), |b, &(k, v)| {
                if v.is_nan() || v > b.1 { (k, v) } else { b }
            })
            .0;
        return bad(
            key,
            format!("the initial energy is {e0:e} J"),
            format!("values that keep the energy finite, |E| <= {MAX_ENERGY:e} J"),
        );
    }
    Ok(())
}

/// The relaxation rate of the slip under the regularised or viscous law
/// \[1/s\]: `λ = μ (g + F_a/m)(1 + m R²/A)/ε`, the rate at which `μ N v/ε`
/// (the law's slope at zero slip) with `N = m g + F_a` damps the slip of the
/// contact point (its horizontal inverse mass is `1/m + R²/A` for a sphere
/// at rest; the estimate the advice below uses). `None` for the Coulomb laws.
pub fn friction_relaxation_rate(sc: &Scenario) -> Option<f64> {
    let eps = sc.surface.law.eps()?;
    let top = &sc.top;
    let load = sc.surface.gravity + sc.adhesion().force / top.mass;
    let inv_mass = 1.0 + top.mass * top.radius * top.radius / top.inertia_transverse;
    Some(sc.surface.friction * load * inv_mass / eps)
}

/// With adhesion the regularised and viscous laws are stiffer by
/// `(g + F_a/m)/g` (docs/physics.md#adhesion): their slip relaxes at
/// [`friction_relaxation_rate`] `λ`. An explicit method needs steps below
/// its stability bound (`h λ <= 6` for DOP853, `h λ <= 2.78` for RK4), so a
/// run that would need more steps than its step limit (adaptive) or whose
/// fixed step is beyond the bound (RK4) is refused here with advice, instead
/// of running into the step limit after minutes or diverging. Checked only
/// with adhesion on; the stiff method is left to its step limit (measured on
/// the nano preset with the graphene values it completes in the vector
/// model and reaches its limit in the others, docs/physics.md#adhesion).
fn check_adhesive_friction(sc: &Scenario) -> Result<(), Error> {
    let Some(lambda) = friction_relaxation_rate(sc).filter(|_| sc.adhesion().is_on()) else {
        return Ok(());
    };
    let so = &sc.solver;
    let law = sc.surface.law.name();
    let eps = sc.surface.law.eps().unwrap_or(0.0);
    let advice = |eps_min: f64| {
        format!(
            "friction_law = \"coulomb\" (exact stick/slip: not stiff), or friction_eps >= {} m/s, or method = \"stiff\"",
            num(eps_min)
        )
    };
    match so.method {
        crate::Method::Adaptive => {
            // DOP853's stability interval on the negative real axis is ~6.
            let need = so.t_end * lambda / 6.0;
            let limit = so.max_steps.unwrap_or(max_steps_for(so.method)) as f64;
            if need > limit {
                return bad(
                    "surface.friction_law",
                    format!(
                        "\"{law}\" with adhesion is stiff: the slip relaxes at mu (g + F_a/m)(1 + m R^2/A)/eps = {} 1/s, so the explicit adaptive method needs ~{} steps over t_end, beyond the step limit {}",
                        num(lambda),
                        num(need),
                        num(limit)
                    ),
                    advice(eps * need / limit),
                );
            }
        }
        crate::Method::Rk4 => {
            let h = so.t_end / so.steps.max(1) as f64;
            if h * lambda > 2.78 {
                return bad(
                    "surface.friction_law",
                    format!(
                        "\"{law}\" with adhesion is stiff: the slip relaxes at {} 1/s, and RK4's step {} s is beyond its stability bound 2.78/rate (needs steps >= {})",
                        num(lambda),
                        num(h),
                        num((so.t_end * lambda / 2.78).ceil())
                    ),
                    advice(eps * h * lambda / 2.78),
                );
            }
        }
        crate::Method::Stiff | crate::Method::Langevin | crate::Method::Brownian => {}
    }
    Ok(())
}

impl crate::physics::units::Scales {
    /// The scales of a scenario.
    pub fn of(sc: &Scenario) -> Self {
        let top = &sc.top;
        // The inverse of the fastest initial rate; the run limits use the
        // same unit (`time_unit`, which names each rate for messages).
        crate::physics::units::Scales {
            length: top.radius,
            mass: top.mass,
            time: time_unit(sc),
        }
    }
}
