"""``symvi reproduce --out DIR [--quick]``: every paper scene into one report, DIR/report.md."""
import sys


def register(sub):
    p = sub.add_parser("reproduce", help="the paper's results and printed formulas cross-checked: "
                                         "DIR/report.md and figures")
    p.add_argument("--out", required=True, help="output folder (report.md, figures, .cache/)")
    p.add_argument("--quick", action="store_true",
                   help="fewer impacts and frequencies (under a minute; says so on each figure)")
    p.add_argument("--no-cache", action="store_true", help="recompute every part")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..reporting.report import build_report
    from ..reporting.scenes import paper_scenes
    from .run import check_out, written
    check_out(args.out)
    scenes = paper_scenes()
    rep = build_report(scenes, args.out, quick=args.quick, use_cache=not args.no_cache,
                       command=" ".join(["symvi"] + sys.argv[1:]))
    return written(rep, args.json)
