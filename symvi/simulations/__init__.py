"""Long runs of the impact map of any model: trajectories, sweeps and the mpmath
reference run (:mod:`.simulation`); Lyapunov exponents, rotation numbers and the
attractor class (:mod:`.diagnostics`).  Never plots.  (Named ``simulations`` so that
``symvi.simulate`` stays the public function.)
"""
