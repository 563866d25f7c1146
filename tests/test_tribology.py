"""Tribometer tests as scenes (brakewear.tribology): the scene files and their messages,
`brakewear run` on the packaged scenes (coarse settings; the full settings are slow
tests), conservation, the closed forms, partial slip, the k s equivalence and the
cycle jump's control."""
import json
import math
import re
from dataclasses import replace
from pathlib import Path

import meshio
import numpy as np
import pytest

from brakewear.cli import main
from brakewear.errors import SceneError, StepSizeError
from brakewear.scene import load_scene
from brakewear.scene.reader import available_scenes, scene_dir, scene_file
from brakewear.tribology import (
    CycleResult,
    JumpControl,
    TribometerScene,
    cycle_jumps,
    run_tribometer,
    tribometer_kinds,
)

SCENES = ("mccoll_fretting", "cruzado_block_on_ring", "pin_on_disc_cap")


def _variant(tmp_path: Path, name: str, **values) -> Path:
    """The packaged scene ``name`` with ``key = value`` lines replaced (file units)."""
    text = scene_file(name).read_text()
    text = text.replace('profile = "data/', f'profile = "{scene_dir()}/data/')
    for key, value in values.items():
        text, n = re.subn(rf"^{key} = [^#\n]*", f"{key} = {value}", text, count=1, flags=re.M)
        assert n == 1, key
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _run(args, capsys):
    rc = main(["run", *map(str, args), "--quiet"])
    return rc, capsys.readouterr()


@pytest.mark.parametrize("name", SCENES)
def test_packaged_scenes_load_and_are_listed(name):
    assert name in available_scenes()
    sc = load_scene(name)
    assert isinstance(sc, TribometerScene) and sc.tribometer
    assert sc.test.name in tribometer_kinds()
    record = sc.to_dict()
    assert json.loads(json.dumps(record))["test"] == sc.test.name
    assert set(sc.bodies) == set(sc.test.bodies)


@pytest.mark.parametrize("edit,message", [
    ({"stroke": "0.025\nspeed = 3.0"},
     r"test\.speed: unknown key 'speed' in \[test\]; allowed keys: radius, load, stroke"),
    ({"size": "0.5"}, r"mesh\.zone: 0\.35 mm is not allowed; the contact zone needs at least "
                      r"four elements"),
    ({"k": "-1e-14"}, r"bodies\.flat\.k: -1e-14 1/Pa is not allowed; it must be >= 0"),
    ({"modulus": '"psi"'}, r"units\.modulus: 'psi' is not allowed; allowed units: 'GPa'"),
    ({"mu": "3.0"}, r"interface\.mu: 3\.0 is not allowed; it must be <= 2"),
    ({"zone": "8.0"}, r"mesh\.zone: 8\.0 mm is not allowed; it must fit in the flat"),
    ({"quantity": '"flat.depth"'}, r"validation\.quantity: 'flat\.depth' is not allowed"),
    ({"test": '"pin_on_plate"'}, r"scene\.test: 'pin_on_plate' is not allowed; allowed: "
                                 r"'pin_on_disc', 'block_on_ring', 'reciprocating'"),
])
def test_bad_input_names_the_file_the_key_and_the_value(tmp_path, edit, message):
    path = _variant(tmp_path, "mccoll_fretting", **edit)
    with pytest.raises(SceneError, match=message) as exc:
        load_scene(path)
    assert str(exc.value).startswith(str(path))


def test_a_missing_body_and_an_unknown_table_are_refused(tmp_path):
    text = scene_file("mccoll_fretting").read_text()
    path = tmp_path / "s.toml"
    path.write_text(text.replace("[bodies.cylinder]", "[bodies.pad]"))
    with pytest.raises(SceneError, match=r"bodies\.pad: unknown body 'pad'; a reciprocating "
                                         r"test has the bodies flat, cylinder"):
        load_scene(path)
    path.write_text(text + "\n[thermal]\nenabled = true\n")
    with pytest.raises(SceneError, match=r"unknown table \[thermal\]"):
        load_scene(path)


def test_fretting_coarse_from_the_command_line(tmp_path, capsys):
    """McColl's test on a 10 um mesh for 600 cycles: gross slip (the tangential force
    reaches mu P), both faces worn, their worn areas in the ratio of their k to
    round-off, and the files a user opens."""
    path = _variant(tmp_path, "mccoll_fretting", size=0.01, cycles=600, frames=3)
    out = tmp_path / "run"
    rc, cap = _run([path, "--out", out], capsys)
    assert rc == 0, cap.err
    assert "worn ratio 1.52632 (k ratio 1.52632)" in cap.out
    s = json.loads((out / "summary.json").read_text())
    assert s["worn_ratio"] == pytest.approx(2.9 / 1.9, rel=1e-9)
    assert s["last_cycle"]["tangential_force_max_N_per_m"] == pytest.approx(0.9 * 18.5e3,
                                                                             rel=1e-6)
    flat = s["bodies"]["flat"]
    assert flat["depth_max"] > 0.1e-6 and flat["worn_area"] > 0
    # the worn area is Archard's k P s: 4 slips of about the stroke per cycle
    slip = s["last_cycle"]["slip_centre_m"]
    assert 0.9 * 100e-6 < slip < 100e-6
    assert flat["worn_area"] == pytest.approx(2.9e-14 * 18.5e3 * slip * 600, rel=0.03)
    m = meshio.read(out / "flat_00003.vtu")
    assert {"wear", "pressure", "displacement"} <= set(m.point_data)
    assert m.point_data["wear"].max() == pytest.approx(flat["depth_max"], rel=1e-12)
    assert 'timestep="600.0"' in (out / "flat.pvd").read_text()
    assert (out / "profile.png").is_file() and (out / "history.csv").is_file()
    # a second run into the folder is refused, --overwrite replaces it, --resume is refused
    rc, cap = _run([path, "--out", out], capsys)
    assert rc == 2 and "holds" in cap.err
    rc, cap = _run([path, "--out", out, "--resume"], capsys)
    assert rc == 2 and "runs from its start" in cap.err


def test_partial_slip_wears_an_annulus(tmp_path):
    """A stroke below the gross-slip displacement: the contact's centre sticks all
    through the cycle and does not wear; its rims slip and wear (fretting's W-shaped scar)."""
    sc = load_scene(_variant(tmp_path, "mccoll_fretting", stroke=0.0003, cycles=50,
                             size=0.005, zone=0.1))
    s = run_tribometer(sc, tmp_path / "run", figures=False)
    assert s["last_cycle"]["slip_centre_m"] < 1e-9 * 0.3e-6         # round-off: it sticks
    assert s["last_cycle"]["tangential_force_max_N_per_m"] < 0.9 * 0.9 * 18.5e3
    flat = s["bodies"]["flat"]
    assert flat["depth_max"] > 0.0 and flat["depth_centre"] < 1e-9 * flat["depth_max"]


def test_block_on_ring_against_the_measurement_and_the_closed_form(tmp_path, capsys):
    """The packaged scene as it is (a few seconds): the block's scar depth within 10 %
    of the measured one, and within 1 % of the rigid conforming scar in depth and width
    (its area is the closed form's to round-off: Archard's volume)."""
    out = tmp_path / "bor"
    rc, cap = _run(["cruzado_block_on_ring", "--out", out], capsys)
    assert rc == 0, cap.err
    s = json.loads((out / "summary.json").read_text())
    v = s["validation"]
    assert v["within_tolerance"] and abs(v["error"]) < 0.10, v
    cf = s["closed_form"]["figures"]
    assert abs(cf["depth_max"]["error"]) < 0.01 and abs(cf["scar_width"]["error"]) < 0.01, cf
    assert abs(cf["worn_area"]["error"]) < 1e-9
    assert len(s["measured_profile"]["x_m"]) > 50


def test_pin_on_disc_coarse_wears_the_cap(tmp_path, capsys):
    """The sphere pin on a disc that does not wear, on a coarse mesh: the worn volume is
    k F s to the track's curvature, the cap's height the closed form's to 3 %."""
    path = _variant(tmp_path, "pin_on_disc_cap", size=0.1, zone=0.4, distance=300000.0)
    out = tmp_path / "pod"
    rc, cap = _run([path, "--out", out], capsys)
    assert rc == 0, cap.err
    s = json.loads((out / "summary.json").read_text())
    cf = s["closed_form"]["figures"]
    assert abs(cf["worn_volume"]["error"]) < 1e-3, cf
    assert abs(cf["depth_max"]["error"]) < 0.03, cf
    assert s["bodies"]["disc"]["worn_volume"] == 0.0
    assert {"wear", "pressure"} <= set(meshio.read(out / "pin_00002.vtu").point_data)


def test_a_flat_pin_wears_at_its_rim_first(tmp_path):
    """A flat-ended pin (1 mm across, meshed as its cylinder): the worn volume is k F s
    to the track's curvature, and the rim, where a flat punch's pressure peaks,
    wears deeper than the centre."""
    text = scene_file("pin_on_disc_cap").read_text()
    text = text.replace('pin = "sphere"', 'pin = "flat"').replace("radius = 5.0 ", "radius = 0.5 ")
    for key, value in (("half_width", "0.5"), ("size", "0.125"), ("zone", "0.5"),
                       ("distance", "20000.0")):
        text = re.sub(rf"^{key} = [^ \n]*", f"{key} = {value}", text, count=1, flags=re.M)
    (tmp_path / "flat.toml").write_text(text)
    sc = load_scene(tmp_path / "flat.toml")
    assert sc.test.pin == "flat" and sc.bodies["pin"].half_width == pytest.approx(0.5e-3)
    s = run_tribometer(sc, tmp_path / "run", figures=False)
    pin = s["bodies"]["pin"]
    assert pin["worn_volume"] == pytest.approx(1.3e-16 * 10.0 * 20.0, rel=2e-3)
    assert pin["depth_max"] > 2 * pin["depth_centre"] > 0
    assert pin["scar_width"] == pytest.approx(1e-3, rel=1e-9)


def test_k_s_equivalence(tmp_path):
    """(k, s) and (2 k, s / 2), first jumps of 2 and 1 revolutions: the same jumps in
    k N, the same profile to round-off."""
    a = load_scene(_variant(tmp_path, "cruzado_block_on_ring", distance=1200000.0,
                            size=0.04))
    b = a.with_options(distance=0.5 * a.test.distance)
    b = replace(b, bodies={**b.bodies, "block": replace(b.bodies["block"],
                                                        k=2 * a.bodies["block"].k)})
    ra = run_tribometer(a.with_options(first_jump=2.0), tmp_path / "a", figures=False)
    rb = run_tribometer(b.with_options(first_jump=1.0), tmp_path / "b", figures=False)
    pa = np.loadtxt(tmp_path / "a" / "profile.csv", delimiter=",", skiprows=1, usecols=2)
    pb = np.loadtxt(tmp_path / "b" / "profile.csv", delimiter=",", skiprows=1, usecols=2)
    assert ra["jumps"] == rb["jumps"]
    assert np.max(np.abs(pa - pb)) <= 1e-9 * np.max(pa), np.max(np.abs(pa - pb)) / np.max(pa)


def _decay(rate0=1.0, tau=50.0):
    """A wear law with a known answer: dh/dn = rate0 exp(-h / (rate0 tau))."""
    def advance(d, last, N):
        h = d["x"]
        # backward Euler in one unknown: h1 = h + N rate0 exp(-h1 / (rate0 tau))
        h1 = h.copy()
        for _ in range(60):
            h1 = h1 - (h1 - h - N * rate0 * np.exp(-h1 / (rate0 * tau))) / (
                1 + N / tau * np.exp(-h1 / (rate0 * tau)))
        return CycleResult(rates={"x": (h1 - h) / N}, pressure=h1, slip=h1, figures={})
    return advance


def test_the_cycle_jump_bounds_its_error_and_grows():
    """On a law with a closed-form answer (h = rate0 tau ln(1 + n / tau)), a tighter
    tolerance gives a smaller error, the jumps grow as the rate settles, and a bound
    no jump can meet raises StepSizeError."""
    exact = 50.0 * math.log(1 + 2000 / 50.0)
    errs = []
    for tol in (0.02, 0.005):
        d, _, jumps = cycle_jumps(_decay(), None, {"x": np.zeros(1)}, 2000.0,
                                  JumpControl(tol=tol, first=1.0, min_jump=1e-6))
        errs.append(abs(d["x"][0] / exact - 1))
        assert jumps[-1].cycles == pytest.approx(2000.0)
        assert max(j.jump for j in jumps) > 20 * jumps[0].jump
    assert errs[1] < errs[0] < 0.05, errs
    with pytest.raises(StepSizeError, match="jumps in a row over the error bound"):
        cycle_jumps(_decay(), None, {"x": np.zeros(1)}, 2000.0,
                    JumpControl(tol=1e-30, first=1.0, min_jump=1e-300, max_rejects=5))


@pytest.mark.slow
def test_mccoll_full_from_the_command_line(tmp_path, capsys):
    """The packaged fretting scene as it is: the flat's scar depth at its centre within
    10 % of the measured 2.89 um, the worn areas in the ratio of the k within 2 %."""
    out = tmp_path / "mcc"
    rc, cap = _run(["mccoll_fretting", "--out", out], capsys)
    assert rc == 0, cap.err
    s = json.loads((out / "summary.json").read_text())
    assert s["validation"]["within_tolerance"], s["validation"]
    assert s["worn_ratio"] == pytest.approx(s["k_ratio"], rel=0.02)


@pytest.mark.slow
def test_pin_on_disc_full_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "pod"
    rc, cap = _run(["pin_on_disc_cap", "--out", out], capsys)
    assert rc == 0, cap.err
    cf = json.loads((out / "summary.json").read_text())["closed_form"]["figures"]
    assert abs(cf["depth_max"]["error"]) < 0.015 and abs(cf["worn_volume"]["error"]) < 1e-3


@pytest.mark.slow
def test_cycle_jump_study_converges():
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "cycle_jump", Path(__file__).resolve().parents[1] / "studies" / "cycle_jump.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    res = study.main(out=None, quick=True)
    d = sorted(res["fixed"], key=lambda r: r["first_jump"])
    errs = [abs(r["depth_centre_m"] / res["richardson_depth_centre_m"] - 1) for r in d]
    assert errs[0] < errs[-1]
