"""studies/readme_timing.py measures commands idle and with a busy core and writes the docs'
tables between their markers; here on commands of a fraction of a second."""
import json
import os
import re
import sys
from pathlib import Path

import pytest

from studyload import load_study

timing = load_study("readme_timing")
timing.WARMUP = 0.05          # the busy process's start, shortened for commands of 0.2 s
ROOT = Path(__file__).resolve().parents[1]


def _quick() -> dict:
    """A command line per command that takes ~0.2 s; the tests' prints pytest durations."""
    nap = [sys.executable, "-c", "import time; time.sleep(0.2)"]
    durations = ("import time; time.sleep(0.2); print('=== slowest durations ===');"
                 "print('12.50s call     tests/test_a.py::test_slow');"
                 "print('3.25s setup    tests/test_b.py::test_x')")
    return {**{n: nap for n in timing.COMMANDS}, "tests": [sys.executable, "-c", durations]}


def test_the_docs_hold_the_markers_the_script_writes_between():
    for path, tag in ((ROOT / "README.md", "readme-timing"),
                      (ROOT / "docs" / "performance.md", "readme-timing-detail")):
        text = path.read_text()
        assert text.count(f"<!-- {tag}:start -->") == 1 == text.count(f"<!-- {tag}:end -->")


def test_a_pass_idle_and_busy_writes_both_tables(tmp_path):
    readme, perf = tmp_path / "README.md", tmp_path / "performance.md"
    readme.write_text(
        "intro\n<!-- readme-timing:start -->\nold\n<!-- readme-timing:end -->\ntail\n"
    )
    perf.write_text("<!-- readme-timing-detail:start -->\n<!-- readme-timing-detail:end -->\n")
    data = tmp_path / "timing.json"
    rec = timing.main(loads=("idle", "busy"), lines=_quick(), work=tmp_path / "w",
                      readme=readme, performance=perf, data=data)
    for load in ("idle", "busy"):
        for name in timing.COMMANDS:
            r = rec["runs"][load][name]
            assert r["returncode"] == 0 and 0.15 < r["wall_s"] < 30, (load, name, r)
    assert tuple(rec["runs"]["idle"]["tests"]["slowest"][0]) == \
        (12.5, "call tests/test_a.py::test_slow")
    text = readme.read_text()
    assert text.startswith("intro\n<!-- readme-timing:start -->\n| command | idle |")
    assert "old" not in text and text.endswith("<!-- readme-timing:end -->\ntail\n")
    assert re.search(r"\| `brakewear run thermal` \| \d+ s \| \d+ s \|", text), text
    assert "`call tests/test_a.py::test_slow` 12 s" in perf.read_text()
    assert json.loads(data.read_text())["runs"]["busy"]["demo"]["returncode"] == 0


def test_the_busy_core_spins_while_it_is_held_and_stops():
    with timing.busy_core(True) as pid:
        with open(f"/proc/{pid}/stat") as fh:
            before = sum(int(v) for v in fh.read().split()[13:15])
        import time
        time.sleep(0.5)
        with open(f"/proc/{pid}/stat") as fh:
            after = sum(int(v) for v in fh.read().split()[13:15])
        assert after > before, "the busy process did not run"
    assert not os.path.exists(f"/proc/{pid}") or \
        open(f"/proc/{pid}/stat").read().split()[2] == "Z"


def test_a_second_pass_replaces_only_what_it_measured(tmp_path):
    readme, perf = tmp_path / "R.md", tmp_path / "P.md"
    readme.write_text("<!-- readme-timing:start -->\n<!-- readme-timing:end -->\n")
    perf.write_text("<!-- readme-timing-detail:start -->\n<!-- readme-timing-detail:end -->\n")
    data = tmp_path / "t.json"
    kw = dict(lines=_quick(), work=tmp_path / "w", readme=readme, performance=perf, data=data)
    timing.main(only=("floating",), loads=("idle",), **kw)
    assert re.search(r"\| `brakewear run floating` \| \d+ s \| not measured \|",
                     readme.read_text())
    failing = {**_quick(), "thermal": [sys.executable, "-c", "raise SystemExit(3)"]}
    timing.main(only=("thermal",), loads=("idle",), **{**kw, "lines": failing})
    text = readme.read_text()
    assert re.search(r"`brakewear run floating` \| \d+ s \|", text) and "exit code 3" in text


def test_dry_run_runs_and_writes_nothing(tmp_path, capsys):
    out = timing.main(dry_run=True, work=tmp_path, data=tmp_path / "never.json")
    said = capsys.readouterr().out
    assert set(out["dry_run"]) == set(timing.COMMANDS) and "pytest" in said
    assert out["dry_run"]["floating"][1:3] == ["run", "floating"]
    assert not (tmp_path / "never.json").exists()
    with pytest.raises(ValueError, match="unknown"):
        timing.main(only=("nope",), dry_run=True)


def test_times_read_as_a_person_writes_them():
    assert [timing.fmt(s) for s in (47.2, 425, 3725, None)] == \
        ["47 s", "7 min 5 s", "1 h 2 min", "-"]
