"""``symvi continue``: continue n-p orbits in any named parameter, with fold, flip, NS and
grazing points located (module named ``continuation``: ``continue`` is a Python keyword)."""
import argparse

from . import NAMED, add_params, describe, old_range, params_from, print_json, print_special


def register(sub):
    p = sub.add_parser("continue", help="continue periodic orbits in a parameter; locate fold, "
                                        "flip, Neimark-Sacker and grazing points")
    add_params(p, model=True)
    p.add_argument("--range", metavar="NAME=A:B",
                   help="the continued parameter and its span: omega or a named parameter of "
                        f"the model ({NAMED}; mu_m, mu_k, f2, b, r for the preset), from A "
                        "to B (either order: the branch starts at A and stays in [A, B])")
    p.add_argument("--param", help=argparse.SUPPRESS)       # deprecated forms of --range
    p.add_argument("--from", dest="start", type=float, help=argparse.SUPPRESS)
    p.add_argument("--to", dest="stop", type=float, help=argparse.SUPPRESS)
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="fix another parameter (omega included when --range is another)")
    p.add_argument("--orbit", default="1-1", metavar="n-p",
                   help="p impacts in n forcing periods (default 1-1)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--start-omega", type=float, metavar="W",
                   help="with --range omega=A:B: start at W inside [A, B] and continue both "
                        "ways")
    g.add_argument("--from-section", metavar="FILE.npz",
                   help="start from the orbit a simulation (symvi simulate --out) settled on")
    p.add_argument("--switch", action="store_true",
                   help="also follow the period-doubled branch born at each flip point")
    p.add_argument("--through", action="store_true",
                   help="follow branches on where their orbits are not admissible (by default "
                        "a branch ends at its grazing point)")
    p.add_argument("--max-points", type=int, default=5000, help="points per branch")
    p.add_argument("--digits", type=int, default=None,
                   help="re-derive each fold, flip and NS point with the independent mpmath "
                        "chain at this many digits (30..200; rigid and elastic stops, with "
                        "or without nonlinear forces; seconds to minutes per point): the "
                        "orbit, the critical multiplier and c or l1")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="draw the branches (.png or .pdf)")
    return p


#: how the library's arguments are called on this command line (its error messages; the
#: range's by the form given, :func:`symvi.cli.old_range`)
FLAGS = {"orbit": "--orbit", "start_omega": "--start-omega", "simulation": "--from-section",
         "max_points": "--max-points", "fixed": "--set", "omega": "--set omega"}
#: the deprecated form of --range NAME=A:B (one release)
OLD_RANGE = {"name": ("param", "--param"), "lo": ("start", "--from"), "hi": ("stop", "--to")}


def _sets(items, model):
    """{name: value} of the ``--set NAME=VALUE`` items: known names, each once, finite
    values, together a valid model."""
    import math

    from ..errors import ParameterError
    out, pars = {}, {}
    for item in items:
        name, eq, val = item.partition("=")
        name = name.strip()
        try:
            v = float(val)
        except ValueError:
            eq = ""
        if not eq or not name:
            raise ParameterError("--set", item, "NAME=VALUE with a number VALUE")
        if not math.isfinite(v):
            raise ParameterError("--set", item, "NAME=VALUE with a finite number VALUE")
        if name in out:
            raise ParameterError("--set", item, f"each name once ({name} is set twice)")
        pars[name] = _known(model, name, "--set")
        out[name] = v
    others = {k: v for k, v in out.items() if not pars[k].is_forcing_frequency}
    try:
        model.with_(**others)
    except ParameterError as exc:
        raise ParameterError("--set", " ".join(items), exc.valid,
                             f"the model's {exc.name}") from None
    return out


def _known(model, name, flag):
    """The parameter called ``name`` (omega included); refuse a name that is not a
    parameter of ``model``, naming ``flag``."""
    from ..errors import ParameterError
    try:
        return model.parameter(name)
    except ParameterError as exc:
        raise ParameterError(flag, name, exc.valid) from None


def run(args):
    from .._io import FIGURE_SUFFIXES, check_output
    from ..continuation import continue_orbits
    from ..errors import ParameterError
    from ..model import Model
    span, flags = old_range(args, "--range", OLD_RANGE, ordered=False)
    model = Model.of(params_from(args))
    fixed = _sets(args.sets, model)
    check_output(args.plot, flag="--plot", suffixes=FIGURE_SUFFIXES)
    if args.digits is not None and not 30 <= args.digits <= 200:
        raise ParameterError("--digits", args.digits, "an integer from 30 to 200")
    param = span.name
    spelled = dict(FLAGS, param=flags["name"], start=flags["lo"], stop=flags["hi"])
    from ..progress import counting
    with counting(f"continuing in {param}"):
        branches = continue_orbits(model, param, span.lo, span.hi, orbit=args.orbit,
                                   start_omega=args.start_omega,
                                   simulation=args.from_section, switch=args.switch,
                                   through=args.through, max_points=args.max_points,
                                   names=spelled, **fixed)
    if args.plot:
        from ..reporting import figures
        names = branches[0].points[0].orbit.names
        fig = figures.branches([b.curve(0) for b in branches], param, ylabel=names[0],
                               title=f"{describe(model)}  ({param} continuation)")
        figures.save(fig, args.plot)
    checks = [()] * len(branches)
    if args.digits is not None:
        from ..studies.nonlinear_check import check_branches
        with counting(f"checking the special points at {args.digits} digits"):
            checks = check_branches(branches, args.digits)
    if args.json:
        print_json(_as_json(param, branches, args.plot, checks))
        return 0
    print(f"model: {describe(model)}   {param} from {span.lo:g} to {span.hi:g}")
    for k, br in enumerate(branches):
        o = br.points[0].orbit
        sticking = hasattr(o, "hold")
        sig = "" if sticking or o.signature is None or not (
            len(model.constraints) > 1 or model.elastic) else \
            " (signature " + ", ".join(o.signature_names) + (
                "" if o.symmetric is None else
                ", symmetric" if br.points[len(br) // 2].orbit.symmetric else ", asymmetric") + ")"
        # an orbit with a sticking phase names itself (n-j+stick: its StickingSignature)
        kind = str(o.signature) if sticking else f"{br.n}-{br.p}"
        print(f"\nbranch {k + 1}: {kind} orbits{sig}, {len(br)} points, {param} in "
              f"[{br.values.min():.10g}, {br.values.max():.10g}]; end: {br.end}")
        for note in br.notes:
            print(f"  note: {note}")
        for j, sp in enumerate(br.special):
            print_special(sp.kind, f"{param} = {sp.value:.15g}", sp.coefficients,
                          sp.detail, sp.orbit, 13)
            if checks[k]:
                print(" " * 16 + checks[k][j].text())
    if args.plot:
        print(f"\nplot: {args.plot}")
    return 0


def _as_json(param, branches, plot, checks=None):
    points, special = [], []
    for k, br in enumerate(branches):
        for pt in br.points:
            d = pt.as_dict()
            d["branch"] = k
            points.append(d)
        for j, sp in enumerate(br.special):
            d = sp.as_dict()
            d["branch"] = k
            if checks and checks[k]:
                d["chain"] = checks[k][j].as_dict()
            special.append(d)
    out = {"param": param, "points": points, "special": special,
           "branches": [{"orbit": f"{br.n}-{br.p}",
                         "signature": br.points[0].orbit.signature_names,
                         "points": len(br), "end": br.end,
                         "notes": list(br.notes)} for br in branches]}
    if plot:
        out["plot"] = plot
    return out
