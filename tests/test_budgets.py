"""Every loop of a run ends within its budget: the fixed steps of a stop to rest end at
its end (the three-step stop that never returned), and each budget, set small on
purpose, raises a named solver error with its figures and where it happened."""
from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from brakewear import Numerics, WearLaw
from brakewear.contact.active_set import EXACT, ActiveSetDriver, Margins
from brakewear.duty import Dwell, Stop, Vehicle, run_schedule
from brakewear.errors import ActiveSetError, ConvergenceError, SolverError, StepSizeError
from brakewear.model import BrakeModel
from brakewear.solvers.amg import AMGSolver
from brakewear.wear import ConstantSpeed, LinearSpeed, Run, wear_history
from brakewear.wear.control import StepControl

CAR = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)
LAWS = (WearLaw(5e-13), WearLaw(5e-14))


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=8e-3, rotor="rigid")


# ---------------------------------------------------- fixed steps of a stop to rest --
@pytest.mark.parametrize("duration", [1.234, 2.0, 7.7, 13.9950857761995, 29.1])
def test_a_stop_to_rest_ends_at_its_end_after_exactly_its_steps(duration):
    """The speed is zero at the end of a stop to rest, so the time at an angle near
    the end is ill-conditioned from the start (``b^2 - 4ac`` cancels: the whole angle
    came back 1e-8 of the stop short).  The root from the end is exact there, and the
    last fixed step ends at the end: N steps, each > 0, and the sum the duration."""
    s = LinearSpeed(52.08, 0.0, duration)
    total = s.angle(duration)
    assert s.time_at_angle(total) == duration
    assert s.time_at_angle(0.0) == 0.0
    for th in np.linspace(0.0, total, 41):      # both roots invert angle() to round-off
        assert s.angle(s.time_at_angle(th)) == pytest.approx(th, rel=1e-12, abs=1e-12 * total)
    for speed in (s, LinearSpeed(52.08, 20.0, duration), ConstantSpeed(30.0)):
        for n in (1, 2, 3, 4, 7, 10, 33):
            c = StepControl(Numerics(steps=n), duration, np.ones(3), speed)
            t, dts = 0.0, []
            while t < duration * (1 - 1e-12):
                dts.append(c.fixed_dt(t))
                assert dts[-1] > 0, (n, t, dts)
                c.check_progress(len(dts), t, t + dts[-1])
                t += dts[-1]
                assert len(dts) <= n
            assert len(dts) == n and t == pytest.approx(duration, rel=1e-15)
            # equal in angle: each step sweeps total / n
            edges = np.concatenate([[0.0], np.cumsum(dts)])
            sweep = np.diff([speed.angle(x) for x in edges])
            assert np.allclose(sweep, speed.angle(duration) / n, rtol=1e-9), (n, sweep)


@pytest.mark.parametrize("numerics, before, after", [
    (Numerics(steps=3), [], []),
    (Numerics(steps=3, scheme="implicit_pad"), [Dwell(5.0)], [Dwell(5.0)]),
])
@pytest.mark.parametrize("pressure", [1e6, 2e6])
def test_the_three_step_stop_to_rest_finishes(model, numerics, before, after, pressure):
    """A stop from 60 km/h to rest under a line pressure, three fixed steps: it never
    returned (its last step ended 1.3e-8 of the stop short, and every step after that
    was zero long).  It now takes three steps and the model's friction work is the
    vehicle's demand within the torque drift of a wearing stop."""
    recs = list(
        run_schedule(
            Run(
                model,
                pad_law=LAWS[0],
                rotor_law=LAWS[1],
                mu=0.4,
                schedule=before + [Stop(60 / 3.6, 0.0, line_pressure=pressure)] + after,
                vehicle=CAR,
                numerics=numerics,
            )
        )
    )
    (stop,) = [r for r in recs if r.kind == "stop"]
    assert stop.steps == 3
    assert abs(stop.torque_drift) < 5e-3, stop.torque_drift


# ------------------------------------------------------------------------- budgets --
def test_a_step_that_does_not_advance_raises_with_its_figures():
    c = StepControl(Numerics(steps=3), 10.0, np.ones(3), None)
    with pytest.raises(StepSizeError, match="did not advance") as exc:
        c.check_progress(4, 9.999, 9.999)
    assert exc.value.figures["dt"] == 0.0 and exc.value.figures["step"] == 4


def test_the_history_step_budget_raises_with_its_figures(model):
    """``numerics.max_steps`` bounds an automatic history: two steps of a long drag,
    then a StepSizeError naming the budget, the time reached and the step."""
    num = Numerics(max_steps=2, dp_tol=0.01)
    with pytest.raises(StepSizeError, match="budget of 2 steps") as exc:
        list(wear_history(Run(model, 1e6, 50.0, 5e3, *LAWS, 0.4, numerics=num)))
    e = exc.value
    assert e.figures["budget"] == 2 and e.figures["step"] == 2
    assert 0 < e.figures["time"] < e.figures["duration"] == 5e3
    assert e.where["step"] == 2 and "[step 2, t " in str(e)


def test_the_retry_budget_raises_with_its_figures(model):
    """No retries allowed and a pressure change that no step meets: the first
    rejected step raises, with the retries, the budget and the last step."""
    num = Numerics(scheme="explicit", dp_tol=1e-12, max_halvings=0, stability=None)
    with pytest.raises(StepSizeError, match="max_halvings = 0") as exc:
        list(wear_history(Run(model, 1e6, 50.0, 100.0, *LAWS, 0.4, numerics=num)))
    f = exc.value.figures
    assert f["retries"] == 1 and f["max_halvings"] == 0 and f["pressure_change"] > 1e-12
    assert f["dt"] > 0 and exc.value.where["step"] == 1


def test_the_active_set_budget_raises_with_the_sizes_seen(model, monkeypatch):
    """One active-set iteration allowed: the contact solve of the first step raises an
    ActiveSetError with the sizes it saw and the last residual, and the schedule names
    the application and the step."""
    from functools import partial

    from brakewear.contact.lagrange import solve_contact
    from brakewear.interfaces import fe

    monkeypatch.setattr(fe, "solve_contact", partial(solve_contact, max_iter=1))
    with pytest.raises(ActiveSetError, match="did not settle in") as exc:
        list(
            run_schedule(
                Run(
                    model,
                    pad_law=LAWS[0],
                    rotor_law=LAWS[1],
                    mu=0.4,
                    schedule=[Dwell(1.0), Stop(60 / 3.6, line_pressure=1e6)],
                    vehicle=CAR,
                    numerics=Numerics(steps=3),
                )
            )
        )
    e = exc.value
    assert e.figures["iterations"] == 1
    assert len(e.figures["active_counts"]) == 1 and e.figures["active_counts"][0] > 0
    assert 0 < e.figures["relative_residual"] < 1
    assert e.where["application"] == "1 (stop)"


def test_the_scripted_active_set_budget_names_its_figures():
    stay = -np.arange(1.0, 21.0)

    class Keep:
        last_residual = 3e-7

        def solve(self, active, tol, rtol0):
            pass

        def margins(self, active, band):
            return Margins(stay, 0.0, -np.ones(20), 0.0)

    driver = ActiveSetDriver(replace(EXACT, max_iter=2), tol=1e-9, exact=True)
    with pytest.raises(ActiveSetError, match="budget max_iter") as exc:
        driver.run(Keep(), np.ones(20, dtype=bool))
    f = exc.value.figures
    # every node tensile: the set shrinks at each iteration and never settles
    assert f["active_counts"] == driver.counts and len(f["active_counts"]) == 2
    assert f["active_counts"][0] == 20 > f["active_counts"][1]
    assert (f["iterations"], f["max_iter"], f["relative_residual"]) == (2, 2, 3e-7)


def test_the_krylov_budget_raises_with_its_figures():
    n = 400
    A = sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tocsr()
    b = np.ones(n)
    for krylov in ("cg", "gmres"):
        solver = AMGSolver(A, tol=1e-14, maxiter=1, max_coarse=10,
                           smoothers=(("jacobi", {"omega": 0.1}),) * 2)
        with pytest.raises(ConvergenceError, match="maxiter 1") as exc:
            solver.solve(b, krylov=krylov)
        f = exc.value.figures
        assert f["iterations"] == 1 and f["maxiter"] == 1 and f["relative_residual"] > 1e-14


def test_the_torque_fixed_point_budget_names_the_application(model, monkeypatch):
    """A stop by deceleration finds its line pressure by a fixed point on the
    effective radius; one iteration allowed, it raises naming the application."""
    from brakewear.duty import runner

    f = runner._Brake.pressure_for_torque
    monkeypatch.setattr(f, "__defaults__", (1e-10, 1))
    with pytest.raises(ConvergenceError, match="did not settle in 1 contact") as exc:
        list(
            run_schedule(
                Run(
                    model,
                    pad_law=LAWS[0],
                    rotor_law=LAWS[1],
                    mu=0.4,
                    schedule=[Stop(60 / 3.6, decel=2.0)],
                    vehicle=CAR,
                    numerics=Numerics(steps=2),
                )
            )
        )
    assert exc.value.figures["iterations"] == 1 and exc.value.figures["relative_change"] > 0
    assert exc.value.where == {"application": "0 (stop)"}


def test_a_solver_error_keeps_the_innermost_place():
    e = SolverError("x", figures={"iterations": 3})
    e.within(step=2).within(step=9, application="1 (drag)")
    assert e.where == {"step": 2, "application": "1 (drag)"}
    assert str(e) == "x [step 2, application 1 (drag)]"


# ------------------------------------------------------------- the progress bar --
def test_the_cli_runs_the_three_step_drive_cycle_and_shows_it_is_alive(tmp_path, capsys):
    """The drive cycle of the hang (a stop from 60 km/h to rest at 1 MPa, three
    fixed steps) through `brakewear run`: it finishes, and its progress bar counts
    the applications and shows the contact solve's iterations while they run."""
    import json
    import re

    from brakewear.cli import main
    from brakewear.scene import scene_file

    text = scene_file("default").read_text()
    # the FE interface, whose active-set iterations the progress bar shows
    for key, value in (("size", "8.0"), ("rotor", '"rigid"'), ("figures", "false"),
                       ("model", '"fe"')):
        text = re.sub(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
    text = re.sub(r"(?m)^(line_pressure|omega|duration) = .*$", "", text)
    text = re.sub(r"(?m)^dp_tol = .*$", "steps = 3", text)
    text += ('\n[vehicle]\nmass = 1800.0\nfront_share = 0.7\ntyre_radius = 320.0\n'
             '\n[schedule]\nfile = "cycle.csv"\n')
    (tmp_path / "cycle.csv").write_text("time_s,speed_kmh,line_pressure_MPa\n0,60,1\n"
                                        "20,0,0\n30,0,0\n")
    (tmp_path / "hang.toml").write_text(text)
    out = tmp_path / "run"
    assert main(["run", str(tmp_path / "hang.toml"), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "/2 applications" in err and re.search(r"contact iteration \d+ \(\d+ active\)", err)
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "finished" and s["braked_applications"] == 1


def test_the_heat_solves_cg_budget_raises_a_solver_error(monkeypatch):
    """A heat step whose length is not a power of two is solved by CG preconditioned
    with its octave's factorisation; with no iteration allowed it raises a
    ConvergenceError (a solver error, not an input error) with its figures."""
    import skfem as fem

    from brakewear.fem import HeatConduction, heat
    from brakewear.materials import MATERIALS

    m = fem.MeshTet.init_tensor(*(np.linspace(0, 4e-3, 4),) * 3).with_boundaries(
        {"x0": lambda x: np.isclose(x[0], 0.0), "x1": lambda x: np.isclose(x[0], 4e-3)})
    body = HeatConduction(m, MATERIALS["pad_resin"], flux_facets="x0", fixed={"x1": 293.15})
    T0 = np.full(body.n, 293.15)
    F = body.flux_load(np.full(body.face.shape, 1e5))
    body.step(T0, F, 0.3)                             # CG converges within its budget
    monkeypatch.setattr(heat, "_CG_MAXITER", 0)
    with pytest.raises(ConvergenceError, match="budget 0") as exc:
        body.step(T0, F, 0.3)
    f = exc.value.figures
    assert f["iterations"] == 0 and f["maxiter"] == 0 and f["relative_residual"] > f["tol"]
