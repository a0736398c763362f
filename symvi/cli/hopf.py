"""``symvi hopf``: every Neimark–Sacker point in an omega interval, with its normal form."""
import argparse

from . import add_params, describe, old_range, params_from, print_json
from ._kernels import HOPF, warm


def register(sub):
    p = sub.add_parser("hopf", help="Neimark-Sacker (Hopf) points in an omega interval, "
                                    "(H1)-(H3), l1 and f1, eqs. (39)-(60)")
    add_params(p, model=True)
    p.add_argument("--range", metavar="omega=LO:HI",
                   help="the omega interval scanned (1e-4 .. 1e4); where the omega_j / n "
                        "accumulate, below the largest 300 of them, nothing is scanned and "
                        "the headline says so")
    p.add_argument("--omega-min", type=float, help=argparse.SUPPRESS)   # deprecated forms
    p.add_argument("--omega-max", type=float, help=argparse.SUPPRESS)   # of --range
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--digits", type=int, default=None,
                   help="also re-run each point at this many digits (mpmath, 30..500): the "
                        "project's chain and an independent finite-difference chain; seconds "
                        "per point")
    return p


#: the deprecated form of --range omega=LO:HI (one release)
OLD_RANGE = {"lo": ("omega_min", "--omega-min"), "hi": ("omega_max", "--omega-max")}


def _names(args):
    """How the library's omega_min, omega_max are called on this command line."""
    return {"omega_min": args.flags["lo"], "omega_max": args.flags["hi"]}


def run(args):
    from ..analysis.hopf import CONSERVATIVE
    from ..errors import ParameterError
    from ..paper.hopf import hopf_points
    args.span, args.flags = old_range(args, "--range", OLD_RANGE, name="omega",
                                      names=("omega",))
    params = params_from(args)
    if args.digits is not None and not 30 <= args.digits <= 500:
        raise ParameterError("--digits", args.digits, "an integer from 30 to 500")
    from ..model import Model
    if isinstance(params, Model) and (not params.one_rigid_stop
                                      or params.nonlinear is not None):
        return _branch_scan(params, args)
    # first run after install: compile the scan's kernels in parallel, and say so
    warm(HOPF, "the Hopf scan")
    try:
        res = hopf_points(params, args.span.lo, args.span.hi)
    except ParameterError as exc:
        raise exc.renamed(_names(args)) from None
    checks = []
    if args.digits is not None:
        from ..studies.mpcheck import check_points
        checks = check_points(params, res.points, digits=args.digits)
    if args.json:
        obj = res.as_dict()
        for d, c in zip(obj["points"], checks):
            d["mpcheck"] = c.as_dict()
        print_json(obj)
        return 0
    print(f"{'model' if 'N=' in describe(params) else 'params'}: {describe(params)}   "
          f"omega in [{res.omega_min:g}, {res.omega_max:g}]"
          f"   ({res.samples} orbit evaluations)")
    if res.conservative:
        print("conservative model: " + CONSERVATIVE)
    if not res.complete:
        # a budget that ran out, or a span not scanned, is never "nothing crosses"
        print(_incomplete(res))
    elif not res.points and not res.conservative:
        print("no complex pair of an admissible period-1 orbit crosses |lambda| = 1 here")
    for i, pt in enumerate(res.points):
        lam = pt.multiplier

        def val(name, fmt=".12g", pt=pt):
            # never print a number automatic precision could not trust
            return format(getattr(pt, name), fmt) if pt.trusted(name) else "UNTRUSTED"
        print(f"\nHopf point {i + 1}: omega_c = {val('omega_c', '.15g')}  (branch {pt.branch})")
        print(f"  lambda1        = {lam.real:+.12f} {lam.imag:+.12f}i   theta/2pi = "
              f"{pt.theta_over_2pi:.10f}")
        print("  other          = " + ", ".join(f"{z.real:+.8f}{z.imag:+.8f}i"
                                                 for z in pt.other_multipliers))
        m, dist = pt.nearest_resonance
        h3 = ("yes" if pt.h3 else "NO (stability regained as omega increases)"
              if pt.crossing_resolved else "NO (crossing speed not resolved, see below)")
        print(f"  (H1) {'yes' if pt.h1 else 'NO '}   (H2) {'yes' if pt.h2 else 'NO '} "
              f"(nearest lambda^{m} = 1 at distance {dist:.3e})   (H3) {h3}")
        err = pt.dmod_domega_branch_error
        print(f"  d|lambda1|/domega = {val('dmod_domega')} (eqs. A1-A3)   "
              f"{pt.dmod_domega_branch:.12g} +/- {err:.1g} (along the branch)")
        print(f"  l1 = {val('l1')}  (Kuznetsov, ||q|| = 1, <p,q> = 1)  -> {pt.kind}")
        if pt.precision is not None:
            print("  precision: " + "; ".join(
                e.text() for e in (pt.precision.omega_c, pt.precision.dmod_domega,
                                   pt.precision.l1)))
        if getattr(pt, "f1_paper", None) is not None:   # the paper's f1 (eq. 60): its model
            print(f"  f1(0) = {pt.f1_paper:.12g} (eq. 60 as printed)   {pt.f1_wan:.12g} "
                  "(eq. 60 corrected = -l1/4; ||r1|| = 1, f1 > 0 attracting)")
        if pt.circle_caveat:
            # the circle of the normal form is a prediction only under its hypotheses
            print(f"  circle: not predicted ({pt.circle_caveat})")
        else:
            c = pt.circle
            side = "omega > omega_c" if c.side > 0 else "omega < omega_c"
            hw = ", ".join(f"{n} {2 * c.coefficient * a:.5g}" for n, a in zip(c.names, c.q_abs))
            print(f"  circle ({'stable' if c.stable else 'unstable'}, {side}): radius "
                  f"{c.coefficient:.6g} sqrt|mu|; half-widths / sqrt|mu|: {hw}")
        if not pt.h2:
            # at lambda^m = 1 the cubic normal form (58) is not the normal form
            kind = "strong resonance" if m <= 4 else "resonance"
            print(f"  caution: (H2) fails, lambda1^{m} = 1 ({kind} 1:{m}); l1, f1 and the circle "
                  "assume (H2) and need not describe the dynamics here")
        if not pt.crossing_resolved:
            print(f"  caution: {pt.detail}; the kind and the circle assume a transversal "
                  "crossing")
        if pt.branch_caveat:
            print(f"  caution: d|lambda1|/domega {pt.branch_caveat}")
        if not pt.h1:
            print("  caution: (H1) fails, another multiplier lies on or outside the unit circle: "
                  "a circle on the centre manifold is not attracting in all directions")
        if checks:
            ag = checks[i].agreement
            print(f"  mpmath ({args.digits} digits), digits of agreement chain A vs B: "
                  + ", ".join(f"{k} {v['A-B']}" for k, v in ag.items())
                  + "; float64 vs A: " + ", ".join(f"{k} {v['float-A']}" for k, v in ag.items()))
    if res.events:
        print("\nevents:")
        counts = {}
        for e in res.events:
            counts[e.kind] = counts.get(e.kind, 0) + 1
        for e in res.events:
            if counts[e.kind] > EVENT_LINES:
                continue                      # summarised below
            br = f"branch {e.branch}" if e.branch else "        "
            if e.kind == "conservative":      # a statement over the whole interval
                print(f"  omega in [{e.span[0]:.13g}, {e.span[1]:.13g}]  {e.kind}: see above")
                continue
            print(f"  omega = {e.omega:.13g}  {br}  {e.kind}: {e.detail}")
        for kind, n in counts.items():
            if n > EVENT_LINES:
                ws = [e.omega for e in res.events if e.kind == kind]
                print(f"  {n} events '{kind}' between omega = {min(ws):.10g} and "
                      f"{max(ws):.10g} (listed one by one with --json)")
    return 0


def _branch_scan(model, args):
    """A model with no period-1 closed form (several stops, a lower one, an elastic stop,
    nonlinear forces):
    the NS points of the branches continued from the attractors found in the interval
    (:func:`symvi.continuation.start.ns_scan`), said to be uncertified."""
    from ..continuation.start import ns_scan
    from ..errors import ParameterError
    if args.digits is not None:
        raise ParameterError("--digits", args.digits, "not given for a model with no "
                             "period-1 closed form (the mpmath chains check period-1 orbits "
                             "of one rigid stop)")
    try:
        res = ns_scan(model, args.span.lo, args.span.hi)
    except ParameterError as exc:
        raise exc.renamed(_names(args)) from None
    if args.json:
        print_json(res.as_dict())
        return 0
    print(f"model: {describe(model)}   omega in [{res.omega_min:g}, {res.omega_max:g}]")
    print(f"NOT CERTIFIED: {res.reason}")
    for w, n, p, sig in res.starts:
        print(f"  started at omega = {w:.6g}: {n}-{p} orbit ({', '.join(sig)})")
    if not res.points:
        print("no NS point on these branches")
    for i, (sp, br) in enumerate(res.points):
        c = sp.coefficients
        print(f"\nNS point {i + 1}: omega_c = {sp.value:.15g}  ({br.n}-{br.p} orbit, "
              f"{', '.join(sp.orbit.signature_names)})")
        if "l1" in c:
            print(f"  theta = {c.get('theta', float('nan')):.10g}   l1 = {c['l1']:.10g}  "
                  "(||q||_2 = 1, <p,q> = 1)")
        print(f"  {sp.detail}")
    return 0


#: events of one kind beyond this many are summarised in one line (all are in --json)
EVENT_LINES = 20
#: at most this many uncertified spans are named in the headline (all are in --json)
SPAN_LINES = 6


def _incomplete(res):
    """The headline of a scan that could not certify the whole interval: the spans (the
    widest SPAN_LINES of them when there are more) and why."""
    from ..analysis.hopf import spans_text
    spans = res.uncertified
    n = len(res.points)
    head = (f"{n} Neimark-Sacker point{'s' if n != 1 else ''} found; " if not res.conservative
            else "real multipliers through +1 or -1: ") + "NOT certified on "
    why = "; ".join(res.uncertified_reasons)
    if len(spans) <= SPAN_LINES:
        return (head + spans_text(spans) + f" ({why}): a crossing there may be "
                "missed, see the 'unresolved' events")
    total = sum(hi - lo for lo, hi in spans)
    widest = sorted(sorted(spans, key=lambda s: s[0] - s[1])[:SPAN_LINES])
    return (head + f"{len(spans)} sub-intervals of total width {total:.3g}: a crossing there "
            f"may be missed\n  widest: {spans_text(widest)} (all with --json)\n"
            f"  why: {why}")
