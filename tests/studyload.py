"""Import a study script of studies/ as a module (the studies are scripts, not a package)."""
import importlib.util
from pathlib import Path


def load_study(name: str):
    """The module ``studies/<name>.py``."""
    spec = importlib.util.spec_from_file_location(
        name, Path(__file__).parents[1] / "studies" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
