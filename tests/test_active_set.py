"""The shared active-set driver on small scripted problems: rules, schedule, guards."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear.contact.active_set import (
    COMPLIANT,
    EXACT,
    LAGRANGE,
    ActiveSetDriver,
    ActiveSetOptions,
    Margins,
    conservative_update,
    pdas_update,
)
from brakewear.errors import ActiveSetError, ContactLostError


class Scripted:
    """A set problem whose margins are a fixed function of the active set."""

    def __init__(self, margins):
        self.margins_of = margins
        self.calls = []

    def solve(self, active, tol, rtol0):
        self.calls.append((active.copy(), tol, rtol0))

    def margins(self, active, band):
        return self.margins_of(active, band)


def test_pdas_rule_keeps_compressive_and_adds_penetrating_nodes():
    active = np.array([True, True, False, False])
    m = Margins(stay=np.array([1.0, -2.0, 0.0, 0.0]), stay_bound=1.0,
                enter=np.array([0.0, 0.0, 3.0, -1.0]), enter_bound=0.5)
    assert pdas_update(active, m).tolist() == [True, False, True, False]


def test_conservative_rule_adds_or_releases_never_both():
    active = np.array([True, True, True, False])
    stay = np.array([-10.0, -6.0, -4.0, 0.0])
    adding = Margins(stay, 1.0, np.array([0, 0, 0, 2.0]), 0.5)
    assert conservative_update(active, adding).tolist() == [True, True, True, True]
    # nothing penetrates: release the nodes pulling at least half as hard as the worst
    releasing = Margins(stay, 1.0, np.zeros(4), 0.5)
    assert conservative_update(active, releasing).tolist() == [False, False, True, False]


def test_a_settled_set_is_confirmed_by_a_tight_solve():
    """Scripted: the solution always asks for nodes 0-2.  The loose first solve is
    followed by loose (inexact) solves, then a medium and a tight one on the final set."""
    want = np.array([True, True, True, False, False])
    prob = Scripted(lambda a, b: Margins(np.where(want, 1.0, -1.0), 1e-6 * 1.0,
                                         np.where(want, 1.0, -1.0), 0.0))
    driver = ActiveSetDriver(LAGRANGE, tol=1e-9)
    out = driver.run(prob, np.array([True, False, False, False, False]))
    assert out.tolist() == want.tolist()
    tols = [(t, r) for _, t, r in prob.calls]
    assert tols[0] == (LAGRANGE.loose_tol, None)
    assert tols[1] == (1e-9, LAGRANGE.inexact)        # inexact: a warm-start cut
    assert tols[-2] == (LAGRANGE.medium_tol, None)    # medium once the set repeats
    assert tols[-1] == (1e-9, None)                   # one tight confirmation
    assert driver.report()["tight_reason"] == "set repeated"


def test_exact_solves_accept_the_first_reproduced_set():
    want = np.array([True, False, True])
    prob = Scripted(lambda a, b: Margins(np.where(want, 1.0, -1.0), 0.0,
                                         np.where(want, 1.0, -1.0), 0.0))
    driver = ActiveSetDriver(EXACT, tol=1e-9, exact=True)
    driver.run(prob, np.ones(3, dtype=bool))
    assert driver.solves == 2


def _two_cycle(active, band):
    """Node 1 is tensile when active and penetrating when open, by 1e-4 of the load."""
    s = np.array([1.0, -1e-4])
    return Margins(s, band * 1.0, -s if not active[1] else s, band * 1.0)


def test_a_lagrange_cycle_turns_conservative_and_ends():
    """Nodes 1 and 2 swap under the primal-dual rule ({0,1} -> {0,2} -> {0,1} ...: each
    pulls when active alone while the other penetrates); held together both press.
    The conservative rule adds before it releases and ends at {0,1,2}."""

    def margins(active, band):
        if active[1] and active[2]:
            return Margins(np.ones(3), band, np.zeros(3), 0.0)
        one = 1 if active[1] else 2
        stay, enter = np.zeros(3), np.zeros(3)
        stay[0], stay[one], enter[3 - one] = 1.0, -0.5, 0.5
        return Margins(stay, band, enter, 0.0)

    driver = ActiveSetDriver(LAGRANGE, tol=1e-9, tight=True)
    out = driver.run(Scripted(margins), np.array([True, True, False]))
    assert driver.conservative and out.all()
    # without the conservative fallback the two sets alternate until a band can't hold
    calls = []
    plain = Scripted(lambda a, b: (calls.append(a.copy()), margins(a, b))[1])
    with pytest.raises(ActiveSetError):
        ActiveSetDriver(replace(LAGRANGE, max_iter=6, wander=None, on_cycle="widen",
                                cycle_band=1e-6), tol=1e-9, tight=True).run(
            plain, np.array([True, True, False]))
    assert len({tuple(c) for c in calls}) == 2


def test_compliant_cycle_widens_the_band_once():
    """A node at 1e-4 of the largest force flips forever under the 1e-6 band; the
    widened 1e-3 band keeps its status and the set is accepted."""
    driver = ActiveSetDriver(COMPLIANT, tol=1e-9, tight=True)
    out = driver.run(Scripted(_two_cycle), np.array([True, True]))
    assert driver.widened and driver.report()["hysteresis_band"] == COMPLIANT.cycle_band
    assert out[0]
    # a band too narrow to hold it raises with its figures
    narrow = replace(COMPLIANT, cycle_band=1e-5)
    with pytest.raises(ActiveSetError, match="cycles after"):
        ActiveSetDriver(narrow, tol=1e-9, tight=True).run(Scripted(_two_cycle),
                                                         np.array([True, True]))


def test_lost_contact_and_budget_raise_with_figures():
    lift = Scripted(lambda a, b: Margins(-np.ones(a.size), 0.0, -np.ones(a.size), 0.0))
    with pytest.raises(ContactLostError, match="separates the bodies \\(why\\)"):
        ActiveSetDriver(EXACT, tol=1e-9, exact=True, hint=" (why)").run(
            lift, np.array([True, False]))
    # an update that empties a big set keeps its least tensile tenth
    stay = -np.arange(1.0, 21.0)
    keep = Scripted(lambda a, b: Margins(stay, 0.0, -np.ones(20), 0.0))
    driver = ActiveSetDriver(replace(EXACT, max_iter=1), tol=1e-9, exact=True)
    with pytest.raises(ActiveSetError, match="did not settle in 1"):
        driver.run(keep, np.ones(20, dtype=bool))
    assert driver.counts == [20]


@pytest.mark.parametrize("options", [LAGRANGE, COMPLIANT])
def test_a_loose_solve_cannot_declare_the_contact_lost(options):
    """A loose solve whose margins release every node (its start guess was already
    within the loose tolerance) is repeated tightly on the same set; only a tight
    solve that releases everything ends in ContactLostError."""
    def margins(active, band):
        tight = prob.calls[-1][1] <= 1e-9
        sign = 1.0 if tight else -1.0
        return Margins(sign * np.ones(active.size), 0.0, -np.ones(active.size), 0.0)

    prob = Scripted(margins)
    start = np.array([True, True, False])
    out = ActiveSetDriver(options, tol=1e-9).run(prob, start)
    assert out.tolist() == start.tolist()
    assert prob.calls[0][1] > 1e-9 and prob.calls[1][1] <= 1e-9      # loose, then tight
    assert all(c[0].tolist() == start.tolist() for c in prob.calls)


@pytest.mark.parametrize("kw", [dict(on_cycle="sometimes"), dict(loose_tol=2.0),
                                dict(max_iter=0), dict(release_tol=-1.0)])
def test_bad_options_are_named(kw):
    name = next(iter(kw))
    with pytest.raises(ValueError, match=name):
        ActiveSetOptions(**kw)


class _Wandering:
    """A set problem on which the primal-dual rule wanders: an active node keeps
    its status only at random (fresh signs each solve) unless every node is
    active, and every open node penetrates.  The conservative update (add the
    penetrating nodes first) settles on the full set at once."""

    def __init__(self, n=40, seed=3):
        self.rng = np.random.default_rng(seed)
        self.n = n

    def solve(self, active, tol, rtol0):
        self.full = bool(active.all())

    def margins(self, active, band):
        stay = np.ones(self.n) if self.full else self.rng.choice([-1.0, 1.0], self.n)
        return Margins(stay, band, np.ones(self.n), band)


def test_compliant_policy_turns_conservative_when_the_set_wanders():
    start = np.zeros(40, dtype=bool)
    start[:5] = True
    driver = ActiveSetDriver(COMPLIANT, 1e-9, name="wandering")
    assert driver.run(_Wandering(), start).all()
    assert driver.conservative and driver.solves < COMPLIANT.max_iter
    # without the wander rule the same problem never settles
    with pytest.raises(ActiveSetError, match="did not settle"):
        ActiveSetDriver(replace(COMPLIANT, wander=None), 1e-9).run(_Wandering(), start)
