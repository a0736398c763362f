"""Automatic precision: error estimates for float64 results, mpmath recomputation when needed.

Every float64 result of the chain (orbit y*, multipliers, v_c, d|lambda1|/dv,
l1) gets a relative-error estimate of the form

    rel_err = eps * (C_EVAL + kappa) [* cancellation]

* ``kappa`` is a relative condition number, the largest of

  - the **input condition**: the relative change of the result per relative
    change of each named parameter of the model (omega, the entries of M, K, C,
    P, the gap and r; for ``Params`` those of ``Model.luo_xie``), from the exact
    derivatives of :func:`symvi.codegen.jets.parameter_derivatives` (no
    perturbed re-solves).  Rounding an input, or an intermediate quantity
    computed from the inputs, moves the result by about kappa * eps.  This is
    what picks up forcing resonance, 1 - cos(2 pi omega_j / omega) -> 0 (eq. 15),
    the merging of the two branches (eq. 16) and grazing (eq. 30); the
    cancellation of the large steady-state terms near resonance, which no input
    derivative sees, is added from the period-1 solve itself;
  - the **linear-algebra condition**: the eigenvalue condition numbers
    1 / |y^H x| (unit left/right eigenvectors) times ||J|| / |lambda|, the
    condition numbers of I - A and e^{2 i theta} I - A (Kuznetsov's h11, h20),
    the eigenvector condition ||J|| / gap, and for l1 the cancellation
    factor (sum of the moduli of the terms of c1) / |l1|.

* ``C_EVAL`` covers the rounding of the generated code itself (a few hundred
  operations), or the **flow condition** when that is larger: the error of the
  modal flow e^{At} from the exact residual of its eigen-decomposition
  (:func:`_flow_condition`; a stiff mode, e.g. a light mass, makes it ~1e6, and no
  input condition sees it).  A condition that cannot be computed (NaN) is infinite:
  the result is then untrusted, with the reason.  C_EVAL was calibrated against
  mpmath at 50 digits
  (``tests/analysis/test_precision.py`` checks that the estimate bounds the
  true error).

When an estimate says fewer than ``MIN_DIGITS`` (= 8) significant digits are
trustworthy, :func:`auto_orbits` / :func:`auto_hopf_point` recompute with the
mpmath backend (``digits=`` of :func:`symvi.period1_orbits` and
:func:`symvi.jets.jet`) at ``MIN_DIGITS + log10(C_EVAL + kappa) + GUARD``
digits, re-estimate there, and say so in ``Estimate.note``.  A result whose
required precision exceeds ``MAX_DIGITS``, or whose condition is infinite (a
singular case within the perturbation), is returned with ``trusted=False`` and
``value=None``: it is never printed as a bare number.

Integration points (for the owners of hopf.py and the CLI)
---------------------------------------------------------
* ``estimate_orbit(params, orbit)`` -> :class:`OrbitEstimate` (``.y``,
  ``.multipliers``: :class:`Estimate`).
* ``auto_orbits(params, omega)`` -> list of :class:`AutoOrbit` (orbit at the
  precision used, estimate, note).
* ``estimate_hopf_point(params, omega_c, branch=None)`` -> :class:`HopfEstimate`
  (``.omega_c``, ``.dmod_domega``, ``.l1``).
* ``auto_hopf_point(params, omega_c, branch=None, refine=None)`` -> the same,
  recomputed at mpmath precision when needed; ``refine(params, omega, digits,
  branch)`` may be hopf.py's own high-precision root polish.
"""
import contextlib
import math
import warnings
from dataclasses import dataclass, field

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError, SymviError
#: float64 unit roundoff used throughout (2^-52)
from ..numerics.tolerances import EPS64

#: significant digits below which a result is recomputed at higher precision
MIN_DIGITS = 8
#: largest mpmath precision tried before a result is declared untrustworthy
MAX_DIGITS = 160
#: extra digits added to the estimated requirement
GUARD = 6
#: rounding constant of the generated evaluators (calibrated, see module doc)
C_EVAL = 256.0


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class Estimate:
    """One result with its estimated relative error.

    ``value`` is the number (float, complex, or a list for vectors; mpf/mpc
    when recomputed with mpmath), or ``None`` when ``trusted`` is False.
    ``rel_err`` is normwise for vectors.  ``condition`` is the relative
    condition number kappa (precision independent).  ``digits_used`` is None
    for float64, else the mpmath precision.
    """

    name: str
    value: object
    rel_err: float
    condition: float
    digits_used: object = None
    trusted: bool = True
    recomputed: bool = False
    note: str = ""
    raw: object = None        # the untrusted number, for diagnostics only

    @property
    def backend(self):
        return "float64" if self.digits_used is None else f"mpmath-{self.digits_used}"

    @property
    def digits(self):
        """Trustworthy significant digits (0 when untrusted)."""
        if not self.trusted or not math.isfinite(self.rel_err):
            return 0.0
        cap = 15.95 if self.digits_used is None else float(self.digits_used)
        if self.rel_err <= 0:
            return cap
        return max(0.0, min(cap, -math.log10(self.rel_err)))

    def __float__(self):
        if not self.trusted:
            raise SingularCaseError("untrusted", f"{self.name} cannot be trusted: {self.note}")
        return float(complex(self.value).real) if not isinstance(self.value, (list, tuple)) \
            else float("nan")

    def as_dict(self):
        """JSON shape: value is null when untrusted; complex numbers as [re, im]."""
        def conv(v):
            if isinstance(v, (list, tuple, np.ndarray)):
                return [conv(x) for x in v]
            z = complex(v)
            return [z.real, z.imag] if z.imag != 0 or isinstance(v, (complex, mpmath.mpc)) \
                else z.real
        return {"name": self.name, "value": None if not self.trusted else conv(self.value),
                "rel_err": _json_float(self.rel_err), "digits": round(self.digits, 2),
                "condition": _json_float(self.condition), "backend": self.backend,
                "recomputed": self.recomputed, "trusted": self.trusted, "note": self.note}

    def text(self, fmt=".10g"):
        """A short human-readable form: value, digits and backend, or UNTRUSTED."""
        if not self.trusted:
            return f"{self.name}: UNTRUSTED ({self.note})"
        v = self.value
        vs = (", ".join(format(complex(x).real, fmt) for x in v)
              if isinstance(v, (list, tuple)) else format(float(complex(v).real), fmt))
        extra = f", recomputed with {self.backend}" if self.recomputed else ""
        return f"{self.name} = {vs}  (~{self.digits:.1f} digits{extra})"


def _json_float(x):
    x = float(x)
    return x if math.isfinite(x) else None


@dataclass(frozen=True)
class OrbitEstimate:
    """Error estimates of a period-1 orbit: fixed point y* and multipliers."""

    y: Estimate
    multipliers: Estimate
    g_theta: float            # dg/d(dtheta) at the orbit (grazing margin, eq. 30)
    eig_condition: tuple      # 1/|y^H x| per multiplier, in the orbit's order
    input_condition: dict     # input name -> relative condition of y*
    input_condition_multipliers: dict = field(default_factory=dict)

    @property
    def digits(self):
        return min(self.y.digits, self.multipliers.digits)

    @property
    def trusted(self):
        return self.y.trusted and self.multipliers.trusted


@dataclass(frozen=True)
class AutoOrbit:
    """An orbit at the precision that was needed, with its estimate."""

    orbit: object
    estimate: OrbitEstimate
    digits_used: object       # None (float64) or the mpmath precision
    note: str


@dataclass(frozen=True)
class HopfEstimate:
    """Error estimates of a Hopf (Neimark–Sacker) point: v_c, d|lambda1|/dv, l1."""

    omega_c: Estimate
    dmod_domega: Estimate
    l1: Estimate
    branch: str = None

    @property
    def trusted(self):
        return self.omega_c.trusted and self.dmod_domega.trusted and self.l1.trusted

    @property
    def digits(self):
        return min(self.omega_c.digits, self.dmod_domega.digits, self.l1.digits)

    def as_dict(self):
        return {"omega_c": self.omega_c.as_dict(), "dmod_domega": self.dmod_domega.as_dict(),
                "l1": self.l1.as_dict()}


# --------------------------------------------------------------------------- helpers
def _eps(digits):
    """Unit roundoff of the backend: 2^-52 for float64, 10^(1 - digits) for mpmath."""
    return EPS64 if digits is None else 10.0 ** (1 - digits)


def _digits_needed(kappa, min_digits):
    return int(math.ceil(min_digits + math.log10(C_EVAL + kappa) + GUARD))


def _mp_eig_condition(J):
    """Eigenvalues and condition numbers 1/|y^H x| (unit vectors), float or mpmath."""
    if J.dtype == object:
        M = mpmath.matrix(J.tolist())
        E, L, R = mpmath.eig(M, left=True, right=True)
        n = M.rows
        conds = []
        for i in range(n):
            x = [R[k, i] for k in range(n)]
            y = [L[i, k] for k in range(n)]      # left eigenvectors are rows of L
            nx = mpmath.sqrt(sum(abs(c) ** 2 for c in x))
            ny = mpmath.sqrt(sum(abs(c) ** 2 for c in y))
            yx = abs(sum(y[k] * x[k] for k in range(n)))
            conds.append(float(nx * ny / yx) if yx != 0 else math.inf)
        return [complex(e) for e in E], conds
    import scipy.linalg
    w, vl, vr = scipy.linalg.eig(J, left=True, right=True)
    conds = []
    for i in range(len(w)):
        x, y = vr[:, i], vl[:, i]
        yx = abs(np.vdot(y, x))
        conds.append(float(np.linalg.norm(x) * np.linalg.norm(y) / yx) if yx else math.inf)
    return [complex(e) for e in w], conds


def _match(vals, ref):
    """Reorder numeric ``vals`` to best match ``ref`` (greedy nearest)."""
    vals = [complex(v) for v in vals]
    out = []
    for r in ref:
        k = min(range(len(vals)), key=lambda i: abs(vals[i] - complex(r)))
        out.append(vals.pop(k))
    return out


def _orbit_on(params, omega, branch, digits, multipliers, admissible=True):
    from ..model import Model
    from ..orbits import period1_orbits
    for o in period1_orbits(Model.of(params), omega, digits=digits, multipliers=multipliers):
        if o.branch == branch:
            if admissible and not o.admissible:
                raise SingularCaseError("inadmissible", o.reason)
            return o
    raise SingularCaseError("no-orbit", "the branch does not exist here")


# --------------------------------------------------------------------------- orbits
def estimate_orbit(params, orbit, *, input_condition=True, reuse=None):
    """Error estimate of an orbit's y* and multipliers, at the orbit's own precision.

    The paper's model is estimated as ``Model.luo_xie`` by :func:`estimate_model_orbit`
    (exact input condition from the derivatives with respect to every named
    parameter, no perturbed re-solves); ``input_condition`` is kept for callers of
    the earlier perturbation estimate, which it switched off: the exact one is cheap
    and always computed.  ``reuse``: an earlier estimate of the same orbit.
    """
    from ..model import Model
    return estimate_model_orbit(Model.of(params), orbit, reuse=reuse)


def _graze_factor(y, g_theta):
    """max(1, |y*|_inf / |dg/d(dtheta)|): amplification of rounding by eq. (37) near grazing."""
    g = abs(complex(g_theta))
    scale = _worst(abs(complex(v)) for v in y[:3])
    return math.inf if g == 0 or math.isnan(g) else _worst([scale / g], 1.0)


def _worst(values, default=0.0):
    """max() that lets no NaN through: a condition that could not be computed (NaN) is
    infinite.  (Python's max keeps its first argument when compared with NaN.)"""
    out = default
    for v in values:
        v = float(v)
        if math.isnan(v):
            return math.inf
        out = max(out, v)
    return out


def _make(name, value, err, kappa, digits, note, recomputed=False):
    err, kappa = float(err), float(kappa)
    if math.isnan(err) or math.isnan(kappa):
        # an estimate that cannot be computed is no estimate: untrusted, saying so
        err = kappa = math.inf
        note = note or "the condition number could not be computed (NaN)"
    trusted = math.isfinite(err) and err < 1
    if not trusted and not note:
        note = f"estimated relative error {err:.1e}"
    return Estimate(name, value if trusted else None, float(err), float(kappa), digits,
                    trusted, recomputed, note, raw=None if trusted else value)


def auto_orbits(params, omega, *, min_digits=MIN_DIGITS, max_digits=MAX_DIGITS):
    """Every period-1 orbit at omega with at least ``min_digits`` trustworthy digits.

    Admissible orbits whose float64 estimate falls short are recomputed with
    mpmath at the digits the condition number asks for (escalating up to
    ``max_digits``); ``AutoOrbit.note`` says so.  An orbit that cannot reach
    ``min_digits`` at ``max_digits`` keeps ``estimate.trusted == False``.
    Inadmissible orbits are returned with their float64 estimate only.
    """
    from ..model import Model
    return auto_model_orbits(Model.of(params), omega, min_digits=min_digits,
                             max_digits=max_digits)


def _per_digits(solve):
    """recompute(branch, digits) for :func:`_auto_orbits`: ``solve(digits)`` (every
    branch at once) is called once per precision, not once per branch (near forcing
    resonance one mpmath solve costs a minute: its first-impact search takes tiny
    steps)."""
    done = {}

    def recompute(branch, d):
        if d not in done:
            done[d] = {o.branch: o for o in solve(d)}
        o = done[d].get(branch)
        if o is None:
            raise SingularCaseError("no-orbit", "the branch does not exist here")
        return o
    return recompute


def _auto_orbits(orbits, estimate, recompute, min_digits, max_digits):
    """Each orbit with its estimate, recomputed at higher precision where needed
    (``estimate(orbit, reuse)``, ``recompute(branch, digits)``; any chain)."""
    out = []
    for o in orbits:
        est = estimate(o, None)
        if _enough(o, est, min_digits):
            out.append(AutoOrbit(o, est, None, "float64"))
            continue
        out.append(_escalate_orbit(o, est, estimate, recompute, min_digits, max_digits))
    return out


def _enough(o, est, min_digits):
    """y* always needs min_digits; multipliers only for an admissible orbit.  A float64
    verdict of grazing is decided within a rounding tolerance (END_TOL of
    :mod:`symvi.orbits.admissibility`), whatever y*'s digits: mpmath settles it."""
    if o.digits is None and "grazing" in o.reason:
        return False
    return est.y.digits >= min_digits and (not o.admissible or
                                           est.multipliers.digits >= min_digits)


def _escalate_orbit(o, est, estimate, recompute, min_digits, max_digits):
    kappa = max(est.y.condition, est.multipliers.condition)
    if not math.isfinite(kappa):
        msg = est.y.note or est.multipliers.note or "infinite condition"
        return AutoOrbit(o, _untrust(est, msg), None, "untrusted: " + msg)
    d = max(30, _digits_needed(kappa, min_digits))
    tried = []
    while d <= max_digits:
        tried.append(d)
        try:
            o2 = recompute(o.branch, d)
        except SingularCaseError as exc:
            return AutoOrbit(o, _untrust(est, f"mpmath-{d}: {exc}"), None,
                             f"untrusted: {exc}")
        est2 = estimate(o2, est)
        if _enough(o2, est2, min_digits):
            note = (f"float64 gave ~{est.y.digits:.1f} digits; recomputed with mpmath at "
                    f"{d} digits (~{est2.y.digits:.1f} digits)")
            if o2.admissible != o.admissible:
                note += (f"; admissibility corrected: float64 said "
                         f"{'admissible' if o.admissible else 'inadmissible (' + o.reason + ')'}"
                         f", mpmath says {'admissible' if o2.admissible else 'inadmissible'}")
            est2 = OrbitEstimate(_re(est2.y, note), _re(est2.multipliers, note), est2.g_theta,
                                 est2.eig_condition, est2.input_condition,
                                 est2.input_condition_multipliers)
            return AutoOrbit(o2, est2, d, note)
        kappa = max(est2.y.condition, est2.multipliers.condition, kappa * 10)
        d = max(2 * d, _digits_needed(kappa, min_digits))
    msg = (f"fewer than {min_digits} trustworthy digits even at mpmath {tried} digits "
           f"(condition {kappa:.1e})")
    return AutoOrbit(o, _untrust(est, msg), None, "untrusted: " + msg)


def _re(e, note):
    return Estimate(e.name, e.value, e.rel_err, e.condition, e.digits_used, e.trusted, True,
                    note if not e.note else f"{note}; {e.note}")


def _untrust(est, msg):
    def u(e):
        return Estimate(e.name, None, math.inf, e.condition, e.digits_used, False, False, msg,
                        raw=e.value if e.value is not None else e.raw)
    return OrbitEstimate(u(est.y), u(est.multipliers), est.g_theta, est.eig_condition,
                         est.input_condition, est.input_condition_multipliers)


# --------------------------------------------------------------------------- Hopf points
def _hopf_quantities(params, omega, branch, digits):
    """(|lambda1| - 1, d|lambda1|/dv, l1, extras) at omega on ``branch`` (jet order 3)."""
    from ..normal_forms import normal_form as nf
    from ..codegen.jets import jet_of_orbit
    from ..model import Model
    o = _orbit_on(params, omega, branch, digits, False)
    jt = jet_of_orbit(Model.of(params), o, 3)
    kw = {} if digits is None else {"digits": digits}
    ctx = mpmath.mp.workdps(digits) if digits else contextlib.nullcontext()
    with ctx:
        e = nf.eigen(jt.jacobian, **kw)
        _, dmod = nf.dmod_A3(jt.jacobian, jt.dA, **kw)
        _, l1 = nf.kuznetsov(jt.jacobian, jt.d2, jt.d3, **kw)
        resid = abs(e.lam) - 1
    return resid, dmod, l1, (jt, e)


def refine_omega_c(params, omega_c, *, digits=None, branch=None, tol_digits=None,
                   max_iter=30):
    """Newton polish of |lambda1(omega)| = 1 at the given precision, (H1):
    :func:`refine_model_omega_c` on ``Model.of(params)``.  Returns omega_c (float, or mpf
    at ``digits``).  ``tol_digits`` is accepted and, as before, unused: the polish runs
    to the working precision."""
    from ..model import Model
    from ..orbits import select_orbit
    if branch is None:
        branch = select_orbit(Model.of(params), float(omega_c)).branch
    return refine_model_omega_c(Model.of(params), omega_c, branch, digits, max_iter)


def estimate_hopf_point(params, omega_c, *, branch=None, digits=None, dmod=None, l1=None,
                        base=None):
    """Error estimates of (v_c, d|lambda1|/dv, l1) at a computed Hopf point.

    ``omega_c`` is the located root of |lambda1| = 1 (float64 or mpf at
    ``digits``).  The residual |lambda1(omega_c)| - 1 over d|lambda1|/dv is added
    to the error of omega_c (a root finder that stopped early shows up here).
    ``dmod``/``l1``, if given, are the values to attach (else computed here).
    ``base`` = (jet, normal form) already computed at ``omega_c`` (float64) by the
    caller: then nothing at the base point is computed again.  The conditions are
    those of any model (:func:`_model_estimate`, on ``Model.luo_xie`` for Params).
    """
    from ..model import Model
    from ..orbits import select_orbit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        if branch is None:
            branch = select_orbit(Model.of(params), float(omega_c)).branch
        est = _hopf_estimate(Model.of(params), omega_c, branch, digits,
                             base if digits is None else None)
    return HopfEstimate(est.omega_c, _attach(est.dmod_domega, dmod, digits),
                        _attach(est.l1, l1, digits), branch)


def _hopf_estimate(model, omega_c, branch, digits, base=None):
    """:func:`_model_estimate` at omega_c (float64 or ``digits``), the residual
    |lambda1(omega_c)| - 1 over d|lambda1|/dv added to the error of omega_c; ``base`` =
    (jet, normal form) already at hand there."""
    with mpmath.mp.workdps(digits) if digits else contextlib.nullcontext():
        w = mpmath.mpf(omega_c) if digits else float(omega_c)
        if base is not None:
            jt, nf = base
        else:
            _, jt, nf = _model_hopf_at(model, w, branch, digits)
        est = _model_estimate(model, w, branch, nf, jt, digits)
        resid = float(abs(abs(nf.lam) - 1))
    wc = est.omega_c
    err_vc = wc.rel_err + resid / max(abs(float(nf.dmod_dv)) * float(w), 1e-300)
    return HopfEstimate(_make("omega_c", w, err_vc, wc.condition, digits, wc.note),
                        est.dmod_domega, est.l1, branch)


def _attach(e, value, digits):
    """Estimate e with ``value`` (the caller's number for the same quantity) attached."""
    if value is None:
        return e
    return _make(e.name, value, e.rel_err, e.condition, digits, e.note)


def _linear_condition(jt, e, digits):
    """Linear-algebra condition numbers at the Hopf point (float estimates)."""
    J = np.array(jt.jacobian.tolist(), dtype=complex) if digits else jt.jacobian.astype(complex)
    Jn = float(np.linalg.norm(J, 2))
    vals, conds = _mp_eig_condition(J)
    lam = complex(e.lam)
    k = min(range(len(vals)), key=lambda i: abs(vals[i] - lam))
    gap = min(abs(vals[i] - lam) for i in range(len(vals)) if i != k)
    I = np.eye(len(J))
    c11 = float(np.linalg.cond(abs(lam) ** 2 * I - J))
    c20 = float(np.linalg.cond(lam * lam * I - J))
    q = np.array([complex(x) for x in e.q])
    p = np.array([complex(x) for x in e.p])
    dA = np.array(jt.dA.tolist(), dtype=complex) if digits else jt.dA.astype(complex)
    d2 = np.array(jt.d2.tolist(), dtype=complex) if digits else jt.d2.astype(complex)
    d3 = np.array(jt.d3.tolist(), dtype=complex) if digits else jt.d3.astype(complex)
    # size of the terms whose sum is d|lambda|/dv and c1 (cancellation factors)
    dmod_terms = float(np.linalg.norm(p) * np.linalg.norm(dA, 2) * np.linalg.norm(q))
    B = lambda u, v: np.einsum("ijk,j,k->i", d2, u, v)           # noqa: E731
    C = lambda u, v, w: np.einsum("ijkl,j,k,l->i", d3, u, v, w)  # noqa: E731
    qb = q.conj()
    h11 = np.linalg.solve(abs(lam) ** 2 * I - J, B(q, qb))
    h20 = np.linalg.solve(lam * lam * I - J, B(q, q))
    terms = [np.vdot(p, C(q, q, qb)), 2 * np.vdot(p, B(q, h11)), np.vdot(p, B(qb, h20))]
    l1_terms = 0.5 * float(sum(abs(t) for t in terms))
    return {"eig": conds[k] * Jn, "vec": max(conds[k], 1.0) * Jn / max(gap, 1e-300),
            "solve": c11 + c20, "dmod_terms": dmod_terms, "l1_terms": l1_terms, "gap": gap}


def auto_hopf_point(params, omega_c, *, branch=None, dmod=None, l1=None,
                    min_digits=MIN_DIGITS, max_digits=MAX_DIGITS, refine=None, base=None):
    """(v_c, d|lambda1|/dv, l1) with at least ``min_digits`` trustworthy digits each.

    Starts from the float64 values (``omega_c`` and optionally ``dmod``, ``l1``
    as computed by hopf.py).  When the estimate falls short, v_c is re-polished
    with mpmath at the digits the condition asks for (``refine(params, omega,
    digits, branch)`` if given, else :func:`refine_model_omega_c`) and all three are
    recomputed there; the notes say so (:func:`_escalate_hopf`, shared with
    :func:`estimate_model_hopf`).  Untrustworthy at ``max_digits``: returned with
    ``trusted=False`` and ``value=None``.
    """
    from ..model import Model
    from ..orbits import select_orbit
    if branch is None:
        branch = select_orbit(Model.of(params), float(omega_c)).branch
    est = estimate_hopf_point(params, omega_c, branch=branch, dmod=dmod, l1=l1, base=base)
    hook = None if refine is None else (lambda d: refine(params, omega_c, d, branch))
    return _escalate_hopf(Model.of(params), omega_c, branch, est, min_digits, max_digits, hook)


def _escalate_hopf(model, omega_c, branch, est, min_digits, max_digits, refine=None):
    """``est`` if it has ``min_digits``, else (v_c, d|lambda1|/dv, l1) recomputed with
    mpmath at the digits the condition asks for, v_c Newton-polished there first
    (``refine(digits)``, else :func:`refine_model_omega_c`), doubling up to
    ``max_digits``; else ``est`` untrusted, saying why."""
    if est.digits >= min_digits:
        return est
    kappa = max(est.omega_c.condition, est.dmod_domega.condition, est.l1.condition)
    if not math.isfinite(kappa):
        return _untrust_hopf(est, est.omega_c.note or "infinite condition")
    d, tried = max(30, _digits_needed(kappa, min_digits)), []
    while d <= max_digits:
        tried.append(d)
        try:
            with mpmath.mp.workdps(d):
                w = (refine(d) if refine is not None
                     else refine_model_omega_c(model, omega_c, branch, d))
            est2 = _hopf_estimate(model, w, branch, d)
        except SingularCaseError as exc:
            return _untrust_hopf(est, f"mpmath-{d}: {exc}")
        except (np.linalg.LinAlgError, ZeroDivisionError, ValueError) as exc:
            # the polish walked onto a singular map (e.g. the grazing point next to it)
            return _untrust_hopf(est, f"mpmath-{d}: the refinement met a singular map "
                                      f"({type(exc).__name__}: {exc})")
        if est2.digits >= min_digits:
            note = f"float64 gave ~{est.digits:.1f} digits; recomputed with mpmath at {d} digits"
            return HopfEstimate(_re(est2.omega_c, note), _re(est2.dmod_domega, note),
                                _re(est2.l1, note), branch)
        kappa = max(est2.omega_c.condition, est2.dmod_domega.condition, est2.l1.condition,
                    10 * kappa)
        if not math.isfinite(kappa):        # a singular case at d digits: more will not help
            return _untrust_hopf(est, f"mpmath-{d}: "
                                      f"{est2.omega_c.note or 'infinite condition'}")
        d = max(2 * d, _digits_needed(kappa, min_digits))
    return _untrust_hopf(est, f"fewer than {min_digits} digits even at mpmath {tried} digits "
                              f"(condition {kappa:.1e})")


def _untrust_hopf(est, msg):
    def u(e):
        if e.digits >= MIN_DIGITS:
            return e
        return Estimate(e.name, None, math.inf, e.condition, e.digits_used, False, False, msg,
                        raw=e.value if e.value is not None else e.raw)
    return HopfEstimate(u(est.omega_c), u(est.dmod_domega), u(est.l1), est.branch)


def auto(kind, params, omega, **kw):
    """Dispatcher for the CLI: ``auto("orbit", p, w)`` or ``auto("hopf", p, omega_c)``."""
    if kind == "orbit":
        return auto_orbits(params, omega, **kw)
    if kind == "hopf":
        return auto_hopf_point(params, omega, **kw)
    raise ParameterError("kind", kind, "'orbit' or 'hopf'")


# --------------------------------------------------------------------------- any model
def _model_inputs(model):
    """The named parameters whose rounding can move a result: the nonzero entries."""
    return [n for n in model.parameter_names()
            if n not in ("mu_m", "mu_k", "f2", "b", "r") and model.value(n) != 0]


def _model_hopf_at(model, w, branch, digits):
    """(orbit, jet, normal form) at omega on ``branch``, float64 or mpmath."""
    from ..codegen.jets import jet_at
    from ..normal_forms.normal_form import normal_form
    from ..orbits import period1_orbits
    o = {x.branch: x for x in period1_orbits(model, w, digits=digits)}.get(branch)
    if o is None or not o.admissible:
        raise SingularCaseError("no-admissible-orbit", f"branch {branch} is not admissible "
                                f"at omega = {float(w):.12g}")
    ctx = mpmath.mp.workdps(digits) if digits else contextlib.nullcontext()
    with ctx:
        T = 2 * mpmath.pi / w if digits else 2 * math.pi / w
        jt = jet_at(model, w, o.y, T, 3, digits=digits)
        # the estimate needs lambda1, p, q, d|lambda1|/dv and l1: not the paper's own
        # reduction (eq. (60)'s f1), which costs 40 % of an mpmath normal form
        nf = normal_form(jt.jacobian, jt.d2, jt.d3, jt.dA, paper=False,
                         **({"digits": digits} if digits else {}))
    return o, jt, nf


def _model_estimate(model, w, branch, nf, jt, digits):
    """HopfEstimate of (v_c, d|lambda1|/dv, l1) from the conditions (see the module doc).

    Input condition of v_c: exact, v_c' = -(d|lambda1|/dp) / (d|lambda1|/dv) for every
    named parameter p (:func:`symvi.codegen.jets.parameter_derivatives` along the
    fixed point); linear-algebra conditions as for the paper (:func:`_linear_condition`),
    amplified near grazing.
    """
    eps = _eps(digits)
    lin = _linear_condition(jt, nf, digits)
    gf = _graze_factor(jt.y, jt.g_theta)
    lin = {k: (v * gf if k in ("eig", "vec", "solve") else v) for k, v in lin.items()}
    lam = complex(nf.lam)
    p = np.array([complex(x) for x in nf.p])
    q = np.array([complex(x) for x in nf.q])
    dmod = float(nf.dmod_dv)
    wf = float(w)
    k_in, note = 1.0, ""
    T = 2 * math.pi / wf
    yf = tuple(float(v) for v in jt.y)
    for name in _model_inputs(model):
        try:
            d = _parameter_derivatives(model, wf, yf, T, name)
        except SymviError as exc:
            k_in, note = math.inf, f"{name}: {exc}"
            break
        with np.errstate(all="ignore"):
            dlam = np.vdot(p, np.asarray(d.dJ_branch, dtype=complex) @ q)
            dmod_p = (lam.conjugate() * dlam).real / abs(lam)
            k_in = _worst([k_in, abs(dmod_p / dmod) * abs(model.value(name)) / wf])
    # the jets' rounding: C_EVAL eps, or the flow's when a stiff mode makes it larger
    ev = _worst([C_EVAL, _flow_condition(model, T, digits)])
    k_vc = _worst([k_in, lin["eig"] * ev / max(abs(dmod) * wf, 1e-300)])
    err_vc = eps * (ev + k_vc)
    k_dm = _worst([k_in, lin["vec"] * lin["dmod_terms"] / max(abs(dmod), 1e-300)
                   * ev / C_EVAL])
    k_l1 = _worst([k_in, (lin["solve"] + lin["vec"]) * lin["l1_terms"]
                   / max(abs(float(nf.l1)), 1e-300) * ev / C_EVAL])
    if not note and not math.isfinite(max(k_vc, k_dm, k_l1)):
        note = "a condition number could not be computed"
    return HopfEstimate(_make("omega_c", w, err_vc, k_vc, digits, note),
                        _make("dmod_domega", nf.dmod_dv, eps * (ev + k_dm), k_dm, digits,
                              note),
                        _make("l1", nf.l1, eps * (ev + k_l1), k_l1, digits, note), branch)


def refine_model_omega_c(model, omega_c, branch, digits=None, max_iter=30):
    """Newton polish of |lambda1(omega)| = 1 for any model, (H1), on float64 or at
    ``digits`` (mpmath, working at digits + 10), with d|lambda1|/dv of eq. (A3) along
    the branch as the derivative (so convergence is quadratic)."""
    from ..normal_forms import normal_form as nfm
    from ..codegen.jets import jet_at
    from ..orbits import period1_orbits
    eps = _eps(digits)
    work = None if digits is None else digits + 10
    with mpmath.mp.workdps(work) if work else contextlib.nullcontext():
        w, prev = (mpmath.mpf(omega_c) if work else float(omega_c)), None
        two_pi = 2 * mpmath.pi if work else 2 * math.pi
        for _ in range(max_iter):
            o = {x.branch: x for x in period1_orbits(model, w, digits=work,
                                                      multipliers=False)}.get(branch)
            if o is None:
                raise SingularCaseError("no-admissible-orbit", f"branch {branch} does not "
                                        f"exist at omega = {float(w):.12g} (Newton polish)")
            jt = jet_at(model, w, o.y, two_pi / w, 2, digits=work)
            e = nfm.eigen(jt.jacobian, **({"digits": work} if work else {}))
            _, dmod = nfm._dmod(e, jt.dA)               # eq. (A3) on the same eigen-solve
            step = (abs(e.lam) - 1) / dmod
            if not (math.isfinite(float(step)) and float(dmod) != 0):
                raise SingularCaseError("no-convergence", "the Newton polish of "
                                        "|lambda1| = 1 met d|lambda1|/domega = "
                                        f"{float(dmod):.3g} at omega = {float(w):.12g}")
            w = w - step
            # converged, or stagnating at the rounding level (no longer quadratic)
            if abs(step) <= 4 * eps * abs(w) or (prev is not None and abs(step) >= prev / 2
                                                 and abs(step) < 1e-11 * abs(w)):
                break
            prev = abs(step)
        return +w


def estimate_model_hopf(model, omega_c, branch, nf, jt, *, min_digits=MIN_DIGITS,
                        max_digits=MAX_DIGITS):
    """(v_c, d|lambda1|/dv, l1) of any model with at least ``min_digits`` trustworthy
    digits each: the float64 estimate at the caller's (jet, normal form), else
    recomputed with mpmath (:func:`_escalate_hopf`), else untrusted."""
    est = _hopf_estimate(model, omega_c, branch, None, (jt, nf))
    return _escalate_hopf(model, omega_c, branch, est, min_digits, max_digits)


def estimate_model_orbit(model, orbit, *, reuse=None):
    """Error estimate of a period-1 orbit of any model: y* and multipliers.

    Input condition, exact: dy*/dp = (I - J)^{-1} dP/dp and, for each multiplier,
    d lambda/dp = u^H (dJ/dp along the orbit) v / u^H v, for every named parameter
    p and omega (:func:`symvi.codegen.jets.parameter_derivatives`); no perturbed
    re-solves.  Linear algebra: the eigenvalue condition numbers, amplified near
    grazing (eq. (37) divides by dg/d(dtheta)).  ``reuse``: an earlier estimate of
    the same orbit whose (precision independent) condition numbers are taken over.
    """
    from ..codegen.jets import jet_at
    digits = orbit.digits
    eps = _eps(digits)
    w = float(orbit.omega)
    T = 2 * math.pi / w
    yf = tuple(float(v) for v in orbit.y)
    lam = list(orbit.multipliers)
    lamc = np.array([complex(z) for z in lam])
    notes = []
    if reuse is not None:
        kin_y, kin_l = dict(reuse.input_condition), dict(reuse.input_condition_multipliers)
        g_theta, eig_conds = reuse.g_theta, reuse.eig_condition
    else:
        kin_y, kin_l = {}, {}
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", NearSingularWarning)
            try:
                jt = jet_at(model, w, yf, T, 1)
                J, g_theta = jt.jacobian, float(abs(jt.g_theta))
            except SingularCaseError as exc:
                J, g_theta = None, 0.0
                notes.append(str(exc))
            if J is not None and not np.isfinite(J).all():
                J, g_theta = None, 0.0
                notes.append("the Jacobian of the map is not finite in float64")
            if J is not None:
                vals, V = np.linalg.eig(J)
                U = np.linalg.inv(V)                       # rows: left eigenvectors, U V = I
                order = [int(np.argmin(np.abs(vals - z))) for z in lamc]
                ynorm = max(np.abs(yf).max(), 1e-300)
                for par in [model.parameter(nm) for nm in ["omega"] + _model_inputs(model)]:
                    name = par.name
                    v = w if par.is_forcing_frequency else abs(par.get(model))
                    try:
                        d = _parameter_derivatives(model, w, yf, T, name)
                    except SymviError as exc:
                        kin_y[name] = kin_l[name] = math.inf
                        notes.append(f"{name}: {exc}")
                        continue
                    kin_y[name] = float(np.abs(d.dy).max()) * v / ynorm
                    dJ = np.asarray(d.dJ_branch, dtype=float)
                    dl = [abs(U[k] @ dJ @ V[:, k]) for k in order]
                    kin_l[name] = _worst(x * v / max(abs(z), 1e-300) for x, z in zip(dl, lamc))
                _, conds = _mp_eig_condition(J)
                eig_conds = tuple(conds[k] for k in order)
            else:
                eig_conds = ()
    ky = _worst(kin_y.values(),
                math.inf if not kin_y and reuse is None and notes else 0.0)
    gf = _graze_factor(orbit.y, g_theta) if g_theta else math.inf
    # rounding of the solve itself: the steady-state terms ~ 1/|omega_j - omega| near
    # forcing resonance cancel in y* (the input condition cannot see that), and the
    # equilibrated period-1 system may be ill-conditioned (1 - cos -> 0)
    ky = _worst([ky, _model_solve_condition(model, w, yf)])
    # the rounding of the modal flow e^{At}: C_EVAL covers it unless a stiff mode makes
    # the eigen-decomposition itself inaccurate (:func:`_flow_condition`)
    ev = _worst([C_EVAL, _flow_condition(model, T, digits)])
    err_y = eps * (ev + ky)                # y* comes from the solve, not from the jet
    if eig_conds:
        kl = _worst([_worst(kin_l.values()), _worst(eig_conds) * ev * gf])
    else:
        kl = math.inf
    err_l = eps * (ev + kl)
    for what, k in (("y*", ky), ("the multipliers", kl)):
        if not math.isfinite(k) and not notes:
            notes.append(f"the condition number of {what} could not be computed")
    note = "; ".join(notes[:2])
    return OrbitEstimate(_make("y*", list(orbit.y), err_y, ky, digits, note),
                         _make("multipliers", lam, err_l, kl, digits, note),
                         g_theta, eig_conds, kin_y, kin_l)


#: mpmath digits at which a parameter derivative is recomputed when float64 overflows
COND_DIGITS = 20


def _parameter_derivatives(model, w, y, T, name):
    """:func:`symvi.codegen.jets.parameter_derivatives` in float64; recomputed with mpmath
    at ``COND_DIGITS`` (a condition number needs few digits) when float64 gives a
    non-finite value: e^{lambda t} of a stiff mode under- or overflows in the Fréchet
    derivative of e^{At}.  Raises SingularCaseError when even that is not finite."""
    from ..codegen.jets import ParameterDerivative, parameter_derivatives
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", NearSingularWarning)
        d = parameter_derivatives(model, w, y, T, name)
        if _finite_derivative(d):
            return d
        d = parameter_derivatives(model, w, y, T, name, digits=COND_DIGITS)
        d = ParameterDerivative(d.name, *(np.array(np.asarray(x).tolist(), dtype=float)
                                        for x in (d.dP, d.dJ, d.dy, d.dJ_branch)))
    if not _finite_derivative(d):
        raise SingularCaseError("condition", f"the derivative with respect to {name} is "
                                "not finite even with mpmath: its condition number cannot "
                                "be computed")
    return d


def _finite_derivative(d):
    return all(np.isfinite(np.asarray(x, dtype=complex)).all()
               for x in (d.dP, d.dJ, d.dy, d.dJ_branch))


_FLOW_COND = {}


def _flow_condition(model, t, digits=None):
    """Relative error of the flow e^{At} = W e^{Lambda t} W^-1 as computed (float64, or
    mpmath at ``digits``) over the unit roundoff :func:`_eps`, times 4.

    The computed modes (Lambda, W) are the exact modes of A - E with E = R W^-1, where
    R = A W - W Lambda is the residual of the computed eigen-decomposition, formed here
    with mpmath at twice the precision (no rounding).  The flow's error is then the
    Fréchet derivative W (G o (W^-1 R)) W^-1 of e^{At} in the direction E, G of
    :func:`symvi.codegen.layout.frechet_kernel` (the larger exponential factored out: a
    stiff mode's e^{lambda t} under- and overflows).  About 300 for a benign
    model; a stiff mode (a light mass, ||A|| ~ 1e8) raises it to ~1e6: the rounding of
    the eigen-decomposition is of order eps ||A||, which no named input's condition
    sees.  Against a 40-digit flow this predicts the flow's error within a few per
    cent, and y*'s error is about half of it (tests/analysis/test_model_precision.py);
    4 is the safety factor of :func:`_model_solve_condition`.  Infinite if it cannot be
    formed."""
    from ..codegen.layout import frechet_kernel
    from ..flow.linear import LinearFlow
    try:
        flow = LinearFlow.of(model, digits)
    except SymviError:
        return math.inf
    if digits is None:
        lam, W, Winv, A = flow.modal64
        key = (lam.tobytes(), W.tobytes(), A.tobytes(), float(t))
    else:
        lam, W, Winv, A = flow.lam, flow.W, flow.Winv, flow.A
        key = (model, digits, float(t))
    hit = _FLOW_COND.get(key)
    if hit is not None:
        return hit
    with mpmath.workdps(2 * (digits or 16) + 10):        # exact products of the data
        Am, Wm = mpmath.matrix(np.asarray(A).tolist()), mpmath.matrix(np.asarray(W).tolist())
        R = Am * Wm - Wm * mpmath.diag([mpmath.mpc(z) for z in lam])
        R = np.array(R.tolist(), dtype=complex)
    lam, W, Winv = (np.array(np.asarray(x).tolist(), dtype=complex) for x in (lam, W, Winv))
    with np.errstate(all="ignore"):
        lt = lam * float(t)
        G = frechet_kernel(lt, np.exp(lt), float(t))
        dPhi = W @ (G * (Winv @ R)) @ Winv
        Phi = ((W * np.exp(lt)) @ Winv).real
        rel = float(np.abs(dPhi).max() / np.abs(Phi).max())
    out = 4 * rel / _eps(digits) if math.isfinite(rel) else math.inf
    if len(_FLOW_COND) > 256:
        _FLOW_COND.clear()
    _FLOW_COND[key] = out
    return out


def _model_solve_condition(model, w, y):
    """4 max(largest steady-state term / |y*|, cond(equilibrated period-1 system)).

    Calibrated against a 40-digit reference on the paper's model: the float64 error
    of y* is 1.0-1.2 eps x the larger of the two near forcing resonance and near
    1 - cos -> 0 (tests/analysis/test_model_precision.py); 4 is the safety factor."""
    from ..orbits.period1 import _line
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        flow, L = _line(model, w, None)
    F = L.forcing
    with np.errstate(all="ignore"):
        big = _worst([np.abs(F.U).max(), np.abs(F.V).max()]) * max(1.0, w)
        cancel = _worst([big / max(float(np.abs(y[:-1]).max()), 1e-300)], 1.0)
        return 4 * _worst([cancel, L.sigma[0] / L.sigma[-1]])


def auto_model_orbits(model, omega, *, min_digits=MIN_DIGITS, max_digits=MAX_DIGITS):
    """Every period-1 orbit of ``model`` at omega with at least ``min_digits``
    trustworthy digits: float64 when its estimate allows, else mpmath at the digits
    the condition asks for; untrusted (value None) past ``max_digits``."""
    from ..orbits import period1_orbits
    return _auto_orbits(period1_orbits(model, omega),
                        lambda o, reuse: estimate_model_orbit(model, o, reuse=reuse),
                        _per_digits(lambda d: period1_orbits(model, omega, digits=d)),
                        min_digits, max_digits)
