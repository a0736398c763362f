"""Normal forms of any map at a fixed point, from its jet: the layer above the orbits.

* :mod:`.normal_form` -- eigen-structure with the pairing checks, the Neimark–Sacker
  normal form (the paper's reduction, eqs. (39)–(60), Kuznetsov's and Wan's forms),
  flip and fold coefficients;
* :mod:`.codim2` -- codimension-two normal forms (CH, R1–R4, LPNS, PDNS, LPPD, CP, GPD).

Nothing here knows a model: the inputs are jets (numpy or mpmath arrays).
"""
