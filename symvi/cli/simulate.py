"""``symvi simulate``: iterate the Poincaré map and save the section (npz), optionally a plot."""
from . import add_params, data_key, describe, params_from, print_json, section_view


def register(sub):
    p = sub.add_parser("simulate", help="simulate impacts and save the Poincaré section, eq. (31)")
    add_params(p, model=True)
    p.add_argument("--omega", type=float, required=True, help="forcing frequency (> 0)")
    p.add_argument("--impacts", type=int, default=5000, help="section points to store")
    p.add_argument("--transient", type=int, default=0, help="impacts dropped first")
    p.add_argument("--y0", type=float, nargs="+", metavar="Y",
                   help="start point: X1DOT X2 X2DOT TAU for the preset, the 2N section "
                        "coordinates for --model (default: the period-1 orbit, slightly "
                        "perturbed)")
    p.add_argument("--out", required=True, help="output .npz with arrays section (n,4) and t")
    p.add_argument("--plot", help="also draw projected sections to this .png/.pdf")
    p.add_argument("--classify", action="store_true",
                   help="report the attractor class and Lyapunov exponents")
    return p


def run(args):
    import numpy as np

    from .._io import atomic_path
    from ..errors import ParameterError
    from ..simulations.simulation import simulate
    params = params_from(args)
    for name in ("out", "plot"):
        path = getattr(args, name)
        if path is not None and not path.strip():
            raise ParameterError(f"--{name}", path, "a file name")
    if args.plot and not args.plot.lower().endswith((".png", ".pdf")):
        raise ParameterError("--plot", args.plot, "a file name ending in .png or .pdf")
    labels, projections, names = section_view(params)
    if args.y0 is not None and len(args.y0) != len(names):
        raise ParameterError("--y0", args.y0, f"{len(names)} numbers: {' '.join(names)}")
    sim = simulate(params, args.omega, y0=args.y0, n_impacts=args.impacts,
                   transient=args.transient)
    with atomic_path(args.out, suffix=".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, section=sim.section, t=sim.t, impact_velocity=sim.impact_velocity,
                     y0=np.array(sim.y0), omega=sim.omega,
                     stop=sim.stop, names=np.array(names), **data_key(params))
    out = {"omega": sim.omega, "n": sim.n, "stop": sim.stop, "y0": list(sim.y0),
           "transient": sim.transient, "out": args.out}
    if args.classify and sim.n >= 3:
        from ..simulations.diagnostics import classify
        cl = classify(sim)
        out["class"] = cl.kind
        if cl.lyapunov is not None:
            out["lyapunov"] = [float(v) for v in cl.lyapunov.exponents]
        if cl.rotation is not None:
            out["rotation_number"] = cl.rotation
    if args.plot:
        from ..reporting import figures
        title = f"{describe(params)}  omega={sim.omega:g}  ({sim.n} impacts, {sim.stop})"
        figures.save(figures.sections(sim.section, title, sim.fixed_point, projections,
                                      labels=labels), args.plot)
        out["plot"] = args.plot
    print_json(out)
    return 0
