"""Scenes: small declarative TOML studies, computed lazily and cached (``symvi run``, ``symvi reproduce``).

A scene file names the parameters of eq. (4), the forcing frequencies and the
outputs it wants::

    [scene]
    name = "fig5"                  # [a-z0-9_-]+, used in file names
    title = "Fig. 5: invariant circle at ω = 0.7369"
    paper = "Fig. 5"               # optional: what it reproduces
    description = "..."            # optional

    [params]                       # the five parameters, or named sets [params.ex1] ...
    mu_m = 2                       # or model = "chain3.toml": a regular .toml model file,
    mu_k = 5                       # a relative path read from the scene file's folder
    f2 = 0                         # (no [params] at all: symvi run SCENE --model FILE)
    b = 1.5
    r = 0.8

    [[output]]
    kind = "section"               # multipliers | hopf | section | bifurcation |
    omega = 0.7369                 # circle_check | audit | numbers | nordmark ...
    impacts = 5000

Validation is strict: an unknown or missing key, a value of the wrong type, a
bad range or a parameter out of range raises :class:`SceneError` or
:class:`symvi.ParameterError` naming the file and the key, never a traceback.

Each output computes only what it needs, and imports lazily: a ``multipliers``
output loads only the first-order generated module (eq. (36)), a ``section``
output never computes a normal form.  Results are cached in ``DIR/.cache`` under
a hash of their inputs (the output's keys, the parameters, the quick flag, the
symvi version and source, and the generated code's input hash from
``generated/manifest.json``); a rerun with nothing changed loads them and
does no work.  Each entry carries the SHA-256 of its content: a corrupt one is
computed again, never a traceback.
"""
import hashlib
import json
import math
import os
import re
import stat
import time
import tomllib
import warnings
from dataclasses import dataclass, field
from importlib import resources

from ..errors import ParameterError, SingularCaseError, SymviError

#: the five parameters of eq. (4), in the order of :class:`symvi.Params`
PARAM_KEYS = ("mu_m", "mu_k", "f2", "b", "r")


class SceneError(SymviError):
    """A scene file is malformed: unknown, missing or mistyped key (message names file and key)."""


class NotAvailable(SymviError):
    """A module an output needs is not part of this checkout (the output says so, no number)."""


# --------------------------------------------------------------------------- schema
_REQ = object()


@dataclass(frozen=True)
class Field:
    """One key of a scene table: type, default (``_REQ``: required) and a range check."""

    type: str                 # number | int | str | bool | numbers | number_or_numbers | any
    default: object = _REQ
    check: object = None      # (predicate, "valid range in words")
    choices: tuple = ()
    length: object = None     # exact length for lists
    compute: bool = True      # False: presentation only, not part of the cache key


def _positive():
    return (lambda v: v > 0, "a number > 0")


def _int_range(lo, hi):
    return (lambda v: lo <= v <= hi, f"an integer from {lo} to {hi}")


_OMEGA = Field("number", check=_positive())
_IMPACTS = Field("int", check=_int_range(1, 10_000_000))
_TRANSIENT = Field("int", 0, check=_int_range(0, 100_000_000))
_PRESENT = dict(title=Field("str", "", compute=False), note=Field("str", "", compute=False),
                id=Field("str", None, compute=False), params=Field("str", None))

ATTRACTORS = ("period-1", "invariant circle", "doubled torus", "chaos")

KINDS = {
    # eq. (36) eigenvalues along omega: figs. 4, 10
    "multipliers": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                        steps=Field("int", 400, check=_int_range(2, 100_000))),
    # Hopf points, (H1)-(H3), eqs. (A1)-(A3), (60)
    "hopf": dict(omega_min=_OMEGA, omega_max=_OMEGA),
    # projected Poincaré sections: figs. 5-9, 11, 12
    "section": dict(omega=_OMEGA, impacts=_IMPACTS, transient=_TRANSIENT,
                    perturbation=Field("numbers", None, length=4),
                    y0=Field("numbers", None, length=4),
                    quick_impacts=Field("int", None, check=_int_range(1, 10_000_000)),
                    quick_transient=Field("int", None, check=_int_range(0, 100_000_000)),
                    classify=Field("bool", True),
                    highlight=Field("numbers", None, length=2, compute=False)),
    # bifurcation diagram over omega
    "bifurcation": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                        steps=Field("int", 200, check=_int_range(2, 100_000)),
                        impacts=Field("int", 200, check=_int_range(1, 100_000)),
                        transient=Field("int", 2000, check=_int_range(0, 10_000_000)),
                        quick_steps=Field("int", None, check=_int_range(2, 100_000)),
                        quick_transient=Field("int", None, check=_int_range(0, 10_000_000)),
                        component=Field("int", 0, check=_int_range(0, 3)),
                        branches=Field("bool", False)),
    # measured vs predicted circle size for v = v_c + mu
    "circle_check": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                         mu=Field("numbers", None, check=(
                             lambda v: len(v) >= 2 and all(0 < abs(m) <= 0.1 for m in v),
                             "two or more numbers with 0 < |mu| <= 0.1")),
                         quick=Field("bool", True, compute=False)),
    # printed formulas vs symvi, eqs. (11)-(16), (21)-(24), (37)-(38), (46), (54), (60), (A2)-(A17)
    "audit": dict(omega_min=_OMEGA, omega_max=_OMEGA, omega_orbit=Field("number", None,
                                                                          check=_positive())),
    # every number the paper prints
    "numbers": dict(row=Field("rows")),
    # a two-parameter curve (NS, flip, fold) from the point of that kind in [omega_min,
    # omega_max], with its codimension-two points (issue 13, symvi curve)
    "curve": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                  plane=Field("str", "omega,b"),
                  curve=Field("str", "ns", choices=("ns", "flip", "fold")),
                  bounds=Field("numbers", None, length=4),
                  max_points=Field("int", 2000, check=_int_range(2, 100_000)),
                  quick_max_points=Field("int", 300, check=_int_range(2, 100_000))),
    # simulation evidence next to a codimension-two point of a curve (symvi.curves.evidence):
    # CH bistability (two runs, two starts), R3/R4 period-m saddle orbits and basins
    "codim2_evidence": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                            plane=Field("str", "omega,r"),
                            bounds=Field("numbers", None, length=4),
                            point=Field("str", "CH", choices=("CH", "R3", "R4")),
                            index=Field("int", 1, check=_int_range(1, 100)),
                            max_points=Field("int", 2000, check=_int_range(2, 100_000))),
    # 50-digit validation of the first Hopf point: chains A and B of symvi.studies.mpcheck
    "mpcheck": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                    digits=Field("int", 50, check=_int_range(30, 200))),
    # Nordmark's map at the first grazing point of the 1-1 branch in [omega_min, omega_max],
    # checked by simulation past grazing (symvi.studies.nordmark_check)
    "nordmark": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                     depths=Field("numbers", None, check=(
                         lambda v: len(v) >= 1 and all(0 < d <= 0.1 for d in v),
                         "one or more depths with 0 < delta <= 0.1"))),
}

CHECKS = {
    "omega_c": dict(omega_min=_OMEGA, omega_max=_OMEGA),
    "dmod_domega": dict(omega_min=_OMEGA, omega_max=_OMEGA),
    "f1": dict(omega_min=_OMEGA, omega_max=_OMEGA),
    "interval": dict(omega_min=_OMEGA, omega_max=_OMEGA,
                     steps=Field("int", 400, check=_int_range(2, 100_000))),
    "attractor": dict(omega=_OMEGA, expect=Field("str", choices=ATTRACTORS), impacts=_IMPACTS,
                      transient=_TRANSIENT, perturbation=Field("numbers", None, length=4),
                      quick_impacts=Field("int", None, check=_int_range(1, 10_000_000)),
                      quick_transient=Field("int", None, check=_int_range(0, 100_000_000)),
                      omega_min=Field("number", None, check=_positive()),
                      omega_max=Field("number", None, check=_positive())),
    "onset": dict(omega_min=_OMEGA, omega_max=_OMEGA, expect=Field("str", choices=ATTRACTORS),
                  steps=Field("int", 41, check=_int_range(2, 10_000)),
                  impacts=Field("int", 3000, check=_int_range(100, 1_000_000)),
                  transient=Field("int", 20000, check=_int_range(0, 100_000_000)),
                  quick_steps=Field("int", None, check=_int_range(2, 10_000)),
                  quick_transient=Field("int", None, check=_int_range(0, 100_000_000))),
    "escape": dict(omega=_OMEGA, impacts=_IMPACTS,
                   offsets=Field("numbers", [1e-4, 1e-6, 1e-8, 1e-10]),
                   threshold=Field("number", 1.0, check=_positive())),
}
_ROW_COMMON = dict(label=Field("str"), printed=Field("any"), check=Field("str", choices=tuple(CHECKS)),
                   params=Field("str", None), where=Field("str", "", compute=False),
                   quote=Field("str", "", compute=False))


def _fail(file, key, value, valid, detail=""):
    raise ParameterError(f"{file}: {key}", value, valid, detail)


def _convert(f, value, key, file):
    t = f.type
    isnum = isinstance(value, (int, float)) and not isinstance(value, bool)
    if t == "number":
        if not isnum or not math.isfinite(value):
            _fail(file, key, value, "a finite number")
        value = float(value)
    elif t == "int":
        if not isinstance(value, int) or isinstance(value, bool):
            _fail(file, key, value, "an integer")
    elif t == "str":
        if not isinstance(value, str):
            _fail(file, key, value, "a string")
        if f.choices and value not in f.choices:
            _fail(file, key, value, "one of " + ", ".join(repr(c) for c in f.choices))
        return value
    elif t == "bool":
        if not isinstance(value, bool):
            _fail(file, key, value, "true or false")
        return value
    elif t == "numbers":
        if not isinstance(value, list) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                for v in value):
            _fail(file, key, value, "a list of finite numbers")
        if f.length is not None and len(value) != f.length:
            _fail(file, key, value, f"a list of {f.length} numbers")
        if not value:
            _fail(file, key, value, "a non-empty list of numbers")
        value = [float(v) for v in value]
    elif t == "any":
        ok = isinstance(value, (int, float, str)) or (
            isinstance(value, list) and all(isinstance(v, (int, float)) for v in value))
        if not ok or isinstance(value, bool):
            _fail(file, key, value, "a number, a list of numbers or a string")
        return value
    if f.check is not None:
        pred, words = f.check
        if not pred(value):
            _fail(file, key, value, words)
    return value


def _table(tbl, spec, where, file):
    """Validate one TOML table against ``spec``: unknown, missing and mistyped keys."""
    if not isinstance(tbl, dict):
        raise SceneError(f"{file}: '{where}' must be a table")
    unknown = sorted(set(tbl) - set(spec))
    if unknown:
        raise SceneError(f"{file}: unknown key '{where}.{unknown[0]}' "
                         f"(allowed: {', '.join(sorted(spec))})")
    out = {}
    for k, f in spec.items():
        if k not in tbl:
            if f.default is _REQ:
                raise SceneError(f"{file}: missing key '{where}.{k}'")
            out[k] = f.default
        elif f.type == "rows":
            out[k] = tbl[k]
        else:
            out[k] = _convert(f, tbl[k], f"{where}.{k}", file)
    for lo, hi in (("omega_min", "omega_max"),):
        if out.get(lo) is not None and out.get(hi) is not None and not out[lo] < out[hi]:
            _fail(file, f"{where}.{hi}", out[hi], f"a number > {where}.{lo} = {out[lo]}")
    return out


def _params(tbl, file, folder=""):
    """The [params] table: one set of the five keys (or ``model = "FILE.toml"``, a model
    file relative to the scene), or named sub-tables of them.  A missing or empty [params]
    gives one set ``default`` with no parameters yet (``None``): the scene then needs a
    model from elsewhere (``symvi run SCENE --model FILE``, :func:`with_model`)."""
    from ..paper.params import Params
    if tbl is None or tbl == {}:
        return {"default": None}
    if not isinstance(tbl, dict):
        raise SceneError(f"{file}: '[params]' must be a table")
    nested = [isinstance(v, dict) for v in tbl.values()]
    if any(nested) and not all(nested):
        raise SceneError(f"{file}: '[params]' mixes parameter keys and named sets; use either "
                         "mu_m, mu_k, f2, b, r or [params.NAME] tables")
    sets = tbl if all(nested) else {"default": tbl}
    out = {}
    for name, s in sets.items():
        where = "params" if name == "default" and not all(nested) else f"params.{name}"
        if "model" in s:
            spec = _table(s, {"model": Field("str")}, where, file)
            out[name] = _load_model(spec["model"], f"{where}.model", file, folder)
            continue
        vals = _table(s, {k: Field("number") for k in PARAM_KEYS}, where, file)
        try:
            out[name] = Params(**vals)
        except ParameterError as exc:
            raise ParameterError(f"{file}: {where}.{exc.name}", exc.value, exc.valid) from None
    return out


_MODEL_FILE = "a model file (a regular file ending in .toml; a relative path is read from " \
              "the scene file's folder)"


def _model_path(value, key, file, folder):
    """The model file a scene names at ``key``, checked before it is opened: a regular file
    ending in ``.toml`` (also after following symlinks, so no device, FIFO, folder or other
    file is read as a model), relative paths resolved against ``folder``, the scene's."""
    if not value.strip() or "\0" in value:
        _fail(file, key, value, _MODEL_FILE, "not a file name")
    if not value.lower().endswith(".toml"):
        _fail(file, key, value, _MODEL_FILE, "not a .toml file")
    path = os.path.join(folder, value) if folder else value
    try:
        st = os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        _fail(file, key, value, _MODEL_FILE, f"no such file: {path}")
    except (OSError, ValueError) as exc:
        _fail(file, key, value, _MODEL_FILE, getattr(exc, "strerror", None) or str(exc))
    if not stat.S_ISREG(st.st_mode):
        _fail(file, key, value, _MODEL_FILE,
              "it is a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file")
    if not os.path.realpath(path).lower().endswith(".toml"):
        _fail(file, key, value, _MODEL_FILE, "a symlink to a file that is not .toml")
    return path


def _load_model(value, key, file, folder):
    """Load the model file a scene names (its errors, one line, prefixed by file and key)."""
    from ..model import load_model
    path = _model_path(value, key, file, folder)
    try:
        return load_model(path)
    except SymviError as exc:
        raise SceneError(f"{file}: {key}: " + " ".join(str(exc).split())) from None


@dataclass(frozen=True)
class Output:
    """One validated ``[[output]]`` of a scene."""

    index: int                # 1-based position in the file
    kind: str
    id: str
    params_name: str
    spec: dict                # all keys with defaults filled in

    def compute_spec(self):
        """The keys that change the computed result (presentation keys left out)."""
        fields = {**_PRESENT, **KINDS[self.kind]}
        return {k: v for k, v in self.spec.items() if k in fields and fields[k].compute}


@dataclass(frozen=True)
class Scene:
    """A validated scene file."""

    name: str
    title: str
    paper: str
    description: str
    params: dict              # name -> Params or Model (None: not given, see with_model)
    outputs: tuple
    source: str               # file name, for messages
    text: str = field(repr=False, default="")

    def params_for(self, output):
        p = self.params[output.params_name]
        if p is None:
            raise SceneError(f"{self.source}: missing key 'params' (the five parameters mu_m, "
                             "mu_k, f2, b, r or model = \"FILE.toml\"; or give a model with "
                             "symvi run --model FILE)")
        return p

    def check_params(self):
        """Raise :class:`SceneError` unless every output has its parameters (a scene with
        no [params] needs :func:`with_model` first)."""
        for o in self.outputs:
            self.params_for(o)


_NAME = re.compile(r"^[a-z0-9][a-z0-9_-]{0,63}$")


def parse_scene(text, source="<scene>"):
    """Validate scene TOML text; returns a :class:`Scene`."""
    file = os.path.basename(str(source))
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{file}: not valid TOML ({exc})") from None
    unknown = sorted(set(doc) - {"scene", "params", "output"})
    if unknown:
        raise SceneError(f"{file}: unknown key '{unknown[0]}' (allowed: output, params, scene)")
    for k in ("scene", "output"):        # no [params]: parameters from symvi run --model
        if k not in doc:
            raise SceneError(f"{file}: missing key '{k}'")
    head = _table(doc["scene"], dict(name=Field("str"), title=Field("str"), paper=Field("str", ""),
                                     description=Field("str", "")), "scene", file)
    if not _NAME.match(head["name"]):
        _fail(file, "scene.name", head["name"], "lower-case letters, digits, '-' and '_'")
    folder = os.path.dirname(os.path.abspath(str(source))) if os.path.exists(str(source)) else ""
    params = _params(doc.get("params"), file, folder)
    outs = doc["output"]
    if not isinstance(outs, list) or not outs:
        raise SceneError(f"{file}: 'output' must be one or more [[output]] tables")
    parsed, ids = [], set()
    for i, o in enumerate(outs, start=1):
        where = f"output[{i}]"
        if not isinstance(o, dict) or "kind" not in o:
            raise SceneError(f"{file}: missing key '{where}.kind' (one of {', '.join(KINDS)})")
        kind = o["kind"]
        if kind not in KINDS:
            _fail(file, f"{where}.kind", kind, "one of " + ", ".join(KINDS))
        spec = _table({k: v for k, v in o.items() if k != "kind"}, {**_PRESENT, **KINDS[kind]},
                      where, file)
        pname = spec["params"]
        if pname is None:
            if len(params) > 1 and kind != "numbers":
                raise SceneError(f"{file}: missing key '{where}.params' (the scene has several "
                                 f"parameter sets: {', '.join(params)})")
            pname = next(iter(params))
        elif pname not in params:
            _fail(file, f"{where}.params", pname, "one of " + ", ".join(params))
        if kind == "numbers":
            spec["row"] = _rows(spec["row"], params, where, file)
        if kind == "section" and spec["y0"] is not None and spec["perturbation"] is not None:
            raise SceneError(f"{file}: '{where}' sets both y0 and perturbation; use one")
        oid = spec["id"] or kind
        if oid in ids:
            oid = f"{oid}{i}"
        if not _NAME.match(oid):
            _fail(file, f"{where}.id", oid, "lower-case letters, digits, '-' and '_'")
        ids.add(oid)
        parsed.append(Output(i, kind, oid, pname, spec))
    _check_kinds(file, params, parsed)
    return Scene(head["name"], head["title"], head["paper"], head["description"], params,
                 tuple(parsed), file, text)


def _rows(rows, params, where, file):
    if not isinstance(rows, list) or not rows:
        raise SceneError(f"{file}: '{where}.row' must be one or more [[output.row]] tables")
    out = []
    for j, r in enumerate(rows, start=1):
        w = f"{where}.row[{j}]"
        if not isinstance(r, dict) or "check" not in r:
            raise SceneError(f"{file}: missing key '{w}.check' (one of {', '.join(CHECKS)})")
        if r["check"] not in CHECKS:
            _fail(file, f"{w}.check", r["check"], "one of " + ", ".join(CHECKS))
        spec = _table(r, {**_ROW_COMMON, **CHECKS[r["check"]]}, w, file)
        if spec["params"] is None:
            if len(params) > 1:
                raise SceneError(f"{file}: missing key '{w}.params' (one of {', '.join(params)})")
            spec["params"] = next(iter(params))
        elif spec["params"] not in params:
            _fail(file, f"{w}.params", spec["params"], "one of " + ", ".join(params))
        out.append(spec)
    return out


#: output kinds that evaluate the paper's own formulas: the paper's parameters only
PAPER_ONLY = ("audit", "numbers")


def _check_kinds(file, params, outputs):
    from ..model import Model
    for o in outputs:
        if o.kind in PAPER_ONLY and isinstance(params[o.params_name], Model):
            raise SceneError(f"{file}: output[{o.index}].kind = {o.kind!r} evaluates the paper's "
                             "printed formulas and needs the paper's parameters (mu_m, mu_k, f2, "
                             "b, r), not a model file")


def with_model(scene, model, source="--model"):
    """The scene with every parameter set replaced by ``model`` (``symvi run --model``)."""
    import dataclasses
    params = {name: model for name in scene.params}
    _check_kinds(source, params, scene.outputs)
    return dataclasses.replace(scene, params=params)


def load_scene(path):
    """Read and validate a scene file; errors name the file and the key."""
    try:
        with open(path, "rb") as fh:
            text = fh.read().decode("utf-8")
    except FileNotFoundError:
        raise SceneError(f"scene file {os.fspath(path)!r} not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"scene file {os.fspath(path)!r} cannot be read: {exc}") from None
    return parse_scene(text, path)


#: the paper's studies, in report order
PAPER_SCENES = ("example1", "example2", "fig4", "fig5", "fig6", "fig7", "fig8", "fig9", "fig10",
                "fig11", "fig12", "numbers", "formula_audit", "circle_check")


def paper_scenes():
    """The scenes shipped with symvi (package data ``symvi/scenes/*.toml``), in report order."""
    base = resources.files("symvi") / "scenes"
    return [parse_scene((base / f"{n}.toml").read_text(encoding="utf-8"), f"{n}.toml")
            for n in PAPER_SCENES]


# --------------------------------------------------------------------------- cache
#: the modules each kind of output calls into; what they import, transitively, is
#: found by :func:`module_closure` (so no dependency can be forgotten)
ENTRY = {"multipliers": ("paper.orbit",),
         "hopf": ("paper.hopf",),
         "section": ("simulations.simulation", "simulations.diagnostics"),
         "bifurcation": ("simulations.simulation", "continuation"),
         "circle_check": ("studies.circle_check",),
         "audit": ("paper.audit",),
         "numbers": ("paper.audit", "simulations.diagnostics"),
         "mpcheck": ("studies.mpcheck",),
         "nordmark": ("studies.nordmark_check",),
         "curve": ("curves", "normal_forms.codim2", "codegen.high"),
         "codim2_evidence": ("curves", "curves.evidence", "normal_forms.codim2", "codegen.high",
                             "simulations.simulation", "simulations.diagnostics")}
_SRC = {}
#: the symvi package folder (module names below are relative to it)
_PKG = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_CLOSURE = {}


def _module_file(dotted):
    """The source file of ``symvi.<dotted>`` (module or package), or None."""
    base = os.path.join(_PKG, *dotted.split(".")) if dotted else _PKG
    for f in (base + ".py", os.path.join(base, "__init__.py")):
        if os.path.isfile(f):
            return f
    return None


def module_imports(name):
    """The symvi modules ``symvi.<name>`` imports directly (ast of its source, imports
    inside functions included; parent packages, whose ``__init__`` runs, included)."""
    import ast
    f = _module_file(name)
    if f is None:
        return ()
    here = name if f.endswith("__init__.py") else name.rpartition(".")[0]
    with open(f, "rb") as fh:
        tree = ast.parse(fh.read())
    out = set()
    for node in ast.walk(tree):
        targets = []
        if isinstance(node, ast.ImportFrom):
            if node.level:
                parts = here.split(".") if here else []
                parts = parts[:len(parts) - (node.level - 1)] if node.level > 1 else parts
                base = ".".join(p for p in parts + ([node.module] if node.module else []) if p)
            elif node.module and node.module.startswith("symvi"):
                base = node.module[len("symvi"):].lstrip(".")
            else:
                continue
            targets.append(base)
            targets += [f"{base}.{a.name}" if base else a.name for a in node.names]
        elif isinstance(node, ast.Import):
            targets += [a.name[len("symvi"):].lstrip(".") for a in node.names
                        if a.name.startswith("symvi")]
        for t in targets:
            if t.startswith("_generated") or t.startswith("_derivations"):
                continue                     # tracked by the generated manifests
            parts = t.split(".")
            for i in range(1, len(parts) + 1):
                m = ".".join(parts[:i])
                if _module_file(m) is not None and m != name:
                    out.add(m)
    return tuple(sorted(out))


def module_closure(names):
    """Every symvi module ``names`` import, transitively, with the package's own
    ``__init__`` (``""``), as sorted dotted names below ``symvi``."""
    key = tuple(sorted(set(names)))
    if key in _CLOSURE:
        return _CLOSURE[key]
    seen, todo = set(), ["", *key]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        todo += module_imports(name)
    _CLOSURE[key] = tuple(sorted(m for m in seen if _module_file(m) is not None))
    return _CLOSURE[key]


def source_hash(modules):
    """Hash of the sources of the symvi modules ``modules`` import, transitively."""
    key = module_closure(modules)
    if key not in _SRC:
        h = hashlib.sha256()
        for name in key:
            h.update(name.encode() + b"\0")
            with open(_module_file(name), "rb") as fh:
                h.update(fh.read())
        _SRC[key] = h.hexdigest()[:16]
    return _SRC[key]


def _generated_hash():
    """Input hash and file hashes of generated/ (from its manifest; imports no generated code)."""
    try:
        texts = [(resources.files("symvi._generated") / f).read_text(encoding="utf-8")
                 for f in ("manifest.json", "impact_manifest.json")]
    except (FileNotFoundError, ModuleNotFoundError):
        return "no-manifest"
    ms = [json.loads(t) for t in texts]
    return hashlib.sha256(json.dumps([[m.get("input_hash"), m.get("files")] for m in ms],
                                     sort_keys=True).encode()).hexdigest()


_STAMP = None


def version_stamp():
    """symvi version, hash of the sources scenes use, generated/ input hash (once per process)."""
    global _STAMP
    if _STAMP is None:
        from .. import __version__
        _STAMP = {"symvi": __version__, "source": source_hash(sum(ENTRY.values(), ("reporting.scenes",))),
                  "generated": _generated_hash()[:16]}
    return _STAMP


def cache_key(scene, output, quick):
    """Hash of everything an output's result depends on."""
    p = scene.params_for(output)
    payload = {"kind": output.kind, "spec": output.compute_spec(), "params": p.as_dict(),
               "params_sets": {k: v.as_dict() for k, v in scene.params.items()}
               if output.kind == "numbers" else None,
               "quick": bool(quick), "symvi": version_stamp()["symvi"],
               "generated": version_stamp()["generated"],
               "source": source_hash(("reporting.scenes",) + ENTRY[output.kind])}
    return hashlib.sha256(json.dumps(payload, sort_keys=True, default=str).encode()).hexdigest()[:24]


class Cache:
    """Results on disk: ``<dir>/<key>.json`` (+ ``.npz`` arrays), written atomically.

    An entry records the SHA-256 of its JSON text and of its arrays file; one that does not
    match (truncated, corrupted, edited), is not a regular file, or does not parse is a miss
    and is computed again, never a traceback.  Only regular files are opened (a FIFO in the
    cache would block a reader)."""

    def __init__(self, folder):
        self.folder = os.fspath(folder)

    def _path(self, key, ext):
        return os.path.join(self.folder, f"{key}.{ext}")

    def _read(self, path):
        """The bytes of ``path`` if it is a regular file (not a symlink), else None."""
        try:
            if not stat.S_ISREG(os.lstat(path).st_mode):
                return None
            with open(path, "rb") as fh:
                return fh.read()
        except (OSError, ValueError):
            return None

    def load(self, key):
        import io

        import numpy as np
        raw = self._read(self._path(key, "json"))
        try:
            entry = json.loads(raw) if raw is not None else None
        except (ValueError, RecursionError):
            return None
        if not isinstance(entry, dict) or not isinstance(entry.get("result"), dict):
            return None
        result = entry["result"]
        if entry.get("sha256") != _digest(_canonical(result)):
            return None
        arrays = {}
        if result.get("_arrays"):
            data = self._read(self._path(key, "npz"))
            if data is None or entry.get("arrays_sha256") != hashlib.sha256(data).hexdigest():
                return None
            try:
                with np.load(io.BytesIO(data), allow_pickle=False) as z:
                    arrays = {k: z[k] for k in z.files}
            except Exception:        # noqa: BLE001 - any unreadable archive is a cache miss
                return None
        return result, arrays

    def store(self, key, result, arrays):
        import io

        import numpy as np

        from .._io import write_bytes, write_text
        result = _jsonable(dict(result, _arrays=bool(arrays)))
        entry = {"result": result, "sha256": _digest(_canonical(result))}
        if arrays:
            buf = io.BytesIO()
            np.savez_compressed(buf, **arrays)
            data = buf.getvalue()
            write_bytes(self._path(key, "npz"), data)
            entry["arrays_sha256"] = hashlib.sha256(data).hexdigest()
        write_text(self._path(key, "json"), json.dumps(entry, sort_keys=True))

    def figure_ok(self, key, path, render_key):
        """True if ``path`` is the figure rendered for ``render_key`` (by its recorded hash)."""
        rec = self._figs(key).get(os.path.basename(path))
        if not isinstance(rec, dict) or rec.get("render") != render_key:
            return False
        data = self._read(path)
        return data is not None and rec.get("sha256") == hashlib.sha256(data).hexdigest()

    def record_figure(self, key, path, render_key):
        from .._io import write_text
        figs = self._figs(key)
        figs[os.path.basename(path)] = {"render": render_key, "sha256": _sha256_file(path)}
        write_text(self._path(key, "figs.json"), json.dumps(figs, sort_keys=True))

    def _figs(self, key):
        raw = self._read(self._path(key, "figs.json"))
        try:
            figs = json.loads(raw) if raw is not None else {}
        except (ValueError, RecursionError):
            return {}
        return figs if isinstance(figs, dict) else {}


def _canonical(result):
    return json.dumps(result, sort_keys=True).encode()


def _digest(data):
    return hashlib.sha256(data).hexdigest()


def _sha256_file(path):
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def _jsonable(x):
    """Plain JSON: complex -> [re, im], numpy scalars -> Python, NaN/inf -> None."""
    import numpy as np
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (complex, np.complexfloating)):
        return [_jsonable(complex(x).real), _jsonable(complex(x).imag)]
    if isinstance(x, (float, np.floating)):
        x = float(x)
        return x if math.isfinite(x) else None
    if x is None or isinstance(x, str):
        return x
    try:     # mpmath numbers
        return _jsonable(complex(x)) if hasattr(x, "imag") and complex(x).imag else float(x)
    except (TypeError, ValueError):
        return str(x)


# --------------------------------------------------------------------------- running
@dataclass
class Part:
    """The result of one output: JSON-able ``result``, numpy ``arrays``, where it came from."""

    scene: Scene
    output: Output
    key: str
    result: dict
    arrays: dict
    source: str               # "computed" or "cache"
    seconds: float

    @property
    def available(self):
        return self.result.get("available", True)


def run_scene(scene, cache_dir, *, quick=False, use_cache=True, progress=None):
    """Compute (or load from the cache) every output of ``scene``; returns a list of :class:`Part`.

    ``progress(label)`` is called before each output.
    """
    scene.check_params()
    parts = []
    for out in scene.outputs:
        if progress is not None:
            progress(f"{scene.name}:{out.id}")
        parts.append(run_output(scene, out, cache_dir, quick=quick, use_cache=use_cache))
    return parts


def run_output(scene, out, cache_dir, *, quick=False, use_cache=True):
    """One output of ``scene`` as a :class:`Part`: from the cache if there, else computed
    (and stored)."""
    cache = Cache(cache_dir)
    key = cache_key(scene, out, quick)
    t0 = time.perf_counter()
    hit = cache.load(key) if use_cache else None
    if hit is not None:
        result, arrays = hit
        return Part(scene, out, key, result, arrays, "cache", time.perf_counter() - t0)
    result, arrays = compute(scene, out, quick)
    result = _jsonable(result)
    cache.store(key, result, arrays)
    return Part(scene, out, key, result, arrays, "computed", time.perf_counter() - t0)


def compute(scene, output, quick=False):
    """Compute one output: (JSON-able result dict, dict of numpy arrays)."""
    fn = _COMPUTE[output.kind]
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result, arrays = fn(scene.params_for(output), output.spec, quick, scene)
    except NotAvailable as exc:
        return {"available": False, "why": str(exc)}, {}
    notes = sorted({f"{w.category.__name__}: {w.message}" for w in caught})
    if notes:
        result["warnings"] = notes[:10]
    return result, arrays


def _need(module):
    """Import ``symvi.<module>`` or raise NotAvailable naming it."""
    import importlib
    try:
        return importlib.import_module(f"symvi.{module}")
    except ModuleNotFoundError as exc:
        if exc.name == f"symvi.{module}":
            raise NotAvailable(f"symvi.{module} is not part of this checkout") from None
        raise


def _multipliers(params, spec, quick, scene):
    import numpy as np

    from ..paper.orbit import multiplier_path
    om = np.linspace(spec["omega_min"], spec["omega_max"], spec["steps"])
    lam, branch, reasons = multiplier_path(params, om)
    mod = np.abs(lam)
    have = np.isfinite(mod[:, 0])
    crossings = []
    for i in range(len(om) - 1):
        if have[i] and have[i + 1] and (mod[i, 0] - 1) * (mod[i + 1, 0] - 1) < 0:
            z = lam[i + 1, 0] if mod[i + 1, 0] > mod[i, 0] else lam[i, 0]
            crossings.append({"between": [om[i], om[i + 1]],
                              "type": "complex pair" if abs(z.imag) > 1e-9 else
                              ("+1" if z.real > 0 else "-1")})
    res = {"omega": [float(om[0]), float(om[-1])], "steps": len(om),
           "admissible": int(have.sum()), "skipped": reasons, "crossings": crossings,
           "max_modulus": [float(np.nanmax(mod[:, 0])) if have.any() else None],
           "branches": sorted(set(b for b in branch if b))}
    return res, {"omega": om, "multipliers": lam}


def _hopf(params, spec, quick, scene):
    hopf = _need("paper.hopf")
    pts = hopf.hopf_points(params, spec["omega_min"], spec["omega_max"])
    events = getattr(pts, "events", None)
    points = getattr(pts, "points", pts)
    # what the scan could not certify: a crossing there may have been missed (never "none")
    uncertified = [[float(lo), float(hi)] for lo, hi in getattr(pts, "uncertified", ())]
    return {"points": [p.as_dict() for p in points],
            "events": [e if isinstance(e, dict) else getattr(e, "as_dict", lambda: str(e))()
                       for e in (events or [])],
            "uncertified": uncertified,
            "uncertified_reasons": list(getattr(pts, "uncertified_reasons", ())),
            "conservative": getattr(pts, "statement", None)
            if getattr(pts, "conservative", False) else None}, {}


def _section(params, spec, quick, scene):
    import numpy as np

    from ..simulations.simulation import DEFAULT_PERTURBATION, simulate
    from ..simulations.simulation import quick_counts
    n, tr, note = quick_counts(spec, quick)
    kw = {}
    if spec["perturbation"] is not None:
        kw["perturbation"] = tuple(spec["perturbation"])
    y0 = tuple(spec["y0"]) if spec["y0"] is not None else None
    sim = simulate(params, spec["omega"], y0=y0, n_impacts=n, transient=tr, **kw)
    res = {"omega": spec["omega"], "impacts": n, "transient": tr, "quick_note": note,
           "stop": sim.stop, "stored": int(sim.n), "y0": list(sim.y0),
           "perturbation": list(kw.get("perturbation", DEFAULT_PERTURBATION)) if y0 is None else None,
           "fixed_point": list(sim.fixed_point) if sim.fixed_point is not None else None}
    if spec["classify"] and sim.n >= 3:
        from ..simulations.diagnostics import classify
        c = classify(sim)
        res["attractor"] = {"kind": c.kind, "period": c.period, "rotation": c.rotation,
                            "branches": c.branches,
                            "lyapunov": None if c.lyapunov is None else
                            [float(v) for v in c.lyapunov.exponents],
                            "lyapunov_points": None if c.lyapunov is None else c.lyapunov.n}
    if sim.n:
        sec = np.asarray(sim.section)
        res["extent"] = {"min": sec.min(axis=0).tolist(), "max": sec.max(axis=0).tolist()}
    return res, {"section": np.asarray(sim.section), "t": np.asarray(sim.t)}


def _bifurcation(params, spec, quick, scene):
    import numpy as np

    from ..simulations.simulation import sweep
    steps, tr, note = spec["steps"], spec["transient"], ""
    if quick:
        steps = spec["quick_steps"] or min(steps, 60)
        tr = spec["quick_transient"] if spec["quick_transient"] is not None else min(tr, 500)
        if (steps, tr) != (spec["steps"], spec["transient"]):
            note = (f"quick mode: {steps} frequencies, transient {tr} "
                    f"(full run: {spec['steps']}, transient {spec['transient']})")
    om = np.linspace(spec["omega_min"], spec["omega_max"], steps)
    sw = sweep(params, om, n_impacts=spec["impacts"], transient=tr)
    stops = {}
    for s in sw.stops:
        stops[s] = stops.get(s, 0) + 1
    res = {"omega": [spec["omega_min"], spec["omega_max"]], "steps": steps, "transient": tr,
           "impacts": spec["impacts"], "stops": stops, "quick_note": note,
           "impacts_total": sw.impacts_total}
    if spec["branches"]:
        # the continued branches and their special points, drawn over the diagram
        from ..continuation import diagram_branches
        res["curves"], special = diagram_branches(params, spec["omega_min"],
                                                  spec["omega_max"], spec["component"])
        res["special"] = [{k: s[k] for k in ("orbit", "kind", "value", "admissible", "detail")}
                          | {"coefficients": {k: v for k, v in s["coefficients"].items()
                                              if isinstance(v, float)}} for s in special]
    return (res,
            {"omega": np.asarray(sw.omegas), "section": np.asarray(sw.section),
             "counts": np.asarray(sw.counts)})


def _plane(spec):
    """(names, bounds) of a curve output's plane and bounds fields."""
    from ..curves import parse_params
    names = parse_params(spec["plane"])
    bounds = None
    if spec["bounds"] is not None:
        lo_a, hi_a, lo_b, hi_b = (float(v) for v in spec["bounds"])
        bounds = {names[0]: (lo_a, hi_a), names[1]: (lo_b, hi_b)}
    return names, bounds


def _codim2_evidence(params, spec, quick, scene):
    from ..curves import curve_from_interval
    from ..curves.evidence import chenciner_coexistence, resonance_dynamics
    from ..model import Model
    model = Model.of(params)
    names, bounds = _plane(spec)
    curve, _ = curve_from_interval(model, spec["omega_min"], spec["omega_max"], names,
                                   bounds=bounds, max_points=spec["max_points"])
    pts = [s for s in curve.special if s.kind == spec["point"]]
    if len(pts) < spec["index"]:
        raise NotAvailable(f"the NS curve in ({', '.join(names)}) has {len(pts)} "
                           f"{spec['point']} point(s), not {spec['index']}")
    pt = pts[spec["index"] - 1]
    fn = chenciner_coexistence if spec["point"] == "CH" else resonance_dynamics
    import numpy as np
    result, arrays = fn(model, curve, pt)
    return result, {k: np.asarray(v) for k, v in arrays.items()}


def _curve(params, spec, quick, scene):
    from ..curves import curve_from_interval
    from ..model import Model
    names, bounds = _plane(spec)
    n = spec["max_points"]
    note = ""
    if quick and spec["quick_max_points"] < n:
        n, note = spec["quick_max_points"], (f"quick mode: at most {spec['quick_max_points']} "
                                             f"points each way (full run: {n})")
    curve, start = curve_from_interval(Model.of(params), spec["omega_min"], spec["omega_max"],
                                       names, kind=spec["curve"], bounds=bounds, max_points=n)
    special = []
    for sp in curve.special:
        d = sp.as_dict()
        special.append({"kind": d["kind"], "params": d["params"], "detail": d["detail"],
                        "admissible": d["admissible"],
                        "coefficients": {k: v for k, v in d["coefficients"].items()
                                         if isinstance(v, (int, float, list, str))}})
    return {"names": list(names), "curve": spec["curve"], "points": len(curve),
            "start": {"omega": start.value, "orbit": f"{start.orbit.n}-{start.orbit.p}"},
            "ends": list(curve.ends), "notes": list(curve.notes), "special": special,
            "bounds": {k: list(v) for k, v in curve.bounds.items()},
            "plot": curve.plot_data(), "quick_note": note}, {}


def _circle_check(params, spec, quick, scene):
    # no Hopf point with a circle, a repelling circle, a circle too large to measure: a
    # property of the model, said in the report (not an error of the scene)
    try:
        return _need("studies.circle_check").study(params, spec, quick)
    except SingularCaseError as exc:
        raise NotAvailable(str(exc)) from None


def _audit(params, spec, quick, scene):
    from ..paper import audit
    return audit.formula_audit(params, spec), {}


def _numbers(params, spec, quick, scene):
    from ..paper import audit
    return audit.numbers_table(spec["row"], scene.params, quick), {}


def _mpcheck(params, spec, quick, scene):
    mp = _need("studies.mpcheck")
    digits = min(spec["digits"], 30) if quick else spec["digits"]
    res = mp.mpcheck(params, spec["omega_min"], spec["omega_max"], digits=digits).as_dict()
    if digits != spec["digits"]:
        res["quick_note"] = f"quick mode: {digits} digits (full run: {spec['digits']})"
    return res, {}


def _nordmark(params, spec, quick, scene):
    # no grazing point in the range, or one whose map cannot be formed: said in the report
    try:
        return _need("studies.nordmark_check").study(params, spec, quick), {}
    except SymviError as exc:
        raise NotAvailable(str(exc)) from None


_COMPUTE = {"multipliers": _multipliers, "hopf": _hopf, "section": _section,
            "bifurcation": _bifurcation, "circle_check": _circle_check, "audit": _audit,
            "numbers": _numbers, "mpcheck": _mpcheck, "curve": _curve,
            "codim2_evidence": _codim2_evidence, "nordmark": _nordmark}
