"""``symvi plane``: the attractor over a grid of two parameters, on Dask, into zarr."""
from . import PRESET_NAMED, add_engine, add_params, deprecated, params_from, print_json


def register(sub):
    p = sub.add_parser("plane", help="attractor, Lyapunov exponent, rotation number and "
                                     "impacts per period over a parameter plane (Dask, zarr)")
    add_params(p, model=True)
    p.add_argument("--x", required=True, metavar="NAME=LO:HI:N",
                   help=f"first axis: omega or a named parameter ({PRESET_NAMED}), N values "
                        "from LO to HI")
    p.add_argument("--y", required=True, metavar="NAME=LO:HI:N", help="second axis")
    p.add_argument("--omega", type=float, default=None,
                   help="forcing frequency, when neither axis is omega")
    p.add_argument("--impacts", type=int, required=True, metavar="K",
                   help="impacts kept per point (after the transient); with elastic stops "
                        "the records are impacts and contact entries, walked in Python "
                        "(about 0.3 ms an event: a slow plane)")
    p.add_argument("--transient", type=int, required=True, metavar="T",
                   help="impacts dropped per point")
    p.add_argument("--out", required=True, metavar="PLANE.zarr",
                   help="zarr store (a folder; names not ending in .zarr are deprecated); "
                        "an interrupted run restarted with the same command computes only "
                        "what is missing; a second run on the same store is refused while "
                        "the first holds PLANE.zarr.lock")
    add_engine(p, "default: the CPU count")
    p.add_argument("--follow", action="store_true",
                   help="start each point from the previous point's attractor along a row")
    p.add_argument("--chunk-rows", type=int, default=None, metavar="R",
                   help="rows per task and zarr chunk (default: about 1024 points)")
    p.add_argument("--progress", choices=("auto", "always", "never"), default="auto",
                   help="progress bar on stderr (auto: when stderr is a terminal)")
    p.add_argument("--json", action="store_true", help="print one JSON summary on stdout")
    return p


def run(args):
    import shlex

    from .._io import check_output
    from ..model import Model
    from ..plane import PlaneSpec, PlaneStore, parse_axis, run_plane
    check_output(args.out, flag="--out", folder=True)
    model = Model.of(params_from(args))
    spec = PlaneSpec(model=model, x=parse_axis(args.x, "--x"), y=parse_axis(args.y, "--y"),
                     impacts=args.impacts, transient=args.transient, follow=args.follow,
                     omega=args.omega, chunk_rows=args.chunk_rows)
    old = [f for f, t in (("--x", args.x), ("--y", args.y)) if "=" not in t]
    if old:
        deprecated(args, f"{' '.join(old)} NAME:LO:HI:N is deprecated: give NAME=LO:HI:N "
                         "(the one form of a range on every command)")
    enabled = {"auto": None, "always": True, "never": False}[args.progress]
    command = "symvi " + " ".join(shlex.quote(a) for a in args._argv)
    store = PlaneStore(args.out, spec)
    with store.lock():
        if not store.path.lower().endswith(".zarr"):
            deprecated(args, f"--out {args.out!r}: a plane store name not ending in .zarr is "
                             "deprecated and will be refused by a future version")
        res = run_plane(spec, store.path, scheduler=args.scheduler, workers=args.workers,
                        progress=enabled, command=command)
    out = res.as_dict()
    if args.json:
        print_json(out)
    else:
        print(f"{out['points']} points ({spec.y.n} x {spec.x.n}) in {store.path}: "
              f"{out['computed_blocks']} blocks computed, {out['resumed_blocks']} already "
              f"there; {out['seconds']:.1f} s on {out['workers']} workers")
        for k, v in sorted(out["attractors"].items(), key=lambda kv: -kv[1]):
            print(f"  {k:14s} {v}")
    return 0
