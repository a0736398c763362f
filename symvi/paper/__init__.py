"""Everything specific to Luo & Xie (1998): its printed formulas evaluated as printed,
the errata and the numbers table (:mod:`.audit_orbit`, :mod:`.audit`).  Nothing below
this package imports it: it runs only when the audit or the report asks."""
