"""``symvi curve``: continue an NS, flip or fold curve in two parameters from the point of
that kind found in an omega interval, with its codimension-two points."""
import argparse

from . import (PRESET_NAMED, add_params, check_value, describe, old_range, params_from,
               parse_range, print_json, print_special)


def register(sub):
    p = sub.add_parser("curve", help="continue a Neimark-Sacker, flip or fold curve in two "
                                     "parameters; locate Chenciner, R1-R4, LPNS, PDNS points")
    add_params(p, model=True)
    p.add_argument("--range", metavar="omega=A:B",
                   help="the start point is the NS (flip, fold) point found in [A, B]")
    p.add_argument("--omega-min", type=float, help=argparse.SUPPRESS)   # deprecated forms
    p.add_argument("--omega-max", type=float, help=argparse.SUPPRESS)   # of --range
    p.add_argument("--params", required=True, metavar="omega,NAME",
                   help="the two curve parameters: omega and a named parameter of the model "
                        f"({PRESET_NAMED})")
    p.add_argument("--bounds", action="append", default=[], metavar="NAME=LO:HI",
                   help="range of a curve parameter (default: half to twice its start value)")
    p.add_argument("--kind", default="ns", choices=("ns", "flip", "fold", "grazing"),
                   help="the curve's bifurcation (default ns); grazing: an impact of the "
                        "orbit arriving with zero velocity")
    p.add_argument("--index", type=int, default=1, metavar="K",
                   help="start from the K-th point of that kind in [A, B], by omega (default 1)")
    p.add_argument("--max-points", type=int, default=2000,
                   help="points on each side of the start (default 2000)")
    p.add_argument("--through", action="store_true",
                   help="follow the curve on where its orbit is not admissible, past "
                        "grazing (an NS curve on a regular test), to its next admissible "
                        "piece; without it a curve ends where it grazes, at the located "
                        "codimension-two point")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="draw the two-parameter diagram")
    return p


def parse_bounds(items, names, model=None):
    """{name: (lo, hi)} of the ``--bounds NAME=LO:HI`` items: a curve parameter each, once,
    finite LO < HI inside the parameter's valid range (of ``model``, when given)."""
    from ..errors import ParameterError
    out = {}
    for item in items:
        name, lo, hi, _ = parse_range(item, "--bounds")    # the one range form
        if name not in names:
            raise ParameterError("--bounds", item, f"a bound of a curve parameter "
                                 f"({', '.join(names)})")
        if name in out:
            raise ParameterError("--bounds", item, f"one range per parameter ({name} has two)")
        if model is not None:
            for v in (lo, hi):
                try:
                    check_value(model, name, v, "--bounds", resonance=False)
                except ParameterError as exc:
                    raise ParameterError("--bounds", item, exc.valid,
                                         f"{name} = {v:g} is outside it") from None
        out[name] = (lo, hi)
    return out


#: the deprecated form of --range omega=A:B (one release)
OLD_RANGE = {"lo": ("omega_min", "--omega-min"), "hi": ("omega_max", "--omega-max")}


def run(args):
    import warnings

    from .._io import FIGURE_SUFFIXES, check_output
    from ..curves import curve_from_interval, curve_params
    from ..errors import NearSingularWarning, ParameterError
    from ..model import Model
    span, flags = old_range(args, "--range", OLD_RANGE, name="omega", names=("omega",))
    model = Model.of(params_from(args))
    names = curve_params(model, args.params)
    bounds = parse_bounds(args.bounds, names, model)
    a, b = span.lo, span.hi
    check_value(model, "omega", a, flags["lo"], resonance=False)
    check_value(model, "omega", b, flags["hi"], resonance=False)
    if not a < b:
        raise ParameterError(flags["hi"], b, f"greater than {flags['lo']} = {a:g}")
    if args.index < 1:
        raise ParameterError("--index", args.index, "an integer >= 1")
    check_output(args.plot, flag="--plot", suffixes=FIGURE_SUFFIXES)
    if not 2 <= args.max_points <= 10 ** 6:
        raise ParameterError("--max-points", args.max_points, "an integer from 2 to 1000000")
    from ..progress import counting
    with warnings.catch_warnings(), counting(f"{args.kind} curve"):
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            curve, start = curve_from_interval(model, a, b, names, kind=args.kind,
                                               index=args.index, bounds=bounds or None,
                                               max_points=args.max_points,
                                               through=args.through)
        except ParameterError as exc:
            # the library names its arguments; name the flags the user gave
            flag = {"index": "--index", "kind": "--kind"}.get(exc.name) or (
                "--bounds" if str(exc.name).startswith("bounds") else None)
            if flag is None:
                raise
            value = exc.value
            if flag == "--bounds" and isinstance(value, tuple) and len(value) == 2:
                value = f"{exc.name[7:-1]}={value[0]:g}:{value[1]:g}"
            raise ParameterError(flag, value, exc.valid) from None
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
    if args.kind == "grazing":
        d = curve.as_dict()
        print(f"grazing: impact {d['impact']} arrives with zero velocity" if "impact" in d
              else f"grazing: flight {d['flight']} touches the stop inside it (followed as "
                   "an impact at zero velocity inserted there)")
    for note in curve.notes:
        print(f"note: {note}")
    for sp in curve.special:
        where = ", ".join(f"{k} = {v:.12g}" for k, v in sp.params.items())
        print_special(sp.kind, where, sp.coefficients, sp.detail, sp.orbit, 9)
    if args.plot:
        print(f"plot: {args.plot}")
    return 0
