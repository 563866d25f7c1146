"""The output folder of a run: does it hold one, may a new run write there, what to clear.

A run (``brakewear run``, the demo) writes its files into one folder.  A
second run into a folder that already holds one is refused unless the user
says what to do with the first: ``--overwrite`` (its files are removed once
the new run's input is checked, then the new run writes its own) or
``--resume`` (continue it).  :func:`finished_run` tells, from the checkpoint
alone, whether the run in a folder has already reached a scene's duration,
so that a ``--resume`` of a finished run can say so before anything is built.
"""
from __future__ import annotations

import logging
import os
import re
from pathlib import Path

from ..errors import SceneError

logger = logging.getLogger(__name__)

__all__ = ["RUN_FILES", "held_run", "check_new_out", "clear_run", "finished_run"]

#: the files whose presence means that a folder holds a run (a scene's or the demo's)
RUN_FILES = ("summary.json", "checkpoint.npz", "scene.json", "history.csv",
             "applications.csv", "pad.pvd", "rotor.pvd", "pad.vtu", "rotor.vtu")

#: every file a run or the demo writes, by name (removed by :func:`clear_run`)
_WRITTEN = re.compile(
    r"(summary\.json|checkpoint\.npz|scene\.json|history\.csv|applications\.csv"
    r"|(pad|rotor)(_\d+)?\.(vtu|pvd)|\.(pad|rotor)\.pvd\.tmp|\.history\.csv\.tmp"
    r"|\.(summary\.json|scene\.json|checkpoint\.npz|(pad|rotor)(_\d+)?\.(vtu|pvd))\.\d+\.tmp"
    r"|(pad_wear|pad_pressure|pad_temperature)(_in|_out)?\.png|rotor_temperature\.png"
    r"|history\.png|applications\.png|brake_surfaces\.png|pad_interface_pressure\.png"
    r"|rotor_von_mises\.png)$")


def held_run(out: str | os.PathLike) -> list[str]:
    """The files of an earlier run in ``out`` (its own, then its ``running_in/``'s, in
    the order of :data:`RUN_FILES`); empty when ``out`` holds none (or does not exist)."""
    out = Path(out)
    found = []
    for folder, prefix in ((out, ""), (out / "running_in", "running_in/")):
        if folder.is_dir():
            found += [prefix + f for f in RUN_FILES if (folder / f).is_file()]
    return found


def check_new_out(out: str | os.PathLike, key: str = "--out", overwrite: bool = False,
                  resume: bool = False, can_resume: bool = True) -> Path:
    """``out`` as a :class:`~pathlib.Path`, refused (:class:`~brakewear.errors.SceneError`,
    exit code 2, nothing written) when it already holds a run and neither
    ``overwrite`` nor ``resume`` is given, or when both are.  ``can_resume``:
    whether the message may offer ``--resume`` (the demo has none)."""
    out = Path(out)
    if overwrite and resume:
        raise SceneError(f"{key} = {str(out)!r}: --overwrite and --resume together; "
                         "--resume continues the run in the folder, --overwrite replaces it: "
                         "give one of them")
    held = held_run(out)
    if held and not (overwrite or resume):
        shown = ", ".join(held[:4]) + (", ..." if len(held) > 4 else "")
        how = ("--overwrite to replace it, --resume to continue it," if can_resume else
               "--overwrite to replace it")
        raise SceneError(f"{key} = {str(out)!r} already holds a run ({shown}); give {how} "
                         f"or another {key}")
    return out


def clear_run(out: str | os.PathLike) -> list[Path]:
    """Remove the files a run writes (by name) from ``out`` and its ``running_in/``;
    other files stay.  Returns the paths removed."""
    out = Path(out)
    removed = []
    for folder in (out, out / "running_in"):
        if not folder.is_dir():
            continue
        for f in sorted(folder.iterdir()):
            if f.is_file() and _WRITTEN.match(f.name):
                f.unlink()
                removed.append(f)
    if removed:
        logger.info("removed %d files of the earlier run in %s", len(removed), out)
    return removed


def finished_run(out: str | os.PathLike, duration: float) -> tuple[int, float] | None:
    """``(step, time)`` of the run in ``out`` when its checkpoint has reached
    ``duration`` (s), else None (no checkpoint, or a run still to continue)."""
    from ..wear.state import checkpoint_progress

    ck = Path(out) / "checkpoint.npz"
    if not ck.is_file():
        return None
    step, t = checkpoint_progress(ck)
    return (step, t) if t >= duration * (1 - 1e-12) else None
