"""Calibrating the rust law (:mod:`brakewear.cleaning.rust`) on a dynamometer record.

A record is a CSV file with one row per stop (lines starting with ``#`` are
comments): ``contact_pressure_MPa`` (the pad's mean contact pressure, the
clamp force over the pad's area), ``sliding_distance_m`` (the rotor's
sliding distance at the pad's mean radius in the stop) and what was
measured -- ``friction`` (the stop's mean friction coefficient) and/or
``oxide_removed_um`` (the mean depth of oxide the stop removed, from
profilometry or the disc's mass loss); an empty cell is not measured.

The forward model is the rust law on a uniformly loaded face (a dynamometer
pad bedded in: its contact pressure close to uniform).  A rotor point spends
``pad_share`` of each revolution under the pad (the pad's arc over 360
degrees), so stop ``n`` can remove ``d_n = k_r max(p_n - p_th, 0) s_n
pad_share`` of oxide, and removes ``min(h_n, d_n)`` of the ``h_n`` left; its
friction coefficient is the iron's raised by ``mu_factor`` over the part of
the stop that slid on rust: ``mu_n = mu_iron (1 + (mu_factor - 1) phi_n)``,
``phi_n = min(h_n, d_n) / d_n`` (1 where it removed nothing from a layer
still there, 0 once it is gone).

:func:`calibrate` fits the parameters by weighted least squares
(``scipy.optimize.least_squares``), each observable weighted by its noise,
estimated from its own residuals; ``k_r`` is fitted on its logarithm.  With
Gaussian measurement noise least squares is the maximum-likelihood fit and
``(J^T J)^-1`` of the whitened residuals its covariance (the Laplace
approximation): the intervals are 95 % (``1.96`` standard deviations, on the
logarithm for ``k_r``).  A parameter the record cannot identify (the
thickness without a removal record, the friction without a friction record)
must be held (``fixed``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path

import numpy as np

from ..checks import read_csv_rows
from ..errors import WearError
from .rust import RUST_PRIORS, RustLaw

__all__ = ["DynoRecord", "read_dyno_record", "write_dyno_record", "predict_record",
           "synthetic_record", "calibrate", "Calibration", "FIT_PARAMETERS", "RECORD_COLUMNS"]

#: the record's columns: the two inputs and the two observables
RECORD_COLUMNS = ("contact_pressure_MPa", "sliding_distance_m", "friction", "oxide_removed_um")
#: what :func:`calibrate` can fit (the :class:`~brakewear.cleaning.rust.RustLaw` fields and ``mu_iron``)
FIT_PARAMETERS = ("k_rust", "threshold", "thickness", "mu_factor", "mu_iron")
_LOG = {"k_rust", "thickness"}     # fitted on their logarithms (positive, over decades)


@dataclass(frozen=True)
class DynoRecord:
    """One dynamometer record: per stop the contact pressure (Pa), the sliding
    distance (m) and the measured friction coefficient and removed oxide depth (m;
    NaN where not measured, None where never)."""

    pressure: np.ndarray
    distance: np.ndarray
    friction: np.ndarray | None = None
    removed: np.ndarray | None = None
    source: str = ""

    @property
    def stops(self) -> int:
        """Number of stops."""
        return int(self.pressure.size)


def read_dyno_record(path: str | PathLike) -> DynoRecord:
    """A record from a CSV file (see the module); errors name the file and the row."""
    path = Path(path)
    rows, header = read_csv_rows(path, "the dynamometer record", WearError)
    missing = [c for c in RECORD_COLUMNS[:2] if c not in header]
    if missing or not any(c in header for c in RECORD_COLUMNS[2:]):
        raise WearError(f"{path}: need the columns {RECORD_COLUMNS[0]}, {RECORD_COLUMNS[1]} and "
                        f"one or both of {RECORD_COLUMNS[2]}, {RECORD_COLUMNS[3]} (the header is "
                        f"{', '.join(header) or '(empty file)'})")
    cols = {c: [] for c in RECORD_COLUMNS if c in header}
    limits = {"contact_pressure_MPa": (0.0, 50.0), "sliding_distance_m": (0.0, 1e5),
              "friction": (0.0, 2.0), "oxide_removed_um": (-100.0, 1000.0)}
    for i, row in enumerate(rows, start=2):
        for c in cols:
            text = (row.get(c) or "").strip()
            try:
                x = float(text) if text or c in RECORD_COLUMNS[:2] else np.nan
            except ValueError:
                raise WearError(f"{path}, row {i}: {c} = {text!r} is not a number") from None
            lo, hi = limits[c]
            if not (np.isnan(x) and c in RECORD_COLUMNS[2:]) and not (
                    np.isfinite(x) and lo <= x <= hi and (x > 0 or c == "oxide_removed_um")):
                raise WearError(f"{path}, row {i}: {c} = {text} is not allowed; need "
                                f"{'a number in' if c == 'oxide_removed_um' else '>'} {lo:g} "
                                f"{'..' if c == 'oxide_removed_um' else 'and <='} {hi:g}")
            cols[c].append(x)
    if len(rows) < 3:
        raise WearError(f"{path}: a record needs at least three stops")
    def get(c, scale):       # a column never filled in is not measured
        x = None if c not in cols else np.array(cols[c]) * scale
        return None if x is None or np.isnan(x).all() else x

    return DynoRecord(get("contact_pressure_MPa", 1e6), get("sliding_distance_m", 1.0),
                      get("friction", 1.0), get("oxide_removed_um", 1e-6), str(path))


def write_dyno_record(path: str | PathLike, record: DynoRecord, header: str = "") -> Path:
    """Write ``record`` in the CSV form :func:`read_dyno_record` reads (``header``:
    comment lines put first)."""
    path = Path(path)
    out = [f"# {ln}" for ln in header.splitlines()]
    out.append(",".join(RECORD_COLUMNS))
    for n in range(record.stops):
        f = "" if record.friction is None or np.isnan(record.friction[n]) else \
            f"{record.friction[n]:.5f}"
        r = "" if record.removed is None or np.isnan(record.removed[n]) else \
            f"{record.removed[n] * 1e6:.4f}"
        out.append(f"{record.pressure[n] / 1e6:.4f},{record.distance[n]:.3f},{f},{r}")
    path.write_text("\n".join(out) + "\n")
    return path


def predict_record(params: dict, pressure, distance, pad_share: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The friction coefficient and the removed depth (m) per stop of the forward
    model (the module) with ``params`` (``k_rust``, ``threshold``, ``thickness``,
    ``mu_factor``, ``mu_iron``)."""
    k, pth, h = params["k_rust"], params["threshold"], params["thickness"]
    d = k * np.maximum(np.asarray(pressure) - pth, 0.0) * np.asarray(distance) * pad_share
    removed, phi = np.zeros(d.size), np.zeros(d.size)
    for n in range(d.size):
        removed[n] = min(h, d[n])
        phi[n] = removed[n] / d[n] if d[n] > 0 else float(h > 0)
        h -= removed[n]
    return params["mu_iron"] * (1.0 + (params["mu_factor"] - 1.0) * phi), removed


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
    logarithm for ``k_rust`` and ``thickness``), the noise of each observable and
    the held values."""

    values: dict
    sd: dict
    interval_95: dict
    correlation: np.ndarray
    names: tuple
    noise: dict
    fixed: dict
    stops: int
    cost: float
    extra: dict = field(default_factory=dict)

    def law(self, **changes) -> RustLaw:
        """The fitted :class:`~brakewear.cleaning.rust.RustLaw` (fields not fitted from ``fixed``
        or the law's defaults; ``changes`` override)."""
        both = {**self.fixed, **self.values}
        keys = ("thickness", "k_rust", "threshold", "mu_factor", "pad_wear_factor")
        return RustLaw(**{**{k: both[k] for k in keys if k in both}, **changes})


def _identifiable(record: DynoRecord) -> tuple:
    has_f = record.friction is not None and np.isfinite(record.friction).any()
    has_r = record.removed is not None and np.isfinite(record.removed).any()
    names = ("k_rust", "threshold") + (("thickness",) if has_r else ()) + \
        (("mu_factor", "mu_iron") if has_f else ())
    return names


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
        The parameters to fit (of :data:`FIT_PARAMETERS`); default: all the record
        identifies (the thickness needs a removal record, ``mu_factor`` and
        ``mu_iron`` a friction record).
    fixed
        Values of the parameters not fitted (SI units); default the priors' medians
        (:data:`~brakewear.cleaning.rust.RUST_PRIORS`) and ``mu_iron`` 0.4.
    start
        Start values of the fitted ones (default: the same).
    """
    from scipy.optimize import least_squares

    if not (0 < pad_share <= 1):
        raise WearError(f"pad_share = {pad_share!r} is not allowed; need 0 < pad_share <= 1 "
                        "(the pad's arc over 360 degrees)")
    names = tuple(_identifiable(record) if fit is None else fit)
    bad = [n for n in names if n not in FIT_PARAMETERS]
    if bad:
        raise WearError(f"fit: {bad[0]!r} is not a rust-law parameter; allowed: "
                        f"{', '.join(FIT_PARAMETERS)}")
    base = {k: RUST_PRIORS[k].a if RUST_PRIORS[k].kind != "uniform" else
            0.5 * (RUST_PRIORS[k].a + RUST_PRIORS[k].b)
            for k in ("k_rust", "threshold", "thickness", "mu_factor")}
    base["mu_iron"] = 0.4
    held = {**base, **(fixed or {})}
    x0 = _to_x({**held, **(start or {})}, names)
    resid = _Residuals(record, pad_share, names, held)
    best = None
    for x in _starts(x0, names):             # the min() kinks: start from a grid
        sol = least_squares(resid, x, method="trf", x_scale="jac")
        if best is None or sol.cost < best.cost:
            best = sol
    for _ in range(3):                        # each observable's noise from its residuals
        resid.reweight(best.x)
        best = least_squares(resid, best.x, method="trf", x_scale="jac")
    return _result(best, resid, names, held, record)


def _starts(x0: np.ndarray, names) -> list:
    """Start vectors: ``x0`` and a grid over ``k_rust`` (a factor 5 either way), the
    threshold (0, 0.05, 0.1 MPa) and the thickness (a factor 2.5 either way)."""
    axes = {"k_rust": np.log(5.0) * np.array([-1.0, 0.0, 1.0]),
            "thickness": np.log(2.5) * np.array([-1.0, 0.0, 1.0])}
    grid = [x0]
    import itertools

    k = [axes["k_rust"] if n == "k_rust" else axes["thickness"] if n == "thickness" else
         np.array([0.0, 0.05e6, 0.1e6]) - x0[i] if n == "threshold" else np.zeros(1)
         for i, n in enumerate(names)]
    grid += [x0 + np.array(d) for d in itertools.product(*k) if any(d)]
    return grid


class _Residuals:
    """Whitened residuals of the record's observables for a parameter vector."""

    def __init__(self, record, pad_share, names, held):
        self.rec, self.share, self.names, self.held = record, pad_share, names, held
        self.obs = {}
        if record.friction is not None and np.isfinite(record.friction).any():
            self.obs["friction"] = np.isfinite(record.friction)
        if record.removed is not None and np.isfinite(record.removed).any():
            self.obs["removed"] = np.isfinite(record.removed)
        # a first noise estimate from successive differences (robust to the trend)
        self.sigma = {k: _difference_noise(getattr(record, k)[m]) for k, m in self.obs.items()}

    def params(self, x) -> dict:
        return {**self.held, **_from_x(x, self.names)}

    def parts(self, x) -> dict:
        mu, rem = predict_record(self.params(x), self.rec.pressure, self.rec.distance,
                                 self.share)
        pred = {"friction": mu, "removed": rem}
        return {k: (pred[k] - getattr(self.rec, k))[m] for k, m in self.obs.items()}

    def __call__(self, x) -> np.ndarray:
        return np.concatenate([r / self.sigma[k] for k, r in self.parts(x).items()])

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
    return np.array([np.log(values[n]) if n in _LOG else values[n] for n in names], dtype=float)


def _from_x(x, names) -> dict:
    return {n: float(np.exp(v)) if n in _LOG else float(v) for n, v in zip(names, x)}


def _result(sol, resid: _Residuals, names, held, record) -> Calibration:
    J = sol.jac
    H = J.T @ J
    var = np.full(len(names), np.nan)
    d = np.sqrt(np.diag(H))
    if np.all(d > 0) and np.linalg.cond(H / np.outer(d, d)) < 1e10:   # scale-free
        cov = np.linalg.inv(H)
        var = np.diag(cov)
    if not (np.all(np.isfinite(var)) and np.all(var > 0)):
        raise WearError(f"the record does not identify {', '.join(names)} together (a singular "
                        "fit): hold some of them (fixed=..., fit=...); a record of the oxide "
                        "removed at several pressures identifies k_rust and the threshold")
    sd_x = np.sqrt(var)
    values = _from_x(sol.x, names)
    sd, interval = {}, {}
    for i, n in enumerate(names):
        if n in _LOG:
            sd[n] = values[n] * sd_x[i]                   # to first order
            interval[n] = (float(np.exp(sol.x[i] - 1.96 * sd_x[i])),
                           float(np.exp(sol.x[i] + 1.96 * sd_x[i])))
        else:
            sd[n] = float(sd_x[i])
            interval[n] = (values[n] - 1.96 * sd[n], values[n] + 1.96 * sd[n])
    corr = cov / np.outer(sd_x, sd_x)
    return Calibration(values, sd, interval, corr, tuple(names), dict(resid.sigma),
                       {k: v for k, v in held.items() if k not in names}, record.stops,
                       float(sol.cost))
