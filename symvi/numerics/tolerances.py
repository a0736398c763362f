"""Shared tolerances, each defined once (issue 24, item 6).

Each constant says what it bounds and why its value.  Modules import it from here
and keep their old module-level names as imports, e.g. ``symvi.params`` and
``symvi.flow.linear`` both expose ``RESONANCE_REFUSE`` as
:data:`FORCING_RESONANCE_REFUSE`.  Two different quantities measured on the same
scale get two names: the *forcing* resonance (omega at a natural frequency, the
steady-state response is infinite) is not the *strong* resonance of a multiplier
(lambda^m = 1, the normal form divides by zero); ``symvi.normal_forms.normal_form``
keeps the names ``RESONANCE_REFUSE`` / ``RESONANCE_WARN`` for the latter.

``tests/test_constants.py`` holds the rule: no module-level UPPER_CASE float
constant is defined under the same name in two modules of ``symvi``.
"""

# --------------------------------------------------------------------------- float64
#: float64 machine epsilon 2^-52 (numpy.finfo(float).eps), written out so that compiled
#: (numba) code reads it as a constant: the unit of every rounding bound below
EPS64 = 2.0 ** -52

# --------------------------------------------------------------------------- valid input ranges
#: forcing frequencies accepted, OMEGA_RANGE[0] <= omega <= OMEGA_RANGE[1]: outside,
#: float64 over- or underflows in the modal solution, eqs. (4)-(16)
OMEGA_RANGE = (1e-4, 1e4)
#: largest |value| of a length- or force-like parameter (the paper's |b| and |f2|; a model's
#: matrix entries, gap and forcing amplitudes): beyond it float64 over- or underflows in
#: the flow, eqs. (4)-(16)
ABS_MAX = 1e6

# --------------------------------------------------------------------------- forcing resonance
# relative distance of omega to an undamped natural frequency, |omega - omega_j| / omega_j
# (for a damped model sigma_min(K~ - omega^2 I + i omega C~) / (2 omega^2), the same to
# first order); the steady-state amplitude grows like 1 / distance
#: refused below this: the amplitude, computed to ~eps / distance, keeps ~6 float64 digits
FORCING_RESONANCE_REFUSE = 1e-10
#: NearSingularWarning below this: results lose about -log10(distance) >= 4 digits
FORCING_RESONANCE_WARN = 1e-4
#: scans and branches through a natural frequency stop this far (relative) on either side:
#: well above the refusal, where the amplitude (~ 1 / distance = 1e6) still keeps ~10 digits
FORCING_RESONANCE_CUT = 1e-6

# --------------------------------------------------------------------------- isolation
# d = |1 - e^{lambda_j T}| of an undamped mode over the period T (= 2 |sin(pi omega_j / omega)|
# for a period-1 orbit, and 1 - cos(2 pi omega_j / omega) = d^2 / 2): where d vanishes,
# omega_j / omega is an integer, eq. (15) divides by zero and the orbit is not isolated.
# symvi.paper.modal_orbit measures |sin(pi omega_j / omega)| = d / 2 (KAPPA_* = ISOLATION_* / 2)
#: refused below this: 1 - cos = 2e-18 is below float64's resolution of cos near 1
ISOLATION_REFUSE = 2e-9
#: NearSingularWarning below this: 1 - cos = 2e-8 loses half of float64's digits
ISOLATION_WARN = 2e-4

# --------------------------------------------------------------------------- strong resonance
# distance |lambda1^m - 1| (m = 1..5) of the critical multiplier to a root of unity; the
# Neimark-Sacker normal form (eqs. (56)-(60)) divides by lambda^m - 1 (m <= 3)
#: refused below this (m <= 3): a divisor of 1e-10 leaves ~6 float64 digits, as for
#: FORCING_RESONANCE_REFUSE
STRONG_RESONANCE_REFUSE = 1e-10
#: NearSingularWarning below this (m = 1..5): (H2) nearly fails and the cubic normal form
#: holds only in a small neighbourhood.  Not FORCING_RESONANCE_WARN's 1e-4: this bounds where
#: the truncated normal form describes the dynamics, not how many digits are lost
STRONG_RESONANCE_WARN = 1e-3

# --------------------------------------------------------------------------- contact and grazing
# The first-contact finders (symvi.flow.linear, its compiled twin symvi.flow.compiled and
# the paper's symvi.paper.modal_flow) share these, so that they agree on contact and grazing
#: eps_h = CONTACT_ULPS * eps * L: h = x_k - b is resolved only to a few ulps of the
#: motion's scale L (sum of the amplitudes and |b|), so h >= -eps_h counts as contact
CONTACT_ULPS = 64.0
#: a contact with speed h' <= GRAZING_SPEED_FACTOR * sqrt(2 M2 eps_h) is grazing: M2 bounds
#: |h''|, so below sqrt(2 M2 eps_h) a contact is not told apart from a tangency within
#: eps_h; the factor 8 is the margin that keeps such a contact from a Newton polish
GRAZING_SPEED_FACTOR = 8.0
#: the Newton polish of a transversal contact time t stops at a step of this many ulps of t
CONTACT_TIME_ULPS = 4.0

# --------------------------------------------------------------------------- admissibility
#: relative margin before the end of a flight inside which a contact is the flight's own
#: impact (symvi.orbits.admissibility): far above the rounding of a float64 flight time,
#: far below the distance of a real earlier contact
END_TOL = 1e-9
#: a multiplier of a conservative model's orbit this close to |z| = 1 is on the unit circle
#: (an elliptic orbit: :func:`symvi.orbits.admissibility.neutral`)
UNIT_CIRCLE = 1e-9

# --------------------------------------------------------------------------- Newton
#: a Newton iteration on a periodic orbit has converged when its last step is below this,
#: relative to 1 + max|u| (and its residual below 1e3 times that): ~45 ulps, near the
#: float64 rounding floor of the shooting residual
NEWTON_TOL = 1e-11

# --------------------------------------------------------------------------- classification
#: stored impacts below which a run is not classified: period detection compares points
#: k apart (k <= n/2) and the chaos test needs 10 blocks of exponents; the CLI
#: (symvi simulate --classify) refuses fewer before it runs anything
MIN_CLASSIFY = 50
