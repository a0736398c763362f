"""Everything specific to Luo & Xie (1998), on top of the package (a client, never a
dependency of the layers below):

* its preset :class:`~symvi.paper.params.Params` (eqs. (3)–(8); ``as_model()`` is the
  :class:`symvi.Model` every analysis runs on);
* its views of the general results, each a subclass of the general type: the period-1
  :class:`~symvi.paper.orbit.Orbit` (ẋ1+, x20, ẋ20, τ0, a_j, b_j), the
  :class:`~symvi.paper.jets.Jet` (F01 … F11) and the Hopf points with eq. (60)'s f1
  (:mod:`.hopf`);
* its centre-manifold reduction, eqs. (39)–(60), (A4)–(A17), with the errata
  (:mod:`.reduction`); its printed formulas evaluated as printed and the numbers table
  (:mod:`.audit_orbit`, :mod:`.audit`);
* its own 2-DOF modal derivation, kept as the independent oracle of the any-model chain:
  the modal flow (:mod:`.modal_flow`), the closed-form orbits (:mod:`.modal_orbit`), the
  map (:mod:`.modal_map`) and the generated modal jets (:mod:`._eval`).
"""
