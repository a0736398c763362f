"""Admissibility of one flight of a periodic orbit: the physical branch, one owner.

A flight from an impact to the next, of duration T, is admissible when

* T > 0;
* the mass leaves the stop: the post-impact velocity at its start is negative
  (v_k+ = -r v_k- with 0 < r <= 1, eq. (2));
* it arrives moving towards the stop: the impact velocity v_k- at its end is
  positive (-> 0 is grazing of the first kind);
* x_k(t) < b on (0, T): no earlier contact, transversal (penetration) or grazing
  (second kind), found by the provably safe first-impact finder of the flow.
  A finder that gives up before the flight's end (its step limit, a non-finite
  state) decides nothing: the flight is then not admissible, "undecided", with
  the reason, never admissible by default.

Every period-1 and n-p orbit of every model (:mod:`symvi.orbits.period1`,
:mod:`symvi.orbits.periodic`) and the paper's own chain (:mod:`symvi.orbit`)
use this test; only the flow that supplies ``first_impact`` differs.
"""
from ..flow.linear import GRAZING, IMPACT, NO_IMPACT
#: relative margin before the end of a flight inside which a contact is the flight's own impact
from ..numerics.tolerances import END_TOL, UNIT_CIRCLE


def stable_of(multipliers, admissible, model):
    """Asymptotic stability of an orbit: admissible and every |multiplier| < 1.  A
    conservative model's map preserves volume (the product of the multipliers is 1), so
    none is asymptotically stable: where its multipliers sit on the unit circle, rounding
    alone would decide the comparison."""
    return bool(admissible and not model.conservative
                and max(abs(complex(z)) for z in multipliers) < 1)


def neutral(multipliers, model, tol=UNIT_CIRCLE):
    """Whether every multiplier of a conservative model's orbit lies on the unit circle
    (within ``tol``): an elliptic orbit, neither asymptotically stable nor unstable by its
    multipliers."""
    return bool(model.conservative and len(multipliers)
                and all(abs(abs(complex(z)) - 1) <= tol for z in multipliers))


def check_flight(first_impact, T, v_start, v_end, *, mass, flight=None, tol=END_TOL,
                 require_return=False, stops=None):
    """(ok, reason) of one flight (see the module docstring).

    ``first_impact(t_max)`` returns the flow's first contact (status, t) after the
    start; ``v_start`` is the post-impact velocity at the start and ``v_end`` the
    impact velocity at the end; ``mass`` the stop's mass (1-based), ``flight`` the
    flight's number in the orbit (None for a period-1 orbit).  ``require_return``
    also demands that the flow itself finds the impact at T (an orbit from closed
    form, not from a solver whose equations already impose it).

    With several constraints, ``stops`` = (the constraint the flight starts from, the one
    it must end on) by 0-based index; ``first_impact`` then also returns the constraint
    met (its ``constraint``), and a flight that meets another one first, or at its end,
    is not admissible.  The speeds are then approach speeds (guard . v, > 0 towards it).
    """
    k = mass
    where = "" if flight is None else f"flight {flight}: "
    if stops is not None:
        return _check_stops(first_impact, T, v_start, v_end, where, tol, *stops)
    if not T > 0:
        return False, f"{where}non-positive flight time t = {float(T):.6g}"
    if not v_end > 0:
        return False, (f"{where}impact velocity v{k}- = {float(v_end):.6g} <= 0: the mass does "
                       "not arrive moving towards the stop (grazing where it passes through 0)")
    if not v_start < 0:
        return False, (f"{where}impact velocity {float(v_end):.6g}, but v{k}+ = "
                       f"{float(v_start):.6g} is not negative: the mass would not move away "
                       "from the stop")
    t_max = T * (2 if require_return else 1 + 1e-6)
    hit = first_impact(t_max)
    if hit.status == NO_IMPACT and not hit.t > t_max:
        # the finder gave up (step limit, non-finite state) before t_max: nothing decided
        return False, (f"{where}admissibility undecided: the first-contact finder stopped at "
                       f"t = {float(hit.t):.9g} < {float(T):.9g} after {hit.steps} steps "
                       "without deciding whether the flight stays off the stop")
    early = hit.t < T * (1 - tol)
    if hit.status == GRAZING and (early or require_return):
        return False, f"{where}grazing contact with the stop at t = {float(hit.t):.9g}"
    if hit.status == IMPACT and early:
        return False, (f"{where}x{k}(t) reaches b (the stop) at t = {float(hit.t):.9g} < "
                       f"{float(T):.9g}: the orbit would penetrate the stop")
    if require_return and hit.status != IMPACT:
        return False, f"{where}the flow found no return to the stop"
    return True, ""


def _check_stops(first_impact, T, v_start, v_end, where, tol, ka, kb):
    """:func:`check_flight` of a flight from constraint ka to constraint kb."""
    a, b = f"stop {ka + 1}", f"stop {kb + 1}"
    if not T > 0:
        return False, f"{where}non-positive flight time t = {float(T):.6g}"
    if not v_end > 0:
        return False, (f"{where}approach speed {float(v_end):.6g} <= 0 at {b}: the flight "
                       "does not arrive moving towards it (grazing where it passes through 0)")
    if not v_start < 0:
        return False, (f"{where}approach speed {float(v_start):.6g} >= 0 at {a} just after "
                       "its impact: the flight would not move away from it")
    t_max = T * (1 + 1e-6)
    hit = first_impact(t_max)
    if hit.status == NO_IMPACT and not hit.t > t_max:
        return False, (f"{where}admissibility undecided: the first-contact finder stopped at "
                       f"t = {float(hit.t):.9g} < {float(T):.9g} after {hit.steps} steps "
                       "without deciding whether the flight stays off every stop")
    met = f"stop {hit.constraint + 1}"
    early = hit.t < T * (1 - tol)
    if hit.status == GRAZING and early:
        return False, f"{where}grazing contact with {met} at t = {float(hit.t):.9g}"
    if hit.status == IMPACT and early:
        return False, (f"{where}the flight reaches {met} at t = {float(hit.t):.9g} < "
                       f"{float(T):.9g}: the orbit would penetrate it")
    if hit.status != NO_IMPACT and hit.constraint != kb:
        return False, (f"{where}the flight meets {met} at its end (t = {float(hit.t):.9g}), "
                       f"not {b}: the orbit would penetrate {met}")
    return True, ""
