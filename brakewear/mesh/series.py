"""ParaView time series of a mesh: ``NAME.pvd`` and one VTU per written step."""
from __future__ import annotations

import logging
import os
import re
from pathlib import Path

import meshio
import numpy as np

from ..errors import MeshError
from ..storage import write_text

logger = logging.getLogger(__name__)

__all__ = ["SeriesWriter", "face_fields", "cell_nodes"]

#: meshio's cell type by the number of nodes of a cell (triangles: plane strain models)
CELL_TYPES = {3: "triangle", 4: "tetra", 10: "tetra10"}


def cell_nodes(mesh) -> np.ndarray:
    """Node numbers (4, n) of a linear tetrahedral mesh's cells, or (10, n) of a
    quadratic one's (``MeshTet2``): the vertices, then the mid-edge nodes (edge
    ``e`` is node ``nvertices + e``) of the edges (0, 1), (1, 2), (0, 2), (0, 3),
    (1, 3), (2, 3) -- skfem's ``RefTet.edges``, which is VTK's tetra10 order."""
    if mesh.p.shape[1] == mesh.nvertices:
        return mesh.t
    return np.vstack([mesh.t, mesh.nvertices + mesh.t2e])


class SeriesWriter:
    """A ParaView time series (``NAME.pvd`` + one VTU per written step) of one mesh;
    ``tets``: (4, n) linear or (10, n) quadratic cells (:func:`cell_nodes`).  A series
    resumed at ``resume_step`` drops the VTU files after it and indexes those before it,
    at ``times`` (step -> s; without them, at the times its old ``NAME.pvd`` gives)."""

    def __init__(self, directory: str | os.PathLike, name: str, points: np.ndarray,
                 tets: np.ndarray, resume_step: int | None = None, times: dict | None = None):
        self.dir, self.name = Path(directory), name
        self.points, self.tets = np.ascontiguousarray(points.T), np.ascontiguousarray(tets.T)
        if tets.shape[0] not in CELL_TYPES:
            raise MeshError(f"cells of {tets.shape[0]} nodes: allowed 3 (triangle), 4 (tetra), "
                            "10 (tetra10)")
        self.cell_type = CELL_TYPES[tets.shape[0]]
        self.entries: list[tuple[float, int]] = []
        pvd = self.dir / f"{name}.pvd"
        if resume_step is not None and times is not None:
            # the index is rebuilt from the VTU files kept and the steps' times (whatever
            # became of the old one)
            for f in sorted(self.dir.glob(f"{name}_*.vtu")):
                tail = f.stem.rsplit("_", 1)[1]
                if tail.isdigit() and int(tail) <= resume_step and int(tail) in times:
                    self.entries.append((float(times[int(tail)]), int(tail)))
        elif resume_step is not None and pvd.exists():
            pat = re.compile(rf'timestep="([^"]+)"[^>]*file="{re.escape(name)}_(\d+)\.vtu"')
            try:
                found = pat.findall(pvd.read_text(encoding="utf-8"))
            except (OSError, UnicodeDecodeError) as e:
                logger.warning("%s cannot be read (%s): the series restarts at the resumed "
                               "step", pvd, e)
                found = []
            for t, s in found:
                # an entry whose VTU is gone is dropped (the pvd is written anew)
                if int(s) <= resume_step and (self.dir / f"{name}_{int(s):05d}.vtu").exists():
                    try:
                        self.entries.append((float(t), int(s)))
                    except ValueError:
                        logger.warning("%s: timestep %r of step %s is not a number; "
                                       "dropped", pvd, t, s)
        for f in self.dir.glob(f"{name}_*.vtu") if resume_step is not None else ():
            tail = f.stem.rsplit("_", 1)[1]       # written after the checkpoint
            if tail.isdigit() and int(tail) > resume_step:
                f.unlink()

    def write(self, step: int, time_s: float, fields: dict) -> Path:
        path = self.dir / f"{self.name}_{step:05d}.vtu"
        tmp = self.dir / f".{path.name}.{os.getpid()}.tmp"
        meshio.Mesh(self.points, [(self.cell_type, self.tets)],
                    point_data={k: np.asarray(v, dtype=float) for k, v in fields.items()}
                    ).write(tmp, file_format="vtu")
        os.replace(tmp, path)          # whole or not at all
        self.entries = [e for e in self.entries if e[1] != step] + [(time_s, step)]
        rows = "\n".join(f'    <DataSet timestep="{t!r}" group="" part="0" '
                         f'file="{self.name}_{s:05d}.vtu"/>' for t, s in self.entries)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")
        write_text(self.dir / f"{self.name}.pvd", text)
        return path


def face_fields(n_nodes: int, face_nodes: np.ndarray, **values) -> dict:
    """Point data of a mesh of ``n_nodes`` nodes from values on its ``face_nodes``
    (zero elsewhere): ``name -> (n_nodes,)`` for each keyword."""
    out = {}
    for name, val in values.items():
        a = np.zeros(n_nodes)
        a[face_nodes] = np.asarray(val, dtype=float)
        out[name] = a
    return out
