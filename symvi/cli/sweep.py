"""``symvi sweep``: a bifurcation diagram over omega from parallel simulations."""
from . import add_engine, add_params, data_key, describe, params_from, print_json, section_view


def register(sub):
    p = sub.add_parser("sweep", help="bifurcation diagram over omega (parallel simulations)")
    add_params(p, model=True)
    p.add_argument("--omega-min", type=float, required=True)
    p.add_argument("--omega-max", type=float, required=True)
    p.add_argument("--steps", type=int, required=True, help="number of omega values (>= 2)")
    p.add_argument("--impacts", type=int, default=200, help="section points kept per omega")
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
    add_engine(p, "default: 0, on numba threads")
    p.add_argument("--progress", choices=("auto", "always", "never"), default="auto",
                   help="progress bar on stderr (auto: when stderr is a terminal)")
    return p


def run(args):
    import numpy as np

    from .._io import atomic_path
    from ..errors import ParameterError
    from ..plane.engine import run_sweep
    params = params_from(args)
    from ..flow import check_omega
    labels, _, names = section_view(params)
    if not 0 <= args.component < len(names):
        raise ParameterError("--component", args.component,
                             f"0 .. {len(names) - 1} ({', '.join(names)})")
    check_omega(params, args.omega_min, "--omega-min", warn=False)
    check_omega(params, args.omega_max, "--omega-max", warn=False)
    if not args.steps >= 2:
        raise ParameterError("--steps", args.steps, "an integer >= 2")
    if not args.omega_min < args.omega_max:
        raise ParameterError("--omega-max", args.omega_max,
                             f"greater than --omega-min = {args.omega_min!r}")
    figs = [p for p in (args.out, args.plot) if p and p.lower().endswith((".png", ".pdf"))]
    data = args.out if args.out.lower().endswith(".npz") else None
    if args.plot and args.plot not in figs:
        raise ParameterError("--plot", args.plot, "a file name ending in .png or .pdf")
    if data is None and args.out not in figs:
        raise ParameterError("--out", args.out, "a file name ending in .npz, .png or .pdf")
    omegas = np.linspace(args.omega_min, args.omega_max, args.steps)
    enabled = {"auto": None, "always": True, "never": False}[args.progress]
    workers = 0 if args.workers is None and args.scheduler is None else args.workers
    res = run_sweep(params, omegas, n_impacts=args.impacts, transient=args.transient,
                    scheduler=args.scheduler, workers=workers, progress=enabled)
    if data:
        with atomic_path(data, suffix=".npz") as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, omegas=res.omegas, section=res.section, counts=res.counts,
                         stops=np.array(res.stops), starts=res.starts,
                         transient=res.transient, names=np.array(names), **data_key(params))
    curves, special = None, []
    if args.branches:
        from ..continuation import diagram_branches
        curves, special = diagram_branches(params, args.omega_min, args.omega_max,
                                           args.component)
    if figs:
        from ..reporting import figures
        title = describe(params)
        for path in figs:
            fig = figures.bifurcation_diagram(res.omegas, res.section, res.counts,
                                              component=args.component, title=title,
                                              labels=labels, curves=curves)
            figures.save(fig, path)
    stops = {s: res.stops.count(s) for s in sorted(set(res.stops))}
    out = {"steps": len(omegas), "omega_min": args.omega_min, "omega_max": args.omega_max,
           "impacts": args.impacts, "transient": args.transient, "stops": stops,
           "outputs": [p for p in (data, *figs) if p]}
    if args.branches:
        out["special"] = special
    print_json(out)
    return 0
