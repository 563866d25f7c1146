"""brakewear: wear of disc-brake pads and rotors by 3D finite elements.

Built on scikit-fem (assembly), pyamg (solvers), meshio (files) and pyvista
(figures).  See docs/ for the theory and the user guide.
"""
import logging

__version__ = "0.1.0"

__all__ = ["__version__"]

logging.getLogger(__name__).addHandler(logging.NullHandler())
