"""What a scene file gets when a value is wrong: the message table of docs/scenes.md.

Each case below is one malformed scene: the packaged default scene (a drag), or a
vehicle's stops (``STOPS``), with one edit -- a key set, a key or table removed, a
map or a drive cycle beside it.  Each is read by the real reader
(:func:`brakewear.scene_from_dict`, what :func:`brakewear.load_scene` calls after
reading the file) as ``my_scene.toml``, and the message it raises is the table's
second column.  Nothing is meshed.

Run ``python studies/scene_messages.py`` to print the table, ``--write`` to put it
into docs/scenes.md between its markers (tests/test_scene_messages.py fails when
the table there differs from what this script makes).
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

from brakewear.errors import InputError
from brakewear.scene import scene_file, scene_from_dict

DOCS = Path(__file__).resolve().parents[1] / "docs" / "scenes.md"
BEGIN = "<!-- the table below is written by studies/scene_messages.py -->"
END = "<!-- end of the table written by studies/scene_messages.py -->"
SOURCE = "my_scene.toml"

#: the edits of the stops scene: the default scene's drag replaced by a vehicle's stops
STOPS = {"environment": {"line_pressure": None, "omega": None, "duration": None},
         "components": {"rotor": "rigid"},
         "vehicle": {"mass": 1800.0, "front_share": 0.7, "tyre_radius": 320.0},
         "schedule": {"stops": 2, "speed_from": 50.0, "deceleration": 1.5,
                      "interval": 60.0}}

#: a gap map that ends at the pad's centre line, a drive cycle braking at 400 km/h, a
#: friction map with a word for a number and one whose speeds end at 5 m/s
FILES = {"gap.csv": "r_mm,theta_deg,gap_um\n" + "".join(
             f"{r},{t},0\n" for r in (90, 140) for t in (-40, 0)),
         "cycle.csv": "time_s,speed_kmh,line_pressure_MPa\n0,400,2\n10,0,0\n",
         "mu.csv": "p_MPa,v_m_s,mu\n0.5,1,0.40\n0.5,5,x\n2,1,0.38\n2,5,0.36\n",
         "mu_slow.csv": "p_MPa,v_m_s,mu\n0.5,1,0.40\n0.5,5,0.39\n2,1,0.38\n2,5,0.36\n"}

#: (what the table shows, the base scene, the edits: table -> key -> value; a value None
#: removes the key, a table None the table)
CASES: list[tuple[str, dict, dict]] = [
    ("`[environment]` `speed = 55.0`", {}, {"environment": {"speed": 55.0}}),
    ('`[units]` `pressure = "psi"`', {}, {"units": {"pressure": "psi"}}),
    ("`[components]` without `pad`", {}, {"components": {"pad": None}}),
    ('`[interface]` `surfaces = ["pad.frction", "rotor.friction"]`', {},
     {"interface": {"surfaces": ["pad.frction", "rotor.friction"]}}),
    ("`[mesh]` `size = 30.0` (mm)", {}, {"mesh": {"size": 30.0}}),
    ("`[environment]` `line_pressure = -1.0` (MPa)", {},
     {"environment": {"line_pressure": -1.0}}),
    ("`[environment]` `ambient = -300.0` (C)", {}, {"environment": {"ambient": -300.0}}),
    ("`[interface]` `mu = 2.5`", {}, {"interface": {"mu": 2.5}}),
    ("`[interface]` `coning = 2.5` (mm)", {}, {"interface": {"coning": 2.5}}),
    ("`[interface]` `gap_file = \"gap.csv\"`, a map that ends at 0 deg", {},
     {"interface": {"gap_file": "gap.csv"}}),
    ('`[interface]` `mu_map = "mu.csv"`, a word in row 3', {},
     {"interface": {"mu_map": "mu.csv"}}),
    ('`[interface]` `mu_map = "mu_slow.csv"` (speeds 1 to 5 m/s), `map_outside = "error"`',
     {}, {"interface": {"mu_map": "mu_slow.csv", "map_outside": "error"}}),
    ('`[wear.pad]` `k = "soft"`', {}, {"wear.pad": {"k": "soft"}}),
    ("`[wear.pad]` `limit = 12.0` (mm)", {}, {"wear.pad": {"limit": 12.0}}),
    ("`[wear.rotor]` `limit = 15.0` (mm)", {}, {"wear.rotor": {"limit": 15.0}}),
    ("`[thermal]` `enabled = true`, `T_max = 10.0` (C)", {},
     {"thermal": {"enabled": True, "T_max": 10.0}}),
    ("`[thermal]` `enabled = true`, `T_initial = 950.0` (C)", {},
     {"thermal": {"enabled": True, "T_initial": 950.0}}),
    ('`[numerics]` `scheme = "rk4"`', {}, {"numerics": {"scheme": "rk4"}}),
    ('`[numerics]` `norm = "l1"`', {}, {"numerics": {"norm": "l1"}}),
    ("`[numerics]` `dh_fraction = 1.5`", {}, {"numerics": {"dh_fraction": 1.5}}),
    ("`[output]` `vtu_every = 0`", {}, {"output": {"vtu_every": 0}}),
    ("stops: `[environment]` `duration = 10.0`", STOPS, {"environment": {"duration": 10.0}}),
    ("stops: no `[vehicle]`", STOPS, {"vehicle": None}),
    ("stops: `[vehicle]` without `mass`", STOPS, {"vehicle": {"mass": None}}),
    ("stops: `[vehicle]` `mass = 20.0`", STOPS, {"vehicle": {"mass": 20.0}}),
    ("stops: `[vehicle]` `tyre_radius = 0.32` (mm)", STOPS,
     {"vehicle": {"tyre_radius": 0.32}}),
    ("stops: `[schedule]` `speed_to = 60.0`", STOPS, {"schedule": {"speed_to": 60.0}}),
    ("stops: `[schedule]` `dwell_speed = -10.0`", STOPS,
     {"schedule": {"dwell_speed": -10.0}}),
    ("stops: `[schedule]` `dwell_speed = 30.0` without `interval`", STOPS,
     {"schedule": {"interval": None, "dwell_speed": 30.0}}),
    ("stops: `[schedule]` `interval = 5.0`", STOPS, {"schedule": {"interval": 5.0}}),
    ("stops: `[schedule]` `deceleration = 15.0`", STOPS,
     {"schedule": {"deceleration": 15.0}}),
    ("stops: `[schedule]` `line_pressure = 3.0` and `interval = 1.0` for `deceleration`",
     STOPS, {"schedule": {"deceleration": None, "line_pressure": 3.0, "interval": 1.0}}),
    ("stops: `[schedule]` `line_pressure = 200.0` for `deceleration`", STOPS,
     {"schedule": {"deceleration": None, "line_pressure": 200.0}}),
    ('stops: `[schedule]` `file = "cycle.csv"`, a row at 400 km/h', STOPS,
     {"schedule": {"stops": None, "speed_from": None, "deceleration": None,
                   "interval": None, "file": "cycle.csv"}}),
]


def _edited(base: dict, edits: dict) -> dict:
    """The default scene's tables with ``base`` and then ``edits`` applied."""
    d = tomllib.loads(scene_file("default").read_text())
    for changes in (base, edits):
        for table, values in changes.items():
            if values is None:
                d.pop(table)
                continue
            t = d
            for part in table.split("."):
                t = t.setdefault(part, {})
            for k, v in values.items():
                if v is None:
                    t.pop(k, None)
                else:
                    t[k] = v
    return d


def message(base: dict, edits: dict, folder: Path) -> str:
    """The message the reader raises for the default scene with ``base`` and ``edits``
    (files of :data:`FILES` in ``folder``, named relative to it)."""
    try:
        scene_from_dict(_edited(base, edits), source=SOURCE, base=folder)
    except InputError as exc:
        return str(exc).replace(str(folder) + "/", "").replace(str(folder) + "\\", "")
    raise AssertionError(f"the scene with {edits} was accepted")


def rows() -> list[tuple[str, str]]:
    """(case, message) of every case of :data:`CASES`."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, text in FILES.items():
            (folder / name).write_text(text)
        return [(case, message(base, edits, folder)) for case, base, edits in CASES]


def table(found: list[tuple[str, str]]) -> str:
    """The Markdown table of docs/scenes.md, between its markers."""
    lines = [BEGIN, "", "| in the scene file | what you get |", "|---|---|"]
    lines += [f"| {case} | `{msg.replace('|', '/')}` |" for case, msg in found]
    return "\n".join([*lines, "", END])


def documented(text: str | None = None) -> str:
    """The table in docs/scenes.md now (markers included)."""
    text = DOCS.read_text(encoding="utf-8") if text is None else text
    return text[text.index(BEGIN):text.index(END) + len(END)]


def main(write: bool = False) -> str:
    """The table of the cases' messages; with ``write`` put into docs/scenes.md."""
    out = table(rows())
    if write:
        text = DOCS.read_text(encoding="utf-8")
        DOCS.write_text(text.replace(documented(text), out), encoding="utf-8")
    return out


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--write", action="store_true", help="write the table into docs/scenes.md")
    print(main(p.parse_args().write))
