"""The step control's measures of a step (brakewear.wear.control): area-weighted norms that
converge under mesh refinement, and step counts that do not grow with the mesh."""
import sys

import numpy as np
import pytest

from brakewear.errors import WearError
from brakewear.scene import scene_file, scene_from_dict
from brakewear.wear import Numerics, NumericsError, StepControl, face_norm
from studyload import load_study

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def _face(n: int, graded: bool = False):
    """Nodes of the unit square (n per side, uniform or graded toward x = 0) and their
    tributary areas (the trapezoid rule's weights: what a lumped face gives a node)."""
    s = np.linspace(0.0, 1.0, n)
    x = s ** 1.5 if graded else s
    def weights(t):
        w = np.zeros_like(t)
        w[:-1] += 0.5 * np.diff(t)
        w[1:] += 0.5 * np.diff(t)
        return w
    X, Y = np.meshgrid(x, s, indexing="ij")
    return X.ravel(), Y.ravel(), np.outer(weights(x), weights(s)).ravel()


def _spreading(x, y, front):
    """A contact pressure with a jump at its edge (Pa): ``(1 + y)(2 - x)`` MPa where
    ``x <= front``, none beyond; a step moves the front."""
    return np.where(x <= front, 1e6 * (1 + y) * (2 - x), 0.0)


def _exact_change(a0, a1):
    """||p1 - p0|| / ||p0|| of :func:`_spreading` as integrals over the square."""
    cube = lambda a: (2 - a) ** 3 / 3          # noqa: E731  int (2 - x)^2 dx = -cube
    return np.sqrt((cube(a0) - cube(a1)) / (cube(0.0) - cube(a0)))


@pytest.mark.parametrize("graded", [False, True])
def test_l2_pressure_change_of_a_spreading_contact_is_the_same_on_every_mesh(graded):
    """The contact's edge moves by 0.1 of a face whose nodes enter contact with a jump of
    up to 85 % of the peak pressure: the area-weighted measure tends to the integral's
    value, sqrt(int_band p^2 / int p^2) = 0.514 here, as the mesh is refined (first
    order in h / band on the uniform faces: 27 % off at 21 nodes a side, 1.8 % at 321);
    the largest nodal change is the entering nodes' jump on every mesh and does not see
    how far the edge moved, so a control on it needs the steps that let the edge cross
    one node at a time."""
    a0, a1 = 0.3, 0.4
    exact = _exact_change(a0, a1)
    l2, peak, half = [], [], []
    for n in (21, 41, 81, 161, 321):
        x, y, area = _face(n, graded)
        p0, p1 = _spreading(x, y, a0), _spreading(x, y, a1)
        ctl = StepControl(Numerics(norm="l2"), 3600.0, np.ones(x.size), area=area)
        l2.append(ctl.pressure_change(p0, p1))
        peak.append(StepControl(Numerics(norm="max"), 3600.0, np.ones(x.size),
                                area=area).pressure_change(p0, p1))
        half.append(ctl.pressure_change(p0, _spreading(x, y, a0 + 0.25 * (a1 - a0))))
    err = np.abs(np.array(l2) / exact - 1)
    assert err[-1] < 0.02 and err[-1] < 0.25 * err[0], (l2, exact)
    assert abs(l2[-1] / l2[-2] - 1) < 0.02
    # a quarter of the move: about half the measure (the swept band's area enters as a root)
    quarter = _exact_change(a0, a0 + 0.25 * (a1 - a0))
    assert quarter / exact == pytest.approx(0.5, rel=0.05)
    assert half[-1] == pytest.approx(quarter, rel=0.1)
    # the max norm: the jump of the entering nodes, the same for any move and any mesh
    jump = (2 - a0) / 2                          # (1 + 1)(2 - a) / max p0 (2 * 2)
    assert np.allclose(peak, jump, rtol=0.15) and max(peak) > 0.5 * jump


def test_l2_wear_error_is_the_root_mean_square_over_the_face():
    """The wear error dt/2 |d rate| in the l2 norm is its root mean square with the
    tributary areas, the same on a coarse and a fine face for a smooth field; in the max
    norm the largest nodal value."""
    dt = 60.0
    rms = []
    for n in (41, 161):
        x, y, area = _face(n)
        d_rate = 1e-9 * np.sin(np.pi * x) * (1 + y)          # m/s
        ctl = StepControl(Numerics(norm="l2"), 3600.0, np.ones(x.size), area=area)
        rms.append(ctl.wear_error(dt, d_rate))
        assert StepControl(Numerics(norm="max"), 3600.0, np.ones(x.size)).wear_error(
            dt, d_rate) == pytest.approx(0.5 * dt * np.abs(d_rate).max(), rel=1e-12)
    # int_0^1 sin^2(pi x) dx int_0^1 (1 + y)^2 dy = 1/2 * 7/3
    exact = 0.5 * dt * 1e-9 * np.sqrt(7.0 / 6.0)
    assert rms[1] == pytest.approx(exact, rel=1e-3) and rms[0] == pytest.approx(exact, rel=1e-2)


def test_face_norm_and_the_max_norm_keep_their_definitions():
    """Three nodes by hand: the weighted root of the sum of squares, the largest
    magnitude, and the pressure change in each norm; "max" is the default."""
    v, a = np.array([3.0, -4.0, 0.0]), np.array([1.0, 2.0, 5.0])
    assert face_norm(v, a) == pytest.approx(np.sqrt(9 + 32))
    assert face_norm(v, None) == pytest.approx(5.0)
    assert face_norm(v, a, "max") == 4.0
    ctl = StepControl(Numerics(norm="max"), 10.0, np.ones(3), area=a)
    p0, p1 = np.array([1.0, 2.0, 0.0]), np.array([1.5, 1.0, 0.2])
    assert ctl.pressure_change(p0, p1) == pytest.approx(1.0 / 2.0)
    ctl = StepControl(Numerics(norm="l2"), 10.0, np.ones(3), area=a)
    assert ctl.pressure_change(p0, p1) == pytest.approx(
        np.sqrt(0.25 + 2 * 1.0 + 5 * 0.04) / np.sqrt(1 + 8))
    assert Numerics().norm == "max"
    with pytest.raises(NumericsError, match=r"numerics\.norm: 'l1' is not allowed"):
        face_norm(v, a, "l1")


def test_a_wrong_norm_is_refused_by_name():
    with pytest.raises(NumericsError, match=r"numerics\.norm") as e:
        Numerics(norm="l1")
    assert isinstance(e.value, WearError)


def test_the_scene_table_takes_the_norm():
    d = tomllib.loads(scene_file("default").read_text())
    d["numerics"].update(steps=None, norm="max")
    del d["numerics"]["steps"]
    assert scene_from_dict(d).numerics.norm == "max"
    d["numerics"]["norm"] = "sum"
    with pytest.raises(NumericsError, match=r"numerics\.norm: 'sum' is not allowed; "
                                            r"allowed: 'l2', 'max'"):
        scene_from_dict(d)


@pytest.mark.slow
def test_the_l2_step_count_does_not_grow_as_the_mesh_is_refined():
    """The default scene's physics, the first 20 minutes (the contact spreads over the
    face), 12 and 6 mm (2 226 and 8 145 DOFs): the l2 controls take the same steps within
    20 % on both meshes (dp_tol: 23 and 26; wear_tol 1e-8 m: 29 and 32), the max norm's
    dp_tol control 38 and 55, growing with the nodes the contact's edge crosses."""
    study = load_study("running_in_steps")
    count = {}
    for size in (12.0, 6.0):
        for run in ("steps=none+norm=l2", "steps=none+wear_tol=1e-8+norm=l2",
                    "steps=none+norm=max"):
            row = study.run_one(size, study.parse_run(run), 1200.0, resolution=False)
            assert row["rotor_volume_error"] < 1e-12
            count[size, run] = row["steps"]
    for run in ("steps=none+norm=l2", "steps=none+wear_tol=1e-8+norm=l2"):
        assert 0.8 <= count[6.0, run] / count[12.0, run] <= 1.2, count
    assert count[6.0, "steps=none+norm=max"] > 1.3 * count[12.0, "steps=none+norm=max"], count
