"""Model files (TOML), a stable contract::

    [model]
    mass = [1.0, 1.5, 0.8]          # the diagonal, or a full matrix [[...], ...]
    stiffness = [[...], ...]
    damping = [[...], ...]          # optional
    forcing = [1.0, 0.0, 0.0]       # P in P sin(omega t + tau)

    [stop]
    mass = 1                        # 1-based index of the mass that hits the stop
    gap = 1.2
    restitution = 0.8

or, for several stops (or a stop between masses, on the lower side, or elastic), one
``[[stop]]`` table per stop, in order (``stop[k]`` in parameter names)::

    [[stop]]
    mass = 1                        # or: between = [1, 2]  (s = x_2 - x_1)
    gap = 0.5
    side = "upper"                  # or "lower" (s >= gap); "upper" by default
    restitution = 0.8               # rigid; or stiffness = 50.0 (and damping = 0.1): elastic

Smooth nonlinear forces (issue 28), one expression per mass on the left-hand side
(M x'' + C x' + K x + f(x, v) = P sin(omega t + tau)), with their named parameters::

    [model]
    ...
    nonlinear = ["beta*x1**3"]      # in x1..xN, v1..vN and the parameters below
    [model.parameters]
    beta = 0.5

(:mod:`symvi.model._forces` parses them in a closed namespace; only ``simulate`` runs
such a model for now.)

(The dynamics take one rigid stop on one mass for now: :meth:`Model.require_one_rigid_stop`.)
A bad file raises :class:`ModelFileError`: one line naming the file and the key.
Sizes are bounded before anything is allocated: the file (MAX_BYTES), the nesting of
its arrays (MAX_DEPTH, checked before the recursive TOML parser runs) and N.
"""
import os
import re
import stat
import tomllib

from ..errors import ParameterError
from ._model import Model, Stop

#: a model file (N <= 8) is a few KB
MAX_BYTES = 1 << 20
#: arrays or inline tables nested deeper than this are refused (a matrix needs 2)
MAX_DEPTH = 8

_MODEL_KEYS = {"mass", "stiffness", "damping", "forcing", "nonlinear", "parameters"}
_STOP_KEYS = {"mass", "between", "gap", "side", "restitution", "stiffness", "damping"}


class ModelFileError(ParameterError):
    """A model file that cannot be read or does not describe a valid model."""

    def __init__(self, path, key, message):
        self.path, self.key = str(path), key
        shown = _cut(self.path, 120)
        Exception.__init__(self, f"{shown}: {key}: {message}" if key else f"{shown}: {message}")
        self.name, self.value, self.valid = key, None, message


#: the most [[stop]] tables a file may hold (each stop is a constraint of the model)
MAX_STOPS = 64


def _key_of(field, where=None):
    """The file key of a constructor field name: ``stop.gap`` is ``[stop] gap`` (or
    ``where``'s, the ``[[stop]] #k`` table being read), ``stop[2].gap`` is ``[[stop]] #2 gap``."""
    m = re.match(r"^stop\[(\d+)\](?:\.(\w+))?$", field)
    if m:
        return f"[[stop]] #{m.group(1)}" + (f" {m.group(2)}" if m.group(2) else "")
    if field.startswith("stop."):
        return f"{where or '[stop]'} {field[5:]}"
    if field in ("stop", "stops"):
        return where or "[stop]"
    if field.startswith("parameters"):
        return "[model.parameters]" + (f" {field[11:]}" if field[11:] else "")
    return "[model] " + field


def _invalid(source, exc, where=None):
    """The model file's error for a constructor's ParameterError: the key as the file says
    it, the range and the detail, not the value (the file holds it)."""
    detail = str(exc).split(f"valid range: {exc.valid}", 1)[-1]
    return ModelFileError(source, _key_of(exc.name, where), f"invalid; valid: {exc.valid}{detail}")


def _table(source, where, t, keys):
    """Check one table: a table of keys, each one known."""
    if not isinstance(t, dict):
        raise ModelFileError(source, where, "must be a table of keys")
    for k in t:
        if k not in keys:
            raise ModelFileError(source, f"{where} {_cut(str(k))}",
                                 f"unknown key; valid keys: {', '.join(sorted(keys))}")


def _stop(source, where, t):
    """One Stop from a ``[stop]`` or ``[[stop]]`` table (``where`` names it)."""
    _table(source, where, t, _STOP_KEYS)
    if "mass" not in t and "between" not in t:
        raise ModelFileError(source, f"{where} mass", "missing (required; or between = [i, j] "
                             "for a stop between two masses)")
    if "gap" not in t:
        raise ModelFileError(source, f"{where} gap", "missing (required)")
    if "restitution" not in t and "stiffness" not in t:
        raise ModelFileError(source, f"{where} restitution",
                             "missing (required: 0 < restitution <= 1 for a rigid stop, or "
                             "stiffness > 0 for an elastic one)")
    try:
        return Stop(**t)
    except ParameterError as exc:
        raise _invalid(source, exc, where) from None


def model_from_dict(data, source="<model>"):
    """A :class:`Model` from the parsed tables ``{"model": {...}, "stop": {...}}`` (one
    ``[stop]`` table) or ``{"model": {...}, "stop": [{...}, ...]}`` (``[[stop]]`` tables)."""
    if not isinstance(data, dict):
        raise ModelFileError(source, "", "expected the tables [model] and [stop]")
    unknown = set(data) - {"model", "stop"}
    if unknown:
        raise ModelFileError(source, _cut(sorted(map(str, unknown))[0]),
                             "unknown table; a model file has [model] and [stop] (or [[stop]])")
    m = data.get("model")
    if m is None:
        raise ModelFileError(source, "[model]", "missing table")
    _table(source, "[model]", m, _MODEL_KEYS)
    for k in ("mass", "stiffness", "forcing"):
        if k not in m:
            raise ModelFileError(source, f"[model] {k}", "missing (required)")
    s = data.get("stop")
    if s is None:
        raise ModelFileError(source, "[stop]", "missing table; a model file has a [stop] "
                             "table or [[stop]] tables")
    if isinstance(s, list):
        if not 1 <= len(s) <= MAX_STOPS:
            raise ModelFileError(source, "[[stop]]", f"{len(s)} tables; valid: 1 to {MAX_STOPS}")
        stops = {"stops": [_stop(source, f"[[stop]] #{k}", t) for k, t in enumerate(s, 1)]}
    else:
        stops = {"stop": _stop(source, "[stop]", s)}
    if "parameters" in m and "nonlinear" not in m:
        raise ModelFileError(source, "[model.parameters]", "only with [model] nonlinear = "
                             "[...] (the named parameters of the nonlinear forces)")
    try:
        return Model(mass=m["mass"], stiffness=m["stiffness"], damping=m.get("damping"),
                     forcing=m["forcing"], nonlinear=m.get("nonlinear"),
                     parameters=m.get("parameters"), **stops)
    except ParameterError as exc:
        raise _invalid(source, exc) from None


def _cut(text, limit=40):
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _too_deep(text):
    """The key ("[table] key") whose value nests arrays or inline tables deeper than
    MAX_DEPTH, or None: a scan that skips strings and comments, so that the recursive
    TOML parser never meets such nesting (a RecursionError, or worse)."""
    i, n, depth = 0, len(text), 0
    table, key, start = "", "", 0
    while True:
        m = _SPECIAL.search(text, i)
        if m is None:
            return None
        i = m.start()
        c = text[i]
        if c in "\"'":
            q = c * 3 if text.startswith(c * 3, i) else c
            j = i + len(q)
            while j < n and not text.startswith(q, j) and (len(q) == 3 or text[j] != "\n"):
                j += 2 if c == '"' and text[j] == "\\" else 1
            i = j + len(q)
            continue
        if c == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if c == "[" and depth == 0 and not text[start:i].strip():
            j = text.find("\n", i)             # a [table] header line
            j = n if j < 0 else j
            table, key, i = text[i:j].split("#")[0].strip().strip("[]").strip(), "", j
            continue
        if c in "[{":
            depth += 1
            if depth > MAX_DEPTH:
                name = _cut(key or "(value)")
                return f"[{_cut(table)}] {name}" if table else name
        elif c in "]}":
            depth = max(0, depth - 1)
        elif c == "=" and depth == 0:
            key = text[start:i].strip()
        elif c == "\n" and depth == 0:
            start = i + 1
        i += 1


def _key_at(text, pos):
    """The "[table] key" of the statement around ``pos`` (for messages only)."""
    head = text[:pos]
    tables = re.findall(r"^[ \t]*\[+[ \t]*([^\[\]\n]+?)[ \t]*\]+", head, re.M)
    keys = re.findall(r"^[ \t]*([A-Za-z0-9_.\-\"' ]+?)[ \t]*=", head, re.M)
    key = _cut(keys[-1]) if keys else "(value)"
    return f"[{_cut(tables[-1])}] {key}" if tables else key


_SPECIAL = re.compile(r"[\"'#\[\]{}=\n]")
_STOP_TABLE = re.compile(r"^[ \t]*\[[ \t]*stop[ \t]*\]", re.M)
_STOP_TABLES = re.compile(r"^[ \t]*\[\[[ \t]*stop[ \t]*\]\]", re.M)


def loads(text, source="<model>"):
    """A :class:`Model` from model file text (see the module docstring)."""
    if len(text) > MAX_BYTES:
        raise ModelFileError(source, "", f"larger than {MAX_BYTES} bytes; a model file "
                             "(N <= 8) is a few KB")
    deep = _too_deep(text)
    if deep is not None:
        raise ModelFileError(source, deep, f"arrays nested more than {MAX_DEPTH} deep; "
                             "valid: a list of numbers or a list of rows")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        if _STOP_TABLE.search(text) and _STOP_TABLES.search(text):
            raise ModelFileError(source, "[stop]", "both [stop] and [[stop]] given; valid: one "
                                 "[stop] table, or one [[stop]] table per stop") from None
        raise ModelFileError(source, "", f"malformed TOML: {_cut(str(exc), 160)}") from None
    except ValueError as exc:              # e.g. an integer of more than 4300 digits
        m = re.search(r"\d{4000,}", text)
        if m:
            raise ModelFileError(source, _key_at(text, m.start()),
                                 f"a number of {len(m.group())} digits; valid: a finite real "
                                 "number (entries |a| <= 1e6)") from None
        raise ModelFileError(source, "", f"unreadable TOML value: {_cut(str(exc), 80)}") \
            from None
    except RecursionError:                 # not reached after _too_deep; kept as a guard
        raise ModelFileError(source, "", "nested too deeply to be a model file") from None
    return model_from_dict(data, source)


def load_model(path):
    """Read a model file (TOML); see the module docstring for the format.

    A ``[model]`` table with ``mass`` (the diagonal, or a matrix as a list of rows),
    ``stiffness``, optional ``damping`` and ``forcing``, as :class:`Model` takes them;
    then one ``[stop]`` table (``mass``, ``gap``, ``restitution``) or one ``[[stop]]``
    table per stop (the fields of :class:`Stop`: ``mass`` or ``between``, ``gap``,
    ``side``, ``restitution`` or ``stiffness`` and ``damping``).  Sizes are bounded
    before anything is allocated: at most 1 MiB, arrays nested at most 8 deep, at most
    64 stops, N <= 8.

    Parameters
    ----------
    path : str or os.PathLike
        The model file: a regular file of UTF-8 TOML text.

    Returns
    -------
    Model

    Raises
    ------
    symvi.model.ModelFileError
        A :class:`ParameterError` whose one-line message names the file and the key: no such
        file, a directory, unreadable, not UTF-8, larger than 1 MiB, invalid TOML, an
        unknown or missing key, or a value the :class:`Model` or :class:`Stop`
        constructor refuses.

    Examples
    --------
    >>> import os, tempfile
    >>> from symvi import load_model
    >>> path = os.path.join(tempfile.mkdtemp(), "one.toml")
    >>> with open(path, "w") as f:
    ...     _ = f.write('''
    ... [model]
    ... mass = [1.0]
    ... stiffness = [[1.0]]
    ... damping = [[0.05]]
    ... forcing = [1.0]
    ...
    ... [stop]
    ... mass = 1
    ... gap = 0.0
    ... restitution = 0.8
    ... ''')
    >>> load_model(path)
    Model(mass=[[1.0]], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
          stop=Stop(mass=1, gap=0.0, restitution=0.8))
    """
    try:
        st = os.stat(path)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(path)
        if not stat.S_ISREG(st.st_mode):
            raise ModelFileError(path, "", "not a regular file (a model file is TOML text)")
        if st.st_size > MAX_BYTES:
            raise ModelFileError(path, "", f"larger than {MAX_BYTES} bytes; a model file "
                                 "(N <= 8) is a few KB")
        with open(path, "rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
        text = raw.decode("utf-8")
    except ModelFileError:
        raise
    except FileNotFoundError:
        raise ModelFileError(path, "", "no such file") from None
    except IsADirectoryError:
        raise ModelFileError(path, "", "is a directory, not a model file") from None
    except PermissionError:
        raise ModelFileError(path, "", "permission denied") from None
    except UnicodeDecodeError:
        raise ModelFileError(path, "", "not UTF-8 text") from None
    except (OSError, ValueError) as exc:   # a name too long, a NUL in the path, ...
        raise ModelFileError(path, "", f"cannot be read ({exc.__class__.__name__}: "
                             f"{_cut(str(exc), 80)})") from None
    return loads(text, path)


def dumps(model):
    """The model file text of ``model`` (round-trips through :func:`load_model`)."""
    def mat(a):
        return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in row) + "]"
                               for row in a) + "]"
    def value(v):
        if isinstance(v, str):
            return f'"{v}"'
        return "[" + ", ".join(map(str, v)) + "]" if isinstance(v, list) else repr(v)
    lines = ["[model]", f"mass = {mat(model.mass)}", f"stiffness = {mat(model.stiffness)}"]
    if model.damped:
        lines.append(f"damping = {mat(model.damping)}")
    lines.append(f"forcing = [{', '.join(repr(float(x)) for x in model.forcing)}]")
    d = model.as_dict()
    if "nonlinear" in d:                   # the forces' texts as given (checked: no quotes)
        lines.append("nonlinear = [" + ", ".join(f'"{t}"' for t in d["nonlinear"]) + "]")
        lines += ["", "[model.parameters]"]
        lines += [f"{k} = {v!r}" for k, v in d["parameters"].items()]
    stops = model.as_dict()["stop"]        # one table for today's stop, else [[stop]]
    for t in (stops if isinstance(stops, list) else [stops]):
        lines += ["", "[[stop]]" if isinstance(stops, list) else "[stop]"]
        lines += [f"{k} = {value(v)}" for k, v in t.items()]
    return "\n".join(lines + [""])
