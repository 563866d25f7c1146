"""The headline question: the stops that clean a corroded rotor.

- :mod:`~brakewear.cleaning.corrosion`: the cleaning criterion judged per face,
  the layered wear law and the pad-rotor non-conformity a routine starts from;
- :mod:`~brakewear.cleaning.rust`: the rust layer's own law (friction and wear
  on rust, the removal threshold) and its priors;
- :mod:`~brakewear.cleaning.rust_fit`: its calibration on dynamometer records
  (:mod:`~brakewear.cleaning.rust_record`: the record's file;
  :mod:`~brakewear.cleaning.rust_model`: its forward model and derivatives);
- :mod:`~brakewear.cleaning.routine`: a cleaning routine run stop by stop.

The modules are imported where they are used (the laws sit low, the routine
on top of the duty runner), so this package imports none of them itself.
"""
