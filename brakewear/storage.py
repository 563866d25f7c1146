"""The files brakewear writes and reads back: written whole or not at all, read checked.

A run writes its files so that a kill at any moment leaves each of them
either as it was or as it is meant to be: :func:`write_text` and
:func:`save_arrays` write a temporary file in the same folder and rename it
over the old one (``os.replace``, atomic on one file system).

What the package reads back of its own (checkpoints, condensation caches,
run records) is read by :func:`load_arrays` / :func:`read_json`, which check
it before anything uses it: an archive that is cut, empty, altered (each
archive carries a SHA-256 digest of its arrays, beside the zip format's own
CRC) or not an archive at all is refused with a
:class:`~brakewear.errors.StoredFileError` (an
:class:`~brakewear.errors.InputError`, exit code 2) naming the file, what is
wrong with it and what to do; nothing is ever unpickled.
"""
from __future__ import annotations

import hashlib
import json
import os
import zipfile
import zlib
from pathlib import Path

import numpy as np

from .errors import StoredFileError

__all__ = ["write_text", "save_arrays", "load_arrays", "load_array", "read_json", "DIGEST"]

#: the archive member that holds the digest of the others
DIGEST = "sha256"


def _temporary(path: Path) -> Path:
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (a temporary file, then a rename)."""
    path = Path(path)
    tmp = _temporary(path)
    try:
        tmp.write_text(text)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def _digest(arrays: dict) -> str:
    h = hashlib.sha256()
    for k in sorted(arrays):
        a = np.ascontiguousarray(arrays[k])
        h.update(f"{k}:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def save_arrays(path: str | os.PathLike, arrays: dict) -> Path:
    """Write ``arrays`` (name -> array) as an ``.npz`` archive at ``path``, atomically,
    with the digest :func:`load_arrays` checks."""
    path = Path(path)
    arrays = {k: np.asarray(v) for k, v in arrays.items()}
    if any(a.dtype == object for a in arrays.values()):
        raise StoredFileError(f"{path}: Python objects are not stored, only numbers",
                              path=path)
    tmp = _temporary(path)
    try:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays, **{DIGEST: np.asarray(_digest(arrays))})
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def _error(kind, message: str, path: Path):
    try:
        return kind(message, path=path)
    except TypeError:           # an error kind without a path
        exc = kind(message)
        exc.path = path
        return exc


def _readable(path: Path, bad, magic: bytes, name: str) -> None:
    try:
        size = path.stat().st_size
    except OSError as e:
        raise bad(f"cannot be read ({e.strerror})") from None
    if size == 0:
        raise bad("is empty (0 bytes)")
    with open(path, "rb") as fh:
        head = fh.read(len(magic))
    if head != magic:
        raise bad(f"is not an {name} file (it begins {head.decode('latin-1')!r}, an {name} "
                  f"file begins {magic.decode('latin-1')!r})")


def _header_dtype(fh) -> np.dtype:
    fmt = np.lib.format
    version = fmt.read_magic(fh)
    header = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
    return header(fh)[2]


def load_array(path: str | os.PathLike, what: str, *, kind=StoredFileError) -> np.ndarray:
    """The array of the ``.npy`` file ``path``, checked as :func:`load_arrays` checks an
    archive's members (not cut, no Python objects); ``kind`` is raised naming the file."""
    path = Path(path)

    def bad(reason: str):
        return _error(kind, f"{what} {path} {reason}", path)

    _readable(path, bad, b"\x93NUMPY", ".npy")
    try:
        with open(path, "rb") as fh:
            if _header_dtype(fh).hasobject:
                raise bad("holds Python objects, not numbers; brakewear never loads those")
        return np.load(path, allow_pickle=False)
    except (ValueError, EOFError, OSError) as e:
        if isinstance(e, kind):
            raise
        raise bad(f"is cut or damaged ({type(e).__name__}: {e})") from None


def load_arrays(path: str | os.PathLike, what: str, *, required=(), remedy: str = "",
                kind=StoredFileError) -> dict:
    """The arrays of the ``.npz`` archive ``path`` (``what`` it is, for the message),
    checked: readable, an archive, every member whole (its CRC and the digest), no
    Python objects, the ``required`` names present.  Anything else raises ``kind``
    naming the file, what is wrong and the ``remedy``."""
    path = Path(path)

    def bad(reason: str):
        return _error(kind, f"{what} {path} {reason}" + (f"; {remedy}" if remedy else ""),
                      path)

    _readable(path, bad, b"PK", ".npz")
    arrays = {}
    try:
        with zipfile.ZipFile(path) as z:
            for info in z.infolist():
                name = info.filename
                if not name.endswith(".npy"):
                    raise bad(f"holds {name!r}, not an array")
                with z.open(info) as member:
                    if _header_dtype(member).hasobject:
                        raise bad(f"holds Python objects in {name[:-4]!r}, not numbers; "
                                  "brakewear never loads those")
                # the whole member, its CRC checked as it is read to its end
                with z.open(info) as member:
                    arrays[name[:-4]] = np.lib.format.read_array(member, allow_pickle=False)
    except (zipfile.BadZipFile, zlib.error, EOFError, ValueError, OSError, KeyError,
            NotImplementedError) as e:
        if isinstance(e, kind):
            raise
        raise bad(f"is cut or damaged ({type(e).__name__}: {e})") from None
    stored = arrays.pop(DIGEST, None)
    if stored is not None and str(stored) != _digest(arrays):
        raise bad("is damaged: its arrays do not match the digest written with them")
    missing = [k for k in required if k not in arrays]
    if missing:
        raise bad(f"lacks {', '.join(missing)}: it is not a {what} brakewear wrote")
    return arrays


def read_json(path: str | os.PathLike, what: str, *, remedy: str = "",
              kind: type[StoredFileError] = StoredFileError) -> dict:
    """The JSON object in ``path`` (``what`` it is); a file that is not one raises
    ``kind`` naming it."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as e:
        raise _error(kind, f"{what} {path} cannot be read ({e.strerror})"
                   + (f"; {remedy}" if remedy else ""), path) from None
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise _error(kind, f"{what} {path} is cut or damaged (not JSON: {e})"
                   + (f"; {remedy}" if remedy else ""), path) from None
    if not isinstance(data, dict):
        raise _error(kind, f"{what} {path} holds a JSON {type(data).__name__}, not an object"
                   + (f"; {remedy}" if remedy else ""), path)
    return data
