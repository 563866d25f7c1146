"""Random valid scene files through the reader and a short `brakewear run` (hypothesis,
derandomised): units, components, mesh, environment, interface, wear, thermal and
numerics drawn at random within what docs/scenes.md allows.  Each run ends with exit
code 0 and a finished summary.json, or with a named error: exit 2 (bad input, the
message naming the scene file), 3 (a solver error) or 4 (worn through), and an early
end still writes summary.json with its status and the reason."""
import json
import math

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from brakewear.cli import main  # noqa: E402
from test_scenefile import _default_dict, _dump  # noqa: E402

EXAMPLES = 80
LENGTH = {"mm": 1.0, "m": 1e-3}                    # mm in the file's unit
PRESSURE = {"Pa": 1e6, "kPa": 1e3, "MPa": 1.0, "bar": 10.0}     # MPa in the file's unit
TIME = {"s": 1.0, "min": 1 / 60, "h": 1 / 3600}
SPEED = {"rad/s": 1.0, "rpm": 60 / (2 * math.pi)}


@st.composite
def scenes(draw):
    d = _default_dict()
    u = {k: draw(st.sampled_from(sorted(v))) for k, v in
         (("length", LENGTH), ("pressure", PRESSURE), ("time", TIME),
          ("angular_speed", SPEED))}
    u["temperature"] = draw(st.sampled_from(["C", "K"]))
    d["units"] = u
    size = draw(st.floats(10.0, 14.0))
    d["mesh"] = {"size": size * LENGTH[u["length"]],
                 "rotor_size": draw(st.floats(1.0, 1.5)) * size * LENGTH[u["length"]]}
    rotor = draw(st.sampled_from(["rigid", "elastic"]))
    d["components"]["rotor"] = rotor
    ambient = draw(st.floats(-20.0, 40.0))
    d["environment"] = {
        "line_pressure": draw(st.floats(0.3, 6.0)) * PRESSURE[u["pressure"]],
        "omega": draw(st.floats(5.0, 150.0)) * SPEED[u["angular_speed"]],
        "duration": draw(st.floats(1.0, 600.0)) * TIME[u["time"]],
        "ambient": ambient + (273.15 if u["temperature"] == "K" else 0.0)}
    d["interface"]["model"] = draw(st.sampled_from(["fe", "fe", "winkler", "condensed"]))
    d["interface"]["mu"] = draw(st.floats(0.0 if d["interface"]["model"] != "condensed"
                                          else 0.2, 0.6))
    d["wear"] = {"pad": {"k": draw(st.floats(1e-15, 1e-13))}}
    if draw(st.booleans()):
        d["wear"]["rotor"] = {"k": draw(st.floats(1e-16, 1e-14))}
    steps = draw(st.one_of(st.none(), st.integers(1, 4)))
    d["numerics"] = {"scheme": draw(st.sampled_from(["implicit", "explicit"])),
                     "max_steps": 25, **({} if steps is None else {"steps": steps})}
    if rotor == "elastic" and d["interface"]["model"] == "fe" and draw(st.booleans()):
        d["thermal"] = {"enabled": True}
    d["output"] = {"figures": False, "vtu_every": draw(st.integers(1, 5))}
    return d


@pytest.mark.slow
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(scene=scenes())
def test_random_scene_files_run_or_end_with_a_named_error(scene, tmp_path_factory, capsys):
    tmp = tmp_path_factory.mktemp("scene")
    path = tmp / "fuzz.toml"
    path.write_text(_dump(scene))
    out = tmp / "run"
    code = main(["run", str(path), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    event(f"exit {code}")
    assert code in (0, 2, 3, 4), (code, err, scene)
    if code == 2:       # refused: names the file, writes nothing
        assert "fuzz.toml" in err or str(out) in err, (err, scene)
        return
    s = json.loads((out / "summary.json").read_text())
    status = {0: ("finished",), 3: ("solver_error", "temperature_limit"), 4: ("worn_through",)}
    assert s["status"] in status[code], (s["status"], err, scene)
    if code:
        event(f"ended by {s['ended']['error']}")
        assert "summary.json" in err, err
        assert s["ended"]["reason"] and s["ended"]["error"].endswith("Error"), s["ended"]
    else:
        assert s["final"]["time_s"] == pytest.approx(s["duration_s"], rel=1e-9)
        assert math.isfinite(s["final"]["pad_wear_max_m"]) and s["final"]["pad_wear_max_m"] >= 0
