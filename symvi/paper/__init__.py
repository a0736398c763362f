"""Everything specific to Luo & Xie (1998): its printed formulas evaluated as printed,
the errata and the numbers table (:mod:`.audit_orbit`, :mod:`.audit`), and the paper's
own 2-DOF modal derivation kept as the independent oracle of the any-model chain (the
closed-form orbits :mod:`.modal_orbit`, the map :mod:`.modal_map`).  The production
path does not import it: it runs when the audit, the report, the 50-digit chain B, a
reference run or a test asks."""
