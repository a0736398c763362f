"""A branch of the symmetric orbit between two elastic stops (examples/contacts/
oscillator_elastic.toml: each flight in its contact phase's flow, the numpy shooting
system), with the same oscillator between rigid stops (the compiled kernel) timed in the
same run as the baseline:

    python benchmarks/bench_elastic_branch.py [--reps 3]

Both continue their symmetric orbit in omega over [2.0, 4.0] with the same step bound,
multipliers, the half map and every test function at each point.  Prints one JSON line:
seconds per point (median of the reps) of each and their ratio."""
import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_symmetric_branch import SYM, timed  # noqa: E402
from symvi.continuation import attractor_orbit, continue_branch  # noqa: E402
from symvi.model import load_model  # noqa: E402

ELASTIC = load_model(Path(__file__).resolve().parents[1] / "examples" / "contacts" /
                     "oscillator_elastic.toml")


def branch(model, orbit):
    return continue_branch(model, "omega", 2.0, 4.0, orbit=orbit, h_max=0.01,
                           max_points=1000)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args()
    oe, orig = attractor_orbit(ELASTIC, 2.0), attractor_orbit(SYM, 2.0)
    branch(ELASTIC, oe)                          # compile and warm
    branch(SYM, orig)
    te, be = timed(lambda: branch(ELASTIC, oe), a.reps)
    tr, br = timed(lambda: branch(SYM, orig), a.reps)
    pe, pr = te / len(be), tr / len(br)
    print(json.dumps({"elastic_points": len(be), "elastic_ms_per_point": round(1e3 * pe, 3),
                      "rigid_points": len(br), "rigid_ms_per_point": round(1e3 * pr, 3),
                      "ratio": round(pe / pr, 2)}))


if __name__ == "__main__":
    main()
