//! Events, typed: what the integrator watches for ([`Watch`]: the zero of
//! an event function, with what the driver does when it fires), and what a
//! run records ([`Happened`], written to `summary.json` as today's strings).

/// A zero crossing a driver asks the integrator to locate. Each driver
/// builds its list of `(Watch, integrate::Event)` for the current phase
/// and mode, and dispatches on the `Watch` of what fired (never on an
/// index into the list, whose length depends on the phase).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Watch {
    /// θ rises through π/2: recorded once, as [`Happened::ThetaAboveHalfPi`].
    ThetaAboveHalfPi,
    /// θ̇ falls through 0 (a maximum of θ): enters the running diagnostics.
    ThetaMax,
    /// The normal force N crosses 0: recorded as contact lost/regained;
    /// terminal where the latched branch flips (bilateral, sliding) or the
    /// top lifts off (unilateral).
    NormalZero,
    /// The sphere's lowest point reaches the plane (rigid model in flight):
    /// touchdown.
    Touchdown,
    /// The sphere's lowest point is a small depth below the plane (rigid
    /// model in flight): the backup of [`Watch::Touchdown`].
    PenetrationGuard,
    /// The slip velocity along its direction at the segment's start falls
    /// through 0 (exact Coulomb law, sliding): stick or slip on.
    SlipZero,
    /// The stick margin μ|N| − |F| falls through 0 (exact Coulomb law,
    /// rolling), or `μ|N| (1 − λ)`, `λ` the gauge of the needed force and
    /// drilling torque (Coulomb–Contensou stick, §contensou): the contact starts
    /// to slip.
    StickLimit,
    /// Sliding and spinning both stop (Coulomb–Contensou friction, §contensou):
    /// the contact sticks there if the needed wrench is inside the limit
    /// curve (it leaves the stick at [`Watch::StickLimit`]).
    ContensouStick,
    /// The contact sphere that is not the active one (the stem's while the
    /// main sphere is, or was last, on the plane, and the other way round)
    /// reaches the plane (rigid model with a stem, docs/physics.md#stem):
    /// an impact of that sphere, which becomes the active one.
    SphereTouchdown,
    /// One of the two normal forces of the two-contact phase (main sphere
    /// and stem both on the plane, rigid model, §stem) falls through 0: that
    /// sphere lifts off and the other carries on alone.
    SphereLiftoff,
    /// θ reaches the stem's touchdown angle θ_td (on-plane models with a
    /// stem, §stem): they cannot follow the stem's contact and stop there.
    StemTouch,
    /// θ crosses the edge level `j` of a watched θ window
    /// ([`crate::sim::watch`]): never terminal.
    ThetaLevel(usize),
    /// The run reaches the time mark `j` of a watched θ window
    /// ([`crate::sim::watch`]): never terminal.
    TimeMark(usize),
}

/// Something a run records in its event list (`Trajectory::events`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Happened {
    /// A switch time of the applied-force schedule.
    ForceSwitch,
    /// Sliding turned to rolling (exact Coulomb law).
    Stick,
    /// Rolling turned to sliding (exact Coulomb law), or sliding starts.
    Slip,
    /// θ first exceeds π/2.
    ThetaAboveHalfPi,
    /// N fell below zero.
    ContactLost,
    /// N rose back above zero.
    ContactRegained,
    /// The rigid body left the plane.
    LiftOff,
    /// The rigid body landed on the plane.
    Touchdown,
    /// The event list reached its cap; later events are not listed.
    EventLimitReached,
    /// Sliding and spinning both stopped and the contact sticks
    /// (Coulomb–Contensou friction; its end is a [`Happened::Slip`]).
    ContensouStick,
    /// The stem's sphere landed on the plane (docs/physics.md#stem).
    StemTouchdown,
    /// The stem's sphere left the plane (into flight, or the main sphere
    /// landed).
    StemLiftoff,
}

impl Happened {
    /// The name written to `summary.json` (`events[].kind`).
    pub fn as_str(self) -> &'static str {
        match self {
            Happened::ForceSwitch => "force_switch",
            Happened::Stick => "stick",
            Happened::Slip => "slip",
            Happened::ThetaAboveHalfPi => "theta_above_half_pi",
            Happened::ContactLost => "contact_lost",
            Happened::ContactRegained => "contact_regained",
            Happened::LiftOff => "lift_off",
            Happened::Touchdown => "touchdown",
            Happened::EventLimitReached => "event_limit_reached",
            Happened::ContensouStick => "contensou_stick",
            Happened::StemTouchdown => "stem_touchdown",
            Happened::StemLiftoff => "stem_liftoff",
        }
    }

    /// Every kind, for documentation and tests.
    #[cfg_attr(not(test), allow(dead_code))]
    pub const ALL: [Happened; 12] = [
        Happened::ForceSwitch,
        Happened::Stick,
        Happened::Slip,
        Happened::ThetaAboveHalfPi,
        Happened::ContactLost,
        Happened::ContactRegained,
        Happened::LiftOff,
        Happened::Touchdown,
        Happened::EventLimitReached,
        Happened::ContensouStick,
        Happened::StemTouchdown,
        Happened::StemLiftoff,
    ];
}

#[cfg(test)]
mod tests {
    use super::Happened;

    #[test]
    fn names_are_unique_snake_case() {
        let names: std::collections::BTreeSet<_> =
            Happened::ALL.iter().map(|h| h.as_str()).collect();
        assert_eq!(names.len(), Happened::ALL.len());
        assert!(
            names
                .iter()
                .all(|n| n.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
        );
    }
}
