"""The terminal's progress bar of a run (``brakewear run``, ``brakewear demo``): a
wear history's in simulated time, a schedule's in applications, and the solvers'
signs of life between them."""
from __future__ import annotations

import logging
import sys
import threading
import time

logger = logging.getLogger(__name__)

__all__ = ["Progress", "TICK_S"]

#: seconds between two redraws of the progress bar while a solve runs
TICK_S = 1.0


class Progress:
    """A progress bar (tqdm on stderr): a wear history's in simulated time, fed by
    its steps; a schedule's in applications, fed by their records.  Between them
    it shows that the run is alive: the solvers' beats (:mod:`brakewear.solvers.heartbeat`:
    the contact solve's active-set iteration and set size) in its postfix, and a
    clock that ticks every :data:`TICK_S` seconds while one solve runs.

    A history's time estimate is the remaining simulated time at the rate of
    the steps since the first one (the first step carries the model's setup and
    the first contact solve, so it says nothing of the rate): none before
    :attr:`MIN_STEPS` steps after it.  The steps grow as the pressure settles,
    so the estimate errs long, never short, on a running-in.  A schedule's is
    tqdm's (the applications at their mean rate).
    """

    MIN_STEPS = 3

    def __init__(self, scene, quiet: bool):
        self.schedule = bool(scene.schedule)
        self.total = len(scene.schedule) if self.schedule else scene.duration
        self.done, self.step, self.where, self.alive = 0.0, 0, "", ""
        self.bar, self._shown, self._stop = None, 0.0, threading.Event()
        self._first: tuple[float, float, int] | None = None   # wall s, simulated s, step
        if quiet:
            return
        from tqdm import tqdm
        counted = ("{n:.0f}/{total:.0f} applications" if self.schedule else
                   "{n:.4g}/{total:.4g} s simulated")
        self.bar = tqdm(total=self.total, unit="s", unit_scale=False, file=sys.stderr,
                        desc=f"{scene.name}", dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| " + counted
                                   + (" [{elapsed}<{remaining}{postfix}]" if self.schedule
                                      else " [{elapsed}{postfix}]"))
        self._ticker = threading.Thread(target=self._tick, daemon=True)
        self._ticker.start()

    def _tick(self) -> None:
        while not self._stop.wait(TICK_S):
            bar = self.bar
            if bar is not None:
                bar.refresh()

    def beat(self, what: str, figures: dict) -> None:
        """A solver's sign of life (a :func:`brakewear.solvers.heartbeat.listening` listener)."""
        if "iteration" in figures:
            self.alive = (f"{what} iteration {figures['iteration']}"
                          + (f" ({figures['active']} active)" if "active" in figures else ""))
            self._postfix(time.monotonic() - self._shown > TICK_S)

    def _postfix(self, refresh: bool) -> None:
        if self.bar is not None:
            self.bar.set_postfix_str(", ".join(x for x in (self.where, self.alive) if x),
                                     refresh=refresh)
            if refresh:
                self._shown = time.monotonic()

    def remaining(self, step: int, t: float, now: float | None = None) -> float | None:
        """Wall seconds left at the rate since the first step (None: too early to tell)."""
        now = time.perf_counter() if now is None else now
        if self._first is None:
            self._first = (now, t, step)
            return None
        w0, t0, k0 = self._first
        if step - k0 < self.MIN_STEPS or now <= w0 or t <= t0:
            return None
        return max(0.0, self.total - t) * (now - w0) / (t - t0)

    def __call__(self, s) -> None:
        if self.schedule:           # an ApplicationRecord
            self.where = f"application {s.index + 1} ({s.kind}) done"
            self._advance(s.index + 1)
            return
        self.step = s.step
        logger.info("step %d: t = %.6g s, dt = %.3g s (%s), %d rejected; pad wear max %.4g um, "
                    "pressure max %.4g MPa", s.step, s.time, s.dt, s.limit, s.rejected,
                    s.pad_wear.max() * 1e6, s.pressure.max() / 1e6)
        left = self.remaining(s.step, s.time)
        if self.bar is not None and s.step and self.done == 0.0 and s.time - s.dt > 0:
            self.done = s.time - s.dt          # resumed: start where the checkpoint was
            self.bar.update(self.done)
        eta = ("done" if s.time >= self.total * (1 - 1e-12) else
               "estimating the time left" if left is None or self.bar is None else
               f"about {self.bar.format_interval(left)} left at the rate so far")
        self.where = f"{eta}; step {s.step}, pad wear {s.pad_wear.max() * 1e6:.3g} um"
        self._advance(min(s.time, self.total))

    def _advance(self, to: float) -> None:
        self.alive = ""
        if self.bar is not None:
            self._postfix(False)
            self.bar.update(to - self.done)
            if to >= self.total * (1 - 1e-12):
                self.close()          # before the figures are drawn
        self.done = to

    def close(self) -> None:
        self._stop.set()
        if self.bar is not None:
            bar, self.bar = self.bar, None
            bar.close()
