//! The cross-key rules of `solver.method = "langevin"` and `[thermal]`,
//! and the step-size rule (docs/physics.md#langevin; the keys themselves:
//! [`crate::input::thermal`]).

use crate::input::thermal::{
    MAX_BROWNIAN_CONTACT_RATIO, MAX_BROWNIAN_STEP_RATE, MAX_STEP_RATE, SEED_RANGE, langevin_steps,
};
use crate::{Error, Scenario};

/// The vertical load that tilts the top in the step rules below,
/// `m g + F_a + max |h_z|` \[N\], and the key of its largest term
/// (`surface.gravity`, `adhesion.force`, or `force.hz` for a window's
/// vertical load), which a rule it limits names.
fn vertical_load(sc: &Scenario) -> (f64, &'static str) {
    let weight = sc.top.mass * sc.surface.gravity;
    let hz = sc
        .forcing
        .windows
        .iter()
        .map(|w| w.hz.abs())
        .fold(0.0, f64::max);
    let terms = [
        (weight, "surface.gravity"),
        (sc.adhesion().force, "adhesion.force"),
        (hz, "force.hz"),
    ];
    let key = terms
        .iter()
        .fold(terms[0], |best, &t| if t.0 > best.0 { t } else { best })
        .1;
    (weight + sc.adhesion().force + hz, key)
}

/// The rates \[1/s\] the step of a Langevin run must resolve, each with the
/// key that sets it and a description: γ_t, γ_r, the contact damping's
/// `c/m` and `c (R + a)²/A`, the thermal angular velocities `sqrt(kT/A)`
/// and `sqrt(kT/C)`, the initial spin, precession and tilt rate, the tilt
/// oscillation under the vertical forces `sqrt((m g + F_a + |h_z|) (R + a)
/// / A)` and each well's curvature `sqrt(depth / width² / A)`. (The
/// horizontal translation has no length scale on the plane: its only rate
/// is γ_t.) In the tube also `sqrt(g/(b − R))` and `sqrt(kT/m)/(b − R)`.
pub fn step_rates(sc: &Scenario) -> Vec<(f64, &'static str, &'static str)> {
    let th = &sc.thermal;
    let top = &sc.top;
    let (m, a_in, c_in) = (top.mass, top.inertia_transverse, top.inertia_axial);
    let lever = top.radius + top.offset;
    let (load, load_key) = vertical_load(sc);
    let mut out = vec![
        (
            th.damping_translational,
            "thermal.damping_translational",
            "damping_translational",
        ),
        (
            th.damping_rotational,
            "thermal.damping_rotational",
            "damping_rotational",
        ),
        (
            th.damping_contact / m,
            "thermal.damping_contact",
            "damping_contact / mass",
        ),
        (
            th.damping_contact * lever * lever / a_in,
            "thermal.damping_contact",
            "damping_contact (radius + offset)^2 / inertia_transverse",
        ),
        (
            (th.kt() / a_in).sqrt(),
            "thermal.temperature",
            "sqrt(kT / inertia_transverse) (thermal tilt rate)",
        ),
        (
            (th.kt() / c_in).sqrt(),
            "thermal.temperature",
            "sqrt(kT / inertia_axial) (thermal spin)",
        ),
        (sc.initial.spin.abs(), "initial.spin", "|spin|"),
        (
            sc.initial.precession.abs(),
            "initial.precession",
            "|precession|",
        ),
        (
            sc.initial.theta_dot.abs(),
            "initial.theta_dot",
            "|theta_dot|",
        ),
        (
            (load * lever / a_in).sqrt(),
            load_key,
            "sqrt((mass gravity + adhesion force + |hz|) (radius + offset) / inertia_transverse)",
        ),
    ];
    for w in &sc.wells() {
        out.push((
            (w.depth / (w.width * w.width * a_in)).sqrt(),
            "well",
            "sqrt(depth / width^2 / inertia_transverse) of a well",
        ));
    }
    // The tube (docs/physics.md#tube-langevin): the contact's pendulum
    // around the axis, and the rate at which a thermal velocity turns the
    // contact's frame.
    if let Some((b, _)) = sc.surface.shape.tube() {
        let arm = b - top.radius;
        out.push((
            (sc.surface.gravity / arm).sqrt(),
            "surface.tube_radius",
            "sqrt(gravity / (tube_radius - radius)) (the contact's pendulum around the axis)",
        ));
        out.push((
            (th.kt() / m).sqrt() / arm,
            "surface.tube_radius",
            "sqrt(kT / mass) / (tube_radius - radius) (a thermal velocity around the axis)",
        ));
    }
    // The body actuators (docs/physics.md#actuators): each window's rate.
    for w in &sc.actuators {
        out.push((
            w.actuator.rate(m, top.radius, a_in),
            "force",
            "a tip's or magnet's rate (sqrt(|F| / (mass radius)), sqrt(|F| |point| / inertia_transverse), sqrt(|moment| |field| / inertia_transverse), ...)",
        ));
    }
    // The force plug-ins' (docs/extending.md): none without their tables.
    out.extend(super::plugins::rates(sc));
    out
}

/// The rates \[1/s\] the step of a Brownian run must resolve: the
/// rotational diffusion rates `kT/(γ_r A)` and `kT/(γ_r C)`, and the
/// relaxation rates of the orientation under the torques, `(curvature)/(γ_r
/// A)`: the tilt under the vertical forces `(m g + F_a + |h_z|)(R + a)` and
/// each well's `d/w²`. (No inertia: the initial rates do not enter.)
pub fn brownian_rates(sc: &Scenario) -> Vec<(f64, &'static str, &'static str)> {
    let th = &sc.thermal;
    let top = &sc.top;
    let (a_in, c_in) = (top.inertia_transverse, top.inertia_axial);
    let lever = top.radius + top.offset;
    let (load, load_key) = vertical_load(sc);
    let gr = th.damping_rotational;
    let mut out = vec![
        (
            th.kt() / (gr * a_in),
            "thermal.temperature",
            "kT / (damping_rotational inertia_transverse) (rotational diffusion)",
        ),
        (
            th.kt() / (gr * c_in),
            "thermal.temperature",
            "kT / (damping_rotational inertia_axial) (spin diffusion)",
        ),
        (
            load * lever / (gr * a_in),
            load_key,
            "(mass gravity + adhesion force + |hz|) (radius + offset) / (damping_rotational inertia_transverse)",
        ),
    ];
    for w in &sc.wells() {
        out.push((
            w.depth / (w.width * w.width * gr * a_in),
            "well",
            "depth / width^2 / (damping_rotational inertia_transverse) of a well",
        ));
    }
    out
}

/// The largest ratio of the contact damping's rates to the bath's own
/// (`c/(m γ_t)`, `c (R + a)²/(γ_r A)`, `c R²/(γ_r C)`): the condition number
/// the contact damping adds to the friction matrix of the overdamped step
/// (docs/physics.md#brownian). Infinite when a bath damping is zero.
pub fn contact_ratio(sc: &Scenario) -> f64 {
    let c = sc.thermal.damping_contact;
    if c == 0.0 {
        0.0
    } else {
        c / bath_contact_scale(sc)
    }
}

/// The smallest of the bath's dampings as contact coefficients \[N s/m\]:
/// `m γ_t`, `γ_r A/(R + a)²`, `γ_r C/R²` (so [`contact_ratio`] is the
/// contact damping over it).
fn bath_contact_scale(sc: &Scenario) -> f64 {
    let th = &sc.thermal;
    let top = &sc.top;
    let lever = top.radius + top.offset;
    let (gt, gr) = (th.damping_translational, th.damping_rotational);
    [
        top.mass * gt,
        gr * top.inertia_transverse / (lever * lever),
        gr * top.inertia_axial / (top.radius * top.radius),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}

/// The rates \[1/s\] the step of the rigid model's Brownian run above a
/// wall (unilateral contact, docs/physics.md#brownian-wall) must resolve besides
/// [`brownian_rates`]: the gap's diffusion over the wall's thermal length
/// `kT/F_w` (`F_w = m g + F_a + |h_z|`, the potential's slope at the
/// wall), `F_w² (1/(m γ_t) + a²/(γ_r A))/kT` (so the rms step of the gap is
/// `<= 0.063 kT/F_w` at the rule's limit), and the adhesion well's
/// curvature rate `F_a²/(E_b m γ_t)`. None at `T = 0`.
pub fn wall_rates(sc: &Scenario) -> Vec<(f64, &'static str, &'static str)> {
    let th = &sc.thermal;
    let top = &sc.top;
    let kt = th.kt();
    let (load, _) = vertical_load(sc);
    let mobility = 1.0 / (top.mass * th.damping_translational)
        + top.offset * top.offset / (th.damping_rotational * top.inertia_transverse);
    let mut out = Vec::new();
    if kt > 0.0 {
        out.push((
            load * load * mobility / kt,
            "surface.contact",
            "(mass gravity + adhesion force + |hz|)^2 (1/(mass damping_translational) + offset^2/(damping_rotational inertia_transverse)) / kT (the gap's diffusion over the wall's thermal length, unilateral contact)",
        ));
    }
    if sc.adhesion().force > 0.0 && sc.adhesion().energy > 0.0 {
        out.push((
            sc.adhesion().force * sc.adhesion().force
                / (sc.adhesion().energy * top.mass * th.damping_translational),
            "adhesion.force",
            "adhesion force^2 / (adhesion energy mass damping_translational) (the adhesion well's curvature, unilateral contact)",
        ));
    }
    out
}

/// The cross-key rules of the thermal keys and `solver.method =
/// "langevin"` (docs/physics.md#langevin):
///
/// - `[thermal]` keys other than the defaults, and `solver.dt`, only with
///   `method = "langevin"`; `"langevin"` needs `solver.dt` and the vector
///   or the rigid model (the reduced model has no stochastic scheme);
/// - no Coulomb friction (`surface.friction = 0`: dry friction has no
///   thermal partner; a viscous contact is `thermal.damping_contact`);
/// - at `T > 0`: a seed, and `γ_t > 0`, `γ_r > 0` (every degree of
///   freedom coupled to the bath: contact damping alone leaves the spin of
///   an upright top undamped);
/// - `method = "brownian"`: `γ_t > 0`, `γ_r > 0` always, a contact damping
///   at most `MAX_BROWNIAN_CONTACT_RATIO` times the bath's own
///   ([`contact_ratio`]: the conditioning of the coupled mobility, §brownian),
///   none for the rigid model with unilateral contact (the free body above
///   a wall, §brownian-wall, whose step rule adds [`wall_rates`]);
/// - the step rule `dt · max(step_rates) <= MAX_STEP_RATE`, the number of
///   steps within the step limit and at least `samples − 1`.
pub fn check(sc: &Scenario) -> Result<(), Error> {
    let so = &sc.solver;
    let th = &sc.thermal;
    if !so.method.is_stochastic() {
        return check_deterministic(sc);
    }
    let brownian = so.method == crate::Method::Brownian;
    let method = if brownian { "brownian" } else { "langevin" };
    let rigid_langevin = so.model == crate::ModelKind::Rigid;
    // The rigid model's Brownian method with unilateral contact is the
    // overdamped free body above a wall (docs/physics.md#brownian-wall): its step
    // must resolve the wall's thermal length too ([`wall_rates`]).
    let wall = rigid_langevin && brownian && sc.surface.contact == crate::ContactMode::Unilateral;
    if so.model != crate::ModelKind::Vector && !rigid_langevin {
        let name = match so.model {
            crate::ModelKind::Reduced => "reduced",
            crate::ModelKind::Rigid => "rigid",
            crate::ModelKind::Vector => "vector",
        };
        return Err(Error::invalid(
            "solver.model",
            format!("\"{name}\" has no {method} scheme yet"),
            format!("model = \"vector\" or \"rigid\" with method = \"{method}\""),
        ));
    }
    let Some(dt) = so.dt else {
        return Err(Error::invalid(
            "solver.dt",
            "missing".into(),
            "required with method = \"langevin\": the fixed step, a finite time > 0 [s]".into(),
        ));
    };
    if !dt.is_finite() || dt <= 0.0 {
        return Err(Error::invalid(
            "solver.dt",
            format!("{} is not allowed", crate::human::exact(dt)),
            "a finite time > 0 [s]".into(),
        ));
    }
    if sc.surface.friction != 0.0 {
        return Err(Error::invalid(
            "surface.friction",
            format!(
                "{} with method = \"langevin\": Coulomb friction has no thermal partner",
                sc.surface.friction
            ),
            "0 with method = \"langevin\"; a viscous contact is thermal.damping_contact [N s/m]"
                .into(),
        ));
    }
    if brownian {
        check_brownian(sc, wall)?;
    }
    if th.is_hot() {
        check_hot(th)?;
    }
    check_step(sc, dt, brownian, wall)
}

/// A deterministic method takes no `solver.dt` and no `[thermal]` key.
fn check_deterministic(sc: &Scenario) -> Result<(), Error> {
    let th = &sc.thermal;
    if let Some(dt) = sc.solver.dt {
        return Err(Error::invalid(
            "solver.dt",
            format!("{dt} given with a deterministic method"),
            "only with solver.method = \"langevin\" or \"brownian\" (rk4 takes solver.steps)"
                .into(),
        ));
    }
    let set = [
        ("temperature", th.temperature != 0.0),
        ("damping_translational", th.damping_translational != 0.0),
        ("damping_rotational", th.damping_rotational != 0.0),
        ("damping_contact", th.damping_contact != 0.0),
        ("seed", th.seed.is_some()),
        ("run", th.run != 0),
    ];
    if let Some((key, _)) = set.iter().find(|(_, on)| *on) {
        return Err(Error::invalid(
            &format!("thermal.{key}"),
            "needs solver.method = \"langevin\" or \"brownian\"".into(),
            "temperature and damping are integrated by the Langevin and Brownian methods only: set solver.method = \"langevin\" and solver.dt".into(),
        ));
    }
    Ok(())
}

/// The Brownian method's mobilities and contact damping (`wall`: the
/// rigid model's free body above a wall).
fn check_brownian(sc: &Scenario, wall: bool) -> Result<(), Error> {
    let th = &sc.thermal;
    for (key, v) in [
        ("damping_translational", th.damping_translational),
        ("damping_rotational", th.damping_rotational),
    ] {
        if v <= 0.0 {
            return Err(Error::invalid(
                &format!("thermal.{key}"),
                format!("{v} with method = \"brownian\""),
                "> 0 [1/s] with method = \"brownian\" (the mobility is its inverse)".into(),
            ));
        }
    }
    if wall && th.damping_contact != 0.0 {
        // Above a wall the body touches the plane at instants only (a
        // reflected diffusion): a viscous slip law has no contact time
        // to act over, and ignoring the key silently would mislead.
        return Err(Error::invalid(
            "thermal.damping_contact",
            format!(
                "{:e} with model = \"rigid\", method = \"brownian\" and contact = \"unilateral\"",
                th.damping_contact
            ),
            "0 for the free body above a wall (it touches the plane at instants only, docs/physics.md#brownian-wall); contact = \"bilateral\" keeps the top on the plane with its contact damping".into(),
        ));
    }
    let ratio = contact_ratio(sc);
    if ratio > MAX_BROWNIAN_CONTACT_RATIO {
        let limit = MAX_BROWNIAN_CONTACT_RATIO * bath_contact_scale(sc);
        return Err(Error::invalid(
            "thermal.damping_contact",
            format!(
                "{:e} with method = \"brownian\" is {ratio:.3e} times the bath's own damping",
                th.damping_contact
            ),
            format!(
                "at most {limit:.3e} [N s/m] with method = \"brownian\" here: {MAX_BROWNIAN_CONTACT_RATIO:e} times the smallest of mass damping_translational, damping_rotational inertia_transverse / (radius + offset)^2 and damping_rotational inertia_axial / radius^2 (beyond, the friction matrix is too ill-conditioned for its mobility)"
            ),
        ));
    }
    Ok(())
}

/// At a temperature > 0: a seed and a heat bath for every degree of freedom.
fn check_hot(th: &crate::Thermal) -> Result<(), Error> {
    if th.seed.is_none() {
        return Err(Error::invalid(
            "thermal.seed",
            "missing".into(),
            SEED_RANGE.into(),
        ));
    }
    for (key, v) in [
        ("damping_translational", th.damping_translational),
        ("damping_rotational", th.damping_rotational),
    ] {
        if v <= 0.0 {
            return Err(Error::invalid(
                &format!("thermal.{key}"),
                format!("{v} at temperature {} K", th.temperature),
                "> 0 at temperature > 0 [1/s]: every degree of freedom needs its heat bath".into(),
            ));
        }
    }
    Ok(())
}

/// The step `dt` \[s\] against the fastest rate, the step limit and the
/// sample count.
fn check_step(sc: &Scenario, dt: f64, brownian: bool, wall: bool) -> Result<(), Error> {
    let so = &sc.solver;
    let method = if brownian { "brownian" } else { "langevin" };
    let rates = if wall {
        let mut r = brownian_rates(sc);
        r.extend(wall_rates(sc));
        r
    } else if brownian {
        brownian_rates(sc)
    } else {
        step_rates(sc)
    };
    let limit = if brownian {
        MAX_BROWNIAN_STEP_RATE
    } else {
        MAX_STEP_RATE
    };
    let (rate, key, what) =
        rates.into_iter().fold(
            (0.0, "solver.dt", ""),
            |best, r| {
                if r.0 > best.0 { r } else { best }
            },
        );
    if !rate.is_finite() {
        return Err(Error::invalid(
            key,
            format!("the rate {what} overflows"),
            "a value whose rate (1/s) is finite".into(),
        ));
    }
    if dt * rate > limit {
        return Err(Error::invalid(
            "solver.dt",
            format!(
                "{} s is too long: {what} = {} 1/s (from {key}) gives dt * rate = {:.3}",
                crate::human::exact(dt),
                crate::human::sig(rate, 4),
                dt * rate
            ),
            format!(
                "dt * rate <= {limit} with method = \"{method}\": dt <= {} s",
                crate::human::sig(limit / rate, 4)
            ),
        ));
    }
    let n = langevin_steps(so.t_end, dt);
    if n > so.step_limit() {
        return Err(Error::invalid(
            "solver.dt",
            format!(
                "{} s needs {n} steps over t_end, beyond the step limit {}",
                crate::human::exact(dt),
                so.step_limit()
            ),
            "t_end / dt <= solver.max_steps (default 20000000): a shorter t_end or an ensemble of shorter runs".into(),
        ));
    }
    if (so.samples as u64 - 1) > n {
        return Err(Error::invalid(
            "solver.samples",
            format!("{} rows for {n} steps", so.samples),
            format!(
                "samples <= steps + 1 = {} with method = \"langevin\" (each row is a step's end)",
                n + 1
            ),
        ));
    }
    Ok(())
}
