"""Error types shared by every symvi module.

Every failure a user can provoke is one of these, carrying a one-line message
that names the offending parameter and its valid range.
"""


class SymviError(Exception):
    """Base class of all symvi errors; the CLI turns it into exit code 2."""


class ParameterError(SymviError, ValueError):
    """A parameter is out of its valid range.

    Attributes
    ----------
    name : the parameter's name as the user wrote it.
    valid : the valid range, in words.
    """

    def __init__(self, name, value, valid, detail=""):
        self.name = name
        self.value = value
        self.valid = valid
        self.detail = detail

        def plain(v):
            # numpy scalars and arrays as plain Python numbers and lists: one line, no
            # np.float64(...) reprs
            if hasattr(v, "tolist") and hasattr(v, "dtype"):
                return v.tolist()
            if isinstance(v, (tuple, list)):
                return type(v)(plain(x) for x in v)
            return v
        msg = f"{name} = {plain(value)!r} is invalid; valid range: {valid}"
        if detail:
            msg += f" ({detail})"
        super().__init__(msg)

    def renamed(self, names):
        """The same error with library keys replaced by what the user typed (``names``:
        {"omega_min": "--omega-min", ...}), in the name, the range and the detail."""
        if self.name not in names:
            return self

        import re

        def sub(text):
            # whole words only: omega_1 is not omega
            for key, flag in names.items():
                text = re.sub(rf"(?<![\w-]){re.escape(key)}(?!\w)", flag, text)
            return text
        return ParameterError(names[self.name], self.value, sub(self.valid), sub(self.detail))


class ConvergenceError(SymviError):
    """Newton did not converge; ``residual`` is the smallest residual reached."""

    def __init__(self, message, residual):
        self.residual = residual
        super().__init__(message)


class SingularCaseError(SymviError):
    """The problem is singular at this point (resonance, grazing, λ^m = 1, ...).

    ``kind`` is a short machine-readable tag such as ``"forcing-resonance"``.
    """

    def __init__(self, kind, message):
        self.kind = kind
        super().__init__(f"{kind}: {message}")


class NearSingularWarning(UserWarning):
    """The problem is close to a singular case; results may lose digits."""


class OutputError(SymviError):
    """An output could not be written (special file, full disk, unwritable folder); the
    target is left as it was."""
