"""``symvi orbit``: the period-1 one-impact orbits at one forcing frequency."""
from . import add_params, params_from, print_json


def register(sub):
    p = sub.add_parser("orbit", help="period-1 one-impact orbits at one omega, eqs. (10)-(18)")
    add_params(p, model=True)
    p.add_argument("--omega", type=float, required=True, help="forcing frequency (> 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..model import Model
    from ..paper.orbit import auto_orbits
    system = params_from(args)
    model = Model.of(system)
    paper = system is not model                 # the preset flags: the paper's view
    omega = args.omega                          # a float: the value the library checked
    if not model.one_rigid_stop:
        return _attractor(model, omega, args.json)
    if model.nonlinear is not None:
        return _nonlinear(model, omega, args.json)
    # error estimates; mpmath recomputation where float64 gives < 8 digits
    autos = auto_orbits(system, omega)
    orbits = [a.orbit for a in autos]
    if args.json:
        items = _json_items(autos)
        if paper:
            for d, a in zip(items, autos):
                d["y"] = [float(v) for v in a.orbit.y]
                d["names"] = list(PAPER_NAMES)
        out = {("params" if paper else "model"): system.as_dict(), "omega": omega,
               "orbits": items}
        if not orbits:
            out["reason"] = _why_none(model, omega)
        print_json(out)
        return 0
    if paper:
        from ..paper.params import modal
        m = modal(system)
        print(f"params: mu_m={system.mu_m:g} mu_k={system.mu_k:g} f2={system.f2:g} "
              f"b={system.b:g} r={system.r:g}   omega={omega:.10g}")
        print(f"modal:  omega1={m.omega1:.10g} omega2={m.omega2:.10g}")
    else:
        print(f"model: N = {model.n}, stop on mass {model.stop.mass} at gap "
              f"{model.stop.gap:g}, r = {model.stop.restitution:g}"
              f"{', damped' if model.damped else ''}   omega={omega:.10g}")
        from ..flow.linear import LinearFlow
        print("natural frequencies: " + " ".join(f"{float(w):.10g}"
                                                  for w in LinearFlow.of(model).omegas))
    if not orbits:
        print("no period-1 one-impact orbit exists here: " + _why_none(model, omega))
        return 0
    names, w = (PAPER_NAMES, 13) if paper else (orbits[0].names, 12)
    print(f"{'branch':6} " + " ".join(f"{n:>{w}}" for n in names)
          + f" {'v_impact':>{w}} {'max|lambda|':>11}  status")
    for a in autos:
        o = a.orbit
        lam = max(abs(complex(z)) for z in o.multipliers)
        status = _status(o)
        print(f"{o.branch:6} " + " ".join(f"{float(v):{w}.8f}" for v in o.y)
              + f" {float(o.impact_velocity):{w}.8f} {float(lam):11.7f}  {status}")
        print("       multipliers: " + ", ".join(
            f"{complex(z).real:+.8f}{complex(z).imag:+.8f}i" for z in o.multipliers))
        if not o.admissible:
            print(f"       reason: {o.reason}")
        print(f"       precision: {_text(a.estimate.y)}; {_text(a.estimate.multipliers)}"
              + (f"  [{a.note}]" if a.digits_used else ""))
    return 0


def _attractor(model, omega, as_json):
    """A model with no period-1 closed form (several stops, a lower one): the periodic
    orbit a run of the map settles on, with its n-p and signature."""
    from ..continuation import attractor_orbit
    from . import describe
    o = attractor_orbit(model, omega)
    found = ("the periodic attractor a run of the map from a default start on stop 1 "
             "settles on, refined by Newton (no period-1 closed form for this model; "
             "precision not estimated)")
    if as_json:
        print_json({"model": model.as_dict(), "omega": omega,
                    "orbits": [{**o.as_dict(), "found": found}]})
        return 0
    print(f"model: {describe(model)}   omega={omega:.10g}")
    print(f"{o.n}-{o.p} orbit, signature {', '.join(o.signature_names)}"
          + ("" if o.symmetric is None else (", symmetric" if o.symmetric else ", asymmetric"))
          + f": {found}")
    _print_orbit(model, o)
    return 0


#: how ``symvi orbit`` found a nonlinear model's orbits (:mod:`symvi.continuation.homotopy`)
NONLINEAR_FOUND = ("continued from the linear part's period-1 orbits in the forces' scale s "
                   "(s f(x, v), s from 0 to 1, paths followed over s in [-{reach:g}, "
                   "{reach:g}]) and the attractor of a run of the map, each refined by "
                   "Newton; orbits on isolas may be missed: the list is not complete by "
                   "construction (precision not estimated)")


def _nonlinear(model, omega, as_json):
    """A model with nonlinear forces: the period-1 orbits the homotopy from its linear
    part's closed form reaches (:mod:`symvi.continuation.homotopy`), each with where it
    came from, and what each path did not reach."""
    from ..continuation.homotopy import REACH
    from ..continuation.start import nonlinear_period1
    from ..flow import check_omega
    from . import describe
    found = nonlinear_period1(model, check_omega(model, omega))
    how = NONLINEAR_FOUND.format(reach=REACH)
    if as_json:
        print_json({"model": model.as_dict(), "omega": omega, "found": how,
                    "orbits": [{**o.as_dict(), "origin": w}
                               for o, w in zip(found.orbits, found.origins)],
                    "notes": list(found.notes)})
        return 0
    print(f"model: {describe(model)}   omega={omega:.10g}")
    print(f"{len(found.orbits)} period-1 one-impact orbit(s): {how}")
    for k, (o, origin) in enumerate(zip(found.orbits, found.origins), start=1):
        print(f"orbit {k} (from the {origin}):")
        _print_orbit(model, o)
    for note in found.notes:
        print(f"note: {note}")
    return 0


def _print_orbit(model, o):
    """The lines of one PeriodicOrbit: its events, multipliers and status."""
    event = "event" if model.elastic else "impact"      # an entry or exit has no impact
    for i, (y, names) in enumerate(zip(o.points, o.point_names)):
        print(f"  {event} {i + 1} ({o.signature_names[i]}): "
              + "  ".join(f"{n} = {v:.10g}" for n, v in zip(names, y))
              + f"   flight {o.times[i]:.10g}")
    print("  multipliers: " + ", ".join(_number(z) for z in o.multipliers))
    status = _status(o)
    print(f"  {status}; residual {o.residual:.3g}" + (f"; reason: {o.reason}" if o.reason else ""))


def _status(o):
    """stable, unstable, neutral (a conservative model's elliptic orbit) or INADMISSIBLE."""
    if not o.admissible:
        return "INADMISSIBLE"
    if o.neutral:
        return "neutral (conservative model: every |multiplier| = 1)"
    return "stable" if o.stable else "unstable"


#: the paper's names of (x1dot+, x20, x20dot, tau0), eq. (9)
PAPER_NAMES = ("x1dot+", "x20", "x20dot", "tau0")


def _why_none(model, omega):
    """The reason a model has no period-1 one-impact orbit at omega (one sentence)."""
    from ..orbits.period1 import no_orbit_reason
    return no_orbit_reason(model, omega) or "the period-1 conditions have no solution"


def _number(z, fmt=".10g"):
    """A real number as itself, a complex one as a+bi (as the multipliers line prints it);
    an imaginary part below the 10 printed digits (rounding of a real multiplier) as 0."""
    z = complex(z)
    if abs(z.imag) <= 1e-10 * abs(z):
        return format(z.real, fmt)
    return f"{format(z.real, fmt)}{format(z.imag, '+' + fmt)}i"


def _text(estimate):
    """An estimate's value (complex multipliers in full), digits and backend, or UNTRUSTED."""
    if not estimate.trusted:
        return f"{estimate.name}: UNTRUSTED ({estimate.note})"
    v = estimate.value
    vs = ", ".join(_number(x) for x in v) if isinstance(v, (list, tuple)) else _number(v)
    extra = f", recomputed with {estimate.backend}" if estimate.recomputed else ""
    return f"{estimate.name} = {vs}  (~{estimate.digits:.1f} digits{extra})"


def _json_items(autos):
    """Each orbit's JSON with its precision estimate (one shape for both chains)."""
    items = []
    for a in autos:
        d = a.orbit.as_dict()
        d["precision"] = {"y": a.estimate.y.as_dict(),
                          "multipliers": a.estimate.multipliers.as_dict(), "note": a.note}
        items.append(d)
    return items
