"""Material data: elastic, thermal and wear properties of brake components.

Every material is a plain frozen dataclass in SI units.  The elastic part is
either isotropic (``E``, ``nu``) or transversely isotropic about the local
z axis (the pad normal), which is how friction materials are usually
characterised: stiff in the plane of the pad, softest through its thickness.

Typical values are from docs/references.md; each default below states the
value it took from the quoted range.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import MaterialError

__all__ = [
    "Isotropic",
    "TransverselyIsotropic",
    "Thermal",
    "Material",
    "MATERIALS",
    "get_material",
    "T_AMBIENT_DEFAULT",
    "H_CONV_DEFAULT",
]


def _positive(owner: str, name: str, value: float) -> float:
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise MaterialError(f"{owner}: {name} = {value!r} is not allowed; it must be > 0")
    return value


def _poisson(owner: str, name: str, value: float) -> float:
    value = float(value)
    if not (-1.0 < value < 0.5):
        raise MaterialError(
            f"{owner}: {name} = {value!r} is not allowed; it must lie in (-1, 0.5) "
            "(nu >= 0.5 is incompressible and not supported)"
        )
    return value


@dataclass(frozen=True)
class Isotropic:
    """Isotropic linear elasticity.

    Parameters
    ----------
    E
        Young's modulus (Pa).
    nu
        Poisson's ratio.
    name
        For messages.
    """

    E: float
    nu: float
    name: str = "isotropic"

    def __post_init__(self):
        _positive(self.name, "E", self.E)
        _poisson(self.name, "nu", self.nu)

    def voigt(self) -> np.ndarray:
        """6x6 stiffness in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear."""
        lam = self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
        mu = self.E / (2.0 * (1.0 + self.nu))
        C = np.zeros((6, 6))
        C[:3, :3] = lam
        C[np.arange(3), np.arange(3)] += 2.0 * mu
        C[np.arange(3, 6), np.arange(3, 6)] = mu
        return C

    @property
    def E_normal(self) -> float:
        """Modulus along the local z axis (used for contact estimates)."""
        return self.E

    @property
    def nu_normal(self) -> float:
        return self.nu


@dataclass(frozen=True)
class TransverselyIsotropic:
    """Transversely isotropic elasticity, symmetry axis = local z (pad normal).

    Parameters
    ----------
    E_p, nu_p
        Young's modulus and Poisson ratio in the plane of isotropy (x, y).
    E_t
        Young's modulus along z (through the pad thickness).
    nu_tp
        Poisson ratio: contraction in the plane under a stress along z
        (``-eps_x / eps_z`` for ``sigma_z`` alone).
    G_t
        Shear modulus in the planes containing z (yz, xz).
    name
        For messages.
    """

    E_p: float
    E_t: float
    nu_p: float
    nu_tp: float
    G_t: float
    name: str = "transversely_isotropic"

    def __post_init__(self):
        for key in ("E_p", "E_t", "G_t"):
            _positive(self.name, key, getattr(self, key))
        _poisson(self.name, "nu_p", self.nu_p)
        if not (-1.0 < self.nu_tp < 1.0):
            raise MaterialError(f"{self.name}: nu_tp = {self.nu_tp!r} must lie in (-1, 1)")
        w = np.linalg.eigvalsh(self.compliance())
        if w.min() <= 0.0:
            raise MaterialError(
                f"{self.name}: the elastic constants E_p={self.E_p}, E_t={self.E_t}, "
                f"nu_p={self.nu_p}, nu_tp={self.nu_tp} do not give a positive definite "
                "stiffness (need 1 - nu_p - 2 nu_tp^2 E_p/E_t > 0)"
            )

    def compliance(self) -> np.ndarray:
        S = np.zeros((6, 6))
        S[0, 0] = S[1, 1] = 1.0 / self.E_p
        S[2, 2] = 1.0 / self.E_t
        S[0, 1] = S[1, 0] = -self.nu_p / self.E_p
        S[0, 2] = S[2, 0] = S[1, 2] = S[2, 1] = -self.nu_tp / self.E_t
        S[3, 3] = S[4, 4] = 1.0 / self.G_t
        S[5, 5] = 2.0 * (1.0 + self.nu_p) / self.E_p
        return S

    def voigt(self) -> np.ndarray:
        """6x6 stiffness in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear."""
        return np.linalg.inv(self.compliance())

    @property
    def E_normal(self) -> float:
        return self.E_t

    @property
    def nu_normal(self) -> float:
        return self.nu_tp


@dataclass(frozen=True)
class Thermal:
    """Thermal data of a material.

    Parameters
    ----------
    rho
        Density (kg/m^3).
    c
        Specific heat capacity (J/kg K).
    kappa
        Conductivity (W/m K).
    alpha
        Linear expansion coefficient (1/K).
    """

    rho: float
    c: float
    kappa: float
    alpha: float

    @property
    def effusivity(self) -> float:
        """sqrt(kappa rho c), the quantity that partitions frictional heat."""
        return float(np.sqrt(self.kappa * self.rho * self.c))


@dataclass(frozen=True)
class Material:
    """A named material.

    Parameters
    ----------
    name
        What geometry files and messages call it.
    elastic
        Its elastic law (:class:`Isotropic` or :class:`TransverselyIsotropic`).
    thermal
        Its :class:`Thermal` data.
    wear_k
        Its Archard wear coefficient (1/Pa), or None (it does not wear).
    notes
        Free text (where it is used).
    """

    name: str
    elastic: Isotropic | TransverselyIsotropic
    thermal: Thermal
    wear_k: float | None = None
    notes: str = field(default="", compare=False)

    def voigt(self) -> np.ndarray:
        return self.elastic.voigt()


MATERIALS: dict[str, Material] = {
    "grey_cast_iron": Material(
        "grey_cast_iron",
        # E 100-125 GPa, nu 0.26-0.29: mid-range grey iron (GG20/GG25 class)
        Isotropic(E=110e9, nu=0.27, name="grey_cast_iron"),
        Thermal(rho=7200.0, c=500.0, kappa=50.0, alpha=1.15e-5),
        wear_k=5e-16,  # order 1e-16..1e-15 m^2/N
        notes="rotor",
    ),
    "pad_resin": Material(
        "pad_resin",
        # resin-bonded friction material: E 1-15 GPa, softest through thickness
        TransverselyIsotropic(E_p=8e9, E_t=3e9, nu_p=0.25, nu_tp=0.20, G_t=1.5e9,
                              name="pad_resin"),
        Thermal(rho=2400.0, c=1000.0, kappa=2.0, alpha=2e-5),
        wear_k=5e-15,  # order 1e-15..1e-14 m^2/N
        notes="pad friction layer",
    ),
    "pad_isotropic": Material(
        "pad_isotropic",
        Isotropic(E=5e9, nu=0.25, name="pad_isotropic"),
        Thermal(rho=2400.0, c=1000.0, kappa=2.0, alpha=2e-5),
        wear_k=5e-15,
        notes="isotropic stand-in for the friction layer",
    ),
    "steel": Material(
        "steel",
        Isotropic(E=210e9, nu=0.3, name="steel"),
        Thermal(rho=7850.0, c=460.0, kappa=50.0, alpha=1.2e-5),
        notes="backplate, piston",
    ),
}


def get_material(name: str) -> Material:
    """Look up a material by name.

    Parameters
    ----------
    name
        A key of :data:`MATERIALS`.

    Returns
    -------
    Material
        The material.

    Raises
    ------
    MaterialError
        For an unknown name, listing the known ones.
    """
    try:
        return MATERIALS[name]
    except (KeyError, TypeError):
        raise MaterialError(
            f"unknown material {name!r}; known materials: {', '.join(sorted(MATERIALS))}"
        ) from None


#: Default convection coefficient on free surfaces (W/m^2 K).  A solid rotor
#: turning at 50-100 rad/s sees roughly 20-100 W/m^2 K (forced convection of a
#: rotating disc); 40 is a moderate value for a light drag.  Calibrate it.
H_CONV_DEFAULT = 40.0


#: Default ambient (and stress-free reference) temperature, 20 C in kelvin.
T_AMBIENT_DEFAULT = 293.15
