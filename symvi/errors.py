"""Error types shared by every symvi module.

Every failure a user can provoke is one of these, carrying a one-line message
that names the offending parameter and its valid range.
"""


class SymviError(Exception):
    """Base class of all symvi errors; the CLI turns it into exit code 2.

    Catch it to handle every failure a user can provoke in one place: a
    :class:`ParameterError` (an input out of its valid range), a
    :class:`SingularCaseError` (a singular problem), a non-converged Newton.

    Examples
    --------
    >>> import symvi
    >>> try:
    ...     symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=1.2)
    ... except symvi.SymviError as exc:
    ...     print(exc)
    r = 1.2 is invalid; valid range: 0 < r <= 1
    """


class ParameterError(SymviError, ValueError):
    """A parameter is out of its valid range.

    Also a :class:`ValueError`.  The message is one line,
    ``"<name> = <value> is invalid; valid range: <valid> (<detail>)"``.

    Parameters
    ----------
    name : str
        The parameter's name as the user wrote it (``"omega"``, ``"stop[2].gap"``,
        ``"--omega-min"``).
    value : object
        The value given (shown in the message).
    valid : str
        The valid range, in words.
    detail : str, optional
        Why the value is invalid, when the range alone does not say (default ``""``:
        nothing added).

    Attributes
    ----------
    name : str
        The parameter's name as the user wrote it.
    value : object
        The value given.
    valid : str
        The valid range, in words.
    detail : str
        The extra reason, or ``""``.

    Examples
    --------
    >>> from symvi import ParameterError, Stop
    >>> try:
    ...     Stop(mass=1, gap=0.5, restitution=0.0)
    ... except ParameterError as exc:
    ...     print(exc.name, "|", exc.valid)
    stop.restitution | 0 < restitution <= 1
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

    The message is ``"<kind>: <message>"``, one line.

    Parameters
    ----------
    kind : str
        A short machine-readable tag, e.g. ``"forcing-resonance"`` (omega at an undamped
        natural frequency), ``"one-minus-cos"`` (an undamped mode's period divides the
        orbit's, eq. (15): the orbit is not isolated), ``"degenerate-forcing"``,
        ``"grazing"``, ``"no-orbit"``, ``"no-admissible-orbit"``,
        ``"two-admissible-orbits"``, ``"multiplier-one"``.
    message : str
        What is singular, and what to change.

    Attributes
    ----------
    kind : str
        The tag given.

    Examples
    --------
    >>> import symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> w1 = symvi.modal(p).omega1          # a natural frequency: eq. (7) is infinite
    >>> try:
    ...     symvi.period1_orbits(p, w1)
    ... except symvi.SingularCaseError as exc:
    ...     print(exc.kind)
    forcing-resonance
    """

    def __init__(self, kind, message):
        self.kind = kind
        super().__init__(f"{kind}: {message}")


class NearSingularWarning(UserWarning):
    """The problem is close to a singular case; results may lose digits.

    A :class:`UserWarning`, issued with the number of digits lost, e.g. where omega lies
    within 1e-4 (relative) of an undamped natural frequency, where the stop's mass is
    near an anti-resonance, or near a multiplier at +1.  Filter it with :mod:`warnings`
    like any other warning.
    """


class OutputError(SymviError):
    """An output could not be written (special file, full disk, unwritable folder); the
    target is left as it was."""
