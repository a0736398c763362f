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
"""
import tomllib

from ..errors import ParameterError
from ._model import Model, Stop

_MODEL_KEYS = {"mass", "stiffness", "damping", "forcing"}
_STOP_KEYS = {"mass", "gap", "restitution"}


class ModelFileError(ParameterError):
    """A model file that cannot be read or does not describe a valid model."""

    def __init__(self, path, key, message):
        self.path, self.key = str(path), key
        Exception.__init__(self, f"{path}: {key}: {message}" if key else f"{path}: {message}")
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
        raise ModelFileError(source, sorted(unknown)[0],
                             "unknown table; a model file has [model] and [stop]")
    for table, keys, required in (("model", _MODEL_KEYS, ("mass", "stiffness", "forcing")),
                                  ("stop", _STOP_KEYS, ("mass", "gap", "restitution"))):
        t = data.get(table)
        if not isinstance(t, dict):
            raise ModelFileError(source, f"[{table}]", "missing table")
        for k in t:
            if k not in keys:
                raise ModelFileError(source, f"[{table}] {k}",
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
        raise ModelFileError(source, _key_of(exc.name),
                             f"invalid; valid: {exc.valid}"
                             + (f" ({str(exc).split(' (', 1)[1]}" if " (" in str(exc)
                                and str(exc).endswith(")") else "")) from None


def load_model(path):
    """Read a model file (TOML); see the module docstring for the format."""
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise ModelFileError(path, "", "no such file") from None
    except IsADirectoryError:
        raise ModelFileError(path, "", "is a directory, not a model file") from None
    except PermissionError:
        raise ModelFileError(path, "", "permission denied") from None
    except UnicodeDecodeError:
        raise ModelFileError(path, "", "not UTF-8 text") from None
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(path, "", f"malformed TOML: {exc}") from None
    return model_from_dict(data, path)


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
