"""``symvi regenerate``: run the SymPy derivations and write generated/.

Plain ``symvi regenerate`` writes (and ``--check`` checks) the whole shipped set;
``--order K`` stops at order K (``--order 3``: the ordinary jobs only); ``--model FILE``
generates the structure of that model's N instead, orders 1..K (default 3), each order
where the loader looks for it (generated/ when shipped, else the per-user cache, unless
``--out`` is given).  Which derivation writes what where, and the per-user cache's own
check: :mod:`symvi.codegen.regenerate`.
"""
import os
import sys

from ..errors import ParameterError


def register(sub):
    p = sub.add_parser("regenerate", help="derive the map's jets with SymPy and write generated/")
    p.add_argument("--order", type=int, default=None, choices=(1, 2, 3, 4, 5),
                   help="highest order to generate (default: the shipped set, orders 1-3 "
                        "of the paper and N = 1..4, orders 4-5 of N = 1, 2; "
                        "with --model, 3)")
    p.add_argument("--check", action="store_true",
                   help="exit 1 if generated/ is stale, write nothing")
    p.add_argument("--force", action="store_true", help="regenerate even if the hash is unchanged")
    p.add_argument("--out", default=None, help="target folder (default: symvi's generated/)")
    p.add_argument("--model", default=None, metavar="FILE",
                   help="generate the N-mass structure of this model file only")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..codegen.regenerate import generate, jobs, stale
    todo = jobs(order=args.order, model=args.model, out=args.out)   # reads --model only
    if args.out is not None:
        from .._io import check_output
        check_output(args.out, flag="--out", folder=True)
        if args.check and not os.path.isdir(args.out):
            raise ParameterError("--out", args.out, "an existing folder of generated code "
                                 "(with --check)")
    where = ", ".join(sorted({str(job.folder) for job in todo}))
    if args.check:
        why = stale(todo)
        if args.json:
            from . import print_json
            print_json({"folders": sorted({str(job.folder) for job in todo}),
                        "fresh": not why, "stale": list(why)})
            return 1 if why else 0
        if why:
            for w in why:
                print(f"stale: {w}", file=sys.stderr)
            print(f"{where} is stale; run `symvi regenerate`", file=sys.stderr)
            return 1
        print(f"{where} is fresh")
        return 0
    done = generate(todo, force=args.force)
    if args.json:
        from . import print_json
        print_json({"jobs": [{"name": g.job.name, "folder": str(g.job.folder),
                              "orders": list(g.job.orders), "written": list(g.written),
                              "seconds": round(g.seconds, 3),
                              "input_hash": g.manifest["input_hash"]} for g in done]})
        return 0
    for g in done:
        name, o, orders = g.job.name, g.job.folder, g.job.orders
        if g.written:
            print(f"{name}: wrote {g.written if name == 'impact' else list(orders)} to {o} in "
                  f"{g.seconds:.1f} s (input hash {g.manifest['input_hash'][:12]})")
        else:
            print(f"{name} (orders {min(orders)}-{max(orders)}): {o} is up to date "
                  "(input hash unchanged); nothing written")
    return 0
