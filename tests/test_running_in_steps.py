"""The study of the default scene's steps (studies/running_in_steps.py) on a coarse mesh."""
import json

import pytest

from studyload import load_study


def test_the_study_runs_reads_back_and_measures_against_its_reference(tmp_path, monkeypatch):
    study = load_study("running_in_steps")
    kw = dict(sizes=(12.0,), runs=("steps=3", "steps=none+dp_tol=0.5"), ref=3, out=tmp_path,
              duration=120.0, resolution=False)
    rows = study.main(**kw)
    assert [r["run"] for r in rows] == ["steps=3", "steps=none+dp_tol=0.5"]
    lines = [json.loads(x) for x in (tmp_path / "data" / "running_in_steps.jsonl")
             .read_text().splitlines()]
    by = {json.dumps(x["settings"], sort_keys=True): x for x in lines}
    coarse, fine = by['{"steps": 3}'], by['{"steps": 6}']
    for r in rows:
        for k in study.KEYS:
            ref = 2 * fine[k] - coarse[k]
            assert r["reference"][k] == pytest.approx(ref, rel=1e-12)
            assert r["errors"][k] == pytest.approx(r[k] / ref - 1, rel=1e-9, abs=1e-15)
        assert r["rotor_volume_error"] < 1e-12
    assert rows[0]["steps"] == 3 and rows[0]["limits"] == {"fixed": 3}
    assert rows[1]["steps"] >= 2 and "fixed" not in rows[1]["limits"]
    assert (tmp_path / "figures" / "running_in_steps.png").stat().st_size > 0

    # a second call reads every run back
    def no_run(*a, **k):
        raise AssertionError("run again")
    monkeypatch.setattr(study, "run_one", no_run)
    again = study.main(**kw, figure=False)
    assert [r["pad_max_um"] for r in again] == [r["pad_max_um"] for r in rows]
    assert study.parse_run("steps=none+scheme=implicit_pad") == {"steps": None,
                                                                  "scheme": "implicit_pad"}
    assert study.parse_run("steps=none+norm=l2") == {"steps": None, "norm": "l2"}
    with pytest.raises(ValueError, match="not one of"):
        study.parse_run("dt=3")
