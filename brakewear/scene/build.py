"""A scene made into its run: the one place a scene's parts are built.

:func:`build_run` turns a checked :class:`~brakewear.scene.Scene` into a
:class:`~brakewear.wear.Run`: the model (meshed here), the wear laws and
limits, the interface model the scene names (built by its entry in
:mod:`brakewear.interfaces.registry`, with its own keys), the initial gap of
the coning, taper and gap map at that interface's pad nodes, thermal
coupling when enabled, and the load: the drag of ``[environment]`` or the
``[schedule]`` with its vehicle.  Every runner takes the result.
"""
from __future__ import annotations

import logging
from dataclasses import replace

from ..wear.bounds import check_run_bounds
from ..wear.limits import WearLimits
from ..wear.run import Run

logger = logging.getLogger(__name__)

__all__ = ["build_run"]


def build_run(scene, model=None, checkpoint=None) -> Run:
    """The :class:`~brakewear.wear.Run` of a scene: what every runner takes.

    Parameters
    ----------
    scene
        The :class:`~brakewear.scene.Scene`.
    model
        Its model, already built (default: built here, which meshes).
    checkpoint
        That of a run being resumed (an ``"auto"`` interface keeps the one it
        was run on), or None.

    Returns
    -------
    Run
        The run, its interface and laws built.
    """
    pad_law, rotor_law = scene.wear_laws()
    model = scene.build_model() if model is None else model
    n = scene.numerics
    limits = WearLimits.for_model(model, scene.pad_wear.limit,
                                  None if scene.rotor_wear is None else scene.rotor_wear.limit,
                                  update=n.update)
    # with a schedule the environment's drag is nominal (what "auto" weighs)
    run = Run(model, scene.line_pressure, scene.omega, scene.duration, pad_law, rotor_law,
              scene.friction(), numerics=n, interface=scene.interface.model, limits=limits,
              thermal=_thermal(scene, model), schedule=scene.schedule, vehicle=scene.vehicle)
    run = run.resolved(scene.line_pressure, scene.interface.options, checkpoint)
    check_run_bounds(run)          # before anything is written
    if scene.interface.nonconforming:
        run = replace(run, initial_gap=scene.initial_gap(run.interface.x))
    logger.info("scene %r: %s interface, %d DOFs", scene.name, type(run.interface).__name__,
                model.dofs)
    return run


def _thermal(scene, model):
    """The scene's :class:`~brakewear.thermal.ThermalModel` (None: not enabled; the
    thermal package is not imported then)."""
    t = scene.thermal
    if not t.enabled:
        return None
    from ..thermal.model import ThermalModel
    return ThermalModel(model, partition=t.partition, h_conv=t.convection_law(),
                        T_ambient=scene.ambient, T_ref=t.T_ref, mass=t.mass,
                        T_initial=t.T_initial,
                        contact_conductance=t.conductance(scene.geometry, scene.line_pressure),
                        T_max=t.T_max, emissivity=t.emissivity)
