"""The state of a wear history and its checkpoints (one format, read and written here).

A checkpoint (``.npz``) holds the whole :class:`WearState` of the loop, the
thermal state when coupled, and a *fingerprint*: every resolved input of the
run (geometry values, material data, wear and friction laws, line pressure,
speed, numerics, interface, thermal settings, package version).  A run
resumed from it repeats the uninterrupted run exactly, because every step is
solved from the stored state alone; a resume whose inputs differ from the
fingerprint is refused with what changed: each changed value in the unit of
the geometry file for its keys (lengths, angles, moduli, stiffnesses), a key a
scene file gave in its units under the file's name for it and in its unit, in SI
with the unit named for the others (:func:`check_fingerprint`).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..checks import user_scale
from ..errors import StoredFileError, WearError
from ..storage import load_arrays, save_arrays

logger = logging.getLogger(__name__)

__all__ = ["WearState", "fingerprint", "checkpoint_progress", "check_fingerprint",
           "read_checkpoint"]

_ARRAYS = ("pad_wear", "rotor_wear", "pressure", "active", "u", "u_prev")
_SCALARS = ("step", "time", "pad_archard", "rotor_archard", "dt_next", "dt_last")


@dataclass
class WearState:
    """Where a wear history stands after an accepted step (cumulative quantities).

    Parameters
    ----------
    step, time
        The accepted steps so far and the time reached (s).
    pad_wear, rotor_wear
        Cumulative depths (m) per pad friction node and per rotor wear node.
    pad_archard, rotor_archard
        The Archard volumes so far (m^3).
    pressure, active
        The contact state the next step starts from (None before the first
        solve).
    dt_next
        The next step's target (None: the limits decide).
    u, u_prev, dt_last
        The last two displacements of the implicit scheme and the step between
        them, from which the next solve's start is extrapolated.
    """

    step: int
    time: float
    pad_wear: np.ndarray
    rotor_wear: np.ndarray
    pad_archard: float = 0.0
    rotor_archard: float = 0.0
    pressure: np.ndarray | None = None
    active: np.ndarray | None = None
    dt_next: float | None = None
    u: np.ndarray | None = None
    u_prev: np.ndarray | None = None
    dt_last: float = float("nan")

    @classmethod
    def fresh(cls, n_pad: int, n_rotor: int, dt_next: float | None = None) -> WearState:
        """The unworn start."""
        return cls(0, 0.0, np.zeros(n_pad), np.zeros(n_rotor), dt_next=dt_next)

    def start_guess(self, dt: float) -> np.ndarray | None:
        """The displacement extrapolated over ``dt`` from the last two steps."""
        if self.u is None or self.u_prev is None:
            return self.u
        return self.u + (dt / self.dt_last) * (self.u - self.u_prev)

    def save(self, path: str | os.PathLike, prints: dict, extra: dict | None = None) -> None:
        """Write atomically: a kill during the write leaves the previous checkpoint intact."""
        path = Path(path)
        out = {k: np.zeros(0) if getattr(self, k) is None else np.asarray(getattr(self, k))
               for k in _ARRAYS}
        out.update({k: np.asarray(np.nan if getattr(self, k) is None else getattr(self, k))
                    for k in _SCALARS})
        out["fingerprint"] = np.asarray(json.dumps(prints, sort_keys=True))
        out.update({k: np.asarray(v) for k, v in (extra or {}).items()})
        save_arrays(path, out)

    @classmethod
    def load(cls, path: str | os.PathLike, prints: dict, n_pad: int,
             n_rotor: int, units: dict | None = None) -> tuple[WearState, dict]:
        """The state in ``path`` and its other arrays (thermal state), after checking
        it belongs to this run: same fingerprint (:func:`check_fingerprint`, changed
        values shown in ``units``), same numbers of wear nodes."""
        path = Path(path)
        d = read_checkpoint(path)
        _compare(path, _prints(path, d), prints, units)
        arrays = {k: d[k] for k in _ARRAYS}
        scalars = {k: d[k].item() for k in _SCALARS}
        extra = {k: d[k] for k in d if k not in _ARRAYS and k not in _SCALARS
                 and k != "fingerprint"}
        for k in _ARRAYS:
            if arrays[k].size == 0:
                arrays[k] = None
        arrays["active"] = None if arrays["active"] is None else arrays["active"].astype(bool)
        scalars["step"] = int(scalars["step"])
        if np.isnan(scalars["dt_next"]):
            scalars["dt_next"] = None
        state = cls(**arrays, **scalars)
        if state.pad_wear.shape != (n_pad,) or state.rotor_wear.shape != (n_rotor,):
            raise WearError(f"checkpoint {path} holds {state.pad_wear.size} pad and "
                            f"{state.rotor_wear.size} rotor wear nodes; this model has "
                            f"{n_pad} and {n_rotor}: it belongs to another model")
        logger.info("resumed at step %d, t = %.6g s", state.step, state.time)
        return state, extra


#: what to do with a checkpoint that cannot be used
REMEDY = ("run again without --resume (with --overwrite), or resume=False, to start from "
          "the beginning")


def read_checkpoint(path: str | os.PathLike) -> dict:
    """The arrays of the checkpoint ``path``, checked (:func:`brakewear.storage.load_arrays`:
    a file that is cut, damaged, foreign or not one a run wrote raises a
    :class:`~brakewear.errors.StoredFileError` naming it)."""
    path = Path(path)
    if not path.exists():
        raise WearError(f"resume=True but the checkpoint {path} does not exist")
    d = load_arrays(path, "the checkpoint", remedy=REMEDY)
    if "fingerprint" not in d:
        raise StoredFileError(f"the checkpoint {path} has no fingerprint of its inputs "
                              f"(written by an older brakewear, or not a checkpoint); {REMEDY}",
                              path=path)
    missing = [k for k in _ARRAYS + _SCALARS if k not in d]
    bad = [k for k in _SCALARS if k in d and d[k].shape != ()]
    if missing or bad:
        raise StoredFileError(f"the checkpoint {path} lacks "
                              f"{', '.join(missing) or ', '.join(bad) + ' as numbers'}: it is "
                              f"not a checkpoint of a wear history; {REMEDY}", path=path)
    step, time = d["step"].item(), d["time"].item()
    if not (float(step) == int(step) >= 0 and np.isfinite(time) and time >= 0):
        raise StoredFileError(f"the checkpoint {path} holds step {step}, t = {time} s: not a "
                              f"state a run reaches; {REMEDY}", path=path)
    return d


def _prints(path: Path, d: dict) -> dict:
    try:
        prints = json.loads(str(d["fingerprint"]))
    except ValueError:
        prints = None
    if not isinstance(prints, dict):
        raise StoredFileError(f"the checkpoint {path} has a damaged fingerprint of its inputs; "
                              f"{REMEDY}", path=path)
    return prints


def checkpoint_progress(path: str | os.PathLike) -> tuple[int, float]:
    """``(step, time)`` a checkpoint has reached (read checked: :func:`read_checkpoint`)."""
    d = read_checkpoint(path)
    return int(d["step"]), float(d["time"])


def check_fingerprint(path: str | os.PathLike, prints: dict,
                      units: dict | None = None) -> None:
    """Refuse the checkpoint ``path`` (a :class:`~brakewear.errors.WearError` naming
    what changed) unless it was written by a run with the inputs ``prints``.

    ``units`` is the ``[units]`` table of the geometry file (``BrakeGeometry.units``):
    changed geometry values are shown in its units (``3 GPa -> 2.9 GPa``), the
    others in SI with the unit named (``5e-15 1/Pa -> 2e-14 1/Pa``), each to 4
    significant digits (more where 4 would not tell them apart).
    """
    path = Path(path)
    _compare(path, _prints(path, read_checkpoint(path)), prints, units)


#: SI units of fingerprint keys outside the geometry file's units (by the whole key,
#: then by its last part)
_SI_UNITS = {"line_pressure": "Pa", "omega": "rad/s", "duration": "s", "limits.pad": "m",
             "limits.rotor": "m", "numerics.max_dh": "m", "wear_k": "1/Pa",
             "rho": "kg/m^3", "c": "J/(kg K)", "kappa": "W/(m K)", "alpha": "1/K",
             "activation_energy": "J/mol", "h_conv": "W/(m^2 K)",
             "contact_conductance": "W/(m^2 K)", "T_ambient": "K", "T_ref": "K",
             "T_initial": "K", "T_threshold": "K", "T_max": "K"}

_LENGTHS = ("radius", "thickness", "diameter", "length", "size", "clearance", "width",
            "depth", "height", "chamfer")


def _file_unit(key: str, units: dict | None) -> tuple[str, float] | None:
    """``(unit, SI value of one unit)`` the geometry file gives ``key`` in, or None."""
    from ..geometry.parts import ANGLE_UNITS, LENGTH_UNITS, MODULUS_UNITS
    from ..geometry.sections import STIFFNESS_UNITS

    if not units or not key.startswith("geometry."):
        return None
    last = key.rsplit(".", 1)[-1]
    if last == "bridge_tilt":
        return "mrad/kN", 1e-6
    if last == "finger_stiffness":
        return "MPa/mm", 1e9
    table, name = None, None
    if ".elastic." in key and last[:1] in ("E", "G"):
        table, name = MODULUS_UNITS, units.get("modulus")
    elif last.endswith("angle") or last == "rotor_margin":
        table, name = ANGLE_UNITS, units.get("angle")
    elif last.endswith("_stiffness"):
        table, name = STIFFNESS_UNITS, units.get("stiffness", "N/mm")
    elif last.endswith(_LENGTHS):
        table, name = LENGTH_UNITS, units.get("length")
    return (name, table[name]) if table is not None and name in table else None


#: fingerprint key -> the scene file's key: a run of a scene file names the key as the
#: file wrote it and shows its values in the file's unit (:func:`brakewear.checks.user_units`)
_SCENE_KEYS = {"line_pressure": "environment.line_pressure", "omega": "environment.omega",
               "duration": "environment.duration", "thermal.T_ambient": "environment.ambient",
               "thermal.T_initial": "thermal.T_initial", "thermal.T_ref": "thermal.T_ref",
               "pad_law.T_threshold": "wear.pad.T_threshold",
               "rotor_law.T_threshold": "wear.rotor.T_threshold",
               "numerics.max_dh": "numerics.max_dh", "numerics.wear_tol": "numerics.wear_tol",
               "limits.pad": "wear.pad.limit", "limits.rotor": "wear.rotor.limit"}


def _scene_unit(key: str) -> tuple[str, tuple[str, float, float]] | None:
    """(the scene file's key, its unit) of fingerprint ``key`` in a run of a scene file
    that gave it in its own units, else None."""
    scene_key = _SCENE_KEYS.get(key)
    scale = None if scene_key is None else user_scale(scene_key)
    return None if scale is None else (scene_key, scale)


def _shown_pair(key: str, old, new, units: dict | None) -> tuple[str, str]:
    """``old`` and ``new`` (fingerprint values) as text in the unit of ``key``."""
    unit = _file_unit(key, units)
    scene = _scene_unit(key)
    if scene is not None:
        unit = scene[1]
    if unit is None:
        si = _SI_UNITS.get(key) or _SI_UNITS.get(key.rsplit(".", 1)[-1])
        unit = None if si is None else (si, 1.0)
    a, b = _number(old), _number(new)
    if a is None and b is None:
        return _text(old), _text(new)
    for digits in range(4, 18):
        sa = _text(old) if a is None else _in_unit(a, unit, digits)
        sb = _text(new) if b is None else _in_unit(b, unit, digits)
        if sa != sb:
            break
    return sa, sb


def _number(v) -> float | list | None:
    """A fingerprint value as a number (a float's repr, an int) or a list of them."""
    if isinstance(v, list):
        vs = [_number(x) for x in v]
        return None if any(x is None or isinstance(x, list) for x in vs) else vs
    if isinstance(v, bool) or v is None:
        return None
    if isinstance(v, int):
        return v
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def _in_unit(v, unit: tuple | None, digits: int) -> str:
    """``v`` (SI) in ``unit``: ``(name, factor)`` or ``(name, factor, offset)``."""
    if isinstance(v, list):
        return "[" + ", ".join(_in_unit(x, unit, digits) for x in v) + "]"
    if isinstance(v, int) and unit is None:
        return str(v)
    if unit is None:
        return f"{v:.{digits}g}"
    name, factor, offset = (*unit, 0.0)[:3]
    return (f"{(v - offset) / factor:.{digits}g} {name}" if math.isfinite(v)
            else f"{v} {name}")


def _text(v) -> str:
    return "(absent)" if v is _ABSENT else str(v)


_ABSENT = object()


def _compare(path: Path, old: dict, new: dict, units: dict | None = None) -> None:
    changed = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
    if changed:
        shown = "; ".join("{}: {} -> {}".format(
            (_scene_unit(k) or (k,))[0], *_shown_pair(k, old.get(k, _ABSENT),
                                                     new.get(k, _ABSENT), units))
            for k in changed[:5])
        more = f" (and {len(changed) - 5} more)" if len(changed) > 5 else ""
        raise WearError(f"checkpoint {path} was written by a run with other inputs: {shown}"
                        f"{more}. Resume with the same inputs, or run again without resume")


def _plain(value, key: str, out: dict) -> None:
    """Flatten ``value`` into ``out`` as dotted keys of JSON-comparable values."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value) if f.compare}
    if isinstance(value, dict):
        for k, v in value.items():
            _plain(v, f"{key}.{k}" if key else str(k), out)
    elif isinstance(value, (list, tuple)) and not any(isinstance(v, (dict, list, tuple))
                                                      or dataclasses.is_dataclass(v)
                                                      for v in value):
        out[key] = [_scalar(v) for v in value]
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _plain(v, f"{key}.{i}", out)
    else:
        out[key] = _scalar(value)


def _scalar(v):
    if v is None or isinstance(v, (bool, str)):
        return v
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return repr(float(v))        # exact, and NaN compares equal to itself
    if isinstance(v, np.ndarray):
        a = np.ascontiguousarray(v)
        return f"array{a.shape}:{hashlib.sha1(a.tobytes()).hexdigest()[:16]}"
    if callable(v):
        return getattr(v, "__qualname__", type(v).__name__)
    return repr(v)


def fingerprint(**inputs) -> dict:
    """Every resolved input of a run, flattened to dotted keys (see the module docstring)."""
    from .. import __version__

    out: dict = {}
    _plain({**inputs, "brakewear_version": __version__}, "", out)
    return out
