"""Type stubs of ``dembound._native``, the compiled part of the package
(PyO3, crates/dembound-py). Use it through :mod:`dembound`. SI units
throughout: m, kg, s, Pa, N, J."""

from os import PathLike
from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike[str]]

def cli_json(argv: list[str]) -> str:
    """Runs ``dembound ARGV…`` (a command with ``--json``) in this process
    and returns its JSON document as compact JSON text (read it with
    ``json.loads``: the CLI's document, floats bit for bit). GIL released
    while it runs; the CLI's warnings become ``UserWarning``.

    Raises ValueError (bad input: exit code 2 of the CLI, the same message,
    naming the key, the value and the allowed range) or RuntimeError (a run
    that failed: exit code 1)."""

def history(scenario: Optional[str], sets: list[str], points: int) -> dict[str, np.ndarray]:
    """The trajectory of a run, at most ``points`` rows evenly decimated:
    ``t`` (s), ``x`` (m, the gap, upward positive), ``v`` (m/s), ``a``
    (m/s²), ``overlap`` (m), ``force`` (N), ``in_contact`` (bool)."""

def batch_keys() -> list[tuple[str, str]]:
    """The scenario keys :func:`batch` can vary case by case, with units."""

def batch(
    scenario: Optional[str],
    sets: list[str],
    columns: list[tuple[str, npt.NDArray[np.float64]]],
) -> dict[str, np.ndarray]:
    """One run per row of ``columns`` through the batched SIMD path, GIL
    released. Returns ``steps`` (n,), ``dt`` (n,) s and per-contact (n,
    contacts) arrays: ``t_contact``, ``t_max_overlap``, ``t_rebound``,
    ``duration`` (s), ``max_overlap`` (m), ``max_force`` (N),
    ``max_acceleration`` (m/s²), ``impact_velocity``, ``rebound_velocity``
    (m/s), ``restitution`` (1), ``energy_dissipated`` (J)."""

class Scene:
    """A many-particle scene: spheres, plane walls, walls of boundary
    particles. SI: m, m/s, N, J, s.

    Every argument is checked: a bad one (None, bytes, complex, a float
    where a whole number is expected, a negative or huge integer, an array
    of a dtype that is not integer or float, a dict nested deeper than 32
    levels) raises ValueError naming it; NumPy scalars and integer or
    float32 arrays are converted to float64. A failure that is not the
    input's (a file that cannot be written) raises RuntimeError."""

    @classmethod
    def from_toml(cls, path: _Path, sets: Optional[list[str]] = None, threads: Optional[int] = None) -> Scene:
        """A scene from a scene file with ``--set``-style overrides
        (``["integration.steps=500"]``); ``threads`` (default 1) does not
        change the results."""
    @classmethod
    def from_dict(
        cls, scene: dict[str, Any], base_dir: Optional[_Path] = None, threads: Optional[int] = None
    ) -> Scene:
        """A scene from a dict with the scene file's structure; its
        ``particles`` may be left out and added with ``add_particles``."""
    @classmethod
    def from_checkpoint(cls, path: _Path, threads: Optional[int] = None) -> Scene:
        """The scene recorded in a checkpoint, continued from it bit for bit;
        the index of one written in parts under MPI (``[parallel]
        checkpoint_per_rank``) has its parts read and merged."""
    def add_particles(
        self,
        positions: npt.NDArray[np.float64],
        radii: npt.NDArray[np.float64],
        velocities: Optional[npt.NDArray[np.float64]] = None,
        fixed: Optional[npt.NDArray[np.bool_]] = None,
        material: Optional[int] = None,
    ) -> None:
        """Adds spheres before the first step: positions (n, 3) m, radii (n,)
        m, velocities (n, 3) m/s, fixed (n,) bool (or 0/1), material index
        (default 0). Arrays of any integer or float dtype, or lists."""
    def add_plane(self, point: tuple[float, float, float] | list[float], normal: tuple[float, float, float] | list[float], material: Optional[int] = None) -> None:
        """Adds a fixed plane wall through ``point`` (m), ``normal`` into the
        domain, before the first step."""
    def add_cylinder(self, point: tuple[float, float, float] | list[float], axis: tuple[float, float, float] | list[float], radius: float, inside: bool = True, length: Optional[float] = None, material: Optional[int] = None) -> None:
        """A fixed cylinder wall (tube of `radius` m about the axis through `point` along `axis`; `inside`: spheres inside it, else outside a post; `length` m: flat caps at point ± length/2·axis)."""
    def add_mesh(self, path: str | PathLike[str], scale: float = 1.0, translate: Optional[tuple[float, float, float] | list[float]] = None, rotate_axis: Optional[tuple[float, float, float] | list[float]] = None, rotate_angle: float = 0.0, material: Optional[int] = None) -> None:
        """A fixed triangle-mesh wall: the triangles of ``path`` (STL, binary or ASCII, or OBJ) placed by x' = R(scale·x) + translate, R a rotation of ``rotate_angle`` degrees about ``rotate_axis``; cleaning counts are warnings."""
    def set_wall_motion(self, k: int, velocity: Optional[tuple[float, float, float] | list[float]] = None, angular_velocity: Optional[tuple[float, float, float] | list[float]] = None, center: Optional[tuple[float, float, float] | list[float]] = None, start: float = 0.0, end: float = float("inf"), amplitude: Optional[tuple[float, float, float] | list[float]] = None, frequency: Optional[float] = None) -> None:
        """Prescribed rigid motion of wall ``k`` (a plane, cylinder, mesh or wall of boundary particles) before the first step: ``velocity`` m/s, ``angular_velocity`` rad/s about the axis through ``center`` (m), from ``start`` to ``end`` s, plus ``amplitude``·sin(2π ``frequency`` t) (m, Hz); its work is ``observe()["work_by_walls_J"]``."""
    def set_group_motion(self, group: int, velocity: Optional[tuple[float, float, float] | list[float]] = None, angular_velocity: Optional[tuple[float, float, float] | list[float]] = None, center: Optional[tuple[float, float, float] | list[float]] = None, start: float = 0.0, end: float = float("inf"), amplitude: Optional[tuple[float, float, float] | list[float]] = None, frequency: Optional[float] = None) -> None:
        """Prescribed rigid motion of the ``[[particles]]`` group ``group`` (file order; all its spheres fixed) before the first step: ``velocity`` m/s, ``angular_velocity`` rad/s about the axis through ``center`` (m), from ``start`` to ``end`` s, plus ``amplitude``·sin(2π ``frequency`` t) (m, Hz)."""
    def set_wall_servo(self, k: int, force: float, axis: tuple[float, float, float] | list[float], max_velocity: float, gain: Optional[float] = None) -> None:
        """Force control of wall ``k`` (a plane, cylinder or mesh without a motion) before the first step: it moves along ``axis`` at ``gain``·``max_velocity``·(F − N)/F m/s, clamped to ±``max_velocity``, N the spheres' push against ``axis`` (N), F = ``force`` N (LIGGGHTS's servo, kp = ``gain``, default 0.01)."""
    def set_wall_active(self, k: int, start: Optional[float] = None, end: Optional[float] = None) -> None:
        """The window wall ``k`` (a plane, cylinder or mesh without a servo) acts in, before the first step (``[[wall]] active = { from, to }``): the steps n with ``start`` ≤ n Δt < ``end`` s (default 0 and inf); the energy its contacts held when it vanishes shows in ``observe()["gate_energy_J"]``."""
    def step(self, n: int) -> None:
        """Advances n steps of Δt, 0 ≤ n ≤ 1e15 (GIL released)."""
    def run(
        self, duration: Optional[float] = None, progress: Optional[Callable[[int, int], Any]] = None
    ) -> int:
        """Runs ``duration`` s (whole steps), or to the scene's end; calls
        ``progress(done, total)`` about 100 times; returns the steps taken."""
    @property
    def time(self) -> float:
        """Simulated time, s."""
    @property
    def dt(self) -> float:
        """Δt, s (ValueError while the scene has no spheres)."""
    @property
    def deleted(self) -> tuple[int, float, float] | None:
        """Spheres removed so far under ``domain.outside = "delete"``:
        ``(count, mass in kg, energy carried out in J)``; None when the
        scene removes none."""
    @property
    def steps_done(self) -> int: ...
    @property
    def total_steps(self) -> int: ...
    def __len__(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Centres, (n, 3) m, input order."""
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """(n, 3) m/s."""
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]:
        """(n, 3) rad/s (zero without friction)."""
    @property
    def forces(self) -> npt.NDArray[np.float64]:
        """Force on each sphere at the last force evaluation, (n, 3) N."""
    @property
    def radii(self) -> npt.NDArray[np.float64]:
        """(n,) m."""
    @property
    def fixed(self) -> npt.NDArray[np.bool_]: ...
    @property
    def masses(self) -> npt.NDArray[np.float64]:
        """(n,) kg: 4/3 π r³ ρ of each sphere's material (fixed spheres too)."""
    @property
    def wall_forces(self) -> npt.NDArray[np.float64]:
        """Force on each wall, (walls, 3) N: what the last force stage applied."""
    @property
    def wall_torques(self) -> npt.NDArray[np.float64]:
        """Torque on each wall about its point in ``wall_torque_points``, (walls, 3) N m."""
    @property
    def wall_torque_points(self) -> npt.NDArray[np.float64]:
        """Each wall's torque point, (walls, 3) m: a plane's point, a cylinder's
        axis point, the centroid of a boundary-particle wall's spheres."""
    def wall_triangle_loads(self, k: int) -> dict[str, npt.NDArray[np.float64]]:
        """Loads of mesh wall ``k`` per triangle of its cleaned mesh (file order,
        degenerate and duplicate triangles dropped): ``force`` (n, 3) N on the
        wall, ``pressure`` (n,) Pa = |F·n|/A, ``shear`` (n,) Pa = |F_t|/A,
        ``area`` (n,) m², ``centroid`` (n, 3) m. ValueError when wall ``k``
        does not exist or is not a mesh."""
    def observe(self) -> dict[str, Any]:
        """The series.csv row now, keyed by its column names (units in the
        names: ``time_s``, ``kinetic_energy_J``, ``wall0_force_z_N``, …)."""
    @property
    def collisions(self) -> dict[str, np.ndarray]:
        """Completed contacts: ``i``, ``j`` (sphere or -1), ``wall`` (or -1),
        ``triangle`` (the mesh triangle of a mesh wall contact, or -1),
        ``t_start``, ``t_end``, ``duration`` (s), ``max_overlap`` (m),
        ``max_normal_force`` (N), ``impact_normal_velocity``,
        ``rebound_normal_velocity`` (m/s)."""
    def write_vtk(self, directory: _Path) -> PathLike[str]:
        """Writes ``snapshot_STEP.vtp`` into ``directory``; returns its path."""
    def checkpoint(self, path: _Path) -> None:
        """Writes a checkpoint (CBOR, the CLI's format)."""
    def restore(self, path: _Path) -> None:
        """Continues from a checkpoint of this same scene (whole, or the
        index of one written in parts: merged)."""
