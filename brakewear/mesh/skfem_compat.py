"""The one place brakewear touches scikit-fem's private state, and the versions it holds for.

scikit-fem keeps a mesh's named facet and element sets in the dataclass
fields ``_boundaries`` and ``_subdomains``, builds its topology tables
(``_facets``, ``_t2f``, ``_f2t``, ``_edges``, ``_t2e``) on first use, and
encodes the named sets into a file's cell data with ``_encode_cell_data`` /
``_decode_cell_data``.  brakewear uses these to build the topology of a big
mesh faster than the lazy route (:func:`~brakewear.mesh.topology.ensure_topology`),
to carry it over to a moved copy of a mesh, and to read and write the named
sets with the mesh files.  Every such use is a function here; the rest of
the package calls these and never an underscored name of scikit-fem.

The names are those of scikit-fem's :data:`SUPPORTED` major versions (the
same in each; setup.cfg bounds ``scikit-fem`` to them), and
:func:`check_version` refuses any other when this module is imported.
"""
from __future__ import annotations

import logging
import re
from importlib.metadata import PackageNotFoundError, version

import numpy as np
import skfem as fem

from ..errors import DependencyError

logger = logging.getLogger(__name__)

__all__ = ["SUPPORTED", "check_version", "mesh_with_sets", "moved_mesh", "has_topology",
           "set_topology", "copy_topology", "encode_cell_data", "decode_cell_data"]

#: The scikit-fem major versions whose private state this module uses: ``lo <= major < hi``
#: (setup.cfg's bound on ``scikit-fem``).
SUPPORTED = (10, 13)

#: the topology tables scikit-fem builds on first use, kept by a copy with the same ``t``
_TOPOLOGY = ("_facets", "_t2f", "_f2t", "_edges", "_t2e")


def _installed() -> str:
    try:
        return version("scikit-fem")
    except PackageNotFoundError:  # pragma: no cover - a source tree on the path
        return str(getattr(fem, "__version__", "unknown"))


def check_version(installed: str | None = None) -> str:
    """Refuse a scikit-fem whose private state brakewear has not been checked against.

    Parameters
    ----------
    installed
        A version string (default: the installed scikit-fem's).

    Returns
    -------
    str
        The version, when it is supported.

    Raises
    ------
    DependencyError
        Naming the installed version and the supported ones.

    Examples
    --------
    >>> check_version("12.0.2")
    '12.0.2'
    >>> check_version("13.1")
    Traceback (most recent call last):
    ...
    brakewear.errors.DependencyError: scikit-fem 13.1 is installed; brakewear supports \
scikit-fem >= 10, < 13 (it uses mesh internals of those versions): pip install \
"scikit-fem>=10,<13"
    """
    installed = _installed() if installed is None else installed
    m = re.match(r"\s*(\d+)\.", f"{installed}.")
    lo, hi = SUPPORTED
    if m is None or not lo <= int(m.group(1)) < hi:
        raise DependencyError(f"scikit-fem {installed} is installed; brakewear supports "
                              f"scikit-fem >= {lo}, < {hi} (it uses mesh internals of those "
                              f"versions): pip install \"scikit-fem>={lo},<{hi}\"")
    return installed


check_version()


def mesh_with_sets(cls: type, p: np.ndarray, t: np.ndarray, boundaries: dict | None,
                   subdomains: dict | None) -> fem.Mesh:
    """A mesh of class ``cls`` with the named sets given, unvalidated.

    Parameters
    ----------
    cls
        A scikit-fem mesh class (``skfem.MeshTet1``).
    p, t
        Its nodes (dim, n) and elements.
    boundaries, subdomains
        Name -> facet / element indices (None: none).

    Returns
    -------
    skfem.Mesh
        The new mesh.
    """
    return cls(p, t, boundaries, subdomains, validate=False)


def moved_mesh(mesh: fem.Mesh, p: np.ndarray) -> fem.Mesh:
    """A new mesh with the coordinates ``p`` and everything else of ``mesh`` (its named
    sets, and its topology tables, which moving the nodes does not change).

    Parameters
    ----------
    mesh
        The mesh.
    p
        New node coordinates, of ``mesh.p``'s shape.

    Returns
    -------
    skfem.Mesh
        A mesh of the same class.
    """
    return copy_topology(mesh_with_sets(type(mesh), p, mesh.t, mesh.boundaries,
                                        mesh.subdomains), mesh)


def has_topology(mesh: fem.Mesh) -> bool:
    """Whether the facets and the facet-element tables of ``mesh`` are built.

    Parameters
    ----------
    mesh
        A scikit-fem mesh.

    Returns
    -------
    bool
        True once ``facets``, ``t2f`` and ``f2t`` are cached.
    """
    return all(hasattr(mesh, name) for name in _TOPOLOGY[:3])


def set_topology(mesh: fem.Mesh, facets: np.ndarray, t2f: np.ndarray,
                 f2t: np.ndarray) -> fem.Mesh:
    """Cache tables that equal what scikit-fem would build as ``mesh``'s own.

    Parameters
    ----------
    mesh
        A scikit-fem mesh (modified in place).
    facets, t2f, f2t
        The facets (sorted vertex tuples, lexicographic order), the facets of
        each element per local facet, and the elements of each facet (-1
        outside), as scikit-fem builds them.

    Returns
    -------
    skfem.Mesh
        ``mesh``.
    """
    mesh._facets, mesh._t2f, mesh._f2t = facets, t2f, f2t
    return mesh


def copy_topology(new: fem.Mesh, old: fem.Mesh) -> fem.Mesh:
    """Carry the cached topology of ``old`` over to ``new`` if their elements are the same
    (the copies ``with_boundaries``, ``with_subdomains`` and :func:`moved_mesh` make
    start without it).

    Parameters
    ----------
    new, old
        Meshes.

    Returns
    -------
    skfem.Mesh
        ``new`` (modified in place).
    """
    if new.t is old.t or np.array_equal(new.t, old.t):
        for name in _TOPOLOGY:
            if hasattr(old, name) and not hasattr(new, name):
                setattr(new, name, getattr(old, name))
    return new


def encode_cell_data(mesh: fem.Mesh) -> dict:
    """The named sets of ``mesh`` as scikit-fem writes them into a file's cell data.

    Parameters
    ----------
    mesh
        A scikit-fem mesh.

    Returns
    -------
    dict
        ``"skfem:..."`` key -> list of one int array per element block.
    """
    return mesh._encode_cell_data()


def decode_cell_data(mesh: fem.Mesh, cell_data: dict) -> tuple[dict, dict]:
    """The named sets a file's ``"skfem:..."`` cell data holds for ``mesh``.

    Parameters
    ----------
    mesh
        The mesh read from the file.
    cell_data
        The file's ``"skfem:..."`` cell data.

    Returns
    -------
    boundaries, subdomains : dict
        Name -> facet / element indices.
    """
    return mesh._decode_cell_data(cell_data)
