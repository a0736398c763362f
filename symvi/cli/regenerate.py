"""``symvi regenerate``: run the SymPy derivations and write generated/.

Two derivations write generated/: the paper's map (``order<K>.py``,
derivations/poincare_jets.py) and the N-mass structures
(``impact_n<N>_order<K>.py``, derivations/impact_jets.py).  Plain
``symvi regenerate`` writes (and ``--check`` checks) the whole shipped set:
orders 1-3 of the paper's map and of N = 1..4, and orders 4-5 of N = 1, 2 (the
state derivatives for l2, issue 13).  ``--order K`` stops at order K
(``--order 3``: the ordinary jobs only).  ``--model FILE`` generates the
structure of that model's N instead, orders 1..K (default 3), each order where
the loader looks for it: generated/ when shipped, else the per-user cache
(unless ``--out`` is given).  The per-user cache is created private and checked
(:mod:`symvi.codegen._usercache`); there ``--check`` runs the derivation again and
compares each module's text with it, never trusting the manifest in that folder.
"""
import os
import sys
import time
from pathlib import Path

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
    return p


def target_dir(out):
    if out:
        return Path(out)
    import symvi._generated as g
    return Path(g.__file__).parent


def jobs_of(args):
    """[(name, derivation module, folder, keyword arguments of generate/check)]."""
    from symvi._derivations import impact_jets as ij
    from symvi._derivations import poincare_jets as pj
    top = args.order or (3 if args.model else max(ij.HIGH_ORDERS))
    low = tuple(K for K in ij.ORDERS if K <= top)
    high = tuple(K for K in ij.HIGH_ORDERS if K <= top)
    if args.model:
        from ..codegen.layout import _user_dir
        from ..model import load_model
        n = load_model(args.model).n
        groups = {}
        for K in low + high:
            o = Path(args.out) if args.out else (target_dir(None) if ij.shipped(n, K)
                                                 else _user_dir())
            groups.setdefault(o, []).append(K)
        return [("impact", _UserCache if o == _user_dir() and not args.out else ij, o,
                 dict(ns=(n,), orders=tuple(ks))) for o, ks in groups.items()]
    out = target_dir(args.out)
    jobs = [("paper", pj, out, dict(orders=low)),
            ("impact", ij, out, dict(ns=ij.NS_SHIPPED, orders=low))]
    if high:
        jobs.append(("impact", ij, out, dict(ns=ij.NS_HIGH, orders=high)))
    return jobs


class _UserCache:
    """``generate``/``check`` of derivations/impact_jets.py for the per-user cache: the
    folder private (created 0700, ownership checked), and ``check`` compares each module
    with the derivation run again instead of with the manifest stored there."""

    @staticmethod
    def generate(out, ns, orders, force=False):
        from ..codegen._usercache import generate
        (n,) = ns
        return generate(out, n, orders, force=force)

    @staticmethod
    def check(out, ns, orders):
        from ..codegen._usercache import stale_text
        (n,) = ns
        return stale_text(out, n, orders)


def run(args):
    jobs = jobs_of(args)                   # reads --model; generates nothing
    if args.out is not None:
        from .._io import check_output
        check_output(args.out, flag="--out", folder=True)
        if args.check and not os.path.isdir(args.out):
            raise ParameterError("--out", args.out, "an existing folder of generated code "
                                 "(with --check)")
    where = ", ".join(sorted({str(o) for _, _, o, _ in jobs}))
    if args.check:
        why = [w for _, mod, o, kw in jobs for w in mod.check(o, **kw)]
        if why:
            for w in why:
                print(f"stale: {w}", file=sys.stderr)
            print(f"{where} is stale; run `symvi regenerate`", file=sys.stderr)
            return 1
        print(f"{where} is fresh")
        return 0
    for name, mod, o, kw in jobs:
        t0 = time.perf_counter()
        wrote, man = mod.generate(o, force=args.force, **kw)
        dt = time.perf_counter() - t0
        if wrote:
            print(f"{name}: wrote {wrote if name == 'impact' else list(kw['orders'])} to {o} in "
                  f"{dt:.1f} s (input hash {man['input_hash'][:12]})")
        else:
            print(f"{name} (orders {min(kw['orders'])}-{max(kw['orders'])}): {o} is up to date "
                  "(input hash unchanged); nothing written")
    return 0
