"""The ``symvi`` command line: argument parsing and printing only.

Each subcommand lives in its own module ``symvi.cli.<name>`` exposing
``register(subparsers)`` (cheap: no heavy imports) and ``run(args) -> int``.
Only the chosen subcommand's module does real work, so ``symvi orbit`` never
imports second- or third-order generated code.
"""
import argparse
import collections
import importlib
import json
import re
import sys

from ..errors import ParameterError, SymviError

#: subcommand modules, in the order ``symvi --help`` lists them
COMMANDS = ["orbit", "regenerate", "hopf", "continuation", "curve", "simulate", "sweep", "plane",
            "plot", "run", "reproduce"]


#: a negative number as an option's value, not an option: argparse's own pattern
#: (``^-\d+$|^-\d*\.\d+$``) misses exponents (``--y0 -1e-3 ...``), ``-1.`` and ``-inf``
_NEGATIVE_NUMBER = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?$|^-(?:inf|infinity|nan)$",
                              re.IGNORECASE)

#: actions meant to be given more than once (``--set``, ``--bounds``)
_REPEATABLE = (argparse._AppendAction, argparse._AppendConstAction, argparse._CountAction,
               argparse._HelpAction, argparse._VersionAction)
_ONCE = {}


def _once(cls):
    """``cls`` refusing a second occurrence of its flag (the last value would silently win)."""
    if cls not in _ONCE:
        def __call__(self, parser, namespace, values, option_string=None):
            if self in parser._given:
                flag = next((s for s in self.option_strings if s.startswith("--")),
                            self.option_strings[0])
                raise argparse.ArgumentError(None, f"argument {flag}: given more than once; "
                                                   "give it once")
            parser._given.add(self)
            cls.__call__(self, parser, namespace, values, option_string)
        _ONCE[cls] = type(f"_Once{cls.__name__}", (cls,), {"__call__": __call__})
    return _ONCE[cls]


class _Defaults(argparse.HelpFormatter):
    """Help that shows each option's default where it has one (not None, not a switch
    that is off) and its text does not already say it: "(default: 5000)" after it
    (issue 26: defaults in --help)."""

    def _get_help_string(self, action):
        text = action.help or ""
        d = action.default
        if ("default" in text.lower() or d is None or d is argparse.SUPPRESS or d is False
                or not action.option_strings or isinstance(d, (list, tuple)) and not d):
            return text
        return text + " (default: %(default)s)"


class _Parser(argparse.ArgumentParser):
    """One-line errors (exit 2); negative numbers with exponents are values; a flag given
    twice is refused (every subcommand's parser is one of these); --help shows the
    defaults (:class:`_Defaults`)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _Defaults)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER
        self._given = set()

    def parse_known_args(self, args=None, namespace=None):
        for action in self._actions:
            if (action.option_strings and not isinstance(action, _REPEATABLE)
                    and type(action) not in _ONCE.values()):
                action.__class__ = _once(type(action))
        self._given = set()
        return super().parse_known_args(args, namespace)

    def error(self, message):
        # one line, exit 2 (argparse's default prints the whole usage)
        message = " ".join(str(message).split())
        sys.stderr.write(f"symvi: error: {message}\n")
        sys.exit(2)


_PRESET_FLAGS = (("mu_m", "--mu-m", "mass ratio M2/M1 (> 0)"),
                 ("mu_k", "--mu-k", "stiffness ratio K2/K1 (> 0)"),
                 ("f2", "--f2", "force share on mass 2, P2/(P1+P2)"),
                 ("b", "--b", "gap to the stop"),
                 ("r", "--r", "coefficient of restitution (0 < r <= 1)"))


#: the named parameters of a model, as the help of --param, --params, --x and --y lists them
#: (symvi.model.parameters parses them)
NAMED = "gap, restitution, mass[i], stiffness[i,j], damping[i,j], forcing[i]"
#: ... with the preset's own names first
PRESET_NAMED = f"b, r, mu_m, mu_k, f2 for the preset; {NAMED}"


#: the one form of a range on every command line (issue 26): ``--range``, the plane's
#: ``--x`` and ``--y``, curve's ``--bounds``
RANGE_FORM = "NAME=LO:HI"


#: (name, lo, hi, n) of a ``NAME=LO:HI[:N]`` argument (n None without ``:N``)
Range = collections.namedtuple("Range", "name lo hi n", defaults=(None,))


def range_form(steps=False, names=None):
    """How a range is written: ``NAME=LO:HI[:N]``, NAME spelled out when only one is
    allowed (``omega=LO:HI``)."""
    head = names[0] if names is not None and len(names) == 1 else "NAME"
    return f"{head}=LO:HI" + (":N" if steps else "")


def parse_range(text, flag, *, steps=False, names=None, ordered=True, most=None):
    """``NAME=LO:HI`` (with ``steps``: ``NAME=LO:HI:N``, N >= 2) -> :class:`Range`; one line
    naming ``flag`` and the form otherwise. ``names``: the names allowed (None: any, the
    model checks them); ``ordered``: LO < HI (else LO != HI: a direction, as continue's)."""
    import math

    from ..errors import ParameterError
    form = range_form(steps, names)
    need = (f"{form} with finite numbers " + ("LO < HI" if ordered else "LO != HI")
            + (f" and an integer N in 2 .. {most}" if steps and most else
               " and an integer N >= 2" if steps else ""))
    name, eq, rest = str(text).partition("=")
    name = name.strip()
    parts = rest.split(":")
    if not eq or not name or len(parts) != (3 if steps else 2):
        raise ParameterError(flag, text, need, "no :N here" if eq and len(parts) == 3 else
                             "the number of values :N is missing" if eq and steps
                             and len(parts) == 2 else "")
    try:
        lo, hi = float(parts[0]), float(parts[1])
        n = int(parts[2]) if steps else None
    except ValueError:
        raise ParameterError(flag, text, need) from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or (lo >= hi if ordered else lo == hi):
        raise ParameterError(flag, text, need)
    if steps and not (2 <= n and (most is None or n <= most)):
        raise ParameterError(flag, text, need)
    if names is not None and name not in names:
        raise ParameterError(flag, text, form if len(names) == 1 else
                             f"{form} with NAME one of {', '.join(names)}")
    return Range(name, lo, hi, n)


def deprecated(args, text):
    """Say ``text`` (one line on stderr, "symvi: warning: ...") after the command's work:
    a refused run stays one line, and an old flag keeps working for one release."""
    args._deprecated = [*getattr(args, "_deprecated", []), text]


def old_range(args, flag, old, *, name=None, **kwargs):
    """The :class:`Range` of ``flag`` (``--range``), or of the deprecated flags ``old``
    ({role: (dest, spelling)}, roles "name", "lo", "hi" and "n"; ``name`` fixes the name
    where no flag gives it) with a deprecation notice; not both, not neither. Returns
    (range, {role: the flag that gave it}) for the library's errors to name."""
    from ..errors import ParameterError
    form = range_form(kwargs.get("steps"), kwargs.get("names"))
    text = getattr(args, flag.lstrip("-").replace("-", "_"))
    given = [role for role, (dest, _) in old.items() if getattr(args, dest) is not None]
    if text is not None:
        if given:
            dest, spell = old[given[0]]
            raise ParameterError(spell, getattr(args, dest),
                                 f"not with {flag} (the deprecated form of {flag} {form})")
        return parse_range(text, flag, **kwargs), dict.fromkeys(("name", *old), flag)
    if not given:
        raise ParameterError(flag, None, form)
    missing = [spell for role, (dest, spell) in old.items() if getattr(args, dest) is None]
    if missing:
        raise ParameterError(missing[0], None, f"given with {old[given[0]][1]} (or give "
                                                f"{flag} {form} instead of both)")
    value = {role: getattr(args, dest) for role, (dest, _) in old.items()}
    spells = " ".join(spell for _, spell in old.values())
    deprecated(args, f"{spells} are deprecated: give {flag} {form} (the one form of a range "
                     "on every command)")
    return (Range(value.get("name", name), value["lo"], value["hi"], value.get("n")),
            {role: spell for role, (_, spell) in old.items()})


def add_params(parser, defaults=None, model=False):
    """The five system parameters of eq. (4) as --mu-m --mu-k --f2 --b --r; with
    ``model``, ``--model FILE`` (a model file) as the alternative to all five."""
    d = defaults or {}
    for name, flag, help_ in _PRESET_FLAGS:
        parser.add_argument(flag, type=float, required=name not in d and not model,
                            default=d.get(name), help=help_)
    if model:
        parser.add_argument("--model", default=None, metavar="FILE",
                            help="model file (TOML: [model] mass, stiffness, damping, forcing; "
                                 "[stop] mass, gap, restitution, or one [[stop]] table per stop "
                                 "with mass or between, gap, side, restitution or "
                                 "stiffness and damping; nonlinear forces: [model] nonlinear "
                                 "and [model.parameters]), instead of the preset flags")


def add_engine(parser, workers_default):
    """--scheduler ADDRESS | --workers W: where the Dask engine (symvi.plane.engine) runs."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on this Dask scheduler (tcp://host:port)")
    where.add_argument("--workers", type=int, metavar="W",
                       help="processes of a local Dask cluster; 0: no Dask, in this "
                            f"process ({workers_default})")


def params_from(args):
    """Params of the preset flags, or the Model of ``--model FILE`` (exit 2 on a mix-up)."""
    from ..paper.params import Params
    if getattr(args, "model", None) is not None:
        given = [flag for name, flag, _ in _PRESET_FLAGS if getattr(args, name) is not None]
        if given:
            raise ParameterError("--model", args.model,
                                 "either --model FILE or the preset flags, not both",
                                 f"also given: {' '.join(given)}")
        from ..model import load_model
        return load_model(args.model)
    missing = [flag for name, flag, _ in _PRESET_FLAGS if getattr(args, name) is None]
    if missing:
        raise ParameterError(missing[0], None, "a number (or give --model FILE)",
                             f"missing: {' '.join(missing)}")
    return Params(args.mu_m, args.mu_k, args.f2, args.b, args.r)


def check_value(model, param, value, flag, *, resonance=True):
    """``value`` of ``param`` valid for ``model``, else one line naming ``flag``
    (:func:`symvi.flow.check_value`)."""
    from ..flow import check_value as check
    return check(model, param, value, flag, resonance=resonance)


def describe(params):
    """A one-line description of the preset parameters or of a model (titles, headers)."""
    from ..model import Model
    if isinstance(params, Model):
        stops = "; ".join(_stop_text(s) for s in params.stops)
        d = params.as_dict()
        forces = "" if "nonlinear" not in d else (
            "  forces " + ", ".join(d["nonlinear"])
            + "".join(f" {k}={v:g}" for k, v in d["parameters"].items()))
        return (f"N={params.n} {'stop' if len(params.stops) == 1 else 'stops'} {stops}"
                + (" damped" if params.damped else "") + forces)
    return (f"mu_m={params.mu_m:g} mu_k={params.mu_k:g} f2={params.f2:g} b={params.b:g} "
            f"r={params.r:g}")


def _stop_text(s):
    """One stop as ``describe`` shows it: today's text for an upper rigid stop on a mass."""
    where = f"on mass {s.mass}" if s.mass is not None else f"between masses {s.between[0]} " \
        f"and {s.between[1]}"
    side = "" if s.side == "upper" else " lower"
    law = f"r={s.restitution:g}" if s.restitution is not None else f"k_s={s.stiffness:g}"
    return f"{where}{side} gap={s.gap:g} {law}"


def section_view(params):
    """(labels, projections, names) of the section of the preset or of a model."""
    from ..model import Model
    if isinstance(params, Model):
        from ..reporting.report import _section_view
        v = _section_view(params)
        return v["labels"], v["projections"], v["labels"]
    from ..reporting.figures import LABELS, PROJECTIONS
    return LABELS, PROJECTIONS, ("x1dot+", "x20", "x20dot", "tau")


def data_key(params):
    """What an .npz output records of the system: the preset key, or the model file text."""
    import numpy as np

    from ..model import Model, dumps
    return {"model": np.array(dumps(params))} if isinstance(params, Model) \
        else {"params": np.array(params.key())}


def save_npz(path, **arrays):
    """Write ``arrays`` (numpy.savez) to ``path`` atomically: the one place the command line
    writes data (and, with :func:`data_key`, the one place it imports numpy)."""
    import numpy as np

    from .._io import atomic_path
    with atomic_path(path, suffix=".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)


def print_special(kind, where, coefficients, detail, orbit, width):
    """Two lines of text for a located special point: kind, where, float coefficients,
    the orbit's admissibility (grazing points are inadmissible by nature); the detail."""
    coef = ", ".join(f"{k} = {v:.8g}" for k, v in coefficients.items() if isinstance(v, float))
    tag = "" if orbit.admissible or kind == "grazing" else "  [inadmissible orbit]"
    print(f"  {kind:{width}s} {where}  {coef}{tag}")
    print(f"  {'':{width}s} {detail}")


def wants_json(args):
    """Whether ``simulate`` / ``sweep`` print JSON: with ``--json``; without it, as they
    always did before issue 26, for one release where stdout is not a terminal (a script
    reads it), with a deprecation notice; a terminal gets text."""
    if args.json:
        return True
    if sys.stdout.isatty():
        return False
    deprecated(args, f"symvi {args.command} without --json prints JSON for one more release "
                     "where its output is not a terminal; then text: add --json to keep JSON")
    return True


def print_json(obj):
    """Exactly one JSON object on stdout; NaN/inf are never emitted."""
    sys.stdout.write(json.dumps(obj, allow_nan=False) + "\n")


def build_parser():
    parser = _Parser(prog="symvi", description="Bifurcation analysis of vibro-impact systems.")
    from .. import __version__
    parser.add_argument("--version", action="version", version=f"symvi {__version__}")
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


def _warn_once():
    """A ``warnings.showwarning`` printing one line per distinct warning of one command,
    without source locations."""
    seen = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = f"symvi: warning: {message}"
        if text not in seen:
            seen.add(text)
            sys.stderr.write(text + "\n")
    return show


def main(argv=None):
    import warnings
    warnings.showwarning = _warn_once()
    parser = build_parser()
    args = parser.parse_args(argv)
    args._argv = list(sys.argv[1:] if argv is None else argv)     # recorded by some outputs
    if not getattr(args, "_module", None):
        parser.print_help()
        return 2
    from .._compiled import announce_compiles
    announce_compiles()            # a compile is never silent (numba: cache misses only)
    try:
        code = int(args._module.run(args) or 0)
        for text in dict.fromkeys(getattr(args, "_deprecated", [])):
            sys.stderr.write(f"symvi: warning: {text}\n")      # once each, every run
        return code
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
    except OSError as exc:
        # a file the user named could not be read or written (full disk, permissions)
        where = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        sys.stderr.write(f"symvi: error:{where} {exc.strerror or exc}\n")
        return 2
    except Exception as exc:   # a bug: one line, not a traceback; SYMVI_DEBUG=1 shows it
        import os
        if os.environ.get("SYMVI_DEBUG"):
            raise
        text = " ".join(str(exc).split())[:300]
        sys.stderr.write(f"symvi: internal error (a bug, please report it; SYMVI_DEBUG=1 "
                         f"shows the traceback): {type(exc).__name__}: {text}\n")
        return 70


if __name__ == "__main__":
    sys.exit(main())
