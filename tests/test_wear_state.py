"""The wear loop's parts: checkpoint state and fingerprint, step control, the interface protocol."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear.errors import StepSizeError, WearError
from brakewear.geometry import SupportGeometry, load_geometry
from brakewear.interfaces import FEInterface, FoundationInterface, Interface, WinklerInterface
from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.wear import (
    Numerics,
    Run,
    StepControl,
    WearState,
    check_fingerprint,
    fingerprint,
    wear_history,
)

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=12e-3)


def _killed_run(model, ck, law=PAD):
    """Three equal steps with a checkpoint every step, stopped while the third is handled
    (a step is checkpointed once its caller asks for the next: the checkpoint is at 2)."""
    for s in wear_history(
        Run(model, 1e6, 55.0, 600.0, law, ROTOR, mu=0.4, numerics=Numerics(steps=3)),
        checkpoint=ck,
        every=1,
    ):
        if s.step == 3:
            break


def test_state_round_trip_is_exact(tmp_path):
    st = WearState.fresh(5, 3, dt_next=2.5)
    st.step, st.time, st.pad_wear[:] = 4, 10.0, np.linspace(0, 1e-6, 5)
    st.active = np.array([True, False, True, True, False])
    prints = fingerprint(a=1.0, b="x")
    st.save(tmp_path / "c.npz", prints, {"T_pad": np.ones(2)})
    back, extra = WearState.load(tmp_path / "c.npz", prints, 5, 3)
    assert back.step == 4 and back.time == 10.0 and back.dt_next == 2.5
    np.testing.assert_array_equal(back.pad_wear, st.pad_wear)
    np.testing.assert_array_equal(back.active, st.active)
    assert back.u is None and back.pressure is None
    np.testing.assert_array_equal(extra["T_pad"], np.ones(2))
    with pytest.raises(WearError, match="belongs to another model"):
        WearState.load(tmp_path / "c.npz", prints, 6, 3)


def test_fingerprint_names_what_changed(tmp_path):
    a = fingerprint(law=PAD, numerics=Numerics(), mu=0.4)
    b = fingerprint(law=replace(PAD, k=2e-14), numerics=Numerics(), mu=0.4)
    assert a != b and a == fingerprint(law=PAD, numerics=Numerics(), mu=0.4)
    st = WearState.fresh(2, 2)
    st.save(tmp_path / "c.npz", a)
    with pytest.raises(WearError, match=r"law\.k: 5e-15 -> 2e-14"):
        WearState.load(tmp_path / "c.npz", b, 2, 2)


def test_changed_values_are_shown_in_the_geometry_files_units(tmp_path):
    """Geometry values in the file's [units]; the others in SI with the unit named, to 4
    significant digits unless more are needed to tell the two apart."""
    def prints(r, E, ang, rho, p, k):
        return fingerprint(geometry={"pad": {"inner_radius": r, "arc_angle": ang,
                                             "friction_material": {"elastic": {"E_t": E},
                                                                   "thermal": {"rho": rho}}}},
                           line_pressure=p, pad_law=replace(PAD, k=k))
    ck = tmp_path / "c.npz"
    WearState.fresh(2, 2).save(ck, prints(0.095, 3.0e9, np.radians(55.0), 2400.0, 1e6, 5e-15))
    new = prints(0.0961234567, 2.9e9, np.radians(50.0), 2400.0 * (1 + 1e-9), 1.5e6, 2e-14)
    with pytest.raises(WearError) as e:
        check_fingerprint(ck, new, {"length": "mm", "angle": "deg", "modulus": "GPa"})
    msg = str(e.value)
    for words in ("geometry.pad.inner_radius: 95 mm -> 96.12 mm",
                  "geometry.pad.friction_material.elastic.E_t: 3 GPa -> 2.9 GPa",
                  "geometry.pad.arc_angle: 55 deg -> 50 deg",
                  "thermal.rho: 2400 kg/m^3 -> 2400.000002 kg/m^3",
                  "line_pressure: 1e+06 Pa -> 1.5e+06 Pa"):
        assert words in msg, msg
    assert "(and 1 more)" in msg      # pad_law.k, the sixth
    # a geometry in metres and pascals: the same change in those units
    with pytest.raises(WearError, match=r"E_t: 3e\+09 Pa -> 2.9e\+09 Pa"):
        check_fingerprint(ck, new, {"length": "m", "angle": "rad", "modulus": "Pa"})
    # an unchanged run passes
    check_fingerprint(ck, prints(0.095, 3.0e9, np.radians(55.0), 2400.0, 1e6, 5e-15))


def test_resume_with_another_wear_law_is_refused(model, tmp_path):
    ck = tmp_path / "run.npz"
    _killed_run(model, ck)
    with pytest.raises(WearError, match=r"pad_law\.k"):
        next(
            wear_history(
                Run(
                    model,
                    1e6,
                    55.0,
                    600.0,
                    replace(PAD, k=2e-14),
                    ROTOR,
                    mu=0.4,
                    numerics=Numerics(steps=3),
                ),
                checkpoint=ck,
                resume=True,
            )
        )


def test_resume_with_a_changed_material_is_refused(model, tmp_path):
    """The same material name with another modulus is another brake."""
    ck = tmp_path / "run.npz"
    _killed_run(model, ck)
    g = load_geometry("default")
    mat = g.pad.friction_material
    el = mat.elastic
    field = "E" if hasattr(el, "E") else "E_t"
    other = replace(mat, elastic=replace(el, **{field: 0.97 * getattr(el, field)}))
    changed = BrakeModel(replace(g, pad=replace(g.pad, friction_material=other)), size=12e-3)
    with pytest.raises(WearError, match=rf"geometry\.pad\.friction_material\.elastic\.{field}"):
        next(
            wear_history(
                Run(changed, 1e6, 55.0, 600.0, PAD, ROTOR, mu=0.4, numerics=Numerics(steps=3)),
                checkpoint=ck,
                resume=True,
            )
        )
    # the load path is the brake too: another bracket is another brake
    push = BrakeModel(replace(g, support=SupportGeometry("push", 2e-4)), size=12e-3)
    with pytest.raises(WearError, match=r"geometry\.support\.type: bilateral -> push"):
        next(
            wear_history(
                Run(push, 1e6, 55.0, 600.0, PAD, ROTOR, mu=0.4, numerics=Numerics(steps=3)),
                checkpoint=ck,
                resume=True,
            )
        )
    # the same inputs resume
    rest = list(
        wear_history(
            Run(model, 1e6, 55.0, 600.0, PAD, ROTOR, mu=0.4, numerics=Numerics(steps=3)),
            checkpoint=ck,
            resume=True,
        )
    )
    assert [s.step for s in rest] == [3]


def test_step_control_takes_the_smallest_limit_and_gives_up_with_figures():
    n = Numerics(scheme="explicit", dp_tol=0.1, max_halvings=2)
    c = StepControl(n, 100.0, np.full(3, 1e-6))
    dt, limit = c.propose(None, 100.0, np.array([1e-8, 0.0, 2e-8]), lambda: 0.5)
    assert limit == "stability" and dt == pytest.approx(2.0)     # 1 / 0.5 < 1e-6 / 2e-8
    dt, limit = c.propose(None, 100.0, np.array([1e-6, 0.0, 0.0]), lambda: 0.0)
    assert limit == "max_dh" and dt == pytest.approx(1.0)
    assert c.accepts(0.05, np.nan) and not c.accepts(0.2, np.nan)
    assert c.retry(4.0, np.nan, 1, 7, 0.2) == (2.0, None)
    with pytest.raises(StepSizeError, match=r"step 7: .* 3 halvings .* pressure change 0.20"):
        c.retry(4.0, np.nan, 3, 7, 0.2)
    # the next step aims at 0.7 dp_tol and at most doubles
    assert c.next_dt(1.0, 0.07, np.nan) == pytest.approx(1.0)
    assert c.next_dt(1.0, 1e-9, np.nan) == pytest.approx(2.0)
    fixed = StepControl(Numerics(steps=4), 100.0, np.ones(3))
    assert fixed.initial_dt() == 25.0 and fixed.propose(25.0, 10.0, np.ones(3), None) == (
        10.0, "fixed")


def test_interfaces_follow_the_protocol_and_foundation_refuses_a_load(model):
    fe = FEInterface(model, 1e6, 0.4)
    fd = FoundationInterface(model, WinklerInterface.from_model(model), 1e6, 0.4)
    assert isinstance(fe, Interface) and isinstance(fd, Interface)
    assert fe.accepts_load and not fd.accepts_load
    sol = fd.solve(np.zeros(fd.area.size), None)
    assert sol.u is None and (sol.pressure * fd.area).sum() == pytest.approx(
        1e6 * model.geometry.piston.hydraulic_area, rel=1e-8)
    with pytest.raises(WearError, match="no nodal load"):
        fd.solve(np.zeros(fd.area.size), None, load=np.zeros(model.dofs))


def test_thermal_with_a_foundation_is_refused_before_solving(model):
    from brakewear.thermal import ThermalModel

    fd = FoundationInterface(model, WinklerInterface.from_model(model), 1e6, 0.4)
    with pytest.raises(WearError, match="thermal coupling needs an interface"):
        next(
            wear_history(
                Run(
                    model,
                    1e6,
                    55.0,
                    60.0,
                    PAD,
                    ROTOR,
                    mu=0.4,
                    interface=fd,
                    thermal=ThermalModel(model, contact_conductance=1e5),
                    numerics=Numerics(scheme="explicit"),
                )
            )
        )


def test_an_interface_of_another_line_pressure_runs_at_the_run_s(model):
    """An interface built for 1 MPa in a 0.5 MPa run: the run's pressure, not its own."""
    def last(itf):
        for s in wear_history(  # noqa: B007  (the last step)
            Run(
                model,
                0.5e6,
                55.0,
                60.0,
                PAD,
                ROTOR,
                mu=0.4,
                interface=itf,
                numerics=Numerics(scheme="implicit", steps=2),
            )
        ):
            pass
        return s.pressure
    p_half = last(FEInterface(model, 0.5e6, 0.4))
    p_other = last(FEInterface(model, 1e6, 0.4))
    np.testing.assert_allclose(p_other, p_half, rtol=1e-8, atol=1e-10 * p_half.max())
    fd = FoundationInterface(model, WinklerInterface.from_model(model), 1e6, 0.4)
    with pytest.raises(WearError, match="built for a line pressure of 1 MPa and the run asks "
                                        "for 0.5 MPa"):
        next(
            wear_history(
                Run(
                    model,
                    0.5e6,
                    55.0,
                    60.0,
                    PAD,
                    ROTOR,
                    mu=0.4,
                    interface=fd,
                    numerics=Numerics(scheme="explicit"),
                )
            )
        )


def test_run_wear_resumed_after_its_end_says_so_in_the_hierarchy(tmp_path):
    """Resuming a finished run from Python is an input error (exit code 2) that says
    the run is finished, not a bare RuntimeError."""
    from brakewear.errors import WearError
    from brakewear.laws.base import WearLaw
    from brakewear.model import BrakeModel
    from brakewear.output.runs import run_wear
    from brakewear.wear import Numerics, Run
    model = BrakeModel("default", size=1.2e-2)
    run = Run(model, 1e6, 55.0, 20.0, WearLaw(5e-15), WearLaw(5e-16), 0.4,
              numerics=Numerics(steps=2))
    run_wear(run, tmp_path)
    with pytest.raises(WearError, match="finished run") as e:
        run_wear(run, tmp_path, resume=True)
    assert e.value.exit_code == 2
