"""dembound from Python: the bounce studies and the many-particle scene engine.

Every study function takes a scenario in one of three forms, which combine:

* ``scenario``: ``None`` (the paper's validation case), a path to a
  scenario TOML file, or a dict (nested ``{"particle": {"radius": 1e-3}}``
  or flat ``{"particle.radius": 1e-3}``), applied as ``--set`` overrides;
* keyword overrides with the keys of ``--set``, ``section__key=value``:
  ``particle__radius=1e-3`` (m), ``contact__law="linear"``,
  ``boundary__radius_ratio=float("inf")``.

They run the very code of the ``dembound`` command in this process and
return its ``--json`` document as plain Python objects (dicts, lists,
floats: the same numbers bit for bit, the same key names). All values SI:
m, kg, s, Pa, N, J. ``dembound keys`` (or :func:`keys`) lists every key
with its unit, default and allowed range.

Bad input raises :class:`ValueError` with the CLI's message, naming the key,
the value and the allowed range; a run that fails raises
:class:`RuntimeError`. The GIL is released while Rust computes.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _native
from ._native import Scene


def _cli(argv: list[str]) -> Any:
    """``dembound ARGV…`` (with ``--json``) in this process: its document."""
    return json.loads(_native.cli_json(argv))

__all__ = [
    "run",
    "exact",
    "validate",
    "sweep",
    "recommend",
    "restitution",
    "keys",
    "scene",
    "history",
    "batch",
    "Scene",
    "__version__",
]

__version__: str = _native.__version__

ScenarioLike = Union[None, str, "os.PathLike[str]", Mapping[str, Any]]
ListLike = Union[str, float, Iterable[float]]


# The deepest nesting of dicts and lists in one value (as the scene dicts
# of :class:`Scene`; a scenario value needs 2: ``law = {power = 1.25}``).
_MAX_DEPTH = 32

_ALLOWED = "allowed: a number, a bool, a str, a list or a dict"


def _refuse(key: str, value: Any, allowed: str = _ALLOWED, argument: bool = False) -> ValueError:
    """The ValueError for ``value`` at scenario key ```key``` (or, with
    ``argument``, the function argument ``key``)."""
    text = repr(value)
    if len(text) > 80:
        text = text[:80] + "…"
    name = key if argument else f"`{key}`"
    return ValueError(f"{name}: {text} of type {type(value).__name__} ({allowed})")


def _toml(value: Any, key: str = "value", depth: int = 1) -> str:
    """A Python value as the VALUE of ``--set SECTION.KEY=VALUE`` (TOML).
    NumPy scalars are the numbers they hold (float32 → float64 exactly),
    NumPy arrays of integers, floats or booleans are lists; anything else
    (None, bytes, complex, NumPy complex, object or string arrays) is a
    ValueError naming ``key``."""
    if depth > _MAX_DEPTH:
        raise ValueError(f"`{key}`: nested deeper than {_MAX_DEPTH} levels of dicts and lists")
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)  # shortest text that reads back as the same double
    if isinstance(value, str):
        return value  # a bare word, as on the command line
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biuf":
            raise _refuse(key, value, f"allowed: an array of integers, floats or booleans, not dtype {value.dtype}")
        return _toml(value.tolist(), key, depth)
    if isinstance(value, Mapping):
        items = []
        for k, v in value.items():
            if not isinstance(k, str):
                raise _refuse(f"{key}.{k!r}", k, "allowed: str keys")
            items.append(f"{k} = {_toml_quoted(v, f'{key}.{k}', depth + 1)}")
        return "{" + ", ".join(items) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_quoted(v, f"{key}[{i}]", depth + 1) for i, v in enumerate(value)) + "]"
    raise _refuse(key, value)


def _toml_quoted(value: Any, key: str, depth: int) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return _toml(value, key, depth)


def _flatten(prefix: str, value: Any, out: list[str]) -> None:
    # Sections and keys nest; a law given as a table ({"power": 1.25}) is
    # still one value, so nesting stops at section.key.
    if isinstance(value, Mapping) and prefix.count(".") < 1:
        for k, v in value.items():
            if not isinstance(k, str):
                raise _refuse(f"{prefix}.{k!r}" if prefix else repr(k), k, "allowed: str keys")
            _flatten(f"{prefix}.{k}" if prefix else k, v, out)
    else:
        out.append(f"{prefix}={_toml(value, prefix)}")


def _whole(name: str, value: Any, minimum: int, maximum: int) -> int:
    """An int (or NumPy integer) in ``minimum..=maximum``; a bool, a float
    (even a whole one) or anything else is a ValueError naming ``name``."""
    allowed = f"allowed: a whole number from {minimum} to {maximum}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise _refuse(name, value, allowed, argument=True)
    if not minimum <= int(value) <= maximum:
        raise ValueError(f"{name}: {int(value)} ({allowed})")
    return int(value)


def _real(name: str, value: Any) -> float:
    """An int or float (or NumPy integer or floating) as a float; a bool,
    a complex or anything else is a ValueError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise _refuse(name, value, "allowed: a real number", argument=True)
    return float(value)


def _flag(name: str, value: Any) -> bool:
    """A bool (or NumPy bool); anything else is a ValueError naming ``name``."""
    if not isinstance(value, (bool, np.bool_)):
        raise _refuse(name, value, "allowed: True or False", argument=True)
    return bool(value)


def _text(name: str, value: Any) -> str:
    """A str; anything else is a ValueError naming ``name``."""
    if not isinstance(value, str):
        raise _refuse(name, value, "allowed: a str", argument=True)
    return value


def _path(name: str, value: Any) -> str:
    """A str or os.PathLike path; anything else is a ValueError naming ``name``."""
    if not isinstance(value, (str, os.PathLike)):
        raise _refuse(name, value, "allowed: a path, str or os.PathLike", argument=True)
    path = os.fspath(value)
    if not isinstance(path, str) or not path:
        raise _refuse(name, value, "allowed: a non-empty path, str or os.PathLike", argument=True)
    return path


# The most rows of a trajectory (history, points): 1e9 rows of 7 columns
# are 56 GB, beyond any machine the rows would be plotted on.
_MAX_ROWS = 1_000_000_000
# The most worker threads (as `dembound scene --threads`).
_MAX_THREADS = 1024


def _scenario_args(scenario: ScenarioLike, keys: Mapping[str, Any]) -> tuple[Optional[str], list[str]]:
    """(scenario file or None, ``--set`` arguments)."""
    path: Optional[str] = None
    sets: list[str] = []
    if scenario is None:
        pass
    elif isinstance(scenario, (str, os.PathLike)):
        path = _path("scenario", scenario)
    elif isinstance(scenario, Mapping):
        _flatten("", scenario, sets)
    else:
        raise ValueError(
            f"scenario: expected None, a TOML path or a dict, got {type(scenario).__name__}"
        )
    for name, value in keys.items():
        _flatten(name.replace("__", "."), value, sets)
    return path, sets


def _argv(command: str, scenario: ScenarioLike, keys: Mapping[str, Any]) -> list[str]:
    path, sets = _scenario_args(scenario, keys)
    argv = [command, "--json"]
    if path is not None:
        argv.append(path)
    for s in sets:
        argv += ["--set", s]
    return argv


def _list(value: ListLike, name: str = "list") -> str:
    """A list option (``--r``, ``--zeta``, ``--law``…): text as on the
    command line (``"1,10,inf"``, ``"log:0.5:1000:13"``) or numbers."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        raise _refuse(name, value, "allowed: numbers, a list of them or the CLI's list text")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return _toml(float(value), name) if not isinstance(value, (int, np.integer)) else str(value)
    if isinstance(value, np.ndarray) and value.dtype.kind not in "iuf":
        raise _refuse(name, value, f"allowed: an array of integers or floats, not dtype {value.dtype}")
    if isinstance(value, (bytes, bytearray, Mapping)) or not isinstance(value, Iterable):
        raise _refuse(name, value, "allowed: numbers, a list of them or the CLI's list text")
    items = []
    for x in np.ravel(np.asarray(list(value), dtype=object)):
        if isinstance(x, str):
            items.append(x)
        elif isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, float, np.integer, np.floating)):
            raise _refuse(name, x, "allowed: numbers or str items")
        else:
            items.append(_toml(float(x), name))
    return ",".join(items)


def _option(argv: list[str], flag: str, value: Any) -> None:
    if value is not None:
        # FLAG=VALUE: a value starting with '-' ("-inf", "-1") is then not
        # read as another flag.
        argv.append(f"{flag}={_list(value, flag.lstrip('-'))}")


def run(
    scenario: ScenarioLike = None,
    *,
    compare_exact: bool = False,
    history: Optional[int] = None,
    force: bool = False,
    **keys: Any,
) -> dict:
    """One scenario, every contact: ``dembound run --json``.

    Returns ``{"scenario", "contacts", "steps", "dt", "contact_time_estimate", …}``
    with SI values (``contacts[k]["max_overlap"]`` in m, ``duration`` in s,
    ``max_force`` in N, velocities in m/s). ``compare_exact=True`` adds
    ``relative_errors`` (value/exact − 1). ``history=N`` adds ``"history"``:
    the trajectory in at most N evenly decimated rows as NumPy arrays
    (t s, x m, v m/s, a m/s², overlap m, force N, in_contact) — the one key
    that is not in the CLI's document.
    """
    argv = _argv("run", scenario, keys) + ["--quiet"]
    if _flag("compare_exact", compare_exact):
        argv.append("--compare-exact")
    if _flag("force", force):
        argv.append("--force")
    rows = None if history is None else _whole("history", history, 1, _MAX_ROWS)
    doc = _cli(argv)
    if rows is not None:
        path, sets = _scenario_args(scenario, keys)
        doc["history"] = _native.history(path, sets, rows)
    return doc


def history(scenario: ScenarioLike = None, *, points: int = 10_000, **keys: Any) -> dict[str, np.ndarray]:
    """The trajectory of a run as NumPy arrays, at most ``points`` rows
    (the CLI's history.csv): ``t`` (s), ``x`` (m, gap, upward positive),
    ``v`` (m/s), ``a`` (m/s²), ``overlap`` (m), ``force`` (N), ``in_contact``.
    The scenario is checked as :func:`run` checks it."""
    rows = _whole("points", points, 1, _MAX_ROWS)
    run(scenario, **keys)  # the CLI's checks (ranges, rebounds, step budget)
    path, sets = _scenario_args(scenario, keys)
    return _native.history(path, sets, rows)


def exact(scenario: ScenarioLike = None, **keys: Any) -> dict:
    """The exact per-contact values and the paper's estimates (eqs 26–30):
    ``dembound exact --json``. SI values."""
    return _cli(_argv("exact", scenario, keys))


def validate() -> dict:
    """The paper's Tables 1–2 against the exact reference and the convergence
    study in Δt: ``dembound validate --json``."""
    return _cli(["validate", "--json", "--quiet"])


def sweep(
    scenario: ScenarioLike = None,
    *,
    r: ListLike,
    zeta: ListLike,
    law: Optional[ListLike] = None,
    vary: Optional[Mapping[str, ListLike]] = None,
    **keys: Any,
) -> dict:
    """The grid of section 5: ``dembound sweep --json``.

    ``r`` (R_b/R_m) and ``zeta`` (E_b/E_m): numbers (``inf`` allowed) or the
    CLI's list text (``"1,10,inf"``, ``"log:0.5:1000:13"``); ``law``:
    ``"linear,hertz"`` or a list; ``vary``: ``{"motion.gap": [1e-3, 5e-3]}``
    (every combination). Returns ``{"variants", "references", "cases"}``;
    each case has its ``key`` (r, ζ, law, ``boundary_radius`` m,
    ``boundary_youngs_modulus`` Pa) and per contact the numerical and exact
    values (``duration`` s, ``max_overlap`` m, ``max_acceleration`` m/s²,
    ``max_force`` N, ``rebound_velocity`` m/s), normalised by the rigid
    half-space, and the relative errors. For NumPy grids see :func:`batch`.
    """
    argv = _argv("sweep", scenario, keys) + ["--quiet"]
    _option(argv, "--r", r)
    _option(argv, "--zeta", zeta)
    _option(argv, "--law", law)
    for key, values in (vary or {}).items():
        argv += ["--vary", f"{key.replace('__', '.')}={_list(values, key.replace('__', '.'))}"]
    return _cli(argv)


def recommend(
    scenario: ScenarioLike = None,
    *,
    tolerance: Union[None, str, float] = None,
    reference: Optional[str] = None,
    law: Optional[ListLike] = None,
    quantity: Optional[ListLike] = None,
    r: Optional[ListLike] = None,
    zeta: Optional[ListLike] = None,
    **keys: Any,
) -> dict:
    """Smallest ζ or r within ``tolerance`` (a fraction, 0.01, or ``"1%"``)
    of the rigid half-space (``reference="rigid"``) or of a flat wall of the
    boundary's material (``"half-space"``), the r–ζ trade-off, or the
    deviations at given r and ζ: ``dembound recommend --json``. Answers as
    ratios and in SI (m, Pa)."""
    argv = _argv("recommend", scenario, keys)
    if tolerance is not None:
        argv.append(f"--tolerance={tolerance if isinstance(tolerance, str) else _toml(_real('tolerance', tolerance))}")
    if reference is not None:
        argv.append(f"--reference={_text('reference', reference)}")
    _option(argv, "--law", law)
    _option(argv, "--quantity", quantity)
    _option(argv, "--r", r)
    _option(argv, "--zeta", zeta)
    return _cli(argv)


def restitution(
    scenario: ScenarioLike = None,
    *,
    target: float,
    law: Optional[ListLike] = None,
    r: Optional[ListLike] = None,
    zeta: Optional[ListLike] = None,
    calibrate: Optional[str] = None,
    **keys: Any,
) -> list:
    """The reverse restitution question: the e to enter (and the raw damping
    coefficient) for a wanted rebound ``target`` (0 < E < 1) on the boundary
    particle ``r``, ``zeta``, for one dissipative ``law``:
    ``dembound restitution --target E --json``, a list of answers (one per
    calibration). The restitution *sweep* has no JSON document in the CLI
    (it writes CSV with ``--out``) and is not offered here."""
    argv = _argv("restitution", scenario, keys)
    argv.append(f"--target={_toml(_real('target', target))}")
    _option(argv, "--law", law)
    _option(argv, "--r", r)
    _option(argv, "--zeta", zeta)
    if calibrate is not None:
        argv.append(f"--calibrate={_text('calibrate', calibrate)}")
    return _cli(argv)


def keys() -> Any:
    """Every scenario key with its unit, default and allowed range
    (``dembound keys --json``)."""
    return _cli(["keys", "--json"])


def scene(path: Union[str, "os.PathLike[str]"], *, threads: Optional[int] = None, **keys: Any) -> dict:
    """Runs a scene file to its end: ``dembound scene FILE --json`` (energies
    J, wall forces N, timings s). ``keys``: scene ``--set`` overrides,
    ``integration__steps=500``. For stepping, arrays and checkpoints use
    :class:`Scene`."""
    argv = ["scene", "--json", "--quiet", _path("path", path)]
    for name, value in keys.items():
        argv += ["--set", f"{name.replace('__', '.')}={_toml(value, name.replace('__', '.'))}"]
    if threads is not None:
        argv += ["--threads", str(_whole("threads", threads, 1, _MAX_THREADS))]
    return _cli(argv)


_ALIASES = {"r": "boundary.radius_ratio", "zeta": "boundary.modulus_ratio"}


def batch(scenario: ScenarioLike = None, **keys: Any) -> dict[str, np.ndarray]:
    """Many runs at once through the batched SIMD path, as NumPy arrays.

    Keyword arguments whose value is an array vary case by case (``r`` and
    ``zeta`` stand for ``boundary__radius_ratio`` and
    ``boundary__modulus_ratio``; also ``motion__gap`` m, ``motion__velocity``
    m/s, ``motion__gravity`` m/s², ``particle__radius`` m,
    ``particle__density`` kg/m³, ``particle__youngs_modulus`` Pa,
    ``particle__poisson_ratio``); they are broadcast together, so
    ``R, Z = np.meshgrid(r, zeta, indexing="ij")`` gives a grid. Scalars are
    ``--set`` overrides of the base scenario.

    Returns ``steps`` and ``dt`` (s) of the broadcast shape, and per contact
    (shape + (contacts,)) ``t_contact``, ``t_max_overlap``, ``t_rebound``,
    ``duration`` (s), ``max_overlap`` (m), ``max_force`` (N),
    ``max_acceleration`` (m/s²), ``impact_velocity``, ``rebound_velocity``
    (m/s), ``restitution`` and ``energy_dissipated`` (J): the integrator's
    values, each as ``run`` reports it. The GIL is released while it runs.
    """
    fixed: dict[str, Any] = {}
    varying: dict[str, np.ndarray] = {}
    for name, value in keys.items():
        key = _ALIASES.get(name, name.replace("__", "."))
        if isinstance(value, (np.ndarray, list, tuple)):
            allowed = [k for k, _ in _native.batch_keys()]
            if key not in allowed:
                raise ValueError(
                    f"`{key}` cannot vary case by case in batch(); the keys that can: {', '.join(allowed)}"
                )
            try:
                array = np.asarray(value)
            except (TypeError, ValueError) as e:
                raise ValueError(f"`{key}`: the values must be numbers ({e})") from None
            if array.dtype.kind not in "iuf":
                # Complex would lose its imaginary part, bool would be 0/1,
                # object and string arrays are not numbers.
                raise _refuse(key, value, f"allowed: integers or floats, not dtype {array.dtype}")
            varying[key] = array.astype(np.float64)
        else:
            fixed[key] = value
    shape: tuple[int, ...] = ()
    columns = []
    if varying:
        try:
            arrays = np.broadcast_arrays(*varying.values())
        except ValueError:
            shapes = ", ".join(f"`{k}` {a.shape}" for k, a in varying.items())
            raise ValueError(f"the per-case arrays do not broadcast to one shape: {shapes}") from None
        shape = arrays[0].shape
        columns = [(k, np.ascontiguousarray(a, dtype=np.float64).ravel()) for k, a in zip(varying, arrays)]
    path, sets = _scenario_args(scenario, {})
    for key, value in fixed.items():
        _flatten(key, value, sets)
    out = _native.batch(path, sets, columns)
    return {k: v.reshape(shape + v.shape[1:]) for k, v in out.items()}


def __dir__() -> list[str]:
    """``dir(dembound)``: the public names (``__all__``), not the modules
    and typing names this file imports."""
    return sorted(__all__)
