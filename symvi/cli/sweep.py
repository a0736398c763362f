"""``symvi sweep``: a bifurcation diagram over omega from parallel simulations."""
import argparse

from . import (add_engine, add_params, data_key, deprecated, describe, old_range, params_from,
               print_json, save_npz, section_view, wants_json)

#: most omega values of one sweep (each needs its period-1 start and a task's share)
MAX_STEPS = 100_000
#: the deprecated form of --range omega=A:B:N (one release)
OLD_RANGE = {"lo": ("omega_min", "--omega-min"), "hi": ("omega_max", "--omega-max"),
             "n": ("steps", "--steps")}
#: most stored section values (values x --impacts x 2N float64: 320 MB); the transient
#: is dropped as it runs and costs time only
MAX_VALUES = 40_000_000


def register(sub):
    p = sub.add_parser("sweep", help="bifurcation diagram over omega (parallel simulations)")
    add_params(p, model=True)
    p.add_argument("--range", metavar="omega=A:B:N",
                   help=f"N omega values from A to B (N in 2 .. {MAX_STEPS})")
    p.add_argument("--omega-min", type=float, help=argparse.SUPPRESS)   # deprecated forms
    p.add_argument("--omega-max", type=float, help=argparse.SUPPRESS)   # of --range
    p.add_argument("--steps", type=int, help=argparse.SUPPRESS)
    p.add_argument("--impacts", type=int, default=200,
                   help="section points kept per omega (values x --impacts x coordinates at most "
                        f"{MAX_VALUES:.0e} stored values)")
    p.add_argument("--transient", type=int, default=2000, help="impacts dropped per omega")
    p.add_argument("--component", type=int, default=0,
                   help="plotted section coordinate: 0 x1dot+, 1 x2, 2 x2dot, 3 tau for the "
                        "preset; 0 .. 2N-1 in the section order for --model")
    p.add_argument("--out", required=True,
                   help="output: .npz (omegas, section (m,n,4), counts, stops) or .png/.pdf")
    p.add_argument("--plot", help="also draw the diagram to this .png/.pdf")
    p.add_argument("--branches", action="store_true",
                   help="overlay the continued period-1 branches (stable solid, unstable "
                        "dashed), their period-doubled branches and special points")
    p.add_argument("--classify", action="store_true",
                   help="also label each omega's attractor with the one classifier of "
                        "symvi simulate --classify and the plane (period-k, circle, "
                        "doubled-torus, chaos, no-impact, sticking, escape, grazing): each "
                        "omega's run is repeated with its tangent map (same start, "
                        "--impacts >= 4 and --transient), in this process; the JSON gains "
                        "\"classes\" (one label per omega, in grid order) and "
                        "\"class_counts\", an .npz the array classes")
    add_engine(p, "default: 0, on numba threads")
    p.add_argument("--progress", choices=("auto", "always", "never"), default="auto",
                   help="progress bar on stderr (auto: when stderr is a terminal)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..errors import ParameterError
    from ..plane.engine import run_sweep
    from ..simulations.classifier import MIN_KEPT, min_kept
    from ..simulations.simulation import MAX_TRANSIENT, omega_grid, symbol_count
    span, flags = old_range(args, "--range", OLD_RANGE, name="omega", names=("omega",),
                            steps=True, most=MAX_STEPS)
    data, figs = check_paths(args)
    if not 2 <= span.n <= MAX_STEPS:
        raise ParameterError(flags["n"], span.n, f"an integer in 2 .. {MAX_STEPS}")
    params = params_from(args)
    labels, _, names = section_view(params)
    most = max(1, MAX_VALUES // (span.n * len(names)))
    if not 1 <= args.impacts <= most:
        raise ParameterError("--impacts", args.impacts, f"an integer in 1 .. {most}",
                             f"values x --impacts x {len(names)} coordinates <= {MAX_VALUES}"
                             if args.impacts > most else "")
    if not 0 <= args.transient <= MAX_TRANSIENT:
        raise ParameterError("--transient", args.transient, f"an integer in 0 .. {MAX_TRANSIENT}")
    if args.classify:
        from ..model import Model
        model = Model.of(params)
        least = min_kept(symbol_count(model))
        if args.impacts < least:
            per = " per stop" + (", entries and exits counted apart" if model.elastic else "")
            raise ParameterError("--impacts", args.impacts, f"an integer >= {least} with "
                                 "--classify" + (f" ({MIN_KEPT}{per})" if least > MIN_KEPT
                                                 else ""))
    if not 0 <= args.component < len(names):
        raise ParameterError("--component", args.component,
                             f"0 .. {len(names) - 1} ({', '.join(names)})")
    omegas = omega_grid(params, span.lo, span.hi, span.n,
                        names={"omega_min": flags["lo"], "omega_max": flags["hi"],
                               "steps": flags["n"]})
    enabled = {"auto": None, "always": True, "never": False}[args.progress]
    workers = 0 if args.workers is None and args.scheduler is None else args.workers
    res = run_sweep(params, omegas, n_impacts=args.impacts, transient=args.transient,
                    scheduler=args.scheduler, workers=workers, progress=enabled,
                    classify=args.classify)
    classes = res.labels()
    extra = {} if classes is None else {"classes": classes}
    if data:
        save_npz(data, omegas=res.omegas, section=res.section, counts=res.counts,
                 stops=res.stops, starts=res.starts, transient=res.transient, names=names,
                 **extra, **data_key(params))
    curves, special = None, []
    if args.branches:
        from ..continuation import diagram_branches
        curves, special = diagram_branches(params, span.lo, span.hi,
                                           args.component)
    if figs:
        from ..reporting import figures
        title = describe(params)
        fig = figures.bifurcation_diagram(res.omegas, res.section, res.counts,
                                          component=args.component, title=title,
                                          labels=labels, curves=curves)
        figures.save(fig, *figs)
    stops = {s: res.stops.count(s) for s in sorted(set(res.stops))}
    out = {"steps": len(omegas), "omega_min": span.lo, "omega_max": span.hi,
           "impacts": args.impacts, "transient": args.transient, "stops": stops,
           "outputs": [p for p in (data, *figs) if p]}
    if args.branches:
        out["special"] = special
    if classes is not None:
        out["classes"] = classes.tolist()
        out["class_counts"] = res.class_counts()
        if res.signatures() is not None:       # several stops: the stops of each orbit
            out["signatures"] = res.signatures()
    if wants_json(args):
        print_json(out)
    else:
        _print_text(out, describe(params))
    if not args.out.lower().endswith(".npz"):
        deprecated(args, "a figure given as --out is deprecated: --out is the data (.npz), "
                         "--plot the figure (the one figure flag of every command)")
    return 0


def _print_text(out, system):
    """The sweep as a few lines of text (the JSON's keys, in words)."""
    print(f"model: {system}   {out['steps']} omega values in [{out['omega_min']:.10g}, "
          f"{out['omega_max']:.10g}], {out['impacts']} impacts kept after "
          f"{out['transient']} dropped")
    print("runs ended: " + ", ".join(f"{k} {v}" for k, v in out["stops"].items()))
    if "class_counts" in out:
        print("attractors: " + ", ".join(f"{k} {v}" for k, v in
                                          sorted(out["class_counts"].items(),
                                                 key=lambda kv: -kv[1])))
    for sp in out.get("special", []):
        print(f"  {sp['kind']:8s} omega = {sp['value']:.12g}  ({sp['orbit']} orbit)")
    print("wrote: " + ", ".join(out["outputs"]))


def check_paths(args):
    """(data path or None, figure paths): --out is .npz, .png or .pdf, --plot a figure;
    both usable and distinct, checked before any work."""
    from .._io import FIGURE_SUFFIXES, check_output, distinct_outputs
    check_output(args.out, flag="--out", suffixes=(".npz", *FIGURE_SUFFIXES))
    check_output(args.plot, flag="--plot", suffixes=FIGURE_SUFFIXES)
    distinct_outputs(("--out", args.out), ("--plot", args.plot))
    data = args.out if args.out.lower().endswith(".npz") else None
    return data, [p for p in (args.out, args.plot)
                  if p and p.lower().endswith(FIGURE_SUFFIXES)]
