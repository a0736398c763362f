"""``symvi run SCENE.toml --out DIR``: run one scene file and write DIR/report.md."""
import sys


def register(sub):
    p = sub.add_parser("run", help="run one scene file (TOML) and write DIR/report.md")
    p.add_argument("scene", help="scene file (.toml); see symvi/scenes/ for examples")
    p.add_argument("--out", required=True, help="output folder (report.md, figures, .cache/)")
    p.add_argument("--quick", action="store_true", help="fewer impacts (says so on each figure)")
    p.add_argument("--no-cache", action="store_true", help="recompute every part")
    p.add_argument("--model", default=None, metavar="FILE",
                   help="run the scene on this model file instead of its [params]")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..reporting.report import build_report
    from ..reporting.scenes import load_scene
    scene = load_scene(args.scene)          # validates before anything is written
    check_out(args.out)
    if args.model:
        from ..model import load_model
        from ..reporting.scenes import with_model
        scene = with_model(scene, load_model(args.model), f"{args.scene} with --model")
    rep = build_report([scene], args.out, quick=args.quick, use_cache=not args.no_cache,
                       command=" ".join(["symvi"] + sys.argv[1:]), title=scene.title)
    return written(rep, args.json)


def written(rep, as_json):
    """What ``run`` and ``reproduce`` print: a line, or with --json one object."""
    n = len(rep.from_cache)
    if as_json:
        from . import print_json
        print_json({"report": rep.path, "figures": list(rep.figures), "parts": len(rep.parts),
                    "from_cache": n, "seconds": round(rep.seconds, 3)})
        return 0
    print(f"wrote {rep.path} ({len(rep.figures)} figures; {len(rep.parts)} parts, {n} from the "
          f"cache) in {rep.seconds:.1f} s")
    return 0


def check_out(out):
    """The output folder, and the report.md in it, usable before any work."""
    import os

    from .._io import check_output
    check_output(out, flag="--out", folder=True)
    check_output(os.path.join(out, "report.md"), flag="--out")
