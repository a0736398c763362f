"""``symvi continue``: continue n-p orbits in any named parameter, with fold, flip, NS and
grazing points located (module named ``continuation``: ``continue`` is a Python keyword)."""
from . import add_params, check_value, describe, params_from, print_json, print_special


def register(sub):
    p = sub.add_parser("continue", help="continue periodic orbits in a parameter; locate fold, "
                                        "flip, Neimark-Sacker and grazing points")
    add_params(p, model=True)
    p.add_argument("--param", required=True, metavar="NAME",
                   help="the continued parameter: omega or a named parameter of the model "
                        "(gap, restitution, mass[i], stiffness[i,j], damping[i,j], "
                        "forcing[i]; mu_m, mu_k, f2, b, r for the preset)")
    p.add_argument("--from", dest="start", type=float, required=True, metavar="A",
                   help="start value of the parameter")
    p.add_argument("--to", dest="stop", type=float, required=True, metavar="B",
                   help="end value (the branch stays between A and B)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="fix another parameter (omega included when it is not --param)")
    p.add_argument("--orbit", default="1-1", metavar="n-p",
                   help="p impacts in n forcing periods (default 1-1)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--start-omega", type=float, metavar="W",
                   help="with --param omega: start at W inside [A, B] and continue both ways")
    g.add_argument("--from-section", metavar="FILE.npz",
                   help="start from the orbit a simulation (symvi simulate --out) settled on")
    p.add_argument("--switch", action="store_true",
                   help="also follow the period-doubled branch born at each flip point")
    p.add_argument("--through", action="store_true",
                   help="follow branches on where their orbits are not admissible (by default "
                        "a branch ends at its grazing point)")
    p.add_argument("--max-points", type=int, default=5000, help="points per branch")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="draw the branches (.png or .pdf)")
    return p


def _orbit_spec(text):
    from ..errors import ParameterError
    try:
        n, p = (int(v) for v in text.split("-"))
        ok = 1 <= n <= 64 and 1 <= p <= 64
    except (ValueError, AttributeError):
        ok = False
    if not ok:
        raise ParameterError("--orbit", text, "n-p with integers 1 <= n, p <= 64, e.g. 1-1, 2-2")
    return n, p


def _sets(items, model):
    """{name: value} of the ``--set NAME=VALUE`` items: known names, each once, finite values."""
    import math

    from ..errors import ParameterError
    out = {}
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
        if name != "omega":
            _known(model, name, "--set")
        out[name] = v
    return out


def _known(model, name, flag):
    """Refuse a name that is not a parameter of ``model``, naming ``flag``."""
    from ..errors import ParameterError
    try:
        model.value(name)
    except ParameterError as exc:
        raise ParameterError(flag, name, exc.valid) from None


def _section_start(path, model):
    """A simulation-like object (section, t, omega, params) from an npz of ``symvi simulate``."""
    import numpy as np

    from ..errors import ParameterError
    try:
        with np.load(path) as f:
            section, t, omega = f["section"], f["t"], float(f["omega"])
    except (OSError, KeyError, ValueError) as exc:
        raise ParameterError("--from-section", path, "an .npz written by symvi simulate --out "
                             "(arrays section, t, omega)", str(exc)) from None

    class _Sim:
        pass
    sim = _Sim()
    sim.section, sim.t, sim.omega, sim.params = section, t, omega, model
    return sim


def run(args):
    import warnings

    from .._io import check_output
    from ..continuation import continue_branch, same_branch, switch_at_flip
    from ..errors import NearSingularWarning, ParameterError
    from ..model import Model
    from ..orbits.periodic import detect_period
    model = Model.of(params_from(args))
    n, p = _orbit_spec(args.orbit)
    if args.param != "omega":
        _known(model, args.param, "--param")
    fixed = _sets(args.sets, model)
    if args.param in fixed:
        raise ParameterError("--set", args.param, "a parameter other than --param")
    check_output(args.plot, flag="--plot", suffixes=(".png", ".pdf"))
    if not 2 <= args.max_points <= 10 ** 6:
        raise ParameterError("--max-points", args.max_points, "an integer from 2 to 1000000")
    # the model with the --set values: the ranges of --from, --to are those of this model
    others = {k: v for k, v in fixed.items() if k != "omega"}
    try:
        at = model.with_(**others) if others else model
    except ParameterError as exc:
        raise ParameterError("--set", " ".join(args.sets), exc.valid,
                             f"the model's {exc.name}") from None
    if args.param != "omega" and "omega" not in fixed and not args.from_section:
        raise ParameterError("--set omega", None, "a fixed forcing frequency: give --set "
                             "omega=VALUE when --param is not omega")
    if "omega" in fixed:
        check_value(at, "omega", fixed["omega"], "--set omega")
    starts_here = args.start_omega is None and not args.from_section
    check_value(at, args.param, args.start, "--from", resonance=starts_here)
    check_value(at, args.param, args.stop, "--to", resonance=False)
    if args.start == args.stop:
        raise ParameterError("--to", args.stop, f"a value != --from = {args.start:g} (the "
                             "branch lies between them)")
    lo, hi = sorted((args.start, args.stop))
    if args.start_omega is not None:
        if args.param != "omega":
            raise ParameterError("--start-omega", args.start_omega, "only with --param omega "
                                 "(fix omega with --set omega=W otherwise)")
        if not lo <= args.start_omega <= hi:
            raise ParameterError("--start-omega", args.start_omega, f"a value in [{lo}, {hi}]")
        check_value(at, "omega", args.start_omega, "--start-omega")
        a, stops = args.start_omega, (lo, hi)
    else:
        a, stops = args.start, (args.stop,)
    guesses = [None]
    if args.from_section:
        sim = _section_start(args.from_section, model)
        if args.param == "omega":
            a = sim.omega
            stops = (lo, hi)
            if not lo <= a <= hi:
                raise ParameterError("--from-section", args.from_section,
                                     f"a simulation at omega in [{lo}, {hi}] (it has {a})")
        else:
            fixed.setdefault("omega", sim.omega)
        found = detect_period(sim)
        if found is None:
            raise ParameterError("--from-section", args.from_section, "a simulation settled on "
                                 "a periodic orbit (none of at most 16 impacts found)")
        if args.orbit != "1-1" and found != (n, p):
            raise ParameterError("--orbit", args.orbit, f"the simulated orbit's {found[0]}-"
                                 f"{found[1]}")
        n, p = found
        guesses = [sim.section[-p:]]
    else:
        # the model and omega at the start, with the --set values
        if args.param != "omega":
            at = at.with_(**{args.param: a})
        w = a if args.param == "omega" else fixed["omega"]
        if (n, p) != (1, 1):
            from ..simulations.simulation import simulate
            sim = simulate(at, w, n_impacts=400, transient=4000)
            if detect_period(sim) != (n, p):
                raise ParameterError("--orbit", args.orbit, f"an orbit the simulation at "
                                     f"{args.param} = {a} settles on (give --from-section)")
            guesses = [sim.section[-p:]]
        else:
            from ..orbits.period1 import admissible_orbits
            guesses = [o.y for o in admissible_orbits(at, w, multipliers=False)]
            if not guesses:
                from ..orbits.period1 import no_orbit_reason
                why = no_orbit_reason(at, w) or "every period-1 orbit there is inadmissible"
                raise ParameterError("--from", a, f"a value where an admissible period-1 "
                                     f"orbit exists", f"none at {args.param} = {a}: {why}")
    branches = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        for guess in guesses:
            for stop in stops:
                if stop == a:
                    continue
                br = continue_branch(model, args.param, a, stop, guess=guess, n=n, p=p,
                                     max_points=args.max_points, through=args.through,
                                     **fixed)
                if not any(same_branch(br, other) for other in branches):
                    branches.append(br)
        if args.switch:
            for br in list(branches):
                for sp in br.special:
                    if sp.kind == "flip":
                        try:
                            branches.append(switch_at_flip(br, sp, max_points=args.max_points,
                                                          through=args.through))
                        except Exception as exc:  # noqa: BLE001 - reported, not hidden
                            warnings.warn(f"branch switching at the flip at {sp.value:.12g} "
                                          f"failed: {exc}")
    if args.plot:
        from ..reporting import figures
        names = branches[0].points[0].orbit.names
        fig = figures.branches([b.curve(0) for b in branches], args.param, ylabel=names[0],
                               title=f"{describe(model)}  ({args.param} continuation)")
        figures.save(fig, args.plot)
    if args.json:
        print_json(_as_json(args.param, branches, args.plot))
        return 0
    print(f"model: {describe(model)}   {args.param} from {args.start:g} to {args.stop:g}")
    for k, br in enumerate(branches):
        print(f"\nbranch {k + 1}: {br.n}-{br.p} orbits, {len(br)} points, {args.param} in "
              f"[{br.values.min():.10g}, {br.values.max():.10g}]; end: {br.end}")
        for note in br.notes:
            print(f"  note: {note}")
        for sp in br.special:
            print_special(sp.kind, f"{args.param} = {sp.value:.15g}", sp.coefficients,
                          sp.detail, sp.orbit, 13)
    if args.plot:
        print(f"\nplot: {args.plot}")
    return 0


def _as_json(param, branches, plot):
    points, special = [], []
    for k, br in enumerate(branches):
        for pt in br.points:
            d = pt.as_dict()
            d["branch"] = k
            points.append(d)
        for sp in br.special:
            d = sp.as_dict()
            d["branch"] = k
            special.append(d)
    out = {"param": param, "points": points, "special": special,
           "branches": [{"orbit": f"{br.n}-{br.p}", "points": len(br), "end": br.end,
                         "notes": list(br.notes)} for br in branches]}
    if plot:
        out["plot"] = plot
    return out
