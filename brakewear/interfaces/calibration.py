"""Calibration of the Winkler foundation against FE contact, and the comparison of the two."""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

import numpy as np

from ..errors import FoundationError
from .winkler_bed import WinklerInterface

logger = logging.getLogger(__name__)

__all__ = ["CalibrationReport", "fe_approach", "fe_lever_arm", "compare", "calibrate"]


@dataclass
class CalibrationReport:
    """What a calibration matched and how far off the rest is (Winkler vs FE).

    Relative errors are (Winkler - FE) / FE; ``cop_distance`` is the distance
    between the centres of pressure (m) and ``cop_dtheta_deg`` their
    difference in angle; ``pressure_l2`` is the area-weighted L2 norm of the
    pressure difference over that of the FE pressure.
    """

    matched: str
    interface: WinklerInterface
    scale: float                      # modulus scale applied (stiffness match)
    errors: dict
    winkler: dict                     # the Winkler figures
    fe: dict                          # the FE figures
    speed_ratio: float                # FE solve time / Winkler solve time

    def summary(self) -> dict:
        return {"matched": self.matched, "scale": self.scale, "errors": self.errors,
                "lever_arm_m": self.interface.lever_arm,
                "winkler": self.winkler, "fe": self.fe, "speed_ratio": self.speed_ratio}


def fe_approach(interface: WinklerInterface, fe) -> float:
    """Approach of the FE pad's load footprint (m): minus the area-weighted mean
    z-displacement of the piston-face nodes, which is the displacement that
    does work with the uniform piston traction (the FE's ``w``)."""
    if interface.load_nodes is None:
        raise FoundationError("this interface does not know the pad's load footprint; "
                              "build it with WinklerInterface.from_model")
    uz = np.asarray(fe.u["pad"]).reshape(-1, 3)[interface.load_nodes, 2]
    return float(-(interface.load_weights * uz).sum())


def fe_lever_arm(model, fe) -> float:
    """Height above the friction face (m) of the line of action of the FE's
    abutment reaction: ``(sum z_j R_j) . S / |S|^2`` over the pad's abutment
    nodes, ``R_j`` their in-plane reactions (``K u - f``) and ``S`` the
    resultant.  Its couple with the friction resultant is what tips the pad
    (the centre of pressure moves by ``lever mu`` toward the leading edge).
    Needs a solve with friction (``mu > 0``): without it the resultant vanishes.
    """
    from ..fem.boundary import boundary_dofs

    pad, off = model.meshes["pad"], model.offsets["pad"]
    f = model.loads(fe.clamp_force / model.geometry.clamp_area)
    f = f[3 * off:3 * (off + pad.nvertices)]
    r = (model.stiffness("pad") @ np.asarray(fe.u["pad"]) - f).reshape(-1, 3)
    nodes = np.unique(boundary_dofs(pad, "abutment", [0, 1]) // 3)
    R = r[nodes, :2]
    S = R.sum(axis=0)
    if float(S @ S) <= (1e-6 * fe.clamp_force) ** 2:
        raise FoundationError("the FE abutment reaction has no resultant (a solve without "
                              "friction?): the lever arm needs mu > 0")
    return float((pad.p[2, nodes][:, None] * R).sum(axis=0) @ S / (S @ S))


def _figures(interface: WinklerInterface, p: np.ndarray, force: float, approach: float) -> dict:
    A, xy = interface.area, interface.xy
    fz = A * p
    cx, cy = (xy * fz).sum(axis=1) / fz.sum()
    return {"stiffness_N_per_m": force / approach, "approach_m": approach, "force_N": force,
            "contact_area_m2": float(A[p > 0].sum()), "peak_pressure_Pa": float(p.max()),
            "cop_x_m": float(cx), "cop_y_m": float(cy), "cop_r_m": float(np.hypot(cx, cy)),
            "cop_theta_deg": float(np.degrees(np.arctan2(cy, cx)))}


def _fe_load(interface: WinklerInterface, fe) -> tuple[float, float]:
    mu = float(fe.info.get("mu", 0.0))
    return fe.clamp_force / interface.hydraulic_area, mu


def compare(interface: WinklerInterface, fe, gap=None) -> dict:
    """Solve the interface at the FE result's load and friction and return the
    Winkler figures, the FE figures and the errors (see :class:`CalibrationReport`)."""
    lp, mu = _fe_load(interface, fe)
    if fe.interface_pressure.shape != (interface.n,):
        raise FoundationError(f"FE result has {fe.interface_pressure.size} interface nodes, the "
                              f"interface {interface.n}: they must come from the same pad mesh")
    t0 = time.perf_counter()
    res = interface.solve(lp, mu, gap)
    t_w = time.perf_counter() - t0
    # approach at the piston footprint (the work-conjugate displacement)
    w = res.approach + float(res.tilts @ (interface.footprint - interface.load_point))
    pfe = np.asarray(fe.interface_pressure, dtype=float)
    if fe.active is not None:
        pfe = np.where(fe.active, pfe, 0.0)
    wf = _figures(interface, res.pressure, res.force, w)
    ff = _figures(interface, pfe, float((interface.area * pfe).sum()), fe_approach(interface, fe))
    A = interface.area
    err = {
        "stiffness": wf["stiffness_N_per_m"] / ff["stiffness_N_per_m"] - 1.0,
        "contact_area": wf["contact_area_m2"] / ff["contact_area_m2"] - 1.0,
        "peak_pressure": wf["peak_pressure_Pa"] / ff["peak_pressure_Pa"] - 1.0,
        "cop_distance_m": float(np.hypot(wf["cop_x_m"] - ff["cop_x_m"],
                                         wf["cop_y_m"] - ff["cop_y_m"])),
        "cop_dtheta_deg": wf["cop_theta_deg"] - ff["cop_theta_deg"],
        "cop_dr_m": wf["cop_r_m"] - ff["cop_r_m"],
        "pressure_l2": float(np.sqrt((A * (res.pressure - pfe) ** 2).sum() / (A * pfe ** 2).sum())),
    }
    t_fe = float(fe.info.get("total_s", np.nan))
    return {"errors": err, "winkler": {**wf, "solve_s": t_w, "iterations": res.iterations},
            "fe": {**ff, "solve_s": t_fe}, "speed_ratio": t_fe / t_w, "result": res,
            "line_pressure": lp, "mu": mu}


def calibrate(interface: WinklerInterface, fe, match: str = "stiffness",
              model=None, lever_arm: str | float = "fe") -> CalibrationReport:
    """Calibrate the foundation modulus against an FE contact solution.

    Parameters
    ----------
    interface
        From :meth:`WinklerInterface.from_model` on the FE result's model.
    fe
        A :class:`brakewear.static.StaticResult` of :func:`brakewear.static.solve_contact`
        (its clamp force and ``info["mu"]`` set the load).
    match
        ``"stiffness"``: scale the modulus (uniformly, keeping any per-node
        pattern) so that the interface stiffness F / w equals the FE's
        F / w_FE (:func:`fe_approach`).  With zero initial gaps the contact
        problem is positively homogeneous -- the solution scales with the
        load and the active set does not change -- so the FE's secant
        stiffness is also its tangent stiffness, and one FE solve suffices;
        the Winkler stiffness is linear in a uniform modulus scale, so one
        scale is exact.

        ``"pressure"``: after the stiffness match, a per-node modulus
        ``k_i = p_FE,i / delta_i`` on the nodes the FE has in contact
        (``delta`` the stiffness-matched interference), on the nodes the
        FE has open an offset that opens them by the FE's own gap, and the
        load point moved to where the FE pressure is in moment balance with
        the rigid backing (the shift is in ``interface.info``).  A uniform
        modulus has no freedom left for the pressure (with zero gaps the
        three balance equations fix the affine pressure field whatever k
        is), so the least-squares fit takes the per-node field, where it has
        a zero residual.  It reproduces the FE pressure exactly without
        friction (and the stiffness), and is right only near the load it was
        calibrated at.
    model
        The :class:`BrakeModel`; needed for ``match="pressure"`` (FE gaps) and
        for ``lever_arm="fe"``.
    lever_arm
        ``"fe"`` (default): with friction in the FE result and ``model``
        given, take the friction couple's lever arm from the FE abutment
        reaction (:func:`fe_lever_arm`); otherwise keep the interface's.  A
        number sets it.

    Returns
    -------
    CalibrationReport
        The calibrated interface, the matched aspect, and the errors of the
        others at the calibration load.
    """
    if match not in ("stiffness", "pressure"):
        raise FoundationError(f"match = {match!r} is not allowed; allowed: 'stiffness', "
                              "'pressure'")
    lp, mu = _fe_load(interface, fe)
    if isinstance(lever_arm, str):
        if lever_arm != "fe":
            raise FoundationError(f"lever_arm = {lever_arm!r}; allowed: 'fe' or a number (m)")
        if mu > 0 and model is not None:
            interface = replace(interface, lever_arm=fe_lever_arm(model, fe),
                                info={**interface.info, "lever_arm_source": "FE abutment"})
    else:
        interface = replace(interface, lever_arm=float(lever_arm))
    w_fe = fe_approach(interface, fe)
    if not w_fe > 0:
        raise FoundationError(f"the FE approach {w_fe:.3e} m is not positive: is this a contact "
                              "solution of the same model under a compressive load?")
    base = interface.solve(lp, mu)
    w0 = base.approach + float(base.tilts @ (interface.footprint - interface.load_point))
    k_fe = fe.clamp_force / w_fe
    scale = k_fe / (base.force / w0)
    cal = interface.with_modulus(interface.modulus * scale, calibrated="stiffness",
                                 calibration_scale=scale)
    if match == "pressure":
        if model is None:
            raise FoundationError("match='pressure' needs model= (the FE gaps of the open nodes)")
        pfe = np.where(fe.active, fe.interface_pressure, 0.0) if fe.active is not None \
            else np.asarray(fe.interface_pressure)
        res = cal.solve(lp, mu)
        d = res.interference
        on = pfe > 0
        if np.any(d[on] <= 0):
            raise FoundationError(f"{int((d[on] <= 0).sum())} node(s) carry FE pressure where the "
                                  "stiffness-matched foundation is open: no per-node modulus fits")
        k = cal.modulus.copy()
        k[on] = pfe[on] / d[on]
        off = cal.offset.copy()
        gfe = _fe_gaps(model, fe)
        off[~on] += d[~on] + np.maximum(gfe[~on], 0.0)
        # the effective load line: where the FE pressure is in moment balance
        # with the rigid-backing model (the FE's abutments also take in-plane
        # reactions of the bending backplate, which the rigid backing lacks)
        fz = cal.area * pfe
        lp_eff = (cal.xy * fz).sum(axis=1) / fz.sum()
        if mu > 0:
            lp_eff = lp_eff + cal.lever_arm * mu * (cal.drag * fz).sum(axis=1) / fz.sum()
        shift = lp_eff - cal.load_point
        cal = replace(cal.with_modulus(k, offset=off, calibrated="pressure",
                                       load_point_shift_m=shift.tolist()), load_point=lp_eff)
    cmp = compare(cal, fe)
    rep = CalibrationReport(match, cal, float(scale), cmp["errors"], cmp["winkler"], cmp["fe"],
                            float(cmp["speed_ratio"]))
    logger.info("calibrated (%s): scale %.4g, errors %s", match, scale, cmp["errors"])
    return rep


def _fe_gaps(model, fe) -> np.ndarray:
    """Normal gap of each pad friction node after the FE solve (m)."""

    pair = model.contact_pair(0.0)
    u = np.concatenate([np.asarray(fe.u[b]) for b in model.bodies])
    return pair.gaps(u)
