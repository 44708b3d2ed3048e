//! Derived quantities: N, slip, Jellett's J, energy, work. (work in progress)
