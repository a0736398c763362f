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

_MODEL_KEYS = {"mass", "stiffness", "damping", "forcing"}
_STOP_KEYS = {"mass", "gap", "restitution"}


class ModelFileError(ParameterError):
    """A model file that cannot be read or does not describe a valid model."""

    def __init__(self, path, key, message):
        self.path, self.key = str(path), key
        shown = _cut(self.path, 120)
        Exception.__init__(self, f"{shown}: {key}: {message}" if key else f"{shown}: {message}")
        self.name, self.value, self.valid = key, None, message


def _key_of(field):
    """The file key of a constructor field name."""
    if field.startswith("stop."):
        return "[stop] " + field[5:]
    return "[model] " + field


def model_from_dict(data, source="<model>"):
    """A :class:`Model` from the parsed tables ``{"model": {...}, "stop": {...}}``."""
    if not isinstance(data, dict):
        raise ModelFileError(source, "", "expected the tables [model] and [stop]")
    unknown = set(data) - {"model", "stop"}
    if unknown:
        raise ModelFileError(source, _cut(sorted(map(str, unknown))[0]),
                             "unknown table; a model file has [model] and [stop]")
    for table, keys, required in (("model", _MODEL_KEYS, ("mass", "stiffness", "forcing")),
                                  ("stop", _STOP_KEYS, ("mass", "gap", "restitution"))):
        t = data.get(table)
        if t is None:
            raise ModelFileError(source, f"[{table}]", "missing table")
        if not isinstance(t, dict):
            raise ModelFileError(source, f"[{table}]", "must be a table of keys")
        for k in t:
            if k not in keys:
                raise ModelFileError(source, f"[{table}] {_cut(str(k))}",
                                     f"unknown key; valid keys: {', '.join(sorted(keys))}")
        for k in required:
            if k not in t:
                raise ModelFileError(source, f"[{table}] {k}", "missing (required)")
    m, s = data["model"], data["stop"]
    try:
        stop = Stop(mass=s["mass"], gap=s["gap"], restitution=s["restitution"])
        return Model(mass=m["mass"], stiffness=m["stiffness"], damping=m.get("damping"),
                     forcing=m["forcing"], stop=stop)
    except ParameterError as exc:
        # keep the range and the detail, not the value (the file holds it)
        detail = str(exc).split(f"valid range: {exc.valid}", 1)[-1]
        raise ModelFileError(source, _key_of(exc.name),
                             f"invalid; valid: {exc.valid}{detail}") from None


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
    """Read a model file (TOML); see the module docstring for the format."""
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
    s = model.stop
    lines = ["[model]", f"mass = {mat(model.mass)}", f"stiffness = {mat(model.stiffness)}"]
    if model.damped:
        lines.append(f"damping = {mat(model.damping)}")
    lines += [f"forcing = [{', '.join(repr(float(x)) for x in model.forcing)}]", "",
              "[stop]", f"mass = {s.mass}", f"gap = {s.gap!r}", f"restitution = {s.restitution!r}",
              ""]
    return "\n".join(lines)
