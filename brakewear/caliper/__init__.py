"""The caliper's load path in one place: from the line pressure to the pads' backs.

- :mod:`~brakewear.caliper.geometry`: the caliper, fingers, pad support and rotor
  mount as data (read from a geometry file's load-path tables);
- :mod:`~brakewear.caliper.loads`: the clamp loads on the backplates (piston
  footprints, fingers) and the pads' in-plane supports;
- :mod:`~brakewear.caliper.parts` and :mod:`~brakewear.caliper.analytic`: the
  seal, the bore and the springs, and their closed forms;
- :mod:`~brakewear.caliper.rows`: the one-sided rows of a rigid piston, the
  fingers and the abutments, with friction;
- :mod:`~brakewear.caliper.static`: a static solve of the pads held that way;
- :mod:`~brakewear.caliper.condensation`, :mod:`~brakewear.caliper.joint`
  (:mod:`~brakewear.caliper.sets`, the nested reference) and
  :mod:`~brakewear.caliper.interface`: the FE model condensed onto the contact
  nodes and the rows, solved by one active-set iteration over both on a kept
  factorisation, as the wear loop's ``"caliper"`` interface model.

The modules are imported where they are used; this package imports none of
them itself, so that the geometry files can read the caliper's data without
loading its solvers.
"""
