"""Long runs of the impact map of any model: trajectories, sweeps and the mpmath
reference run (:mod:`.simulation`); the one attractor classifier and its vocabulary
(:mod:`.classifier`, for ``simulate --classify`` and parameter planes alike); Lyapunov
exponents and rotation numbers (:mod:`.diagnostics`).  Every compiled run goes through
the one loop :func:`symvi.flow.compiled._run_into`.  Never plots.  (Named
``simulations`` so that ``symvi.simulate`` stays the public function.)
"""
