"""``symvi regenerate``: run the SymPy derivation and write generated/."""
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
    return p


def target_dir(out):
    if out:
        return Path(out)
    import symvi._generated as g
    return Path(g.__file__).parent


def run(args):
    from symvi._derivations import poincare_jets as pj
    out = target_dir(args.out)
    orders = tuple(range(1, args.order + 1))
    if args.check:
        why = pj.check(out, orders)
        if why:
            for w in why:
                print(f"stale: {w}", file=sys.stderr)
            print(f"{out} is stale; run `symvi regenerate`", file=sys.stderr)
            return 1
        print(f"{out} is fresh")
        return 0
    t0 = time.perf_counter()
    wrote, man = pj.generate(out, orders, force=args.force)
    dt = time.perf_counter() - t0
    if wrote:
        print(f"wrote orders {list(orders)} to {out} in {dt:.1f} s (input hash {man['input_hash'][:12]})")
    else:
        print(f"{out} is up to date (input hash unchanged); nothing written")
    return 0
