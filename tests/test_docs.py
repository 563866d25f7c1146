"""Docs, README, package and studies speak of the software as it is, not of its development."""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
FILES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md"),
                *(ROOT / "brakewear").rglob("*.py"), *(ROOT / "studies").rglob("*.py")])

#: what tells the story of the development: work periods, issue numbers, commit
#: hashes, dates of work, other jobs on the machine
HISTORY = [
    (r"\b[Ss]ession[ -]\d+\b|\b[Ss]essions \d", "a work period"),
    (r"\bthe issue\b|\b[Ii]ssue #?\d+\b", "an issue"),
    (r"\bcommit\s+(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b|"
     r"`(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}`", "a commit hash"),
    (r"\b20\d\d-\d\d-\d\d\b|\b\d{1,2} (Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]* 20\d\d\b",
     "a date of work"),
    (r"\bwork period\b|\bother agents\b|\bthis session\b", "the development"),
]


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_development_history(path):
    hits = []
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        for pattern, what in HISTORY:
            if re.search(pattern, line):
                hits.append(f"{path.relative_to(ROOT)}:{n}: {what}: {line.strip()[:100]}")
    assert not hits, "\n".join(hits)


def test_the_history_patterns_catch_what_they_should():
    caught = ["measured in session 7", "the issue asks", "commit 5d4a881", "(`e07a9f4`)",
              "run on 2026-11-21", "21 Nov 2026", "shared with other agents"]
    clean = ["1e-9 relative", "`pad_wear`", "exit code 4", "the rotor issue of heat",
             "`1000000`"]
    def hit(s):
        return any(re.search(p, s) for p, _ in HISTORY)
    assert all(hit(s) for s in caught)
    assert not any(hit(s) for s in clean)


@pytest.mark.parametrize("path", [p for p in FILES if p.suffix == ".md"],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_point_to_files(path):
    text = path.read_text(encoding="utf-8")
    bad = []
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
        if re.match(r"[a-z]+://|mailto:", target):
            continue
        if not (path.parent / target).exists():
            bad.append(target)
    assert not bad, f"{path.relative_to(ROOT)}: broken links {bad}"
