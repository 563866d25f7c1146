"""How the wear loop integrates: the numerics shared by Python calls and scene files."""
from __future__ import annotations

import logging
from dataclasses import dataclass

from ..checks import check_choice, check_int, check_number
from ..errors import SceneError, WearError

logger = logging.getLogger(__name__)

__all__ = ["Numerics", "NumericsError"]


class NumericsError(SceneError, WearError):
    """A value of :class:`Numerics` out of range: a scene error when read from a
    file, a wear error when given from Python."""


@dataclass(frozen=True)
class Numerics:
    """How the wear loop integrates (SI units).

    The one set of defaults shared by :func:`brakewear.wear.wear_history` and a
    scene's ``[numerics]`` table.

    Parameters
    ----------
    scheme : {"implicit", "explicit", "implicit_pad"}
        ``"implicit"`` (backward Euler for both surfaces: the pad and the
        rotor's rings wear with the pressure at the end of the step, solved
        as contact through the step's wear compliance of both,
        :mod:`brakewear.contact.compliant` and
        :mod:`~brakewear.contact.compliant_rings`; unconditionally stable, so
        the step is set by ``dp_tol`` / ``wear_tol`` and ``max_dh`` alone;
        needs pad and rotor laws with a = 1), ``"explicit"`` (Euler: the
        pressure at the start, within the ``stability`` bound) or
        ``"implicit_pad"`` (backward Euler for the pad, the rotor's
        ring-averaged wear explicit within its own ``stability`` bound, which
        shrinks with the face's elements).  An implicit step whose pad wear
        compliance is below ``implicit_floor`` is taken explicitly (with the
        rings' bound).
    update : {"gap", "geometry"}
        ``"gap"`` (the worn depths offset the contact gap; meshes stay) or
        ``"geometry"`` (after every accepted step both worn faces move and the
        layers beneath follow, :class:`brakewear.motion.brake.BrakeMotion`).
    steps : int or None
        A number of equal steps (no step control); None: automatic control.
    dp_tol : float
        Largest accepted change of the pressure field per step (automatic
        control without ``wear_tol``), measured by ``norm``.
    dh_fraction, max_dh
        Largest wear per step at a pad node (pad + rotor seen by it):
        ``max_dh`` (m) everywhere, or by default ``dh_fraction`` times the
        height of the pad element under the node.
    wear_tol : float or None
        Local wear error per step (m) of the automatic control, instead of
        ``dp_tol``: a step is accepted if its embedded estimate ``dt/2
        |rate(p_end) - rate(p_start)|``, measured by ``norm``, is below it
        (docs: theory, "Step control on the wear error").
    norm : {"max", "l2"}
        How the automatic control measures a step over the pad's friction
        face.  ``"max"`` (the default): the largest nodal pressure change
        relative to the peak pressure, the largest nodal wear error; while
        the contact spreads, every node it reaches jumps by a few per cent of
        the peak, so the steps grow in number as the face's elements shrink.
        ``"l2"``: area-weighted, with each node's tributary area ``A_i``;
        the pressure change is ``||p_end - p_start|| / ||p_start||`` and the
        wear error the root mean square over the face of the local error of
        the worn depth, ``||x|| = (sum_i A_i x_i^2)^(1/2)``.  A node that
        enters or leaves contact counts by its area, so both measures tend
        to integrals over the face as the mesh is refined, and so do the
        steps they choose.  The same tolerance takes fewer, longer steps in
        ``"l2"`` (a tighter one for the same error; docs: wear, "The
        default scene's steps").
    stability : float or None
        Fraction of the monotone explicit-Euler bound on the step (1 keeps
        every mode from overshooting, 2 is the stability limit; None switches
        it off): of pad and rotor wear in the explicit scheme, of the rotor's
        ring wear where it is explicit (``implicit_pad``, and implicit steps
        taken explicitly under ``implicit_floor``).
    implicit_floor : float
        The implicit scheme takes a step explicitly when the pad's wear
        compliance over it (``dt k v``) is below this fraction of the
        contact's elastic compliance at every node (``lambda dt`` below it:
        the explicit step is then far inside its stability bound, and the
        two schemes differ by less than this fraction of the step's pressure
        change).  The compliant solve of such a step is a penalty method with
        a penalty ``1 / implicit_floor`` or more times the elastic stiffness:
        ill-conditioned, and its active set can wander.  0: never.
    tol : float
        Relative residual of the contact solves.
    max_halvings : int
        Retries of a step before :class:`~brakewear.errors.StepSizeError`.
    max_steps : int
        Accepted steps a history under automatic control may take before
        :class:`~brakewear.errors.StepSizeError` (the loop's budget; with
        ``steps`` the budget is ``steps``).
    memory_budget : float or None
        Largest model a scene may ask for (GB; None: ``BRAKEWEAR_MEMORY_GB`` or
        the machine's available memory).

    Raises
    ------
    NumericsError
        A value out of range, naming ``numerics.<key>`` (a
        :class:`~brakewear.errors.SceneError` and a
        :class:`~brakewear.errors.WearError`).
    """

    scheme: str = "implicit"
    update: str = "gap"
    steps: int | None = None
    dp_tol: float = 0.05
    dh_fraction: float = 0.1
    max_dh: float | None = None
    wear_tol: float | None = None
    norm: str = "max"
    stability: float | None = 1.0
    implicit_floor: float = 1e-3
    tol: float = 1e-9
    max_halvings: int = 12
    max_steps: int = 20_000
    memory_budget: float | None = None

    def __post_init__(self):
        try:
            self._check()
        except SceneError as e:
            raise NumericsError(str(e)) from None

    def _check(self) -> None:
        check_choice("numerics.scheme", self.scheme, ("explicit", "implicit", "implicit_pad"))
        check_choice("numerics.update", self.update, ("gap", "geometry"))
        check_int("numerics.steps", self.steps, 1, allow_none=True)
        check_number("numerics.dp_tol", self.dp_tol, 0.0)
        check_number("numerics.dh_fraction", self.dh_fraction, 0.0, 1.0)
        check_number("numerics.max_dh", self.max_dh, 0.0, unit="m", allow_none=True)
        check_number("numerics.wear_tol", self.wear_tol, 0.0, unit="m", allow_none=True)
        check_choice("numerics.norm", self.norm, ("l2", "max"))
        check_number("numerics.stability", self.stability, 0.0, 2.0, allow_none=True)
        check_number("numerics.implicit_floor", self.implicit_floor, 0.0, 1.0, lo_open=False)
        check_number("numerics.tol", self.tol, 0.0, 1e-3)
        check_int("numerics.max_halvings", self.max_halvings, 0)
        check_int("numerics.max_steps", self.max_steps, 1)
        check_number("numerics.memory_budget", self.memory_budget, 0.0, unit="GB",
                     allow_none=True)

    def refuses_law(self, surface: str, a: float) -> str | None:
        """Why this scheme cannot wear ``surface`` (``"pad"`` or ``"rotor"``) by a law
        of exponent ``a`` (backward Euler needs a law linear in p); None where it can."""
        implicit = self.scheme != "explicit" if surface == "pad" else self.scheme == "implicit"
        if not implicit or a == 1.0:
            return None
        other = ("'explicit'" if surface == "pad" else
                 "'implicit_pad' (the rotor's wear explicit) or 'explicit'")
        return (f"numerics.scheme = {self.scheme!r} needs a {surface} wear law linear in p "
                f"(a = 1, backward Euler): allowed 1, or use scheme = {other}")
