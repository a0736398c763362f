"""Simulation evidence for the codimension-two points of a Neimark–Sacker curve.

* :func:`chenciner_coexistence` -- next to a Chenciner point, on the side where
  l1 > 0 > l2 and on the stable side of the NS curve, a stable fixed point and a stable
  invariant circle coexist: two runs at the same parameters from two starts.
* :func:`resonance_dynamics` -- next to an R3 or R4 point, the period-3 / period-4 orbit
  the truncated normal form predicts (amplitude, phase, multipliers, type), checked
  against the orbit Newton finds in the full impact map, and two runs that show the
  basin of the stable fixed point bounded by it.

Both return a JSON-able dict and a dict of section arrays (``result``, ``arrays``), for
:func:`symvi.figures.codim2_evidence`.

The Chenciner wedge
-------------------
Normal form of the NS map near a CH point (||q||_2 = 1, <p, q> = 1,
x = x* + w q + conj(w q) + O(|w|^2)) [Kuznetsov, Elements, Sec. 9.3]::

    |w'| = |w| (1 + d mu + l1 |w|^2 + l2 |w|^4),    d mu = |lambda| - 1.

Invariant circles |w| = rho solve d mu + l1 s + l2 s^2 = 0 with s = rho^2, i.e.
s_+- = (l1 +- sqrt(l1^2 - 4 |l2| |d mu|)) / (2 |l2|) for l2 < 0.  Both are real and
positive (sum -l1/l2 > 0, product d mu / l2 > 0) exactly when l1 > 0 > l2, d mu < 0 and
0 < -d mu < -l1^2 / (4 l2): the bistable wedge.  There the fixed point is stable
(d mu < 0), the inner circle rho_- repels and the outer one rho_+ attracts: the radial
map's derivative at s is 1 + 2 s (l1 + 2 l2 s), = 1 -+ 2 s_+- sqrt(disc) at s_+-.
The outer circle attracts at only ~2 s_+ sqrt(disc) per iterate, which is why the runs
are long, and the wedge is narrow: -d mu < l1^2 / (4 |l2|).  Parameters are chosen as
``-d mu = fraction * l1^2 / (4 |l2|)`` at a point where the predicted rho_+ is ``rho``.

References
----------
[Kuznetsov, Elements] Yu. A. Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed.,
Springer 2004, Secs. 9.3 (Chenciner), 9.5.3-9.5.4 (1:3 and 1:4 resonances).
"""
import math

import numpy as np

from ..codim2 import chenciner, resonance_1_3, resonance_1_4
from ..errors import ParameterError, SingularCaseError
from ..orbits.periodic import ConvergenceError, periodic_orbit

#: the largest number of impacts any one run of this module iterates
MAX_RUN = 5_000_000


# --------------------------------------------------------------------------- helpers
def _params_of(curve, params):
    return {**dict(curve.fixed), **{k: float(v) for k, v in params.items()}}


def _model_at(model, params):
    rest = {k: v for k, v in params.items() if k != "omega"}
    return model.with_(**rest) if rest else model, float(params["omega"])


def _orbit(model, curve, params, guess):
    return periodic_orbit(model, n=curve.n, p=curve.p, guess=guess, **_params_of(curve, params))


def _critical(orbit):
    """The multiplier of the critical pair (largest modulus, Im >= 0)."""
    mu = np.array(orbit.multipliers, dtype=complex)
    k = int(np.argmax(np.abs(mu) + 1e-12 * (mu.imag > 0)))
    z = mu[k]
    return complex(z.real, abs(z.imag))


def _shift(model, curve, params, orbit, dmu, name, h=1e-5, maxit=8):
    """Move ``name`` from ``params`` until |lambda| - 1 = dmu (secant on the orbit)."""
    p0 = dict(params)

    def at(v):
        pp = dict(p0)
        pp[name] = v
        o = _orbit(model, curve, pp, orbit)
        return pp, o, abs(_critical(o)) - 1

    v0 = p0[name]
    _, _, g0 = at(v0)
    _, _, g1 = at(v0 + h)
    slope = (g1 - g0) / h
    if slope == 0:
        raise SingularCaseError("flat", f"|lambda| does not change with {name}")
    v = v0 + (dmu - g0) / slope
    for _ in range(maxit):
        pp, o, g = at(v)
        if abs(g - dmu) <= 1e-3 * abs(dmu):
            return pp, o, g
        v += (dmu - g) / slope
    return pp, o, g


def _w(sec, ys, p):
    """Normal-form coordinate w = <p, y - y*> of each section point (tau wrapped)."""
    d = np.asarray(sec, dtype=float) - np.asarray(ys, dtype=float)
    d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
    return d @ np.conj(np.asarray(p, dtype=complex))


def _half_widths(sec, ys):
    d = np.asarray(sec, dtype=float) - np.asarray(ys, dtype=float)
    d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
    return (d.max(axis=0) - d.min(axis=0)) / 2


def _run(model_at, omega, y0, n, transient, p):
    """simulate, keeping every p-th point from the first (the section of P^p)."""
    from ..simulation import simulate
    if n + transient > MAX_RUN:
        raise ParameterError("transient", transient, f"n_impacts + transient <= {MAX_RUN}")
    sim = simulate(model_at, omega, y0=tuple(float(v) for v in y0), n_impacts=n * p,
                   transient=transient * p)
    return sim, np.asarray(sim.section)[::p]


def _classify(sim):
    from ..diagnostics import classify
    c = classify(sim)
    out = {"kind": c.kind, "period": c.period, "rotation": c.rotation}
    if c.lyapunov is not None:
        out["lyapunov"] = float(c.lyapunov.largest)
    return out


def _complex(z):
    return [float(z.real), float(z.imag)]


def _check_kind(point, kinds, what):
    if getattr(point, "kind", None) not in kinds:
        raise ParameterError("point", getattr(point, "kind", point), f"a codimension-two point "
                             f"of kind {' or '.join(kinds)} ({what})")


# --------------------------------------------------------------------------- Chenciner
def wedge(l1, l2, dmu):
    """The circles s = rho^2 of d mu + l1 s + l2 s^2 = 0 (rho_-, rho_+), or None outside
    the wedge 0 < -d mu < -l1^2/(4 l2), l1 > 0 > l2."""
    if not (l1 > 0 > l2 and dmu < 0):
        return None
    disc = l1 * l1 - 4 * l2 * dmu
    if disc <= 0:
        return None
    r = math.sqrt(disc)
    sm, sp = (l1 - r) / (2 * -l2), (l1 + r) / (2 * -l2)
    return math.sqrt(sm), math.sqrt(sp), r


def _along_l1(curve, point, l1_target):
    """Parameters on the curve, beside ``point``, where l1 = l1_target > 0 (linear
    interpolation between the two curve points that bracket it) and the orbit there."""
    pts = curve.points
    i = point.index
    for step in (1, -1):
        j = i + 1 if step > 0 else i
        prev = None
        while 0 <= j < len(pts) and pts[j].l1 is not None and pts[j].l1 > 0 and pts[j].ns:
            if pts[j].l1 >= l1_target:
                if prev is None:
                    return dict(pts[j].params), pts[j].orbit, pts[j].l1
                a, b = pts[prev], pts[j]
                t = (l1_target - a.l1) / (b.l1 - a.l1)
                par = {k: a.params[k] + t * (b.params[k] - a.params[k]) for k in a.params}
                return par, (a.orbit if t < 0.5 else b.orbit), l1_target
            prev = j
            j += step
    raise SingularCaseError("no-l1", f"l1 does not reach {l1_target:.3g} on the l1 > 0 side "
                            f"of the CH point at {point.params}")


def chenciner_coexistence(model, curve, point, *, rho=0.25, fraction=0.5, along=None,
                          transient=300_000, n_impacts=5000, kick=1e-3,
                          fixed_impacts=1_000_000, outer_start=1.2):
    """Bistability next to a Chenciner point: a stable fixed point and a stable invariant
    circle at the same parameters, [Kuznetsov, Elements, Sec. 9.3].

    Parameters: on the curve beside ``point`` where l1 = 2 |l2| rho^2 / (1 + sqrt(1 -
    fraction)) (so that the predicted outer circle has radius ~``rho``), then ``along``
    (default: the curve's second parameter) moved off the curve to the stable side with
    d mu = |lambda| - 1 = -fraction l1^2 / (4 |l2|) (l1, l2 re-evaluated there).
    Runs: (1) from x* + 2 Re(kick q) for ``fixed_impacts``: the distance |w| to x* must
    shrink at the rate log|lambda| (a stable fixed point); (2) from x* + 2 Re(outer_start rho_+ q)
    for ``transient`` then ``n_impacts`` impacts, twice: it must stay outside rho_-,
    and its half-widths (measured) are compared with 2 rho_+ |q_k| (predicted, leading
    order) and between the two blocks (convergence).
    Returns (result, arrays): a JSON-able dict and the section arrays.
    """
    _check_kind(point, ("CH",), "Chenciner")
    if curve.kind != "ns":
        raise ParameterError("curve", curve.kind, "an NS curve")
    if not 0 < fraction < 1:
        raise ParameterError("fraction", fraction, "0 < fraction < 1 (inside the wedge)")
    l2_ch = float(point.coefficients["l2"])
    if not l2_ch < 0:
        raise SingularCaseError("l2-positive", f"l2 = {l2_ch:.3g} >= 0 at the CH point: the "
                                "outer circle is unstable, no bistability of attractors")
    along = along or curve.names[1]
    l1_target = 2 * -l2_ch * rho ** 2 / (1 + math.sqrt(1 - fraction))
    par_c, guess, _ = _along_l1(curve, point, l1_target)
    o_c = _orbit(model, curve, par_c, guess)
    l1_c, l2_c = _ch_coefficients(o_c)
    dmu_target = -fraction * l1_c ** 2 / (4 * -l2_c)
    par, orb, dmu = _shift(model, curve, par_c, o_c, dmu_target, along)
    l1, l2 = _ch_coefficients(orb)
    A, d2, d3, d4, d5 = orb.jet(5)
    ch = chenciner(A, d2, d3, d4, d5, tol=0.05)
    q, p = np.asarray(ch.q, dtype=complex), np.asarray(ch.p, dtype=complex)
    w = wedge(l1, l2, dmu)
    if w is None:
        raise SingularCaseError("outside-wedge", f"d mu = {dmu:.3g}, l1 = {l1:.3g}, l2 = "
                                f"{l2:.3g}: outside the bistable wedge")
    rho_m, rho_p, sq = w
    lam = _critical(orb)
    model_at, omega = _model_at(model, _params_of(curve, par))
    ys = np.asarray(orb.y, dtype=float)
    P = curve.p
    # run 1: from next to the fixed point
    y0 = ys + 2 * (kick * q).real
    sim_a, sec_a0 = _run(model_at, omega, y0, 2000, 0, P)
    sim_b, sec_a1 = _run(model_at, omega, sim_a.section[-1], 2000, fixed_impacts, P)
    wa0, wa1 = np.abs(_w(sec_a0, ys, p)), np.abs(_w(sec_a1, ys, p))
    rate = float(np.log(wa1.mean() / wa0.mean()) / (2000 + fixed_impacts)) if wa1.mean() > 0 \
        else -math.inf
    fixed_ok = bool(sim_b.stop == "completed" and wa1.max() < wa0.max()
                    and wa1.max() < 0.5 * rho_m)
    # run 2: from the predicted outer circle
    y1 = ys + 2 * (outer_start * rho_p * q).real
    sim_c, sec_c0 = _run(model_at, omega, y1, n_impacts, transient, P)
    sim_d, sec_c1 = _run(model_at, omega, sim_c.section[-1], n_impacts, transient, P)
    wc = np.abs(_w(sec_c1, ys, p))
    hw0, hw1 = _half_widths(sec_c0, ys), _half_widths(sec_c1, ys)
    pred = 2 * rho_p * np.abs(q)
    drift = float(np.max(np.abs(hw1 - hw0) / np.maximum(hw1, 1e-300)))
    cls = _classify(sim_d)
    circle_ok = bool(sim_d.stop == "completed" and wc.min() > rho_m
                     and (cls["kind"] == "invariant circle"
                          or (cls["period"] or 0) > 1) and drift < 0.05)
    rel = (hw1 - pred) / pred
    verdict = ("coexistence shown: " if fixed_ok and circle_ok else "NOT shown: ") + (
        f"from |w| = {kick:g} the distance to x* shrinks at {rate:.3g} per iterate "
        f"(log|lambda| = {math.log(abs(lam)):.3g}); from |w| = {outer_start:g} rho_+ (rho_+ = {rho_p:.4g}) the run "
        f"settles on a {cls['kind']} with |w| in [{wc.min():.4g}, {wc.max():.4g}] (inner "
        f"repelling circle rho_- = {rho_m:.4g}), half-widths within "
        f"{np.abs(rel).max():.1%} of 2 rho_+ |q_k| (leading order; the block-to-block drift "
        f"is {drift:.1%})")
    result = {
        "kind": "CH", "ch_point": {k: float(v) for k, v in point.params.items()},
        "l2_at_ch": l2_ch, "params": _params_of(curve, par), "along": along,
        "curve_params": {k: float(v) for k, v in par_c.items()},
        "l1": l1, "l2": l2, "dmu": dmu, "lambda": _complex(lam), "fraction": fraction,
        "wedge": {"dmu_min": -l1 * l1 / (4 * -l2), "condition": "l1 > 0 > l2, 0 < -dmu < "
                  "-l1^2/(4 l2)", "rho_inner": rho_m, "rho_outer": rho_p,
                  "outer_attraction_per_iterate": 2 * rho_p ** 2 * sq,
                  "inner_repulsion_per_iterate": 2 * rho_m ** 2 * sq},
        "fixed_point": [float(v) for v in ys], "fixed_point_stable": bool(orb.stable),
        "run_fixed": {"start_w": kick, "impacts": int((fixed_impacts + 4000) * P),
                      "w_first_block": float(wa0.mean()), "w_last_block": float(wa1.mean()),
                      "rate": rate, "predicted_rate": math.log(abs(lam)),
                      "stop": sim_b.stop, "stays": fixed_ok},
        "run_circle": {"start_w": outer_start * rho_p, "impacts": int(2 * (transient + n_impacts) * P),
                       "w_min": float(wc.min()), "w_mean": float(wc.mean()),
                       "w_max": float(wc.max()), "half_widths": hw1.tolist(),
                       "predicted_half_widths": pred.tolist(), "rel_error": rel.tolist(),
                       "block_drift": drift, "classification": cls, "stop": sim_d.stop,
                       "circle": circle_ok},
        "variables": list(getattr(orb, "names", ())),
        "coexist": bool(fixed_ok and circle_ok), "verdict": verdict,
        "normalisation": "||q||_2 = 1, <p,q> = 1, x = x* + w q + conj(w q); |w'| = |w|(1 + "
                         "dmu + l1|w|^2 + l2|w|^4); dmu = |lambda| - 1",
    }
    arrays = {"fixed_first": sec_a0, "fixed_last": sec_a1, "circle": sec_c1,
              "fixed_point": ys, "predicted_outer": _ring(ys, q, rho_p),
              "predicted_inner": _ring(ys, q, rho_m)}
    return result, arrays


def _ch_coefficients(orbit):
    A, d2, d3, d4, d5 = orbit.jet(5)
    c = chenciner(A, d2, d3, d4, d5, tol=0.05)
    return float(c.l1), float(c.l2)


def _ring(ys, q, rho, k=200):
    t = np.linspace(0, 2 * math.pi, k + 1)
    return np.asarray(ys)[None, :] + 2 * (rho * np.exp(1j * t)[:, None] * q[None, :]).real
