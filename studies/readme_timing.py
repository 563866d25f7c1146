"""How long the README's commands take, measured by one script: idle, and with a busy second core.

```
python studies/readme_timing.py                # every command, idle then busy; writes the docs
python studies/readme_timing.py --only floating thermal --loads idle
python studies/readme_timing.py --dry-run      # the commands it would run; nothing run or written
```

The commands, each in a fresh process (wall time, and the CPU time of the
process and its children):

- ``install``: ``pip install "ROOT[test]"`` into a fresh venv (created
  first, not timed), with pip's download cache as the machine has it
  (``--no-cache``: without it, which adds the downloads);
- ``demo``: ``brakewear demo`` with that venv, into a scratch folder;
- ``tests``: ``python -m pytest -n auto`` in the checkout with that venv, the
  README's second command (``--durations=40``: the slowest tests are kept);
- ``floating``, ``thermal``: ``brakewear run floating|thermal --quiet``.

Loads: ``idle`` starts nothing (``--wait-idle L`` first waits until the
1-minute load average is below ``L``); ``busy`` keeps one process spinning on
a core through every command, the second core of a 2-core machine.  The load
averages before and after each command are recorded, so a pass that was not
idle says so.

Writes the table between ``<!-- readme-timing:start -->`` and
``<!-- readme-timing:end -->`` in README.md, the details (CPU times, load
averages, the slowest tests) between ``<!-- readme-timing-detail:start -->``
and ``<!-- readme-timing-detail:end -->`` in docs/performance.md, and the
numbers to docs/data/readme_timing.json.  A command measured again replaces
its old figures; the others stay.  ``main()`` returns the record.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = ("install", "demo", "tests", "floating", "thermal")
LOADS = ("idle", "busy")
#: what each command is called in the tables
LABELS = {"install": '`pip install ".[test]"` (a fresh venv)', "demo": "`brakewear demo`",
          "tests": "`python -m pytest -n auto` (the whole suite, one process per core)",
          "floating": "`brakewear run floating`", "thermal": "`brakewear run thermal`"}
MARKERS = {"readme": "readme-timing", "detail": "readme-timing-detail"}
#: seconds the busy process gets to take its core before a command starts
WARMUP = 1.0


def commands(root: Path, venv: Path, work: Path, no_cache: bool = False) -> dict[str, list]:
    """The command lines that are timed (``venv``: the fresh venv's folder)."""
    py = str(venv / "bin" / "python")
    bw = str(venv / "bin" / "brakewear")
    pip = [py, "-m", "pip", "install", "-q"] + (["--no-cache-dir"] if no_cache else [])
    return {
        "install": pip + [f"{root}[test]"],
        "demo": [bw, "demo", "--out", str(work / "demo"), "--quiet"],
        "tests": [
            py,
            "-m",
            "pytest",
            "-n",
            "auto",
            "-q",
            "-p",
            "no:cacheprovider",
            "--durations=40",
        ],
        "floating": [bw, "run", "floating", "--out", str(work / "floating"), "--quiet"],
        "thermal": [bw, "run", "thermal", "--out", str(work / "thermal"), "--quiet"],
    }


def measure(argv: list, cwd: Path, log: Path) -> dict:
    """Run ``argv`` (output to ``log``); its wall and CPU seconds, exit code, load averages."""
    load0 = os.getloadavg()[0]
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    with open(log, "w") as fh:
        rc = subprocess.run(argv, cwd=cwd, stdout=fh, stderr=subprocess.STDOUT).returncode
    wall = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    return {"wall_s": wall, "cpu_s": cpu, "returncode": rc, "load_before": load0,
            "load_after": os.getloadavg()[0], "log": str(log)}


@contextlib.contextmanager
def busy_core(busy: bool):
    """One process spinning on a core while the block runs (its own, ended by its pid)."""
    if not busy:
        yield None
        return
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(WARMUP)        # let it take its core
        yield proc.pid
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def wait_idle(bound: float | None, timeout: float = 1800.0, poll: float = 15.0) -> float:
    """Wait until the 1-minute load average is below ``bound`` (None: do not wait);
    the load average then."""
    t0 = time.monotonic()
    while bound is not None and os.getloadavg()[0] >= bound and \
            time.monotonic() - t0 < timeout:
        time.sleep(poll)
    return os.getloadavg()[0]


def slowest_tests(log: Path, n: int = 40) -> list[tuple[float, str]]:
    """The ``n`` slowest test phases pytest's ``--durations`` printed in ``log``."""
    rows = re.findall(r"^([\d.]+)s (call|setup|teardown)\s+(\S+)", Path(log).read_text(), re.M)
    return sorted(((float(s), f"{what} {tid}") for s, what, tid in rows), reverse=True)[:n]


def _fresh_venv(path: Path) -> None:
    subprocess.run([sys.executable, "-m", "venv", str(path)], check=True)
    subprocess.run([str(path / "bin" / "python"), "-m", "pip", "install", "-q", "--upgrade",
                    "pip"], check=True)


def run_pass(load: str, only, root: Path, work: Path, lines: dict | None,
             no_cache: bool, wait: float | None) -> dict:
    """Every command of ``only`` under ``load``; ``lines`` replaces the command lines
    (tests of this script), else a fresh venv is made for the pass."""
    venv = work / f"venv-{load}"
    argv = lines if lines is not None else commands(root, venv, work / load, no_cache)
    if lines is None:             # a fresh venv per pass; installed untimed unless timed
        _fresh_venv(venv)
        if "install" not in only:
            subprocess.run(argv["install"], check=True)
    (work / load).mkdir(parents=True, exist_ok=True)
    out = {}
    for name in only:
        if load == "idle":
            wait_idle(wait)
        with busy_core(load == "busy"):
            out[name] = measure(argv[name], root, work / f"{load}-{name}.log")
        if name == "tests":
            out[name]["slowest"] = slowest_tests(work / f"{load}-{name}.log")
        print(f"{load:5s} {name:9s} {fmt(out[name]['wall_s']):>12s} wall "
              f"(exit {out[name]['returncode']}, load {out[name]['load_before']:.1f} -> "
              f"{out[name]['load_after']:.1f})", flush=True)
    return out


def fmt(seconds: float | None) -> str:
    """``1 h 2 min``, ``7 min 5 s``, ``47 s``."""
    if seconds is None:
        return "-"
    s = int(round(seconds))
    if s >= 3600:
        return f"{s // 3600} h {s % 3600 // 60} min"
    return f"{s // 60} min {s % 60} s" if s >= 60 else f"{s} s"


def _cell(record: dict, load: str, name: str, cpu: bool = False) -> str:
    r = record.get("runs", {}).get(load, {}).get(name)
    if r is None:
        return "not measured"
    text = fmt(r["wall_s"]) + (f" ({fmt(r['cpu_s'])} CPU)" if cpu else "")
    return text if r["returncode"] == 0 else f"{text}, exit code {r['returncode']}"


def machine() -> str:
    """The CPU's model and the number of cores."""
    model = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        found = re.search(r"^model name\s*:\s*(.+)$", Path("/proc/cpuinfo").read_text(), re.M)
        model = found.group(1).strip() if found else model
    return f"{os.cpu_count()} cores, {model}"


def tables(record: dict) -> dict[str, str]:
    """The README table and the performance.md details, from ``record``."""
    loads = {load: record.get("runs", {}).get(load, {}) for load in LOADS}
    readme = ["| command | idle | second core busy |", "|---|---:|---:|"]
    readme += [f"| {LABELS[n]} | {_cell(record, 'idle', n)} | {_cell(record, 'busy', n)} |"
               for n in COMMANDS]
    loaded = {load: [r["load_before"] for r in runs.values()] for load, runs in loads.items()}
    note = "; ".join(f"{load}: load average {min(v):.1f} to {max(v):.1f} at the starts"
                     for load, v in loaded.items() if v)
    readme += ["", (f"Wall times measured by `python studies/readme_timing.py` on "
                    f"{record.get('machine', machine())} ({note}; busy: one process spinning "
                    "on a core throughout)." if note else
                    "`python studies/readme_timing.py` measures these times and writes them "
                    "here.")
               + " Details, CPU times and the slowest tests: "
               "[docs/performance.md](docs/performance.md), \"The README's commands\"."]
    detail = ["| command | idle: wall (CPU) | second core busy: wall (CPU) |", "|---|---:|---:|"]
    detail += [f"| {LABELS[n]} | {_cell(record, 'idle', n, True)} | "
               f"{_cell(record, 'busy', n, True)} |" for n in COMMANDS]
    for load in LOADS:
        slow = loads[load].get("tests", {}).get("slowest")
        if slow:
            detail += ["", f"The ten slowest test phases ({load}; `--durations=40` in "
                           f"`docs/data/readme_timing.json`): "
                       + "; ".join(f"`{tid}` {sec:.0f} s" for sec, tid in slow[:10]) + "."]
    return {"readme": "\n".join(readme), "detail": "\n".join(detail)}


def write_between(path: Path, tag: str, text: str) -> None:
    """Replace what stands between ``<!-- tag:start -->`` and ``<!-- tag:end -->``."""
    src = path.read_text()
    start, end = f"<!-- {tag}:start -->", f"<!-- {tag}:end -->"
    if src.count(start) != 1 or src.count(end) != 1 or src.index(start) > src.index(end):
        raise ValueError(f"{path}: needs one {start} ... {end} pair")
    head, rest = src.split(start)
    path.write_text(head + start + "\n" + text + "\n" + end + rest.split(end, 1)[1])


def main(only=COMMANDS, loads=LOADS, write: bool = True, dry_run: bool = False,
         root: Path = ROOT, work: Path | None = None, lines: dict | None = None,
         no_cache: bool = False, wait_idle_below: float | None = None,
         readme: Path | None = None, performance: Path | None = None,
         data: Path | None = None) -> dict:
    """Time the commands ``only`` under each of ``loads``; merge them into the record in
    ``data`` and (``write``) the docs' tables; return the record.  ``lines`` replaces
    the command lines (``name -> argv``; no venv is made).  ``dry_run``: print the
    command lines and return them, nothing run or written."""
    readme = readme or root / "README.md"
    performance = performance or root / "docs" / "performance.md"
    data = data or root / "docs" / "data" / "readme_timing.json"
    unknown = set(only) - set(COMMANDS) or set(loads) - set(LOADS)
    if unknown:
        raise ValueError(f"unknown commands or loads {sorted(unknown)}; allowed: "
                         f"{', '.join(COMMANDS)}; {', '.join(LOADS)}")
    with contextlib.ExitStack() as stack:
        work = Path(work) if work else Path(stack.enter_context(
            tempfile.TemporaryDirectory(prefix="readme-timing-")))
        if dry_run:
            shown = lines or commands(root, work / "venv-LOAD", work / "LOAD", no_cache)
            for name in only:
                print(f"{name}: {' '.join(map(str, shown[name]))}")
            return {"dry_run": {n: shown[n] for n in only}}
        record = json.loads(data.read_text()) if data.exists() else {}
        record["machine"] = machine()
        for load in loads:
            runs = run_pass(load, only, root, work, lines, no_cache, wait_idle_below)
            record.setdefault("runs", {}).setdefault(load, {}).update(runs)
    if write:
        data.parent.mkdir(parents=True, exist_ok=True)
        data.write_text(json.dumps(record, indent=2))
        text = tables(record)
        write_between(readme, MARKERS["readme"], text["readme"])
        write_between(performance, MARKERS["detail"], text["detail"])
    return record


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", choices=COMMANDS, default=list(COMMANDS))
    ap.add_argument("--loads", nargs="+", choices=LOADS, default=list(LOADS))
    ap.add_argument("--dry-run", action="store_true", help="print the commands only")
    ap.add_argument("--no-write", action="store_true", help="leave README and docs as they are")
    ap.add_argument("--no-cache", action="store_true", help="pip without its download cache")
    ap.add_argument("--wait-idle", type=float, default=None, metavar="LOAD",
                    help="before each idle command, wait until the 1-minute load average "
                         "is below LOAD")
    ap.add_argument("--work", default=None, help="scratch folder (default: a temporary one)")
    a = ap.parse_args(argv)
    return main(a.only, a.loads, write=not a.no_write, dry_run=a.dry_run, work=a.work,
                no_cache=a.no_cache, wait_idle_below=a.wait_idle)


if __name__ == "__main__":
    _cli()
