"""The errors brakewear raises: one base, an input branch and a solver branch.

Every error of the package is a :class:`BrakewearError`, in one of two
branches that the command line maps to its exit codes:

* :class:`InputError` (a ``ValueError``, exit code 2): the input asks for
  something brakewear cannot do.  The message names the file or the
  parameter (the scene key), the value in the user's units and what is
  allowed; it is raised before any long computation and before anything is
  written.
* :class:`SolverError` (a ``RuntimeError``, exit code 3): a computation
  that did not succeed (a linear solve that did not converge, an active set
  that cycles, no acceptable wear step, a degenerate element, a face hotter
  than the thermal plausibility bound).  The message
  gives the figures a user needs to act; nothing returns a wrong answer
  quietly.
* :class:`WornThroughError` (exit code 4): not a failure but the end of the
  brake's life -- a surface reached its wear limit; the message says which,
  when and where (:mod:`brakewear.wear.limits`).

The kinds below say which part of the input or which solver; catch a
branch to handle all of its kinds::

    import brakewear as bw

    try:
        bw.load_scene("no/such/scene.toml")
    except bw.InputError as exc:
        print(f"bad input (exit code {exc.exit_code}): {exc}")
"""
from __future__ import annotations

from contextlib import contextmanager

__all__ = [
    "BrakewearError",
    "InputError",
    "SolverError",
    "GeometryError",
    "MaterialError",
    "MeshFileError",
    "SceneError",
    "WearError",
    "IdentifiabilityError",
    "StoredFileError",
    "DutyError",
    "ThermalError",
    "FoundationError",
    "LawError",
    "MapError",
    "MeshError",
    "ContactError",
    "MotionError",
    "SolverSettingsError",
    "BenchError",
    "RoughnessError",
    "DependencyError",
    "ConvergenceError",
    "CondensedRangeError",
    "ActiveSetError",
    "ContactLostError",
    "ComplementarityError",
    "ContactSearchError",
    "StepSizeError",
    "TemperatureLimitError",
    "MeshQualityError",
    "FoundationSolveError",
    "WornThroughError",
]


class BrakewearError(Exception):
    """Base of every error brakewear raises; ``exit_code`` is the CLI's exit status."""

    exit_code = 1


class InputError(BrakewearError, ValueError):
    """The input asks for something brakewear cannot do (exit code 2)."""

    exit_code = 2


class SolverError(BrakewearError, RuntimeError):
    """A computation did not succeed; the message gives its figures (exit code 3).

    :meth:`within` adds where it happened (the wear step, the application of a
    schedule) as the error passes up through the loops; the message names that
    place too.

    Parameters
    ----------
    message
        What failed, with the figures a user needs to act.
    figures
        The figures as data (iterations, residual, the active-set sizes seen, ...).
    """

    exit_code = 3

    def __init__(self, message: str = "", *, figures: dict | None = None):
        super().__init__(message)
        self.figures = dict(figures or {})
        self.where: dict = {}

    def within(self, **where) -> SolverError:
        """Add where the error happened (keys already set by an inner loop are kept);
        returns the error itself, to re-raise."""
        if not hasattr(self, "where"):      # a subclass that set up its own state
            self.where, self.figures = {}, getattr(self, "figures", {})
        for k, v in where.items():
            self.where.setdefault(k, v)
        return self

    @staticmethod
    @contextmanager
    def located(**where):
        """Name where a solver error raised inside the block happened (:meth:`within`:
        a loop's step, a schedule's application)."""
        try:
            yield
        except SolverError as exc:
            exc.within(**where)
            raise

    def __str__(self) -> str:
        msg = super().__str__()
        where = getattr(self, "where", None)
        if not where:
            return msg
        return f"{msg} [{', '.join(f'{k} {v}' for k, v in where.items())}]"


# ------------------------------------------------------------------ input --

class GeometryError(InputError):
    """Invalid brake geometry (names the file, the field, the value and the allowed range)."""


class MaterialError(InputError):
    """Invalid or unknown material data (names the field and allowed range)."""


class MeshFileError(InputError):
    """A mesh file that cannot be used (no tetrahedra, missing tags, ...)."""


class SceneError(InputError):
    """A scene asks for something inconsistent (names the file, the key and the allowed values)."""


class WearError(InputError):
    """Invalid wear input (names the parameter, the value and what is allowed)."""


class IdentifiabilityError(WearError):
    """A calibration asked to fit a parameter its record does not constrain.

    Parameters
    ----------
    message
        Each parameter and why the record does not constrain it.
    parameters
        Parameter name -> the reason (kept as the attribute ``parameters``).
    """

    def __init__(self, message: str = "", *, parameters: dict | None = None):
        super().__init__(message)
        self.parameters = dict(parameters or {})


class StoredFileError(InputError):
    """A file brakewear reads back that is missing, cut, damaged or not what it should be.

    Parameters
    ----------
    message
        The file, what is wrong with it and what to do.
    path
        The file (kept as the attribute ``path``): a checkpoint, a run's history
        or record, a cache.
    """

    def __init__(self, message: str = "", *, path=None):
        super().__init__(message)
        self.path = path


class ThermalError(InputError):
    """Invalid thermal input; the message names the body, the field and the value."""


class DutyError(InputError):
    """A vehicle, application or schedule that is not allowed (names the key or the CSV row)."""


class FoundationError(InputError):
    """Bad input to the foundation model (names the parameter, the value, what is allowed)."""


class LawError(InputError):
    """A friction or wear law that cannot be used.

    The message names the law, the parameter, the value and what is allowed.
    """


class MapError(LawError):
    """A friction or wear map that cannot be used.

    A bad CSV names the file, the row (its line number) and the column; a
    look-up outside the grid of a map that refuses it names the quantity, the
    value in the map's units and the grid's range.
    """


class MeshError(InputError):
    """A mesh, or a setting of one, that cannot be used.

    An element size or order, a grading, subdomains without a material, a field
    that does not fit the mesh's nodes or elements, a named facet set the mesh
    does not have.
    """


class ContactError(InputError):
    """A contact pair, support or contact-solve setting that cannot be used.

    The message names the pair, the argument, its value and what is allowed.
    """


class MotionError(InputError):
    """Bad input to the geometry update.

    A band depth, a quality bound or worn depths that cannot be used: the
    message names the argument, the value in m and what is allowed.
    """


class SolverSettingsError(InputError):
    """A setting or operand of a linear solver that cannot be used.

    A matrix of the wrong shape, an unknown Krylov method, a direct solve beyond
    its size bound.
    """


class BenchError(InputError):
    """A benchmark option that is not allowed (names the option and the allowed values)."""


class RoughnessError(InputError):
    """Bad input to the rough-surface tools (:mod:`brakewear.rough`).

    A topography file that cannot be read (the message names the file, the row
    and column), or a parameter out of range (names it, the value in the user's
    units and what is allowed).
    """


class DependencyError(InputError):
    """An installed library of a version brakewear does not support.

    The message names the installed and the supported versions, and the command
    that installs one.
    """


# ----------------------------------------------------------------- solver --

class ConvergenceError(SolverError):
    """An iterative solve stopped without reaching its tolerance.

    Parameters
    ----------
    message
        What failed.
    info
        The solve's record (its ``iterations`` and ``relative_residual`` become
        the figures unless ``figures`` is given).
    figures
        As :class:`SolverError`.
    """

    def __init__(self, message: str, info=None, *, figures: dict | None = None):
        if figures is None and info is not None and hasattr(info, "iterations"):
            figures = {"iterations": info.iterations,
                       "relative_residual": getattr(info, "relative_residual", None)}
        super().__init__(message, figures=figures)
        self.info = info


class ActiveSetError(SolverError):
    """The active-set iteration did not settle (names its figures).

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class ContactLostError(SolverError):
    """No node is left in contact: the load separates the bodies.

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class ComplementarityError(SolverError):
    """No state of a complementarity problem (contact nodes and one-sided rows) was
    found that satisfies its sign conditions, by any of its methods (names their
    iterations and merits).

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class ContactSearchError(SolverError):
    """A slave node found no master facet within the search radius.

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class StepSizeError(SolverError):
    """The step control could not find an acceptable wear step.

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class MeshQualityError(SolverError):
    """A geometry update would leave an inverted or degenerate element.

    Parameters
    ----------
    message
        What failed.
    step, body, element
        Where: the wear step, the body and the element (an index into the
        body's ``mesh.t``); kept as attributes, as are the others.
    quality, min_quality
        How bad: the element's quality and the bound it passed.
    """

    def __init__(self, message: str, *, step=None, body: str = "", element: int = -1,
                 quality: float = float("nan"), min_quality: float = float("nan")):
        super().__init__(message, figures={"step": step, "body": body, "element": element,
                                           "quality": quality, "min_quality": min_quality})
        self.step, self.body, self.element = step, body, element
        self.quality, self.min_quality = quality, min_quality


class TemperatureLimitError(SolverError):
    """A face temperature passed the plausibility bound ``T_max`` of a thermal run.

    The answer would be physically absurd: the message names the face, the
    temperature, the step and the likely causes.

    Parameters
    ----------
    message
        What failed.
    body
        The face's body; kept as an attribute, as are the others.
    temperature, T_max
        The temperature reached and the bound (K).
    step, time
        When: the wear step and the time (s).
    """

    def __init__(self, message: str, *, body: str = "", temperature: float = float("nan"),
                 T_max: float = float("nan"), step: int = -1, time: float = float("nan")):
        super().__init__(message, figures={"body": body, "temperature_K": temperature,
                                           "T_max_K": T_max, "step": step, "time_s": time})
        self.body, self.temperature, self.T_max = body, temperature, T_max
        self.step, self.time = step, time


class CondensedRangeError(SolverError):
    """The gap offset of a condensed interface passed its range of validity.

    The geometry would have to follow the wear: the message names the depth,
    the limit and the alternative (the FE interface with the geometry update).

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


class FoundationSolveError(SolverError):
    """No equilibrium: the pad lifts off entirely or tips off its contact (with the figures).

    Parameters
    ----------
    message, figures
        As :class:`SolverError`.
    """


# ------------------------------------------------------------ end of life --

class WornThroughError(BrakewearError):
    """A surface reached its wear limit (exit code 4): the run ends there.

    Parameters
    ----------
    message
        Which surface, when and where.
    body
        ``"pad"`` or ``"rotor"``; kept as an attribute, as are the others.
    time, step
        When the node reached the limit (s) and the wear step.
    r, theta
        Where: the node's radius (m) and angle (deg).
    depth, limit
        The node's depth at the end of the step that reached the limit, and
        the limit (m).
    step_end
        When that step ended (s): the time that goes with ``depth``.
    """

    exit_code = 4

    def __init__(self, message: str, *, body: str = "", time: float = float("nan"),
                 step: int = -1, r: float = float("nan"), theta: float = float("nan"),
                 depth: float = float("nan"), limit: float = float("nan"),
                 step_end: float = float("nan")):
        super().__init__(message)
        self.body, self.time, self.step = body, time, step
        self.r, self.theta, self.depth, self.limit = r, theta, depth, limit
        self.step_end = step_end

    def record(self) -> dict:
        """The figures as a JSON-ready dict (for summary.json): ``time_s`` with
        ``limit_m`` (the limit reached), ``step_end_s`` with ``depth_m``."""
        return {"body": self.body, "time_s": self.time, "step": self.step, "r_m": self.r,
                "theta_deg": self.theta, "limit_m": self.limit, "step_end_s": self.step_end,
                "depth_m": self.depth, "message": str(self)}

