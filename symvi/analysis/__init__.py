"""Bifurcation analysis along period-1 branches of any model: the certified scan for
Neimark–Sacker points and events, (H1)–(H3) (:mod:`.hopf`), and error estimates with
automatic mpmath recomputation (:mod:`.precision`).  Built on the orbits, the
continuation's locator and the normal forms; imported by the studies, report and CLI.
"""
