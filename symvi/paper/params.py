"""System parameters and modal analysis, eqs. (3)–(8).

The non-dimensional model of eq. (3), with the second derivative the printed
equation drops (``\\dot x`` there is a typo for ``\\ddot x``)::

    M x'' + K x = P sin(omega t + tau),   x1 < b,
    M = diag(1, mu_m),  K = [[1, -1], [-1, 1 + mu_k]],  P = (1 - f2, f2).

Modal matrix ``psi`` is mass-normalised, ``psi^T M psi = I`` and
``psi^T K psi = Lambda = diag(omega1^2, omega2^2)`` with ``omega1 < omega2``;
the first row of ``psi`` is positive (our sign convention).
"""
import functools
from dataclasses import dataclass

from ..numerics.backend import FLOAT64
from ..model import _preset
from ..model._preset import MU_RANGE as MU_RANGE
from ..model._preset import finite as _finite
# the old module-level names of the shared tolerances (symvi.numerics.tolerances)
from ..numerics.tolerances import ABS_MAX as ABS_MAX
from ..numerics.tolerances import OMEGA_RANGE as OMEGA_RANGE
from ..numerics.tolerances import FORCING_RESONANCE_REFUSE as RESONANCE_REFUSE  # noqa: F401
from ..numerics.tolerances import FORCING_RESONANCE_WARN as RESONANCE_WARN  # noqa: F401


@dataclass(frozen=True)
class Params:
    """Non-dimensional parameters of the paper's two-mass model, eq. (4).

    Mass ratio, stiffness ratio, force split, gap and coefficient of restitution of
    ``M x'' + K x = P sin(omega t + tau)``, x1 < b, with M = diag(1, mu_m),
    K = [[1, -1], [-1, 1 + mu_k]], P = (1 - f2, f2) (eq. (3)).
    Validated on construction: mu_m > 0, mu_k > 0, 0 < r <= 1, all finite,
    and within the representable ranges MU_RANGE and ABS_MAX.  Frozen and hashable;
    every analysis takes it where it takes a :class:`symvi.Model`
    (:meth:`as_model`).

    Parameters
    ----------
    mu_m : float
        Mass ratio m2 / m1, 1e-6 <= mu_m <= 1e6 (MU_RANGE).
    mu_k : float
        Stiffness ratio k2 / k1 (k1 couples the masses, k2 holds mass 2 to the
        frame), 1e-6 <= mu_k <= 1e6.
    f2 : float
        Share of the forcing on mass 2 (mass 1 gets 1 - f2), ``abs(f2) <= 1e6``
        (ABS_MAX).
    b : float
        The gap: mass 1 meets the stop at x1 = b, ``abs(b) <= 1e6``.
    r : float
        Coefficient of restitution of the impact law v1+ = -r v1-, eq. (2),
        0 < r <= 1.

    Raises
    ------
    ParameterError
        A value not a finite real number or out of its range, naming it.

    Examples
    --------
    >>> from symvi import Params
    >>> p = Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)     # the paper's example 1
    >>> p
    Params(mu_m=2.0, mu_k=5.0, f2=0.0, b=1.5, r=0.8)
    >>> Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=1.2)
    Traceback (most recent call last):
    ...
    symvi.errors.ParameterError: r = 1.2 is invalid; valid range: 0 < r <= 1
    """

    mu_m: float
    mu_k: float
    f2: float
    b: float
    r: float

    def __post_init__(self):
        vals = _preset.values(self.mu_m, self.mu_k, self.f2, self.b, self.r)
        for name, v in vals.items():
            object.__setattr__(self, name, v)

    def as_model(self):
        """The same system as a :class:`symvi.Model` (``Model.luo_xie``), built once.

        What every analysis below the paper runs on (:meth:`symvi.Model.of`); the same
        Model object for equal Params (cached), so its flows and compiled constants are
        reused.

        Returns
        -------
        Model
            ``Model.luo_xie(mu_m, mu_k, f2, b, r)``.

        Examples
        --------
        >>> from symvi import Params
        >>> Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8).as_model()
        Model.luo_xie(mu_m=2.0, mu_k=5.0, f2=0.0, b=1.5, r=0.8)
        """
        return _as_model(self)

    def as_dict(self):
        return {"mu_m": self.mu_m, "mu_k": self.mu_k, "f2": self.f2,
                "b": self.b, "r": self.r}

    def key(self):
        """A stable tuple for hashing and caching."""
        return (self.mu_m, self.mu_k, self.f2, self.b, self.r)


@functools.lru_cache(maxsize=256)
def _as_model(params):
    # one Model per Params: its flows and compiled constants are cached by the model
    from ..model import Model
    return Model.luo_xie(**params.as_dict())


@dataclass(frozen=True)
class Modal:
    """Modal data of eqs. (5)–(8) in one arithmetic backend.

    ``psi[i][j]`` is psi_{i+1, j+1}; ``F[j] = psi_j^T P`` is the modal forcing
    (eq. 6); ``D = det psi`` (so ``psi^{-1} = adj(psi) / D``, as in eqs. 21–24).
    """

    omega1: object
    omega2: object
    psi: tuple
    F: tuple
    D: object

    @property
    def omegas(self):
        return (self.omega1, self.omega2)


def modal(params, lib=FLOAT64):
    """Eigenfrequencies and mass-normalised modes of eq. (3), eqs. (5)–(6).

    det(K - w^2 M) = 0 gives mu_m w^4 - (1 + mu_k + mu_m) w^2 + mu_k = 0.
    The mode for w_j^2 is (1, 1 - w_j^2) before normalisation.
    The modal matrix psi is mass-normalised, psi^T M psi = I and
    psi^T K psi = diag(omega1^2, omega2^2), omega1 < omega2, its first row positive.

    Parameters
    ----------
    params : Params
        The paper's parameters.
    lib : backend, optional
        The arithmetic: :data:`symvi.numerics.backend.FLOAT64` (the default, cached per
        Params) or an mpmath backend, ``symvi.numerics.backend.backend(digits)``.

    Returns
    -------
    Modal
        ``omega1``, ``omega2`` (the natural frequencies, ascending); ``psi``, with
        ``psi[i][j]`` = psi_{i+1, j+1}; ``F``, the modal forcing ``F[j] = psi_j^T P``
        (eq. (6)); ``D = det psi``.  Numbers in the backend's type.

    Examples
    --------
    >>> from symvi import Params, modal
    >>> md = modal(Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8))
    >>> round(md.omega1, 6), round(md.omega2, 6)
    (0.880486, 1.795757)
    >>> w = md.omega1 ** 2                                  # a root of the quartic
    >>> abs(2 * w ** 2 - (1 + 5 + 2) * w + 5) < 1e-12
    True
    """
    if lib is FLOAT64:
        return _modal_float(params)
    return _modal(params, lib)


@functools.lru_cache(maxsize=1024)
def _modal_float(params):
    # hot path of every jet and map evaluation; Params is frozen and hashable
    return _modal(params, FLOAT64)


def _modal(params, lib):
    mu_m, mu_k = lib.num(params.mu_m), lib.num(params.mu_k)
    s = 1 + mu_k + mu_m
    disc = lib.sqrt((mu_m - mu_k) ** 2 + 2 * (mu_m + mu_k) + 1)  # = sqrt(s^2 - 4 mu_m mu_k) > 0
    # smaller root via the product of roots: no cancellation
    w2_hi = (s + disc) / (2 * mu_m)
    w2_lo = mu_k / (mu_m * w2_hi)
    psi_cols = []
    for w2 in (w2_lo, w2_hi):
        u = 1 - w2
        nrm = lib.sqrt(1 + mu_m * u * u)
        psi_cols.append((1 / nrm, u / nrm))
    psi = ((psi_cols[0][0], psi_cols[1][0]), (psi_cols[0][1], psi_cols[1][1]))
    P = (1 - lib.num(params.f2), lib.num(params.f2))
    F = tuple(psi[0][j] * P[0] + psi[1][j] * P[1] for j in range(2))
    D = psi[0][0] * psi[1][1] - psi[0][1] * psi[1][0]
    return Modal(lib.sqrt(w2_lo), lib.sqrt(w2_hi), psi, F, D)


def check_omega(params, omega, name="omega", warn=True):
    """Validate a forcing frequency: finite, > 0 and not at a natural frequency (where A_j
    of eq. (7) is infinite): :meth:`symvi.flow.linear.LinearFlow.check_omega` of the
    preset's model, the one owner of the rule (refused at resonance, warned within a
    relative 1e-4)."""
    from ..flow import check_omega as check
    _finite(name, omega)                  # true, "1.5": not numbers (the flow's float() is lax)
    return check(params.as_model(), omega, name, warn=warn)
