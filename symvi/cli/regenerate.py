"""``symvi regenerate``: run the SymPy derivations and write generated/.

Two derivations write generated/: the paper's map (``order<K>.py``,
derivations/poincare_jets.py) and the N-mass structures
(``impact_n<N>_order<K>.py``, derivations/impact_jets.py, N = 1..4 shipped).
``--model FILE`` generates the structure of that model's N instead (into the
per-user cache when N is not shipped, unless ``--out`` is given).
"""
import sys
import time
from pathlib import Path


def register(sub):
    p = sub.add_parser("regenerate", help="derive the map's jets with SymPy and write generated/")
    p.add_argument("--order", type=int, default=3, choices=(1, 2, 3),
                   help="highest order to generate (default 3)")
    p.add_argument("--check", action="store_true",
                   help="exit 1 if generated/ is stale, write nothing")
    p.add_argument("--force", action="store_true", help="regenerate even if the hash is unchanged")
    p.add_argument("--out", default=None, help="target folder (default: symvi's generated/)")
    p.add_argument("--model", default=None, metavar="FILE",
                   help="generate the N-mass structure of this model file only")
    return p


def target_dir(out):
    if out:
        return Path(out)
    import symvi._generated as g
    return Path(g.__file__).parent


def run(args):
    from symvi._derivations import impact_jets as ij
    from symvi._derivations import poincare_jets as pj
    orders = tuple(range(1, args.order + 1))
    if args.model:
        from ..codegen.layout import _user_dir
        from ..model import load_model
        n = load_model(args.model).n
        ns = (n,)
        out = Path(args.out) if args.out else (target_dir(None) if n in ij.NS_SHIPPED
                                               else _user_dir())
        jobs = [("impact", ij, out, dict(ns=ns, orders=orders))]
    else:
        out = target_dir(args.out)
        jobs = [("paper", pj, out, dict(orders=orders)),
                ("impact", ij, out, dict(ns=ij.NS_SHIPPED, orders=orders))]
    if args.check:
        why = [w for _, mod, o, kw in jobs for w in mod.check(o, **kw)]
        if why:
            for w in why:
                print(f"stale: {w}", file=sys.stderr)
            print(f"{out} is stale; run `symvi regenerate`", file=sys.stderr)
            return 1
        print(f"{out} is fresh")
        return 0
    for name, mod, o, kw in jobs:
        t0 = time.perf_counter()
        wrote, man = mod.generate(o, force=args.force, **kw)
        dt = time.perf_counter() - t0
        if wrote:
            print(f"{name}: wrote {wrote if name == 'impact' else list(orders)} to {o} in "
                  f"{dt:.1f} s (input hash {man['input_hash'][:12]})")
        else:
            print(f"{name}: {o} is up to date (input hash unchanged); nothing written")
    return 0
