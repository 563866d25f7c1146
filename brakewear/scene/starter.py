"""Starting files for your own brake: an annotated geometry and a scene to edit.

:func:`write_new_scene` (``brakewear new-scene NAME``) writes ``NAME.toml``,
a brake geometry, and ``NAME_scene.toml``, a scene that runs it, into a
folder.  They start from a packaged pair -- ``default`` (the idealised
brake: one pad, a solid ring clamped at its inner radius, a fixed caliper's
mirror plane) or ``floating`` (a single-piston floating caliper on a hat
rotor) -- with every key and its comment as packaged, under a header that
says what to take from the drawing for each table.  Both files load as they
are written (a scene of the packaged brake under another name); an existing
file is never overwritten.  docs/howto_own_brake.md goes through them step by
step.
"""
from __future__ import annotations

import logging
import re
from os import PathLike
from pathlib import Path

from ..errors import SceneError
from ..geometry.files import geometry_file
from .reader import scene_file

logger = logging.getLogger(__name__)

__all__ = ["STARTS", "write_new_scene"]

#: the packaged brakes a new scene can start from
STARTS = ("default", "floating")

_GEOMETRY_HEADER = """\
# {name}: a brake geometry to edit from your drawing.  Written by
# `brakewear new-scene {name} --from {start}`: the packaged {start!r} geometry,
# {what},
# whose values and comments stand here until you replace them.  Step by step:
# docs/howto_own_brake.md; every key and its allowed range: docs/geometry.md.
# From the drawing:
#   [rotor]   outer_radius: half the rotor diameter; inner_radius: the friction
#             ring's inner edge; thickness: the ring's full thickness; a vented
#             ring: [rotor.vents]; held by a hat: mount = "hat" and [rotor.hat]
#   [pad]     the lining's inner and outer radius and its arc angle
#             (2 asin(c / 2r) for a chord c at radius r), the lining's and the
#             backplate's thickness, their materials (your own: [materials.NAME])
#   [piston]  bore_diameter: the hydraulic bore (it sets the clamp force);
#             diameter: the footprint on the backplate; radius: the piston
#             axis's distance from the rotor axis
#   [caliper] "fixed" (the same pistons on both sides) or "floating" (the
#             piston on the inboard pad, [[caliper.fingers]] on the outboard)
#   [mesh]    the element size the scene's [mesh] table refines
# Coordinates: rotor axis z, friction interface at z = 0, pad centred on the
# +x axis; the rotor turns in +theta, so the leading pad end is at
# center_angle - arc_angle/2.

"""

_SCENE_HEADER = """\
# {name}_scene: what to run on the brake of {name}.toml.  Written by
# `brakewear new-scene {name} --from {start}` from the packaged {start!r} scene,
# {what}.
# Set the line pressure, the speed, the duration, the friction coefficient and
# the wear laws of your question.  Every key: docs/scenes.md; step by step:
# docs/howto_own_brake.md.
# `brakewear run {name}_scene.toml` first prints the mesh and the estimated
# error of its pad wear from the mesh-converged answer, with a warning when
# the mesh is coarser than the 2 % mesh of the default brake.

"""

_WHAT = {"default": ("the idealised brake (one pad, a solid ring clamped inside, a mirror plane)",
                     "an hour of drag at 1 MPa and 55 rad/s, mu 0.4"),
         "floating": ("a single-piston floating caliper on a hat rotor, both pads",
                      "an hour of drag at 1 MPa and 55 rad/s, mu 0.4, both pads")}

#: the default scene's comment on its mesh speaks of the default brake; a new brake reads this
_MESH_NOTE = """\
# The default brake's 2 % mesh (docs/performance.md, "The accuracy every run
# states"): the pad's in-plane size and the layers through its backplate set
# the pad wear's error.  For another brake keep the pad's element size at
# about its lining's radial width / 29 (1.5 mm on the default's 43 mm) and 8
# layers through the backplate; the rotor matters less.
"""


def _body(text: str) -> str:
    """A packaged file from its first table on (its own header left out)."""
    return text[text.index("\n[") + 1:]


def _replace(text: str, pattern: str, new: str) -> str:
    out, n = re.subn(pattern, new, text, count=1, flags=re.M)
    if n != 1:  # pragma: no cover - the packaged files and this module must agree
        raise RuntimeError(f"new-scene: the packaged scene has no line matching {pattern!r}")
    return out


def write_new_scene(name: str, folder: str | PathLike = ".",
                    start: str = "default") -> tuple[Path, Path]:
    """Write ``folder/NAME.toml`` (a geometry) and ``folder/NAME_scene.toml`` (a scene
    that runs it), both copies of a packaged pair (``start``) under headers that say
    what to take from a drawing; return their paths.

    Raises :class:`~brakewear.errors.SceneError` (nothing written) for a name that is
    not a plain file name, an unknown ``start``, or when either file exists.
    """
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name) or name.endswith(".toml"):
        raise SceneError(f"new-scene: name {name!r} is not allowed; give a plain file name "
                         "without .toml (letters, digits, _ . -), e.g. my_brake")
    if start not in STARTS:
        raise SceneError(f"new-scene: --from {start!r} is not allowed; allowed: "
                         f"{', '.join(STARTS)}")
    folder = Path(folder)
    geo, scn = folder / f"{name}.toml", folder / f"{name}_scene.toml"
    there = [str(p) for p in (geo, scn) if p.exists()]
    if there:
        raise SceneError(f"new-scene: {' and '.join(there)} already "
                         f"{'exists' if len(there) == 1 else 'exist'}; nothing was written "
                         "(choose another name or --dir, or move the files away)")
    what_geo, what_scene = _WHAT[start]
    geometry = (_GEOMETRY_HEADER.format(name=name, start=start, what=what_geo)
                + _body(geometry_file(start).read_text()))
    scene = _body(scene_file(start).read_text())
    scene = _replace(scene, r'^name = ".*"$', f'name = "{name}"')
    scene = _replace(scene, r'^description = ".*"$',
                     f'description = "{name}: edit from the packaged {start} scene"')
    scene = _replace(scene, r'^geometry = .*$',
                     f'geometry = "{name}.toml"'.ljust(27) + "# the brake, relative to this file")
    if start == "default":
        scene = _replace(
            scene,
            r"^# Fine where the pad wear's error is(?:.*\n)*?# changes the pad's "
            r"answer little and stays coarser\.\n",
            _MESH_NOTE,
        )
    scene = _SCENE_HEADER.format(name=name, start=start, what=what_scene) + scene
    folder.mkdir(parents=True, exist_ok=True)
    geo.write_text(geometry)
    scn.write_text(scene)
    logger.info("wrote %s and %s", geo, scn)
    return geo, scn
