"""What a run leaves on disk: its folder, VTU/PVD series, CSV, JSON and figures.

- :mod:`~brakewear.output.runs`: a wear run or a scene run written to a folder
  (:func:`run_wear`, :func:`run_scene`);
- :mod:`~brakewear.output.folder`: whether a folder holds a run, and what to clear;
- :mod:`~brakewear.output.figures`: off-screen pyvista pictures of meshes and fields;
- :mod:`~brakewear.output.face_maps`: maps of a friction face read without the docs.
"""
from .runs import run_scene, run_wear

__all__ = ["run_wear", "run_scene"]
