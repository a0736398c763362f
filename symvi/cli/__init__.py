"""The ``symvi`` command line: argument parsing and printing only.

Each subcommand lives in its own module ``symvi.cli.<name>`` exposing
``register(subparsers)`` (cheap: no heavy imports) and ``run(args) -> int``.
Only the chosen subcommand's module does real work, so ``symvi orbit`` never
imports second- or third-order generated code.
"""
import argparse
import importlib
import json
import sys

from ..errors import SymviError

#: subcommand modules, in the order ``symvi --help`` lists them
COMMANDS = ["orbit", "regenerate", "hopf", "simulate", "sweep", "run", "reproduce"]


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        # one line, exit 2 (argparse's default prints the whole usage)
        sys.stderr.write(f"symvi: error: {message}\n")
        sys.exit(2)


def add_params(parser, defaults=None):
    """The five system parameters of eq. (4) as --mu-m --mu-k --f2 --b --r."""
    d = defaults or {}
    parser.add_argument("--mu-m", type=float, required="mu_m" not in d, default=d.get("mu_m"),
                        help="mass ratio M2/M1 (> 0)")
    parser.add_argument("--mu-k", type=float, required="mu_k" not in d, default=d.get("mu_k"),
                        help="stiffness ratio K2/K1 (> 0)")
    parser.add_argument("--f2", type=float, required="f2" not in d, default=d.get("f2"),
                        help="force share on mass 2, P2/(P1+P2)")
    parser.add_argument("--b", type=float, required="b" not in d, default=d.get("b"),
                        help="gap to the stop")
    parser.add_argument("--r", type=float, required="r" not in d, default=d.get("r"),
                        help="coefficient of restitution (0 < r <= 1)")


def params_from(args):
    from ..params import Params
    return Params(args.mu_m, args.mu_k, args.f2, args.b, args.r)


def print_json(obj):
    """Exactly one JSON object on stdout; NaN/inf are never emitted."""
    sys.stdout.write(json.dumps(obj, allow_nan=False) + "\n")


def build_parser():
    parser = _Parser(prog="symvi", description="Bifurcation analysis of vibro-impact systems.")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser, metavar="COMMAND")
    for name in COMMANDS:
        try:
            mod = importlib.import_module(f"symvi.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"symvi.cli.{name}":
                continue   # not built yet
            raise
        p = mod.register(sub)
        p.set_defaults(_module=mod)
    return parser


def _warn_once(message, category, filename, lineno, file=None, line=None, _seen=set()):
    # one line per distinct warning, without source locations
    text = f"symvi: warning: {message}"
    if text not in _seen:
        _seen.add(text)
        sys.stderr.write(text + "\n")


def main(argv=None):
    import warnings
    warnings.showwarning = _warn_once
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "_module", None):
        parser.print_help()
        return 2
    try:
        return int(args._module.run(args) or 0)
    except SymviError as exc:
        sys.stderr.write(f"symvi: error: {exc}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write("symvi: interrupted\n")
        return 130
    except BrokenPipeError:
        # output piped into e.g. `head`: stop quietly, as Unix tools do
        import os
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
