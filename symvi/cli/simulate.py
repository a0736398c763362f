"""``symvi simulate``: iterate the Poincaré map and save the section (npz), optionally a plot."""
from . import (add_params, data_key, deprecated, describe, params_from, print_json, save_npz,
               section_view, wants_json)

#: kept impacts below which --classify refuses (symvi.simulations.diagnostics.MIN_CLASSIFY;
#: from symvi.numerics, so that registering the command imports nothing heavy)
from ..numerics.tolerances import MIN_CLASSIFY


def register(sub):
    p = sub.add_parser("simulate", help="simulate impacts and save the Poincaré section, eq. (31)")
    add_params(p, model=True)
    p.add_argument("--omega", type=float, required=True, help="forcing frequency (> 0)")
    p.add_argument("--impacts", type=int, default=5000,
                   help=f"section points to store (with --classify at least {MIN_CLASSIFY})")
    p.add_argument("--transient", type=int, default=0, help="impacts dropped first")
    p.add_argument("--y0", type=float, nargs="+", metavar="Y",
                   help="start point: X1DOT X2 X2DOT TAU for the preset, the 2N section "
                        "coordinates for --model (default: the period-1 orbit, slightly "
                        "perturbed)")
    p.add_argument("--out", required=True,
                   help="output .npz with arrays section (n,4) and t (other names than "
                        "*.npz are deprecated)")
    p.add_argument("--plot", help="also draw projected sections to this .png/.pdf")
    p.add_argument("--classify", action="store_true",
                   help="report the attractor class and Lyapunov exponents")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..errors import ParameterError
    from ..simulations.simulation import MAX_STORED, MAX_TRANSIENT, simulate
    check_paths(args)
    lo = MIN_CLASSIFY if args.classify else 1
    if not lo <= args.impacts <= MAX_STORED:
        raise ParameterError("--impacts", args.impacts, f"an integer in {lo} .. {MAX_STORED}"
                             + (" with --classify" if args.classify else ""),
                             f"too few impacts to classify (need >= {lo})"
                             if args.classify and args.impacts < lo else "")
    if not 0 <= args.transient <= MAX_TRANSIENT:
        raise ParameterError("--transient", args.transient, f"an integer in 0 .. {MAX_TRANSIENT}")
    params = params_from(args)
    labels, projections, names = section_view(params)
    if args.y0 is not None and len(args.y0) != len(names):
        raise ParameterError("--y0", args.y0, f"{len(names)} numbers: {' '.join(names)}")
    if not args.out.lower().endswith(".npz"):
        deprecated(args, f"--out {args.out!r}: an output name not ending in .npz is deprecated "
                         "and will be refused by a future version")
    try:
        sim = simulate(params, args.omega, y0=args.y0, n_impacts=args.impacts,
                       transient=args.transient)
    except ParameterError as exc:
        raise exc.renamed({"y0": "--y0", "omega": "--omega"}) from None
    several = sim.stops > 1
    # with several stops each point lies on the section of the stop it hit: "hits"
    extra = {"hits": sim.hits} if several else {}
    if sim.sticks is not None and len(sim.sticks):
        # the sticking phases (t_stick, t_release, stop 0-based) and each impact's stop:
        # what symvi continue --from-section reads to solve the sticking orbit
        extra.update(sticks=sim.sticks, hits=sim.hits)
    save_npz(args.out, section=sim.section, t=sim.t, impact_velocity=sim.impact_velocity,
             y0=sim.y0, omega=sim.omega, stop=sim.stop, names=names, **extra,
             **data_key(params))
    out = {"omega": sim.omega, "n": sim.n, "stop": sim.stop, "y0": list(sim.y0),
           "transient": sim.transient, "out": args.out}
    if several:
        out["impacts_per_stop"] = sim.impacts_per_stop()
    if sim.sticks is not None and len(sim.sticks):
        # complete chatter and sticking went through: each phase (t_stick, t_release, stop)
        out["sticks"] = [[float(a), float(b), int(k) + 1] for a, b, k in sim.sticks]
    if sim.stop_reason:
        out["stop_reason"] = sim.stop_reason
    if args.classify:
        from ..simulations.diagnostics import classify
        cl = classify(sim)
        out["class"] = cl.kind
        if cl.code is not None:
            # the same class in the plane's vocabulary (symvi.simulations.classifier)
            out["attractor"] = cl.label
            if cl.impacts is not None:
                out["impacts_per_orbit"] = cl.impacts
            if cl.signature is not None:
                out["signature"] = cl.signature_names
            if "sticks" in out:
                # the attractor holds sticking phases (its label stays period-k, as the
                # plane's)
                out["sticking"] = True
        # null only where the run stopped or was too short (the class says which)
        out["lyapunov"] = (None if cl.lyapunov is None
                           else [float(v) for v in cl.lyapunov.exponents])
        if cl.rotation is not None:
            out["rotation_number"] = cl.rotation
    if args.plot:
        from ..reporting import figures
        title = f"{describe(params)}  omega={sim.omega:g}  ({sim.n} impacts, {sim.stop})"
        # one section in one figure: with several stops, the points on the first stop's
        points = sim.on_stop(0) if several else sim.section
        if several:
            title += f", the {len(points)} on stop 1"
        figures.save(figures.sections(points, title, sim.fixed_point, projections,
                                      labels=labels), args.plot)
        out["plot"] = args.plot
    if wants_json(args):
        print_json(out)
    else:
        _print_text(out, describe(params))
    return 0


def _print_text(out, system):
    """The run as a few lines of text (the JSON's keys, in words)."""
    print(f"model: {system}   omega = {out['omega']:.10g}")
    print(f"{out['n']} impacts kept after {out['transient']} dropped; run ended: {out['stop']}")
    if "impacts_per_stop" in out:
        print("impacts per stop: " + ", ".join(f"{k} {v}" for k, v in
                                                out["impacts_per_stop"].items()))
    if "sticks" in out:
        print(f"sticking phases: {len(out['sticks'])} (chatter accumulated, held, released)")
    if "stop_reason" in out:
        print(f"why the run stopped: {out['stop_reason']}")
    if "class" in out:
        line = f"attractor: {out.get('attractor', out['class'])}"
        if out.get("sticking"):
            line += " with sticking"
        if "impacts_per_orbit" in out:
            line += f", {out['impacts_per_orbit']} impacts per orbit"
        if "signature" in out:
            line += f" ({', '.join(out['signature'])})"
        print(line)
        if out["lyapunov"] is not None:
            print("Lyapunov exponents (per impact): "
                  + ", ".join(f"{v:.6g}" for v in out["lyapunov"]))
        if "rotation_number" in out:
            print(f"rotation number: {out['rotation_number']:.8g}")
    print("wrote: " + ", ".join(out[k] for k in ("out", "plot") if k in out))


def check_paths(args):
    """--out (a new or regular .npz file) and --plot (.png/.pdf), before any work."""
    from .._io import FIGURE_SUFFIXES, check_output, distinct_outputs
    from ..errors import ParameterError
    if args.out.lower().endswith(FIGURE_SUFFIXES):
        raise ParameterError("--out", args.out, "a data file name ending in .npz",
                             "a figure name: draw the figure with --plot")
    check_output(args.out, flag="--out")
    check_output(args.plot, flag="--plot", suffixes=FIGURE_SUFFIXES)
    distinct_outputs(("--out", args.out), ("--plot", args.plot))
