"""Calibrating the rust law (:mod:`brakewear.cleaning.rust`) on a dynamometer record.

A record (:mod:`brakewear.cleaning.rust_record`) has one row per stop: the pad's mean
contact pressure, the rotor's sliding distance at the pad's mean radius and
what was measured, the stop's friction coefficient and/or the depth of oxide
it removed.

The forward model (:mod:`brakewear.cleaning.rust_model`) is the rust law on a
uniformly loaded face (a dynamometer pad bedded in: its contact pressure
close to uniform).  A rotor point spends ``pad_share`` of each revolution
under the pad (the pad's arc over 360 degrees), so stop ``n`` can remove
``d_n = k_r max(p_n - p_th, 0) s_n pad_share`` of oxide, and removes
``min(h_n, d_n)`` of the ``h_n`` left; its friction coefficient is the
iron's raised by ``mu_factor`` over the part of the stop that slid on rust:
``mu_n = mu_iron (1 + (mu_factor - 1) phi_n)``, ``phi_n = min(h_n, d_n) /
d_n`` (1 where it removed nothing from a layer still there, 0 once it is
gone).

:func:`calibrate` fits the parameters by weighted least squares
(``scipy.optimize.least_squares`` with the model's derivatives in closed
form, within bounds: ``p_th >= 0``), each observable weighted by its noise,
estimated from its own residuals; ``k_r`` and ``h_c`` are fitted on their
logarithms.  The model is piecewise smooth (its pieces: the stop the layer
runs out in, the pressure levels above the threshold); the fit starts from
the best pieces, each fitted by linear least squares
(:func:`brakewear.cleaning.rust_model.screen`), so that the minimum it reports is
the record's, not the nearest to a guess.  With Gaussian measurement noise
least squares is the maximum-likelihood fit and ``(J^T J)^-1`` of the
whitened residuals its covariance (the Laplace approximation, with ``J^T J``
averaged over the sides of a kink the fit stops on): the intervals are 95 %
(Student's t of the residuals' degrees of freedom, on the logarithm for
``k_r`` and ``h_c``).

Whether the record identifies each fitted parameter is decided from the
record, not from the optimiser: a parameter a record's columns cannot give
(the friction without friction, the threshold and the thickness apart from
``k_r`` without the removed depth) is refused before the fit; after it, the
fit must explain the record better than one with nothing removed and than
one whose layer lasts (likelihood-ratio tests, :data:`FALSE_EVIDENCE`),
else the parameters that need a removal (``k_r``, ``p_th``, ``h_c``) or a
run-out (``h_c``, and ``mu_factor`` with ``mu_iron``: the friction is
never split) are refused, and the threshold needs removal at two pressures
while the layer lasts.  Each refusal (:class:`~brakewear.errors.IdentifiabilityError`)
names the parameter and why.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import IdentifiabilityError, WearError
from .rust import RUST_PRIORS, RustLaw
from .rust_model import COORDINATES, LOG, curvature, record_model, screen
from .rust_record import RECORD_COLUMNS, DynoRecord, read_dyno_record, write_dyno_record

__all__ = ["DynoRecord", "read_dyno_record", "write_dyno_record", "predict_record",
           "synthetic_record", "calibrate", "Calibration", "FIT_PARAMETERS", "RECORD_COLUMNS",
           "FALSE_EVIDENCE"]

#: what :func:`calibrate` can fit (the :class:`~brakewear.cleaning.rust.RustLaw` fields and
#: ``mu_iron``)
FIT_PARAMETERS = ("k_rust", "threshold", "thickness", "mu_factor", "mu_iron")


def predict_record(params: dict, pressure, distance, pad_share: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The friction coefficient and the removed depth (m) per stop of the forward
    model (the module) with ``params`` (``k_rust``, ``threshold``, ``thickness``,
    ``mu_factor``, ``mu_iron``; :func:`brakewear.cleaning.rust_model.record_model`)."""
    return record_model(params, pressure, distance, pad_share)


def synthetic_record(law: RustLaw, mu_iron: float, pressure, distance, pad_share: float, *,
                     noise_friction: float = 0.01, noise_removed: float = 0.2e-6,
                     seed: int = 1) -> DynoRecord:
    """A record made by the forward model with ``law`` and ``mu_iron``, measured with
    Gaussian noise of the given standard deviations (a synthetic record: to show and
    test :func:`calibrate`)."""
    rng = np.random.default_rng(seed)
    params = {"k_rust": law.k_rust, "threshold": law.threshold, "thickness": law.thickness,
              "mu_factor": law.mu_factor, "mu_iron": mu_iron}
    p, s = np.asarray(pressure, dtype=float), np.asarray(distance, dtype=float)
    mu, rem = predict_record(params, p, s, pad_share)
    return DynoRecord(p, s, mu + noise_friction * rng.standard_normal(p.size),
                      rem + noise_removed * rng.standard_normal(p.size), "synthetic")


@dataclass
class Calibration:
    """What :func:`calibrate` found: per fitted parameter its value, standard deviation
    and 95 % interval (SI units), the correlation of the fitted parameters (on the
    logarithm for ``k_rust`` and ``thickness``), the noise of each observable, the
    held values and ``evidence``: how much better the fit explains the record than
    one with nothing removed (``removal``) and one whose layer lasts (``run_out``),
    as chi-square differences, with the ``critical`` values they must pass."""

    values: dict
    sd: dict
    interval_95: dict
    correlation: np.ndarray
    names: tuple
    noise: dict
    fixed: dict
    stops: int
    cost: float
    evidence: dict = field(default_factory=dict)

    def law(self, **changes) -> RustLaw:
        """The fitted :class:`~brakewear.cleaning.rust.RustLaw` (fields not fitted from ``fixed``
        or the law's defaults; ``changes`` override)."""
        both = {**self.fixed, **self.values}
        keys = ("thickness", "k_rust", "threshold", "mu_factor", "pad_wear_factor")
        return RustLaw(**{**{k: both[k] for k in keys if k in both}, **changes})


#: the chance of a record that does not show a removal or a run-out passing for one
#: (the likelihood-ratio tests of :func:`calibrate`, shared among the pieces it chooses from)
FALSE_EVIDENCE = 1e-3


def _columns(record: DynoRecord) -> tuple[bool, bool]:
    has_f = record.friction is not None and np.isfinite(record.friction).any()
    has_r = record.removed is not None and np.isfinite(record.removed).any()
    return has_f, has_r


def _default_names(record: DynoRecord) -> tuple:
    has_f, has_r = _columns(record)
    return ("k_rust", "threshold") + (("thickness",) if has_r else ()) + \
        (("mu_factor", "mu_iron") if has_f else ())


def calibrate(record: DynoRecord, pad_share: float, *, fit=None, fixed: dict | None = None,
              start: dict | None = None) -> Calibration:
    """Fit the rust law to ``record`` (see the module).

    Parameters
    ----------
    record
        The :class:`DynoRecord`.
    pad_share
        The share of a revolution a rotor point spends under the pad (arc / 360 deg).
    fit
        The parameters to fit (of :data:`FIT_PARAMETERS`); default: ``k_rust`` and
        ``threshold``, the thickness with a removal record, ``mu_factor`` and
        ``mu_iron`` with a friction record.
    fixed
        Values of the parameters not fitted (SI units); default the priors' medians
        (:data:`~brakewear.cleaning.rust.RUST_PRIORS`) and ``mu_iron`` 0.4.
    start
        Start values of the fitted ones (default: the same, and a grid about them).

    Returns
    -------
    Calibration
        The fit with its intervals.

    Raises
    ------
    IdentifiabilityError
        A fitted parameter the record does not constrain, named with the reason (its
        ``parameters``: name -> reason): no oxide removed measurably (``k_rust``,
        ``threshold``, ``thickness``), a layer not seen to wear through
        (``thickness``; ``mu_factor`` with ``mu_iron``: the friction is never
        split between rust and iron), removal seen at one pressure only
        (``threshold``), a record without the removed depth (it sees the layer
        only through when it wore through: one figure for the three).
    """
    from scipy.optimize import least_squares
    from scipy.stats import chi2

    if not (0 < pad_share <= 1):
        raise WearError(f"pad_share = {pad_share!r} is not allowed; need 0 < pad_share <= 1 "
                        "(the pad's arc over 360 degrees)")
    names = tuple(_default_names(record) if fit is None else fit)
    bad = [n for n in names if n not in FIT_PARAMETERS]
    if bad or not names:
        raise WearError(f"fit: {bad[0]!r} is not a rust-law parameter; allowed: "
                        f"{', '.join(FIT_PARAMETERS)}" if bad else "fit: no parameter named")
    base = {k: RUST_PRIORS[k].a if RUST_PRIORS[k].kind != "uniform" else
            0.5 * (RUST_PRIORS[k].a + RUST_PRIORS[k].b)
            for k in ("k_rust", "threshold", "thickness", "mu_factor")}
    base["mu_iron"] = 0.4
    held = {**base, **(fixed or {})}
    _refuse(_by_columns(record, names))
    resid = _Residuals(record, pad_share, names, held)
    best, values = None, {**held, **(start or {})}
    for _ in range(2):      # the pieces again with the noise of the first round's fit
        starts = _starts(resid, values if best is None else resid.params(best.x))
        for x in starts + ([] if best is None else [best.x]):
            sol = least_squares(resid, x, jac=resid.jac, bounds=resid.bounds, method="trf",
                                x_scale="jac")
            if best is None or sol.cost < best.cost:
                best = sol
        for _ in range(3):                    # each observable's noise from its residuals
            resid.reweight(best.x)
            best = least_squares(resid, best.x, jac=resid.jac, bounds=resid.bounds,
                                 method="trf", x_scale="jac")
    evidence = _evidence(resid, best, chi2)
    _refuse(_by_data(resid, best, evidence))
    cal = _result(best, resid, names, held, record)
    cal.evidence = evidence
    return cal


def _refuse(reasons: dict) -> None:
    if reasons:
        shown = "; ".join(f"{k}: {v}" for k, v in reasons.items())
        raise IdentifiabilityError(f"the record does not identify {shown}", parameters=reasons)


_LAYER = ("k_rust", "threshold", "thickness")
_SPLIT = ("mu_factor", "mu_iron")


def _by_columns(record: DynoRecord, names) -> dict:
    """What the record's columns cannot identify, whatever their values."""
    has_f, has_r = _columns(record)
    out = {}
    if not has_f:
        for n in _SPLIT:
            if n in names:
                out[n] = ("the record has no friction column; hold it (fixed=...) or give the "
                          "stops' friction coefficients")
    layer = [n for n in _LAYER if n in names]
    if not has_r and len(layer) > 1:
        keep = "k_rust" if "k_rust" in layer else layer[0]
        for n in layer:
            if n != keep:
                out[n] = ("a record without the oxide removed sees the layer only through the "
                          "stop it wore through in: one figure for k_rust, threshold and "
                          f"thickness together; fit {keep} and hold the others (fixed=...)")
    return out


def _by_data(resid: _Residuals, sol, evidence: dict) -> dict:
    """What this record's values do not constrain (see :func:`calibrate`)."""
    names, out = resid.names, {}
    has_f, has_r = "friction" in resid.obs, "removed" in resid.obs
    params = resid.params(sol.x)
    split = all(n in names for n in _SPLIT)
    gain, crit = evidence["removal"], evidence["critical_removal"]
    seen = f"the fit gains chi-square {gain:.3g} over nothing removed, {crit:.3g} needed"
    if gain < crit:
        hi = float(np.max(resid.rec.pressure)) / 1e6
        why = {"k_rust": f"no stop removed oxide measurably ({seen}): the removal rate is "
                         "not seen",
               "threshold": f"no stop removed oxide measurably ({seen}): the threshold is "
                            f"only bounded, above the record's highest pressure {hi:.4g} MPa "
                            "unless k_rust is small",
               "thickness": f"no stop removed oxide measurably ({seen}): the layer is not "
                            "seen"}
        out.update({n: why[n] for n in _LAYER if n in names})
        if split and has_f:
            out.update({n: "the friction is never seen off the rust (nothing was removed): "
                           "only mu_iron x mu_factor is seen; hold one of them" for n in _SPLIT})
        return out
    gain, crit = evidence["run_out"], evidence["critical_run_out"]
    if gain < crit:
        seen = f"the fit gains chi-square {gain:.3g} over a layer that lasts, {crit:.3g} needed"
        total = float(np.nansum(np.clip(resid.rec.removed, 0, None))) * 1e6 if has_r else None
        if "thickness" in names:
            out["thickness"] = (f"the layer is not seen to wear through within the record "
                                f"({seen})" + (f"; the {total:.3g} um removed in all bound it "
                                               "from below only" if total is not None else ""))
        if not has_r:
            for n in _LAYER:
                if n in names:
                    out[n] = (f"the friction does not show the layer wearing through ({seen}); "
                              "a friction record sees the layer only then")
        if split and has_f:
            mu = params["mu_iron"] * params["mu_factor"]
            out.update({n: f"the friction is never split between rust and iron (the layer "
                           f"lasts through the record): only mu_iron x mu_factor = {mu:.4g} is "
                           "seen; hold one of them" for n in _SPLIT})
    if has_r and "threshold" in names and "k_rust" in names:
        levels = resid.removal_levels(sol.x)
        if levels.size < 2:
            at = f"at {levels[0] / 1e6:.4g} MPa only" if levels.size else "at no pressure"
            out["threshold"] = (f"oxide is removed {at} while the layer lasts: k_rust and the "
                                "threshold are seen only as k_rust x (p - threshold); hold the "
                                "threshold or add stops at another pressure")
    return out


def _evidence(resid: _Residuals, sol, chi2) -> dict:
    """Chi-square gains of the fit over a record with nothing removed and over a layer that
    lasts (both fitted with the same noise), and the critical values they must pass."""
    from scipy.optimize import least_squares

    names, params = resid.names, resid.params(sol.x)
    full = float(np.sum(resid(sol.x) ** 2))
    split = int(all(n in names for n in _SPLIT) and "friction" in resid.obs)
    flat = {"friction": 0.0, "removed": 0.0}
    if "friction" in resid.obs:
        m = resid.rec.friction[resid.obs["friction"]]
        flat["friction"] = float(np.sum((m - m.mean()) ** 2)) / resid.sigma["friction"] ** 2
    none = flat["friction"]
    if "removed" in resid.obs:
        r = resid.rec.removed[resid.obs["removed"]]
        none += float(np.sum(r ** 2)) / resid.sigma["removed"] ** 2
    lasting = flat["friction"]
    if "removed" in resid.obs:          # the removal of a layer that never runs out
        fit = tuple(n for n in ("k_rust", "threshold") if n in names)
        lr = _Residuals(resid.rec, resid.share, fit, {**params, "thickness": 1.0},
                        obs=("removed",), sigma=resid.sigma)
        if fit:
            best = None
            for x in _starts(lr, params, never=True):
                s = least_squares(lr, x, jac=lr.jac, bounds=lr.bounds, method="trf",
                                  x_scale="jac")
                best = s if best is None or s.cost < best.cost else best
            lasting += 2.0 * best.cost
        else:
            lasting += float(np.sum(lr(np.zeros(0)) ** 2))
    # the fit picks the stop the layer runs out in and the levels above the threshold:
    # the chance of a false gain is shared among those pieces (Bonferroni)
    n_layer = sum(n in names for n in _LAYER)
    stops, levels = resid.rec.stops, np.unique(resid.rec.pressure).size
    return {"removal": none - full, "run_out": lasting - full,
            "critical_removal": float(chi2.isf(FALSE_EVIDENCE / (stops * levels),
                                               max(n_layer + split, 1))),
            "critical_run_out": float(chi2.isf(FALSE_EVIDENCE / stops, 1 + split))}


#: bounds of the fit's coordinates (log k_r, p_th, log h_c, mu_factor, mu_iron)
_BOUNDS = {"k_rust": (np.log(1e-18), np.log(1e-8)), "threshold": (0.0, 10e6),
           "thickness": (np.log(1e-9), np.log(1e-3)), "mu_factor": (1e-3, 3.0),
           "mu_iron": (1e-3, 2.0)}


def _starts(resid: _Residuals, values: dict, never: bool | None = None) -> list:
    """Start vectors of the fitted coordinates: ``values`` and the best pieces of
    the model (:func:`brakewear.cleaning.rust_model.screen`)."""
    rec, names = resid.rec, resid.names
    pieces = screen(rec.pressure, rec.distance, resid.share,
                    rec.removed if "removed" in resid.obs else None,
                    rec.friction if "friction" in resid.obs else None,
                    sigma=resid.sigma, held=values, never=never)
    lo, hi = _bound_arrays(names)
    out = [np.clip(_to_x(x, names), lo, hi) for x in [values, *pieces]]
    return [x for i, x in enumerate(out) if not any(np.allclose(x, y) for y in out[:i])]


def _bound_arrays(names) -> tuple[np.ndarray, np.ndarray]:
    return (np.array([_BOUNDS[n][0] for n in names]), np.array([_BOUNDS[n][1] for n in names]))


class _Residuals:
    """Whitened residuals of the record's observables for a parameter vector (the
    fitted ``names``; the others ``held``), and their Jacobian."""

    def __init__(self, record, pad_share, names, held, obs=("friction", "removed"),
                 sigma=None):
        self.rec, self.share, self.names, self.held = record, pad_share, tuple(names), held
        self.obs = {}
        for k in obs:
            y = getattr(record, k)
            if y is not None and np.isfinite(y).any():
                self.obs[k] = np.isfinite(y)
        self.cols = [COORDINATES.index(n) for n in self.names]
        self.bounds = _bound_arrays(self.names)
        # a first noise estimate from successive differences (robust to the trend)
        self.sigma = dict(sigma) if sigma is not None else \
            {k: _difference_noise(getattr(record, k)[m]) for k, m in self.obs.items()}

    def params(self, x) -> dict:
        return {**self.held, **_from_x(x, self.names)}

    def _model(self, x, side=(0, 0), jac=False):
        return record_model(self.params(x), self.rec.pressure, self.rec.distance, self.share,
                            side, jac)

    def parts(self, x) -> dict:
        mu, rem = self._model(x)
        pred = {"friction": mu, "removed": rem}
        return {k: (pred[k] - getattr(self.rec, k))[m] for k, m in self.obs.items()}

    def __call__(self, x) -> np.ndarray:
        return np.concatenate([r / self.sigma[k] for k, r in self.parts(x).items()])

    def jac(self, x, side=(0, 0)) -> np.ndarray:
        _, _, J_mu, J_rem = self._model(x, side, jac=True)
        J = {"friction": J_mu, "removed": J_rem}
        return np.concatenate([J[k][m][:, self.cols] / self.sigma[k]
                               for k, m in self.obs.items()])

    def removal_levels(self, x) -> np.ndarray:
        """The pressures (Pa) of the measured stops that removed oxide while the layer
        lasted (their removal depends on ``k_rust`` and the threshold)."""
        _, _, _, J_rem = self._model(x, jac=True)
        seen = self.obs.get("removed", np.zeros(self.rec.stops, dtype=bool))
        return np.unique(self.rec.pressure[seen & (J_rem[:, 1] != 0.0)
                                           & (J_rem[:, 2] == 0.0)])

    def reweight(self, x) -> None:
        """Each observable's noise: its residuals' RMS, corrected for the parameters fitted
        (shared over the observables by their counts)."""
        parts = self.parts(x)
        n = sum(r.size for r in parts.values())
        for k, r in parts.items():
            dof = max(r.size - len(self.names) * r.size / n, 1.0)
            self.sigma[k] = max(float(np.sqrt((r ** 2).sum() / dof)), 1e-12)


def _difference_noise(y: np.ndarray) -> float:
    """The noise of a series from the median of its successive differences' size."""
    d = np.abs(np.diff(y))
    sig = float(np.median(d)) / (0.6745 * np.sqrt(2.0)) if d.size else 0.0
    return sig if sig > 0 else float(np.std(y)) or 1.0


def _to_x(values: dict, names) -> np.ndarray:
    return np.array([np.log(values[n]) if n in LOG else values[n] for n in names], dtype=float)


def _from_x(x, names) -> dict:
    return {n: float(np.exp(v)) if n in LOG else float(v) for n, v in zip(names, x)}


def _result(sol, resid: _Residuals, names, held, record) -> Calibration:
    H = curvature(lambda side: resid.jac(sol.x, side))
    d = np.sqrt(np.diag(H))
    cov = None
    if np.all(d > 0):
        Hn = H / np.outer(d, d)                              # scale-free
        w, V = np.linalg.eigh(Hn)
        if w[0] > 1e-10 * w[-1]:
            cov = np.linalg.inv(H)
    if cov is None:
        null = np.zeros(len(names))
        null[d == 0] = 1.0
        if np.all(d > 0):
            null = np.abs(V[:, 0])
        which = [n for n, v in zip(names, null) if v > 0.3 * null.max()]
        _refuse({n: f"the record does not separate {' and '.join(which)} (a singular fit): "
                    "hold some of them (fixed=..., fit=...); a record of the oxide removed at "
                    "several pressures identifies k_rust and the threshold" for n in which})
    from scipy.stats import t as student

    sd_x = np.sqrt(np.diag(cov))
    values = _from_x(sol.x, names)
    sd, interval = {}, {}
    # the noise is estimated from the residuals: Student's t of their degrees of freedom
    z = float(student.ppf(0.975, max(sol.fun.size - len(names), 1)))
    for i, n in enumerate(names):
        lo, hi = sol.x[i] - z * sd_x[i], sol.x[i] + z * sd_x[i]
        if n in LOG:
            sd[n] = values[n] * sd_x[i]                   # to first order
            interval[n] = (float(np.exp(lo)), float(np.exp(hi)))
        else:
            sd[n] = float(sd_x[i])
            b = _BOUNDS[n]
            interval[n] = (float(max(lo, b[0])), float(min(hi, b[1])))
    corr = cov / np.outer(sd_x, sd_x)
    return Calibration(values, sd, interval, corr, tuple(names), dict(resid.sigma),
                       {k: v for k, v in held.items() if k not in names}, record.stops,
                       float(sol.cost))
