"""Simulation evidence for the codimension-two points of a Neimark–Sacker curve.

* :func:`chenciner_coexistence` -- next to a Chenciner point, on the side where
  l1 > 0 > l2 and on the stable side of the NS curve, a stable fixed point and a stable
  invariant circle coexist: two runs at the same parameters from two starts.
* :func:`resonance_dynamics` -- next to an R3 or R4 point, the period-3 / period-4 orbit
  the truncated normal form predicts (amplitude, phase, multipliers, type), checked
  against the orbit Newton finds in the full impact map, and two runs that show the
  basin of the stable fixed point bounded by it.

Both return a JSON-able dict and a dict of section arrays (``result``, ``arrays``), for
:func:`symvi.reporting.figures.codim2_evidence`.

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

from ..normal_forms.codim2 import chenciner, resonance_1_3, resonance_1_4
from ..errors import ParameterError, SingularCaseError
from ..orbits.periodic import ConvergenceError, periodic_orbit

#: the largest number of impacts any one run of this module iterates
MAX_RUN = 5_000_000


# --------------------------------------------------------------------------- helpers
def _params_of(curve, params):
    return {**dict(curve.fixed), **{k: float(v) for k, v in params.items()}}


def _model_at(model, params):
    rest = {k: v for k, v in params.items() if not model.parameter(k).is_forcing_frequency}
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
    from ..simulations.simulation import simulate
    if n + transient > MAX_RUN:
        raise ParameterError("transient", transient, f"n_impacts + transient <= {MAX_RUN}")
    sim = simulate(model_at, omega, y0=tuple(float(v) for v in y0), n_impacts=n * p,
                   transient=transient * p)
    return sim, np.asarray(sim.section)[::p]


def _classify(sim):
    from ..simulations.diagnostics import classify
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
    # the runs must be long against the rates, or nothing is decided
    efold_fixed = abs(math.log(abs(lam))) * (2000 + fixed_impacts)
    efold_circle = 2 * rho_p ** 2 * sq * 2 * transient
    fixed_ok = bool(sim_b.stop == "completed" and wa1.max() < wa0.max()
                    and wa1.max() < 0.5 * rho_m and efold_fixed >= 0.3)
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
                          or (cls["period"] or 0) > 1) and drift < 0.05
                     and efold_circle >= 2)
    rel = (hw1 - pred) / pred
    verdict = ("coexistence shown: " if fixed_ok and circle_ok else "NOT shown: ") + (
        f"from |w| = {kick:g} the distance to x* shrinks at {rate:.3g} per iterate "
        f"(log|lambda| = {math.log(abs(lam)):.3g}); from |w| = {outer_start:g} rho_+ (rho_+ = {rho_p:.4g}) the run "
        f"ends on a {cls['kind']} with |w| in [{wc.min():.4g}, {wc.max():.4g}] (inner "
        f"repelling circle rho_- = {rho_m:.4g}), half-widths within "
        f"{np.abs(rel).max():.1%} of 2 rho_+ |q_k| (leading order; the block-to-block drift "
        f"is {drift:.1%}); e-folds of the linear rates over the runs: {efold_fixed:.2g} "
        f"(fixed point), {efold_circle:.2g} (outer circle; >= 0.3 and >= 2 needed)")
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
                      "rate": rate, "predicted_rate": math.log(abs(lam)), "efolds": efold_fixed,
                      "stop": sim_b.stop, "stays": fixed_ok},
        "run_circle": {"start_w": outer_start * rho_p, "impacts": int(2 * (transient + n_impacts) * P),
                       "w_min": float(wc.min()), "w_mean": float(wc.mean()),
                       "w_max": float(wc.max()), "half_widths": hw1.tolist(),
                       "predicted_half_widths": pred.tolist(), "rel_error": rel.tolist(),
                       "block_drift": drift, "efolds": efold_circle, "classification": cls, "stop": sim_d.stop,
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


# --------------------------------------------------------------------------- R3 and R4
def _umap(lam, lam0, c1, b, m):
    """The truncated normal form in the frame turning with lam0 = e^{2 pi i/m}:
    w = lam0^k u turns w -> lam w + c1 w|w|^2 + b conj(w)^{m-1} into the autonomous
    u -> (lam u + c1 u|u|^2 + b conj(u)^{m-1}) / lam0  (conj(lam0)^{k(m-1)} = lam0^k);
    its fixed points are the period-m orbits of the normal form."""
    def G(u):
        return (lam * u + c1 * u * abs(u) ** 2 + b * np.conj(u) ** (m - 1)) / lam0
    return G


def _real_jac(G, u, h=1e-7):
    J = np.empty((2, 2))
    for j, du in enumerate((h, 1j * h)):
        d = (G(u + du) - G(u - du)) / (2 * h)
        J[:, j] = d.real, d.imag
    return J


def _fixed_points(G, rho0, m, n_phase=48):
    """Nonzero fixed points of G by Newton from a ring of starts, one per orbit of the
    Z_m symmetry u -> lam0 u (kept with phase in [0, 2 pi/m))."""
    found = []
    for k in range(n_phase):
        for s in (0.5, 1.0, 2.0):
            u = s * rho0 * np.exp(2j * math.pi * k / n_phase)
            for _ in range(60):
                F = G(u) - u
                J = _real_jac(G, u) - np.eye(2)
                try:
                    d = np.linalg.solve(J, [-F.real, -F.imag])
                except np.linalg.LinAlgError:
                    break
                u = u + d[0] + 1j * d[1]
                if abs(d[0] + 1j * d[1]) < 1e-14 * (1 + abs(u)):
                    break
            if abs(G(u) - u) > 1e-12 or abs(u) < 1e-3 * rho0 or abs(u) > 20 * rho0:
                continue
            ph = math.atan2(u.imag, u.real) % (2 * math.pi / m)
            u = abs(u) * np.exp(1j * ph)
            if not any(abs(u - v) < 1e-6 * abs(u) for v in found):
                found.append(u)
    return found


def _type(mults, tol=1e-9):
    a = np.abs(np.asarray(mults))
    if np.all(a < 1 - tol):
        return "stable"
    if np.all(a > 1 + tol):
        return "repelling"
    if np.any(a < 1 - tol) and np.any(a > 1 + tol):
        return "saddle"
    return "neutral"


def resonance_dynamics(model, curve, point, *, dmu=None, along=None, basin=(0.5, 1.5),
                       n_impacts=None, stored=4000):
    """The period-m orbits (m = 3 for R3, 4 for R4) the truncated normal form predicts next
    to a strong resonance, checked against the full impact map [Kuznetsov, Elements,
    Secs. 9.5.3, 9.5.4].

    ``along`` (default the curve's second parameter) moves the point off the NS curve to
    the stable side, |lambda| - 1 = ``dmu`` (default -1e-3 for R3, -1e-5 for R4; the R4
    orbit's amplitude grows like sqrt|lambda - i|, the R3 orbit's like |lambda^3 - 1|).
    There the coefficients (b1, c1 or c1, d1) and q, p are recomputed at the fixed point,
    the fixed points of the truncated map in the rotating frame (:func:`_umap`) are
    found with their Jacobians J (predicted: amplitude |u|, phase, multipliers eig(J)^m
    of the period-m orbit and its type), and each is continued by Newton in the full map
    (n-p orbit with n, p multiplied by m) from the predicted points.  Checked: the orbit
    exists, its |w| = |<p, y - x*>| and phase, its two critical multipliers and its type.
    Then two runs from x* + ``basin`` times the offset of the nearest predicted orbit point
    along the same ray: inside, the run returns to x* (stable fixed point whose basin
    the saddle orbit bounds); outside, it leaves the neighbourhood.  Runs last
    ``n_impacts`` (default 10 / |dmu|: the critical multipliers are within ~|dmu| of the
    unit circle), of which ``stored`` evenly spaced points are kept.  Not checked: the
    global structure (heteroclinic connections, the invariant circles of R4 when |A| > 1).
    """
    _check_kind(point, ("R3", "R4"), "a strong resonance 1:3 or 1:4")
    m = 3 if point.kind == "R3" else 4
    along = along or curve.names[1]
    dmu = (-1e-3 if m == 3 else -1e-5) if dmu is None else float(dmu)
    if not dmu < 0:
        raise ParameterError("dmu", dmu, "< 0 (the stable side of the NS curve)")
    par0 = {k: float(v) for k, v in point.params.items()}
    o0 = _orbit(model, curve, par0, point.orbit)
    par, orb, got = _shift(model, curve, par0, o0, dmu, along)
    A, d2, d3 = orb.jet(3)
    lam0 = np.exp(2j * math.pi / m)
    tol = 2 * abs(_critical(orb) - lam0) + 1e-9     # the pair is this far from lam0
    if m == 3:
        r = resonance_1_3(A, d2, d3, tol=tol)
        b, coef = complex(r.b1), {"b1": _complex(complex(r.b1)), "c1": _complex(complex(r.c1)),
                                  "re": float(r.re), "im": float(r.im)}
    else:
        r = resonance_1_4(A, d2, d3, tol=tol)
        b, coef = complex(r.d1), {"d1": _complex(complex(r.d1)), "c1": _complex(complex(r.c1)),
                                  "A": _complex(complex(r.A)), "re": float(r.re),
                                  "im": float(r.im)}
    lam, c1 = complex(r.lam), complex(r.c1)
    q, p = np.asarray(r.q, dtype=complex), np.asarray(r.p, dtype=complex)
    G = _umap(lam, lam0, c1, b, m)
    e = abs(lam / lam0 - 1)
    rho0 = e / abs(b) if m == 3 else math.sqrt(e / abs(b))
    preds = _fixed_points(G, rho0, m)
    if not preds:
        raise SingularCaseError("no-orbit", f"the truncated 1:{m} normal form has no period-"
                                f"{m} orbit at d mu = {dmu:g}")
    ys = np.asarray(orb.y, dtype=float)
    model_at, omega = _model_at(model, _params_of(curve, par))
    orbits, arrays = [], {"fixed_point": ys}
    for i, u in enumerate(preds):
        J = _real_jac(G, u)
        ev = np.linalg.eigvals(np.linalg.matrix_power(J, m))
        guess = [tuple(ys + 2 * (lam0 ** k * u * q).real) for k in range(m)]
        entry = {"predicted": {"abs_w": abs(u), "phase": math.atan2(u.imag, u.real),
                               "multipliers": [_complex(z) for z in ev], "type": _type(ev)}}
        try:
            o = periodic_orbit(model, n=m * curve.n, p=m * curve.p, guess=guess,
                               **_params_of(curve, par))
        except ConvergenceError as exc:
            entry.update({"found": False, "reason": str(exc)})
            orbits.append(entry)
            continue
        pts = np.asarray(o.points)[::curve.p]
        w = _w(pts, ys, p)
        k = int(np.argmin(np.abs(w - u)))
        mu = np.array(o.multipliers, dtype=complex)
        crit = mu[np.argsort(-np.abs(mu))[:2]]
        entry.update({"found": True, "n": o.n, "p": o.p, "admissible": bool(o.admissible),
                      "abs_w": [float(v) for v in np.abs(w)],
                      "phase": float(np.angle(w[k])),
                      "multipliers": [_complex(z) for z in crit], "type": _type(crit),
                      "all_multipliers": [_complex(z) for z in mu],
                      "rel_error_abs_w": float(np.abs(w).mean() / abs(u) - 1),
                      "type_agrees": _type(crit) == _type(ev)})
        arrays[f"orbit_{i}"] = np.asarray(o.points)
        orbits.append(entry)
    # basin: the ray through the first predicted orbit point
    u = preds[0]
    runs = {}
    n_run = int(min(MAX_RUN, n_impacts or 10 / abs(got)))
    for s in basin:
        y0 = ys + 2 * (s * u * q).real
        try:
            sim, sec = _run(model_at, omega, y0, n_run, 0, curve.p)
        except SingularCaseError as exc:
            runs[str(s)] = {"start": s, "stop": str(exc)}
            continue
        wr = np.abs(_w(sec, ys, p))
        tail = wr[-max(10, n_run // 20):]
        sec = sec[::max(1, len(sec) // stored)]
        runs[str(s)] = {"start_over_orbit": s, "impacts": n_run * curve.p, "stop": sim.stop, "w_start": float(wr[0]),
                        "w_end": float(tail.max()), "back_to_fixed_point":
                        bool(sim.stop == "completed" and tail.max() < 0.05 * abs(u)),
                        "left": bool(sim.stop != "completed" or tail.min() > 2 * abs(u))}
        arrays[f"run_{s}"] = sec
    found = [o for o in orbits if o.get("found")]
    inside, outside = runs.get(str(basin[0]), {}), runs.get(str(basin[-1]), {})
    ok = bool(found and all(o["type_agrees"] for o in found)
              and all(abs(o["rel_error_abs_w"]) < 0.2 for o in found))
    verdict = (f"{len(preds)} period-{m} orbit(s) predicted, {len(found)} found in the full "
               "map; " + "; ".join(
                   f"|w| {o['predicted']['abs_w']:.4g} predicted vs "
                   f"{np.mean(o['abs_w']):.4g} found" + (
                       f", {o['predicted']['type']} predicted, {o['type']} found"
                       if o.get("found") else ", not found") for o in orbits)
               + f"; run from {basin[0]:g}x the orbit's offset: "
               + ("returns to x*" if inside.get("back_to_fixed_point") else "does not return")
               + f"; from {basin[-1]:g}x: " + ("leaves" if outside.get("left") else
                                               "does not leave") + " the neighbourhood")
    result = {"kind": point.kind, "m": m, "r_point": par0, "params": _params_of(curve, par),
              "along": along, "dmu": got, "lambda": _complex(lam),
              "lambda_over_lambda0_minus_1": _complex(lam / lam0 - 1),
              "coefficients_here": coef,
              "coefficients_at_point": {k: (_complex(v) if isinstance(v, complex) else v)
                                        for k, v in point.coefficients.items()
                                        if k in ("re", "im", "A", "coef", "b1", "c1", "d1")},
              "fixed_point": [float(v) for v in ys], "fixed_point_stable": bool(orb.stable),
              "variables": list(getattr(orb, "names", ())), "orbits": orbits, "runs": runs, "agrees": ok, "verdict": verdict,
              "checked": f"period-{m} orbit: existence, |w|, phase, critical multipliers, "
                         "type; basin runs along one ray",
              "not_checked": "global phase portrait (heteroclinic structure), invariant "
                             "circles born on the nearby NS curve",
              "normalisation": "||q||_2 = 1, <p,q> = 1, x = x* + w q + conj(w q); w = "
                               "lam0^k u, u -> (lam u + c1 u|u|^2 + b conj(u)^(m-1))/lam0"}
    return result, arrays
