"""tippetop: tippe-top dynamics, from the 15 g toy to the C60 nano tippe top.

Scenarios as the CLI resolves them (preset, file, ``set`` = ``--set``), runs
with the GIL released, trajectories as numpy float64 arrays (SI units, angles
in radians), parameter sweeps, and a steppable ``Simulation``.

    >>> import tippetop as tt
    >>> sc = tt.Scenario.preset("nano").set("surface.friction", 0.2)
    >>> tr = tt.run(sc)
    >>> tr.t, tr.theta                       # s, rad
    >>> sw = tt.sweep(sc, vary={"top.offset": (1e-11, 1e-10, 5)}, threads=2)
    >>> sw["top.offset"], sw["theta_final"]  # m, rad

Bad input raises ``ValueError`` with the CLI's one-line message without its
``error: `` prefix: ``<key>: <what is wrong> (<valid range>)``; an argument
of the wrong type raises ``TypeError`` (a bool is not a number; numpy's
integers are ints), a number out of its range ``ValueError`` (never
``AttributeError``, ``OverflowError`` or ``RecursionError``); a size past its
bound is refused before anything is allocated, naming the key and the bound.
An internal error (a bug) raises ``RuntimeError``. The long calls (``run``,
``sweep``, ``ensemble``, ``rare``, ``Simulation.integrate_to``) release the
GIL and stop within a second on Ctrl-C (``KeyboardInterrupt``), the runs in
progress with them.
"""

from os import PathLike
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union, final

import numpy as np
from numpy.typing import NDArray

__all__ = ["Scenario", "Trajectory", "Simulation", "Snapshot", "run", "sweep", "ensemble", "rare", "COLUMNS", "__version__"]

__version__: str
"""The package version (that of the Rust crates)."""

COLUMNS: List[str]
"""The trajectory.csv columns in order (see ``Trajectory``): ``t`` [s],
``theta`` [rad], ``theta_dot`` [rad/s], ``Omega`` [rad/s], ``omega`` [rad/s],
``ux``, ``uy``, ``uz`` [m/s], ``N`` [N], ``slip`` [m/s], ``J`` [kg m^3/s],
``energy``, ``work_friction``, ``work_applied`` [J], ``hx``, ``hy`` [N],
``rolling`` [0 or 1], ``x``, ``y``, ``z`` [m], ``qw``, ``qx``, ``qy``, ``qz`` [1],
``xp``, ``yp`` [m]."""

@final
class Scenario:
    """A tippe-top scenario: the top, the surface, forces, initial state and
    solver settings (SI units; ``to_toml()`` lists every key). Immutable:
    ``set`` returns a new scenario. Made with ``Scenario.preset``,
    ``Scenario.from_file`` or ``Scenario.from_toml`` (no constructor);
    ``repr()`` is a Python expression that makes it again, e.g.
    ``tippetop.Scenario.preset('nano').set_many({'surface.friction': '0.2'})``."""

    @staticmethod
    def preset(name: str) -> "Scenario":
        """A built-in scenario: ``"nano"`` (the C60 nano tippe top of the
        paper), ``"nano-physical"`` (C60 on graphene at 300 K, a Langevin
        run), ``"nano-adhesive"`` (the same without temperature) or
        ``"classical"`` (the 15 g toy).
        ValueError (key ``preset``) for another name."""
    @staticmethod
    def from_file(path: Union[str, "PathLike[str]"]) -> "Scenario":
        """A scenario from a TOML file (the CLI's ``tippetop run FILE``; the
        file may name a ``preset`` to start from). ValueError naming the
        file if it cannot be read or is larger than 16 MiB, or naming the
        bad key."""
    @staticmethod
    def from_toml(text: str) -> "Scenario":
        """A scenario from TOML text (the format of scenario files)."""
    def set(self, key: str, value: Union[float, int, bool, str, Sequence[float], NDArray[Any]]) -> "Scenario":
        """A new scenario with ``key`` (``"table.key"``, e.g.
        ``"surface.friction"``, ``"force.0.hx"``) set to ``value`` in the key's
        SI unit: the CLI's ``--set key=value``, same keys and checks
        (ValueError naming the key and its valid range). Floats are passed
        exactly; a str is taken as on the command line."""
    def set_many(
        self, values: Mapping[str, Union[float, int, bool, str, Sequence[float], NDArray[Any]]]
    ) -> "Scenario":
        """A new scenario with every ``key: value`` of ``values`` (in its
        order) set at once: the CLI's ``--set k1=v1 --set k2=v2 ...``,
        checked together, for keys that depend on each other (e.g.
        ``{"surface.friction_law": "regularized", "surface.friction_eps":
        1e-2}`` [m/s], which ``set`` one at a time rejects). Values as in
        ``set``. TypeError if ``values`` is not a mapping (a list, ``None``)
        or a key is not a str."""
    def get(self, key: str) -> Any:
        """The value of ``key`` (``"top.radius"`` [m], ``"force.0.hx"`` [N],
        ...) as ``to_toml()`` writes it: float, int, bool, str, list or dict.
        ValueError if there is no such key."""
    def to_toml(self) -> str:
        """The complete scenario as TOML (every key explicit, floats exact):
        what the CLI writes to ``scenario.toml``."""
    def __eq__(self, other: object, /) -> bool:
        """True if ``other`` is a Scenario with exactly the same values."""

@final
class Trajectory:
    """The result of a run: one numpy float64 array per trajectory.csv
    column, one element per sample (``solver.samples`` rows, fewer for a
    run that failed part-way). Columns by attribute (``tr.theta``) or by
    name (``tr["Omega"]``); ``columns`` lists them. Frames and definitions:
    ``tippetop run --help``."""

    t: NDArray[np.float64]
    """Time [s]."""
    theta: NDArray[np.float64]
    """Nutation angle between the symmetry axis and the vertical [rad]
    (0: standing on the heavy end; pi: inverted)."""
    theta_dot: NDArray[np.float64]
    """d theta / dt [rad/s]."""
    Omega: NDArray[np.float64]
    """Precession rate d phi / dt [rad/s]."""
    omega: NDArray[np.float64]
    """Spin: angular velocity along the symmetry axis [rad/s]."""
    ux: NDArray[np.float64]
    """Centre-of-mass velocity, precessing frame, horizontal towards the
    tilt [m/s]."""
    uy: NDArray[np.float64]
    """Centre-of-mass velocity, precessing frame, y = Z x x [m/s]."""
    uz: NDArray[np.float64]
    """Centre-of-mass velocity, vertical [m/s]."""
    N: NDArray[np.float64]
    """Normal force of the plane on the top [N] (negative: the plane would
    have to pull)."""
    slip: NDArray[np.float64]
    """Slip speed of the contact point on the plane [m/s]."""
    J: NDArray[np.float64]
    """Jellett's quantity [kg m^3/s] (its drift measures the integration
    error)."""
    energy: NDArray[np.float64]
    """Total energy, kinetic + m g h [J]."""
    work_friction: NDArray[np.float64]
    """Work done by friction since t = 0 [J] (<= 0)."""
    work_applied: NDArray[np.float64]
    """Work done by the applied force since t = 0 [J]."""
    hx: NDArray[np.float64]
    """Applied force H_x in effect, precessing frame [N]."""
    hy: NDArray[np.float64]
    """Applied force H_y in effect, precessing frame [N]."""
    rolling: NDArray[np.float64]
    """1 while rolling (exact Coulomb friction, slip held at zero), else 0."""
    x: NDArray[np.float64]
    """Centre-of-mass position on the plane, lab frame [m]."""
    y: NDArray[np.float64]
    """Centre-of-mass position on the plane, lab frame [m]."""
    z: NDArray[np.float64]
    """Centre-of-mass height above the plane [m]."""
    qw: NDArray[np.float64]
    """Attitude quaternion body -> lab, scalar part [1]."""
    qx: NDArray[np.float64]
    """Attitude quaternion body -> lab, x part [1]."""
    qy: NDArray[np.float64]
    """Attitude quaternion body -> lab, y part [1]."""
    qz: NDArray[np.float64]
    """Attitude quaternion body -> lab, z part [1]."""
    xp: NDArray[np.float64]
    """Contact point on the plane, lab frame [m]."""
    yp: NDArray[np.float64]
    """Contact point on the plane, lab frame [m]."""

    @property
    def columns(self) -> List[str]:
        """The column names, in trajectory.csv order (``COLUMNS``)."""
    @property
    def summary(self) -> Dict[str, Any]:
        """summary.json of the CLI as a dict: ``theta_final`` [rad],
        ``omega_final`` [rad/s], ``steps``, ``status``, ``events``,
        ``scenario`` (TOML), ``wall_seconds`` [s], ..."""
    @property
    def error(self) -> Optional[Dict[str, Any]]:
        """``None``, or for a run that failed part-way a dict ``time`` [s],
        ``kind`` (``"painleve"``, ``"step_limit"``, ...) and ``message``; the
        arrays then hold the samples up to the failure."""
    def to_dict(self) -> Dict[str, NDArray[np.float64]]:
        """All columns as a new dict of arrays, in column order."""
    def to_pandas(self) -> Any:
        """The columns as a pandas DataFrame (needs pandas)."""
    def __getitem__(self, name: str, /) -> NDArray[np.float64]:
        """The column ``name`` (KeyError if there is none)."""
    def __contains__(self, name: str, /) -> bool:
        """True if ``name`` is a column."""
    def __len__(self) -> int:
        """The number of samples (rows)."""

def run(scenario: Scenario, pose: bool = True) -> Trajectory:
    """Run ``scenario`` to ``solver.t_end`` (the CLI's ``tippetop run``),
    with the GIL released. Bit for bit the CLI's trajectory.csv and
    summary.json. Bad input raises ValueError; a run that fails part-way
    returns its partial trajectory with ``error`` set. Ctrl-C raises
    KeyboardInterrupt within a second. ``pose=False`` (``tippetop run
    --no-pose``): the pose is not computed and its columns (x, y, z, qw,
    qx, qy, qz, xp, yp) are left out; the vector model then integrates 10
    state components instead of 17 (the reduced model 8 instead of 14),
    every other column and the summary the same bits."""

_Grid = Union[Tuple[float, float, int], Tuple[float, float, int, Literal["log"]]]
"""``(lo, hi, n)``: n values from lo to hi, both included, evenly spaced;
``(lo, hi, n, "log")``: geometrically spaced (lo, hi > 0). The CLI's
``--vary KEY=LO:HI:N[:log]``."""

def sweep(
    scenario: Scenario,
    vary: Mapping[str, Union[_Grid, Sequence[float], NDArray[Any]]],
    threads: Optional[int] = None,
) -> Dict[str, NDArray[Any]]:
    """Run a grid of scenarios (the CLI's ``tippetop sweep``) on ``threads``
    threads (1 to 1024, an int; default one per core; fewer if that many
    runs at once would need more than 3 GiB), with the GIL released. At
    most 1 000 000 cases (the result is kept in memory; the CLI streams
    larger sweeps to disk).

    ``vary`` maps scenario keys (as in ``Scenario.set``) to their values in
    the key's SI unit: a tuple ``(lo, hi, n)`` or ``(lo, hi, n, "log")`` is
    the CLI's grid, a list or numpy array is taken as given. The cases are
    the grid over all keys, the first key varying slowest; each is
    ``scenario`` with every key set to its value.

    Returns one numpy array per sweep.csv column, in its order: the varied
    keys, then ``theta_final``, ``theta_max`` [rad], ``omega_final``,
    ``Omega_final`` [rad/s], ``first_time_theta_above_half_pi``,
    ``contact_lost_at`` [s], ``negative_normal_fraction``,
    ``rolling_fraction``, ``J_max_rel_drift`` [1], ``energy_final`` [J],
    ``steps``, ``rhs_evaluations`` (counts), all float64 with NaN where the
    CSV field is empty (an event that never happened, a case that did not
    load), and ``status`` (str: ``"ok"`` or the case's error; a failing case
    does not stop the sweep). Bit for bit the CLI's sweep.csv, whatever
    ``threads``. Bad input raises ValueError naming the key; Ctrl-C
    (KeyboardInterrupt) stops the sweep."""

def ensemble(
    scenario: Scenario,
    runs: int,
    threads: Optional[int] = None,
    first_passage: Optional[str] = None,
    step_check: bool = True,
) -> Dict[str, Any]:
    """Run a Langevin (or Brownian) scenario ``runs`` times with independent
    noise (the CLI's ``tippetop ensemble``) on ``threads`` threads (1 to
    1024, an int; fewer if that many runs at once would need more than 3
    GiB), with the GIL released. ``runs``: an int, 1 to 1 000 000
    (ValueError beyond, TypeError for another type). Run K is the scenario with ``thermal.run = r0 + K``
    (``r0`` its own ``thermal.run``), so
    ``run(scenario.set("thermal.run", r0 + K))`` replays it bit for bit.
    ``first_passage`` is the CLI's ``--first-passage`` (e.g.
    ``"theta<1.07,theta>2.07"``: each run stops at its first output row
    where it holds).

    Returns one numpy array per ensemble.csv column, in its order: ``run``,
    ``seed``, ``<col>_final`` for every trajectory column (its SI unit),
    ``theta_max``, ``theta_min`` [rad], ``N_min`` [N],
    ``negative_normal_fraction``, ``first_passage_time`` [s], ``censored``
    (1 or 0), ``t_reached`` [s] (float64, NaN where empty), ``status``
    (str), and ``summary`` (dict): the statistics of summary.json (means
    with 95 % intervals of the final theta, omega, Omega, energy; first
    passages with the Kaplan-Meier median and the escape rate [1/s]). Bit
    for bit the CLI's ensemble.csv, whatever ``threads``. Bad input raises
    ValueError naming the key; Ctrl-C (KeyboardInterrupt) stops it.

    ``step_check`` (default True) is the CLI's step check: the same runs
    again at ``solver.dt / 2`` (the step limit doubled, an independent
    seed ``thermal.seed + 0x9E3779B97F4A7C15``), about twice the
    ensemble's cost again. ``summary`` then carries summary.json's
    ``dt_converged`` (True: every statistic's change below its 95 %
    half-width; False: a step error resolved, use a smaller ``solver.dt``;
    None: unchecked), ``step_check`` (by statistic, ``theta_final`` ...
    ``first_passage.escape_rate``: ``scale``, ``at_dt`` and ``at_half_dt``
    each ``{dt [s], estimate, ci95}`` in the statistic's unit,
    ``step_error`` the change and ``statistical`` its 95 % half-width (that
    unit; ``|ln ratio|`` [1] on the log scale), ``family``, ``converged``;
    None unchecked) and ``step_unchecked`` (why not, absent when checked:
    ``"step_check=False"``, one run, fewer than 2 ok runs): the CLI's
    figures for the same inputs."""

def rare(
    scenario: Scenario,
    target: str,
    reset: Optional[str] = None,
    method: Literal["exact", "direct", "ams"] = "direct",
    replicas: Optional[int] = None,
    horizon: Optional[float] = None,
    max_steps: Optional[int] = None,
    threads: Optional[int] = None,
    coordinate: Optional[str] = None,
    particles: Optional[int] = None,
    kill: Optional[int] = None,
    max_trajectories: Optional[int] = None,
    crossings: Optional[int] = None,
    direct_steps: Optional[int] = None,
    pilot_steps: Optional[int] = None,
    basin: Optional[float] = None,
    interface: Optional[float] = None,
    step_check: bool = True,
) -> Dict[str, Any]:
    """A rare-event question about a stochastic scenario (the CLI's
    ``tippetop rare``), from its initial state: with ``reset`` (or
    ``horizon`` [s]) the probability ``P(target before reset [and before
    horizon])``, else the mean first-passage time to ``target`` [s].
    ``target`` and ``reset`` use the ``--first-passage`` grammar (e.g.
    ``"theta<1.22,theta>1.92"``).

    ``method``: ``"exact"``, the one-dimensional answer where theta is
    exactly a 1D diffusion (the Brownian mode on the plane; elsewhere
    ValueError with the reason); ``"direct"``, ``replicas`` runs (default
    1000) each until the target or the reset holds at the end of a step, or
    ``max_steps`` steps (default 1000000; censored); ``"ams"``, adaptive
    multilevel splitting: ``replicas`` independent replicas (default 20) of
    ``particles`` (default 100), ``kill`` killed per level (default 1), on
    the reaction ``coordinate`` (the CLI's ``--coordinate``: a
    trajectory.csv column, ``-COLUMN``, ``|COLUMN-C|`` or ``tilt_energy``;
    default theta towards the target), at most ``max_trajectories`` paths
    per replica (default 100000) and ``max_steps`` steps per path (default
    10000000); without ``reset`` the mean first-passage time by the flux
    relation (``crossings``, ``direct_steps``, ``pilot_steps``, ``basin``,
    ``interface`` as the CLI's options). The result has an ``ams`` dict
    (``coordinate``, ``particles``, ``standard_error``, ``interval``,
    ``extinct``, ``replica_estimates``, ``flux``, ...); no particle at the
    target gives estimate 0 with an upper bound. A replica out of budget
    raises RuntimeError. The GIL is released; Ctrl-C stops the run.

    Returns rare.json as a dict, the same figures as the CLI's (apart from
    ``wall_seconds``): ``quantity`` (``"probability"`` or
    ``"mean_first_passage_time"``), ``unit``, ``estimate``, ``ln_estimate``,
    ``ci95`` ([lo, hi]; Wilson for a probability, mean +- t s/sqrt(n) for a
    time), ``method``, ``replicas``, ``trajectories``, ``steps``,
    ``wall_seconds``, ``exact`` (``value``, ``ln_value``, ``watched`` and
    ``ln_watched`` for the path watched at every ``solver.dt``, the theta
    window; None where it does not apply, ``exact_unavailable`` saying
    why), ``target``, ``reset``, ``horizon``, ``max_steps``, ``tally``
    (direct: runs ending at the target, reset, horizon, budget, failed),
    ``seed``, ``first_run``, ``temperature``, ``scenario`` (TOML). Numbers
    past f64 or unknown are None. Bad input raises ValueError naming the
    option.

    ``step_check`` (default True; methods direct and ams) is the CLI's step
    check: the same question at ``solver.dt / 2`` (an independent seed,
    ``thermal.seed + 0x9E3779B97F4A7C15``; budgets in steps doubled),
    about twice the cost, compared with the answer returned (at
    ``solver.dt``). The dict then carries rare.json's ``dt_converged``
    (True: the change below its 95 % half-width; False: a step error
    resolved, use a smaller ``solver.dt``; None: unchecked),
    ``step_check`` (``scale``, ``at_dt`` and ``at_half_dt`` each ``{dt
    [s], estimate, ci95}``, ``step_error`` the change and ``statistical``
    its 95 % half-width in the answer's unit (``|ln ratio|`` [1] on the
    log scale), ``family``, ``converged``, ``refined_trajectories``,
    ``refined_steps``, ``refined_seed_offset``; None unchecked) and
    ``step_unchecked`` (why not, absent when checked:
    ``"step_check=False"``; the exact method, which has no step): the
    CLI's figures for the same inputs."""

@final
class Snapshot:
    """A copy of a ``Simulation`` at one instant (``Simulation.snapshot()``),
    exact to the bit; ``Simulation.restore`` goes back to it, in a
    simulation of the same scenario only."""

@final
class Simulation:
    """A run you can step, inspect, copy and continue. ``integrate_to(t)``
    integrates until the run has passed ``t`` [s] without ever shortening a
    step, so stepping in pieces gives the same trajectory, bit for bit, as
    ``run``; ``state`` is the state at ``time``. Used from two threads at
    once, the second gets RuntimeError (busy) instead of waiting."""

    def __new__(cls, scenario: Scenario) -> "Simulation":
        """A run of ``scenario`` at t = 0 (ValueError for bad input)."""
    def integrate_to(self, t: float) -> None:
        """Integrate until the run has passed ``t`` [s] (or ended, or failed:
        see ``error``), with the GIL released. ValueError (key ``t``) if ``t``
        is before the last time integrated to or after ``solver.t_end``,
        TypeError if it is not a number.
        Ctrl-C raises KeyboardInterrupt within a second; the run then stands
        at its last step (``time``) and goes on from there, bit for bit,
        with the next call."""
    @property
    def time(self) -> float:
        """The time [s] ``state`` refers to: the last time integrated to
        (earlier if the run failed before it)."""
    @property
    def state(self) -> Dict[str, float]:
        """The state at ``time`` as a dict: one trajectory.csv row, keyed by
        ``COLUMNS`` (SI units, radians)."""
    @property
    def error(self) -> Optional[Dict[str, Any]]:
        """``None``, or the failure that ended the run (as
        ``Trajectory.error``: ``time`` [s], ``kind``, ``message``)."""
    @property
    def is_finished(self) -> bool:
        """True once the run has reached ``solver.t_end`` or failed."""
    def snapshot(self) -> Snapshot:
        """A copy of the whole run as it stands (exact floats)."""
    def restore(self, snapshot: Snapshot) -> None:
        """Go back to ``snapshot`` (it replaces the run entirely).
        ValueError if the snapshot was taken from a simulation of another
        scenario (snapshots carry a fingerprint of their resolved
        scenario), naming the first key whose value differs."""
    def into_trajectory(self) -> Trajectory:
        """The run so far as a ``Trajectory``; after ``integrate_to(t_end)``
        it equals ``run(scenario)``. The simulation is left as it is (it is
        copied), so it can go on."""
