"""Parts defined here, outside the package, registered by name and run from scene files.

A toy interface model (a rigid pad on a uniform elastic bed), a toy wear law
(Archard's, written out) and a toy application (a brake application over a
number of rotor revolutions) are each defined in this file, registered with
the package's tables, named in a scene file and run -- and the interface and
the law resumed after the run was stopped -- without a change to any file of
the package (docs/extending.md walks through the same three).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace

import numpy as np
import pytest

from brakewear.duty import (
    ApplicationRecord,
    application_kinds,
    register_application,
    unregister_application,
)
from brakewear.errors import SceneError, WearError
from brakewear.interfaces import (
    InterfaceSolution,
    interface_models,
    register_interface,
    unregister_interface,
)
from brakewear.laws.base import archard_rate, register_wear_law, unregister_wear_law
from brakewear.mesh.rings import ring_wear_nodes
from brakewear.mesh.surface import surface_nodes, tributary_areas
from brakewear.output.runs import run_scene
from brakewear.registry import OptionKey
from brakewear.scene import load_scene
from brakewear.wear import ConstantSpeed, check_resume

CLAMP_MPA = 1.0


# --- a toy interface model ------------------------------------------------------------------

class ToyBed:
    """The pad's friction face pressed as a rigid body onto a uniform elastic bed:
    ``p_i = k max(0, d - g_i)`` with the approach ``d`` that carries the clamp force.
    The rotor wears in rings (an unmeshed rotor); no capability is declared."""

    name = "toy_bed"
    keys = (OptionKey("bed_modulus", "num", 1e12, lo=0.0, unit="Pa/m"),)

    @classmethod
    def build(cls, request):
        return cls(request.model, request.line_pressure, request.options["bed_modulus"])

    def __init__(self, model, line_pressure: float, modulus: float):
        pad = model.meshes["pad"]
        self.pad_nodes = surface_nodes(pad, "friction")
        self.x = pad.p[:, self.pad_nodes]
        self.r = np.hypot(self.x[0], self.x[1])
        self.area = tributary_areas(pad, "friction", self.pad_nodes)
        self.W, self.ring, self.rotor_area, self.rotor_x = ring_wear_nodes(self.r)
        self.rotor_nodes = None
        self.line_pressure, self.modulus = line_pressure, modulus
        self.force = line_pressure * model.geometry.clamp_area
        self.normal_stiffness = modulus * self.area

    @property
    def settings(self) -> dict:
        return {"modulus": self.modulus}

    def solve(self, offset, active, *, compliance=None, x0=None, load=None, mu=None):
        k = np.full(self.area.size, self.modulus)
        if compliance is not None:              # the implicit step's wear in series
            k = 1.0 / (1.0 / k + compliance)
        g, c = np.asarray(offset, dtype=float), k * self.area
        order = np.argsort(g)
        cs, cg = np.cumsum(c[order]), np.cumsum((c * g)[order])
        for m in range(g.size):                 # the m + 1 closest nodes touch
            d = (self.force + cg[m]) / cs[m]
            if m + 1 == g.size or d <= g[order[m + 1]]:
                break
        p = k * np.maximum(d - g, 0.0)
        return InterfaceSolution(p, p > 0)



# --- a toy wear law ---------------------------------------------------------------------------

@dataclass(frozen=True)
class ToyLaw:
    """Archard's law written out: ``dh/dt = k p v`` with one ``k`` everywhere."""

    k: float
    a: float = 1.0
    b: float = 1.0
    needs_temperature: bool = False

    name = "toy_law"
    keys = (OptionKey("toy_k", "num", lo=0.0, unit="1/Pa"),)

    @classmethod
    def build(cls, options, material):
        return cls(options["toy_k"])

    def coefficient_at(self, p, v, T=None):
        return np.full(np.broadcast(np.asarray(p), np.asarray(v)).shape, self.k)

    def rate(self, p, v, T=None):
        return archard_rate(self, self.coefficient_at(p, v, T), p, v)



# --- a toy application ------------------------------------------------------------------------

@dataclass(frozen=True)
class Turns:
    """The brake applied at ``line_pressure`` (Pa) while the rotor turns ``turns``
    times at ``omega`` (rad/s)."""

    line_pressure: float
    turns: float
    omega: float

    name = "turns"
    keys = (OptionKey("line_pressure", unit="MPa", scale=1e6), OptionKey("turns"),
            OptionKey("omega", unit="rad/s"))
    braked = True
    needs_vehicle = False

    def check(self, ctx):
        return 2.0 * math.pi * self.turns / self.omega

    def check_scene(self, vehicle, index):
        return None

    def run(self, brake, index):
        rec = ApplicationRecord(index, self.name, 0.0, 2.0 * math.pi * self.turns / self.omega,
                                line_pressure=self.line_pressure, omega0=self.omega,
                                omega1=self.omega)
        rec.r_eff = brake.r_eff(brake.solve(self.line_pressure).pressure,
                                self.line_pressure)
        rec.torque = 2 * brake.mu * self.line_pressure * brake.clamp_area * rec.r_eff
        return brake.wear(ConstantSpeed(self.omega), rec)


@pytest.fixture
def toys():
    """The three toys registered for one test, and taken out again."""
    register_interface(ToyBed)
    register_wear_law(ToyLaw)
    register_application(Turns)
    yield
    unregister_interface("toy_bed")
    unregister_wear_law("toy_law")
    unregister_application("turns")
    assert "toy_bed" not in interface_models() and "turns" not in application_kinds()


def _scene(tmp_path, name="toy", interface='model = "toy_bed"\nbed_modulus = 2e12',
           pad='k = 5e-15', extra="", numerics='scheme = "explicit"'):
    path = tmp_path / f"{name}.toml"
    path.write_text(f"""
[units]
length = "mm"
pressure = "MPa"
time = "s"
angular_speed = "rad/s"
temperature = "C"

[scene]
name = "{name}"
geometry = "default"

[components]
rotor = "rigid"
pad = "elastic"

[mesh]
size = 12.0

[environment]
line_pressure = {CLAMP_MPA}
omega = 55.0
duration = 60.0

[interface]
{interface}
mu = 0.4

[wear.pad]
{pad}

[wear.rotor]
k = 5e-16

[numerics]
{numerics}

[output]
figures = false
checkpoint_every = 1
vtu_every = 1
{extra}
""")
    return path


class _Stop(Exception):
    pass


def _stopped_then_resumed(scene, out, after: int) -> dict:
    """Run ``scene`` into ``out``, stop it while step ``after`` is reported (its checkpoint
    is the one before: a step is checkpointed once the next is asked for), resume it to
    the end."""
    def stop(step):
        if step.step == after:
            raise _Stop
    with pytest.raises(_Stop):
        run_scene(scene, out, progress=stop)
    return run_scene(scene, out, resume=True)


def test_a_toy_interface_runs_from_a_scene_file_and_resumes(toys, tmp_path):
    """The toy bed, named in a scene file with its own key, carries the clamp force
    as a uniform pressure on the flat new pad (the closed form ``F / A``); the
    explicit scheme books exactly the Archard volume as wear; a run stopped after
    two steps and resumed ends where an uninterrupted one does; and the checkpoint
    holds the bed's own setting, so a resume with another modulus is refused."""
    scene = load_scene(_scene(tmp_path))
    assert scene.interface.options == {"bed_modulus": 2e12}
    whole = run_scene(scene, tmp_path / "whole")
    model = scene.build_model()
    A = tributary_areas(model.meshes["pad"], "friction",
                        surface_nodes(model.meshes["pad"], "friction")).sum()
    first = json.loads(json.dumps(whole))["final"]     # a JSON round trip, as on disk
    rows = (tmp_path / "whole" / "history.csv").read_text().splitlines()
    p0 = float(rows[1].split(",")[rows[0].split(",").index("pressure_max_Pa")])
    assert p0 == pytest.approx(CLAMP_MPA * 1e6 * model.geometry.clamp_area / A, rel=1e-12)
    assert whole["pad_archard_m3"] == pytest.approx(first["pad_volume_m3"], rel=1e-12)
    assert whole["steps"] >= 4
    resumed = _stopped_then_resumed(scene, tmp_path / "resumed", after=2)
    assert resumed["resumed_from_step"] == 1 and resumed["steps"] == whole["steps"]
    assert resumed["final"]["pad_wear_max_m"] == pytest.approx(
        whole["final"]["pad_wear_max_m"], rel=1e-12)
    run = scene.build_run(model)
    other = replace(run, interface=ToyBed(model, run.line_pressure, 3e12))
    with pytest.raises(WearError, match=r"interface\.modulus"):
        check_resume(other, checkpoint=tmp_path / "whole" / "checkpoint.npz",
                     every=scene.output.checkpoint_every)


def test_a_toy_interface_key_is_checked_in_the_files_units(toys, tmp_path):
    """The model's own key is checked by its entry (SceneError naming it); a key of
    another model, or an interface the run's thermal coupling would need a load
    from, is refused by the scene before anything is meshed."""
    with pytest.raises(SceneError, match=r"interface\.bed_modulus: -1\.0 Pa/m is not allowed"):
        load_scene(_scene(tmp_path, interface='model = "toy_bed"\nbed_modulus = -1.0'))
    with pytest.raises(SceneError, match=r"interface\.winkler_modulus: a key of "
                                         r"interface\.model = 'winkler'"):
        load_scene(_scene(tmp_path, interface='model = "toy_bed"\nwinkler_modulus = 1e12'))
    with pytest.raises(SceneError, match=r"thermal\.enabled: true needs interface\.model = "
                                         r"'fe' or 'condensed'"):
        load_scene(_scene(tmp_path, extra="[thermal]\nenabled = true\n"))


def test_a_toy_interface_without_implicit_rings_takes_the_pads_compliance(toys, tmp_path):
    """The toy declares no ``implicit_rings``: the implicit scheme with a rotor that wears
    (its rings solved with the pad) is refused by the scene, naming the models that
    solve them and ``implicit_pad``, and by a run made in Python; ``implicit_pad`` is
    taken.  With a rotor that does not wear the implicit scheme hands the toy the pad's
    compliance alone: one backward Euler step from the flat new pad matches its
    closed form."""
    with pytest.raises(SceneError, match=r"numerics\.scheme: 'implicit' .*'implicit_pad'.* "
                                         r"needs interface\.model = 'fe' or 'winkler' or "
                                         r"'condensed'"):
        load_scene(_scene(tmp_path, numerics='scheme = "implicit"'))
    scene = load_scene(_scene(tmp_path, numerics='scheme = "implicit_pad"\nsteps = 1'))
    model = scene.build_model()
    run = scene.build_run(model)
    with pytest.raises(WearError, match=r"does not declare implicit_rings = True, which "
                                        r"numerics\.scheme = 'implicit'"):
        replace(run, numerics=replace(run.numerics, scheme="implicit")).resolved()
    path = _scene(tmp_path, "still", numerics='scheme = "implicit"\nsteps = 1')
    path.write_text(path.read_text().replace("[wear.rotor]\nk = 5e-16", ""))
    summary = run_scene(load_scene(path), tmp_path / "pad")
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    A, r = tributary_areas(pad, "friction", nodes), np.hypot(*pad.p[:2, nodes])
    # each node's wear compliance eps = k v dt in series with the bed (modulus K):
    # p_i = d / (1/K + eps_i) with the approach d that carries the clamp force
    eps = 5e-15 * 55.0 * r * 60.0
    d = CLAMP_MPA * 1e6 * model.geometry.clamp_area / np.sum(A / (1 / 2e12 + eps))
    assert summary["final"]["pad_wear_max_m"] == pytest.approx(
        np.max(eps * d / (1 / 2e12 + eps)), rel=1e-9)


def test_a_toy_wear_law_runs_from_a_scene_file_and_resumes(toys, tmp_path):
    """The toy law, named in [wear.pad] with its own key, gives the numbers of the
    built-in Archard law with the same k (both through one rate function), and
    resumes to the uninterrupted run."""
    toy = load_scene(_scene(tmp_path, "law", pad='model = "toy_law"\ntoy_k = 5e-15',
                            interface='model = "winkler"'))
    assert toy.wear_laws()[0] == ToyLaw(5e-15)
    builtin = load_scene(_scene(tmp_path, "builtin", interface='model = "winkler"'))
    a = run_scene(toy, tmp_path / "toy")
    b = run_scene(builtin, tmp_path / "builtin")
    assert a["steps"] == b["steps"]
    for key in ("pad_wear_max_m", "pad_volume_m3", "pressure_max_Pa"):
        assert a["final"][key] == pytest.approx(b["final"][key], rel=1e-12), key
    resumed = _stopped_then_resumed(toy, tmp_path / "resumed", after=2)
    assert resumed["final"]["pad_wear_max_m"] == pytest.approx(a["final"]["pad_wear_max_m"],
                                                               rel=1e-12)
    with pytest.raises(SceneError, match=r"wear\.pad\.toy_k: -1\.0 1/Pa is not allowed"):
        load_scene(_scene(tmp_path, pad='model = "toy_law"\ntoy_k = -1.0'))
    with pytest.raises(SceneError, match=r"wear\.pad\.k: .*model = 'toy_law'"):
        load_scene(_scene(tmp_path, pad='model = "toy_law"\ntoy_k = 5e-15\nk = 1e-15'))


def test_a_toy_application_runs_from_a_scene_file(toys, tmp_path):
    """The toy application, listed by kind in [schedule] applications, turns the rotor
    its number of turns (the angle 2 pi n, the time 2 pi n / omega) and wears the
    brake as a drag of that time does; a scene with a schedule starts from the
    beginning again (schedules keep no checkpoint)."""
    sched = ('[schedule]\napplications = [{kind = "turns", line_pressure = 0.5, turns = 20, '
             'omega = 40.0}, {kind = "drag", line_pressure = 0.5, duration = %r, '
             'omega = 40.0}]\n' % (2 * math.pi * 20 / 40.0))
    path = _scene(tmp_path, "turns", interface='model = "fe"', extra=sched,
                  numerics='scheme = "explicit"\nsteps = 2')
    text = path.read_text()
    for key in ("line_pressure", "omega", "duration"):     # the schedule sets them
        text = "\n".join(s for s in text.splitlines() if not s.startswith(key))
    path.write_text(text)
    scene = load_scene(path)
    assert [a.name for a in scene.schedule] == ["turns", "drag"]
    summary = run_scene(scene, tmp_path / "out")
    rows = (tmp_path / "out" / "applications.csv").read_text().splitlines()
    head = rows[0].split(",")
    turns, drag = (dict(zip(head, r.split(","))) for r in rows[1:])
    assert turns["kind"] == "turns" and summary["braked_applications"] == 2
    assert float(turns["rotor_angle"]) == pytest.approx(2 * math.pi * 20, rel=1e-12)
    assert float(turns["duration"]) == pytest.approx(2 * math.pi * 20 / 40.0, rel=1e-12)
    # the same load, time and speed from the same worn state's neighbour: the same
    # work to the torque drift of the second application's own wear
    assert float(drag["friction_face_J"]) == pytest.approx(float(turns["friction_face_J"]),
                                                           rel=0.05)
    with pytest.raises(SceneError, match=r"\[schedule\] runs from its start"):
        run_scene(scene, tmp_path / "out", resume=True)


def test_a_decision_entry_builds_the_model_it_chooses(tmp_path):
    """An entry may decide instead of build (an "auto" choice): the scene names it, its
    decision sees what the run needs, and the model it names is built with its own
    keys; names are registered once, and keys are read one way by every model."""
    from brakewear.interfaces import FEInterface, FoundationInterface

    class Cheapest:
        name, accepts_load = "cheapest", True

        @staticmethod
        def decide(request):
            return "fe" if "accepts_load" in request.needs else "winkler"

    class Again(Cheapest):
        name = "cheapest"

    class Odd(ToyBed):
        name, keys = "odd", (OptionKey("winkler_rotor", "num"),)

    register_interface(Cheapest)
    try:
        with pytest.raises(SceneError, match=r"'cheapest' is registered already"):
            register_interface(Again)
        with pytest.raises(SceneError, match=r"interface\.winkler_rotor: read as 'num'"):
            register_interface(Odd)
        cold = load_scene(_scene(tmp_path, interface='model = "cheapest"'))
        assert isinstance(cold.build_run().interface, FoundationInterface)
        hot = load_scene(_scene(tmp_path, interface='model = "cheapest"',
                                extra="[thermal]\nenabled = true\n"))
        assert isinstance(hot.build_run().interface, FEInterface)
    finally:
        unregister_interface("cheapest")
    assert "odd" not in interface_models()
