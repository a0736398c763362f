"""``symvi plot``: draw a plane store (``symvi plane``) with the bifurcation curves over it."""
from . import deprecated, print_json


def register(sub):
    p = sub.add_parser("plot", help="draw a parameter plane (attractor and Lyapunov maps, "
                                    "with the NS, flip and fold curves over them)")
    p.add_argument("store", metavar="PLANE.zarr", help="a store written by symvi plane")
    p.add_argument("--plot", metavar="FIG.png", help="figure (.png or .pdf)")
    p.add_argument("--out", metavar="FIG.png", help="deprecated spelling of --plot (the one "
                   "figure flag of every command); kept for one release")
    p.add_argument("--no-curves", action="store_true",
                   help="do not continue and draw the two-parameter curves")
    p.add_argument("--json", action="store_true", help="print one JSON summary on stdout")
    return p


def run(args):
    import os

    from .._io import FIGURE_SUFFIXES, check_output
    from ..errors import ParameterError
    from ..plane import PlaneStore
    from ..reporting import figures
    if args.plot is None and args.out is None:
        raise ParameterError("--plot", None, "a figure file (.png or .pdf)")
    if args.plot is not None and args.out is not None:
        raise ParameterError("--out", args.out, "not with --plot (its old spelling)")
    flag = "--plot" if args.plot is not None else "--out"
    if args.out is not None:
        args.plot = args.out
    check_output(args.plot, flag=flag, suffixes=FIGURE_SUFFIXES)
    st = PlaneStore.read(args.store)
    ds = st.dataset()
    done = int(ds["done"].sum())
    curves, notes = [], []
    spec = st.spec
    if not args.no_curves:
        from ..curves import curves_of_plane
        from ..progress import counting
        with counting("curves over the plane"):
            curves, notes = curves_of_plane(spec)
    title = os.path.basename(os.path.normpath(args.store))
    if done < spec.y.n:
        title += f" (incomplete: {done} of {spec.y.n} rows)"
    figures.save(figures.plane_maps(ds, curves, title=title), args.plot)
    out = {"store": args.store, "plot": args.plot, "out": args.plot, "rows_done": done,
           "rows": spec.y.n,
           "curves": [{"kind": c["kind"], "points": len(c["a"]),
                       "special": [s[0] for s in c["special"]]} for c in curves],
           "notes": notes}
    if args.json:
        print_json(out)
    else:
        print(f"{args.plot}: {len(curves)} curves over {args.store}")
        for n in notes:
            print(f"  note: {n}")
    if flag == "--out":
        deprecated(args, "symvi plot --out is deprecated: the figure flag of every command is "
                         "--plot")
    return 0
