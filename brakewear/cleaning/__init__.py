"""The headline question: the stops that clean a corroded rotor.

- :mod:`~brakewear.cleaning.corrosion`: the band a face's pad sweeps, the layered
  wear law and the pad-rotor non-conformity of a new pad;
- :mod:`~brakewear.cleaning.rust`: the rust layer's own law (friction and wear
  on rust, the removal threshold), its priors and its schedule state;
- :mod:`~brakewear.cleaning.rust_fit`: its calibration on dynamometer records
  (:mod:`~brakewear.cleaning.rust_record`: the record's file;
  :mod:`~brakewear.cleaning.rust_model`: its forward model and derivatives);
- :mod:`~brakewear.cleaning.criteria`: the candidate criteria of a clean rotor;
- :mod:`~brakewear.cleaning.bedding`, :mod:`~brakewear.cleaning.steady`: the
  pads bedded to their rotor, by a bedding history and solved directly;
- :mod:`~brakewear.cleaning.heat`: the stops' heat as the gap it cones;
- :mod:`~brakewear.cleaning.routine`: a routine as a car maker states it, run
  as a schedule with its states;
- :mod:`~brakewear.cleaning.priors`, :mod:`~brakewear.cleaning.brake`,
  :mod:`~brakewear.cleaning.car`: the uncertain inputs, the brake and the car
  of a draw;
- :mod:`~brakewear.cleaning.sample`, :mod:`~brakewear.cleaning.sweep`,
  :mod:`~brakewear.cleaning.sensitivity`: one routine on one draw, the design
  curve over many, and what decides it;
- :mod:`~brakewear.cleaning.command`, :mod:`~brakewear.cleaning.report`:
  ``brakewear clean`` and its files.

The modules are imported where they are used (the laws sit low, the routine on
top of the duty runner), so this package imports none of them itself.
"""
