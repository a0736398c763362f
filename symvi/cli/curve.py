"""``symvi curve``: continue an NS, flip or fold curve in two parameters from the point of
that kind found in [omega_min, omega_max], with its codimension-two points."""
from . import add_params, describe, params_from, print_json, print_special


def register(sub):
    p = sub.add_parser("curve", help="continue a Neimark-Sacker, flip or fold curve in two "
                                     "parameters; locate Chenciner, R1-R4, LPNS, PDNS points")
    add_params(p, model=True)
    p.add_argument("--omega-min", type=float, required=True, metavar="A",
                   help="the start point is the NS (flip, fold) point found in [A, B]")
    p.add_argument("--omega-max", type=float, required=True, metavar="B")
    p.add_argument("--params", required=True, metavar="omega,NAME",
                   help="the two curve parameters: omega and a named parameter of the model "
                        "(b, r, mu_m, mu_k, f2 for the preset; gap, restitution, mass[i], "
                        "stiffness[i,j], damping[i,j], forcing[i])")
    p.add_argument("--bounds", action="append", default=[], metavar="NAME=LO:HI",
                   help="range of a curve parameter (default: half to twice its start value)")
    p.add_argument("--kind", default="ns", choices=("ns", "flip", "fold"),
                   help="the curve's bifurcation (default ns)")
    p.add_argument("--index", type=int, default=1, metavar="K",
                   help="start from the K-th point of that kind in [A, B], by omega (default 1)")
    p.add_argument("--max-points", type=int, default=2000,
                   help="points on each side of the start (default 2000)")
    p.add_argument("--through", action="store_true",
                   help="follow the curve on where its orbit is not admissible")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="draw the two-parameter diagram")
    return p


def parse_bounds(items, names):
    from ..errors import ParameterError
    out = {}
    for item in items:
        name, eq, rng = item.partition("=")
        lo, colon, hi = rng.partition(":")
        try:
            lo, hi = float(lo), float(hi)
            ok = bool(eq and colon and name.strip()) and lo < hi
        except ValueError:
            ok = False
        if not ok:
            raise ParameterError("--bounds", item, "NAME=LO:HI with numbers LO < HI")
        if name.strip() not in names:
            raise ParameterError("--bounds", item, f"a bound of a curve parameter "
                                 f"({', '.join(names)})")
        out[name.strip()] = (lo, hi)
    return out


def run(args):
    import math
    import warnings

    from ..curves import curve_from_interval, parse_params
    from ..errors import NearSingularWarning, ParameterError
    from ..model import Model
    model = Model.of(params_from(args))
    names = parse_params(args.params)
    for nm in names:
        if nm != "omega":
            model.value(nm)                       # names it or exits 2 with the valid names
    bounds = parse_bounds(args.bounds, names)
    a, b = args.omega_min, args.omega_max
    if not (math.isfinite(a) and math.isfinite(b) and 0 < a < b):
        raise ParameterError("--omega-min/--omega-max", (a, b), "finite 0 < A < B")
    if args.plot and not args.plot.lower().endswith((".png", ".pdf")):
        raise ParameterError("--plot", args.plot, "a file name ending in .png or .pdf")
    if not 2 <= args.max_points <= 10 ** 6:
        raise ParameterError("--max-points", args.max_points, "an integer from 2 to 1000000")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        curve, start = curve_from_interval(model, a, b, names, kind=args.kind,
                                           index=args.index, bounds=bounds or None,
                                           max_points=args.max_points, through=args.through)
    if args.plot:
        from ..reporting import figures
        fig = figures.two_parameter([curve.plot_data()], names,
                                    title=f"{describe(model)}  ({args.kind} curve)")
        figures.save(fig, args.plot)
    if args.json:
        out = curve.as_dict()
        out["start"] = {"omega": start.value, "kind": start.kind,
                        "orbit": f"{start.orbit.n}-{start.orbit.p}"}
        if args.plot:
            out["plot"] = args.plot
        print_json(out)
        return 0
    print(f"model: {describe(model)}   {args.kind} curve in ({', '.join(names)}), started at "
          f"the {start.kind} point omega = {start.value:.12g} ({start.orbit.n}-"
          f"{start.orbit.p} orbit)")
    print(f"{len(curve)} points; ends: {curve.ends[0]}  |  {curve.ends[-1]}")
    for note in curve.notes:
        print(f"note: {note}")
    for sp in curve.special:
        where = ", ".join(f"{k} = {v:.12g}" for k, v in sp.params.items())
        print_special(sp.kind, where, sp.coefficients, sp.detail, sp.orbit, 9)
    if args.plot:
        print(f"plot: {args.plot}")
    return 0
