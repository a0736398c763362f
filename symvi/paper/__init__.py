"""Everything specific to Luo & Xie (1998): its printed formulas evaluated as printed
(:mod:`.audit_orbit`, :mod:`.audit`: errata, the numbers table) and its circle-check
study (:mod:`.circle_check`).  Nothing below this package imports it: it runs only
when the audit or the report asks."""
