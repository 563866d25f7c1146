"""The wear loop (gap-offset mode): conservation, resume, step control, bad input."""
import numpy as np
import pytest

from brakewear.errors import StepSizeError, WearError
from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.wear import Numerics, Run, wear_history

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=8e-3)


def test_worn_volume_equals_archard_integral(model):
    steps = list(
        wear_history(
            Run(model, 1e6, 55.0, 180.0, PAD, ROTOR, numerics=Numerics(scheme="explicit", steps=4))
        )
    )
    assert len(steps) == 4 and steps[-1].time == pytest.approx(180.0)
    for s in steps:
        assert abs(s.pad_volume - s.pad_archard) <= 1e-10 * s.pad_archard
        assert abs(s.rotor_volume - s.rotor_archard) <= 1e-10 * s.rotor_archard
    # the pad loses k_pad/k_rotor = 10 times the rotor's volume
    assert steps[-1].pad_volume / steps[-1].rotor_volume == pytest.approx(10.0, rel=1e-10)


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_resume_from_checkpoint_repeats_the_run(model, tmp_path, scheme):
    # implicit: the steps start from the displacement extrapolated from the last
    # two steps, so the checkpoint must carry both
    # (300 s: six explicit steps within the scheme's stability bound, 54 s)
    ck = tmp_path / "run.npz"
    full = list(
        wear_history(
            Run(model, 1e6, 55.0, 300.0, PAD, ROTOR, numerics=Numerics(steps=6, scheme=scheme))
        )
    )
    gen = wear_history(
        Run(model, 1e6, 55.0, 300.0, PAD, ROTOR, numerics=Numerics(steps=6, scheme=scheme)),
        checkpoint=ck,
        every=2,
    )
    for s in gen:
        if s.step == 3:   # "killed" after step 3: the checkpoint holds step 2
            break
    rest = list(
        wear_history(
            Run(model, 1e6, 55.0, 300.0, PAD, ROTOR, numerics=Numerics(steps=6, scheme=scheme)),
            checkpoint=ck,
            every=2,
            resume=True,
        )
    )
    assert [s.step for s in rest] == [3, 4, 5, 6]
    a, b = full[-1], rest[-1]
    assert np.abs(a.pad_wear - b.pad_wear).max() <= 1e-12 * np.abs(a.pad_wear).max()
    assert np.abs(a.rotor_wear - b.rotor_wear).max() <= 1e-12 * np.abs(a.rotor_wear).max()


def test_step_control_rejects_and_recovers(model):
    # max_dh far too large: the first try would make the pressure jump; it is halved
    steps = list(
        wear_history(
            Run(
                model,
                1e6,
                55.0,
                600.0,
                PAD,
                ROTOR,
                numerics=Numerics(scheme="explicit", max_dh=1e-3, dp_tol=0.25, stability=None),
            )
        )
    )
    assert sum(s.rejected for s in steps) > 0
    assert steps[-1].time == pytest.approx(600.0)


def test_step_control_gives_up_with_its_figures(model):
    with pytest.raises(StepSizeError, match="halvings"):
        list(
            wear_history(
                Run(
                    model,
                    1e6,
                    55.0,
                    7200.0,
                    PAD,
                    ROTOR,
                    numerics=Numerics(
                        scheme="explicit", max_dh=1e-3, dp_tol=1e-9, max_halvings=2, stability=None
                    ),
                )
            )
        )


@pytest.mark.parametrize("kw,match", [({"omega": 0.0}, "omega"), ({"omega": -5.0}, "omega"),
                                      ({"duration": 0.0}, "duration"), ({"steps": 0}, "steps"),
                                      ({"resume": True}, "checkpoint"),
                                      ({"max_dh": -1.0}, "max_dh")])
def test_bad_input_raises_before_solving(model, kw, match):
    args = dict(model=model, line_pressure=1e6, omega=55.0, duration=100.0, pad_law=PAD)
    numerics = {k: kw.pop(k) for k in ("steps", "max_dh") if k in kw}
    runner = {k: kw.pop(k) for k in ("resume",) if k in kw}
    args.update(kw)
    with pytest.raises(WearError, match=match):
        next(wear_history(Run(**args, numerics=Numerics(**numerics)), **runner))


def test_rigid_rotor_wears_by_rings_and_conserves_volume():
    m = BrakeModel("default", size=8e-3, rotor="rigid")
    steps = list(
        wear_history(
            Run(m, 1e6, 55.0, 120.0, PAD, ROTOR, numerics=Numerics(scheme="explicit", steps=3))
        )
    )
    s = steps[-1]
    assert abs(s.pad_volume - s.pad_archard) <= 1e-10 * s.pad_archard
    assert abs(s.rotor_volume - s.rotor_archard) <= 1e-10 * s.rotor_archard
    assert s.pad_volume / s.rotor_volume == pytest.approx(10.0, rel=1e-10)
    # one wear value per ring of pad friction-node radii, every ring worn
    from brakewear.mesh.surface import surface_nodes
    pad = m.meshes["pad"]
    x = pad.p[:, surface_nodes(pad, "friction")]
    assert s.rotor_wear.size == np.unique(np.round(np.hypot(x[0], x[1]), 9)).size
    assert np.all(s.rotor_wear > 0)
