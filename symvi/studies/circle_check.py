"""The invariant circle measured by simulation against the normal-form prediction.

For v = v_c + mu the Neimark–Sacker normal form (eqs. (56)–(60); :mod:`symvi.analysis.hopf`)
predicts a circle of radius ~ sqrt(mu) whose projection on each state
variable (x1dot+, x2, x2dot, tau) has half-width ``circle.half_widths(mu)``.
Here the circle is measured on the simulated section: half-width =
(max - min) / 2 of each coordinate over a block of impacts (tau about the
fixed point, wrapped), after the run has converged onto the circle.

Convergence is bracketed: one run starts just off the fixed point y*(v)
(inside the circle) and one starts outside it; both are continued block by
block until their half-widths agree to ``rtol``.  The attraction rate of the
circle is only ~2 d|lambda|/dv mu per impact, so near v_c this takes many
impacts; the bracket, not a fixed transient, decides when to stop.

The prediction is leading order: the relative error must be O(mu) (the
O(rho^3) terms of the half-width and the O(mu) drift of the fixed point's
Jacobian), so it must shrink ~linearly as mu -> 0.
"""
import math
from dataclasses import dataclass

import numpy as np

from ..errors import SingularCaseError
from ..flow import check_omega
from ..flow import compiled as cf
from ..model import Model
from ..simulations.simulation import fixed_point

NAMES = ("x1dot+", "x2", "x2dot", "tau")


@dataclass(frozen=True)
class Measurement:
    """Half-widths of the simulated circle at one omega."""

    omega: float
    half_widths: np.ndarray   # (4,) mean of the inside and outside runs
    spread: np.ndarray        # (4,) |inside - outside|: bound on the convergence error
    impacts: int              # map iterations used (both runs)
    converged: bool
    fixed_point: tuple


def _half_widths(sec, tau0):
    d = sec.copy()
    d[:, -1] = (d[:, -1] - tau0 + math.pi) % (2 * math.pi) - math.pi   # tau: last coordinate
    return (d.max(axis=0) - d.min(axis=0)) / 2


def measure(params, omega, *, block=4000, rtol=1e-4, max_impacts=4_000_000, kick=1e-6):
    """Measure the circle's half-widths at omega, bracketed from inside and outside.

    Where y* attracts (no circle) the run from y* + kick decays and the
    half-widths returned are those of the last block (converged when <= 1e-10).

    Raises SingularCaseError when a run leaves by grazing/chatter or no
    period-1 orbit exists.
    """
    omega = check_omega(params, omega)
    ys = fixed_point(params, omega)
    if ys is None:
        raise SingularCaseError("no-orbit", f"no admissible period-1 orbit at omega = {omega!r}")
    ys = np.array(ys)
    c = cf.constants(Model.of(params), omega)
    used = 0

    def advance(y):
        nonlocal used
        code, sec, _, _, _ = cf.run(c, y, block)
        used += block
        if code != cf.COMPLETED:
            raise SingularCaseError("circle-lost", f"run stopped ({cf.STOP_NAMES[code]}) at "
                                    f"omega = {omega!r} while measuring the circle")
        return sec[-1], _half_widths(sec, ys[-1])

    # inside: grow from y* until a block hardly changes the size
    y_in, hw_in = advance(ys + kick)
    while used < max_impacts / 2:
        y_in, hw = advance(y_in)
        if hw.max() < 0.9 * hw_in.max():
            # shrinking onto y*: no attracting circle here (v on the stable side)
            while hw.max() > 1e-10 and used < max_impacts:
                y_in, hw = advance(y_in)
            return Measurement(omega, hw, hw, used, bool(hw.max() <= 1e-10), tuple(ys))
        grown = np.abs(hw - hw_in).max() <= 0.05 * hw.max()
        hw_in = hw
        if grown:
            break
    # outside: the same phase, twice as far from y*
    y_out, hw_out = advance(ys + 2 * (y_in - ys))
    while used < max_impacts:
        if np.all(np.abs(hw_in - hw_out) <= rtol * np.maximum(hw_in, hw_out)):
            break
        y_in, hw_in = advance(y_in)
        y_out, hw_out = advance(y_out)
    conv = bool(np.all(np.abs(hw_in - hw_out) <= rtol * np.maximum(hw_in, hw_out)))
    return Measurement(omega, (hw_in + hw_out) / 2, np.abs(hw_in - hw_out), used, conv,
                       tuple(ys))


def names_of(params):
    """Names of the section coordinates (the paper's, or a model's section layout)."""
    if isinstance(params, Model):
        from ..maps.section import Section
        return Section.of(params).names
    return NAMES


@dataclass(frozen=True)
class CircleCheck:
    """Measured against predicted half-widths for v = v_c + mu (one row per mu)."""

    omega_c: float
    mu: np.ndarray            # (k,)
    measured: np.ndarray      # (k, 4)
    predicted: np.ndarray     # (k, 4)
    spread: np.ndarray        # (k, 4) convergence bracket of the measurement
    converged: tuple
    printed_scale: object = None  # radius(eq. (60) as printed) / radius(standard f1), or None
    names: tuple = NAMES      # the section coordinates (2N of them for a model)

    @property
    def predicted_printed(self):
        """Half-widths if f1 came from eq. (60) as printed (same d|lambda|/dv), or None."""
        return None if self.printed_scale is None else self.predicted * self.printed_scale

    @property
    def rel_error(self):
        """(measured - predicted) / predicted, (k, 4)."""
        return (self.measured - self.predicted) / self.predicted

    @property
    def error_slope(self):
        """Log-log slope of max |relative error| against |mu| (1 for an O(mu) error; mu < 0
        where the circle lies below omega_c)."""
        e = np.abs(self.rel_error).max(axis=1)
        return float(np.polyfit(np.log(np.abs(self.mu)), np.log(e), 1)[0])

    @property
    def measured_coefficients(self):
        """Half-width / sqrt(mu) extrapolated to mu -> 0 (linear fit in mu), (4,)."""
        k = self.measured / np.sqrt(np.abs(self.mu))[:, None]
        return np.array([np.polyfit(self.mu, k[:, i], 1)[1] for i in range(k.shape[1])])

    def table(self):
        """Plain-text table: mu, measured, predicted and relative error per variable."""
        head = f"{'mu':>9}  " + "  ".join(f"{n + ' sim':>12} {n + ' nf':>12} {'rel.err':>9}"
                                          for n in self.names)
        rows = [f"omega_c = {self.omega_c:.10g}", head]
        for i, mu in enumerate(self.mu):
            cells = "  ".join(f"{self.measured[i, k]:12.6e} {self.predicted[i, k]:12.6e} "
                              f"{self.rel_error[i, k]:+9.2e}" for k in range(len(self.names)))
            rows.append(f"{mu:9.2e}  {cells}")
        rows.append(f"log-log slope of max |rel.err| vs mu: {self.error_slope:.2f} "
                    "(1 expected for an O(mu) error)")
        if self.printed_scale is not None:
            e = np.abs(self.measured / self.predicted_printed - 1).max(axis=1)
            rows.append(f"with f1 from eq. (60) as printed the half-widths scale by "
                        f"{self.printed_scale:.4f}: max |rel.err| "
                        + ", ".join(f"{v:.2f}" for v in e))
        return "\n".join(rows)

    def as_dict(self):
        return {"omega_c": self.omega_c, "mu": self.mu.tolist(),
                "measured": self.measured.tolist(), "predicted": self.predicted.tolist(),
                "rel_error": self.rel_error.tolist(), "spread": self.spread.tolist(),
                "converged": list(self.converged), "error_slope": self.error_slope,
                "printed_scale": self.printed_scale,
                "variables": list(self.names)}


def check(params, point, mus, **measure_kw):
    """Compare the circle of ``point`` (``.omega_c`` and ``.circle.half_widths(mu)``,
    as from :func:`symvi.analysis.hopf.hopf_points`) with simulation at v_c + mu."""
    return _check(params, point, mus, False, **measure_kw)[0]


def _check(params, point, mus, skip_lost, **measure_kw):
    """:func:`check`, and the values of mu whose run was lost (``skip_lost``: a run that
    stops by chatter or grazing leaves its mu out, with the reason, instead of raising;
    at least two must remain for the error's slope)."""
    mus = np.asarray(mus, dtype=float)
    if not point.circle.stable:
        raise SingularCaseError("repelling-circle", f"the circle born at omega_c = "
                                f"{float(point.omega_c):.10g} is repelling (subcritical); forward "
                                "simulation cannot measure it")
    meas, kept, lost = [], [], []
    for mu in mus:
        try:
            meas.append(measure(params, point.omega_c + mu, **measure_kw))
            kept.append(mu)
        except SingularCaseError as exc:
            if not skip_lost or exc.kind != "circle-lost":
                raise
            lost.append({"mu": float(mu), "why": str(exc).removeprefix("circle-lost: ")})
    if lost and len(kept) < 2:
        raise SingularCaseError("circle-lost", f"{len(lost)} of {len(mus)} values of mu lost "
                                f"next to omega_c = {float(point.omega_c):.10g}, fewer than two "
                                f"measured (smaller |mu| may keep the run on the circle): "
                                + lost[0]["why"])
    kept = np.array(kept)
    pred = np.array([point.circle.half_widths(mu) for mu in kept])
    return (CircleCheck(float(point.omega_c), kept, np.array([m.half_widths for m in meas]), pred,
                        np.array([m.spread for m in meas]), tuple(m.converged for m in meas),
                        _printed_scale(point), tuple(names_of(params))), lost)


def _printed_scale(point):
    """rho ~ 1/sqrt(f1): the radius ratio of eq. (60) as printed to the standard f1."""
    nf = getattr(point, "normal_form", None)
    f_std, f_pr = (getattr(nf, "f1_wan", None), getattr(nf, "f1_printed", None))
    if f_std is None or f_pr is None or not float(f_std) * float(f_pr) > 0:
        return None
    return math.sqrt(float(f_std) / float(f_pr))


def hopf_point(params, omega_min, omega_max):
    """The first Hopf point with a predicted circle in [omega_min, omega_max] (symvi.analysis.hopf)."""
    from ..analysis.hopf import spans_text
    from ..paper.hopf import hopf_points
    res = hopf_points(params, omega_min, omega_max)
    pts = [h for h in res if h.circle is not None and not h.circle_caveat]
    if not pts:
        where = (f" (not certified on {spans_text(res.uncertified)}: a point there may have "
                 "been missed)") if res.uncertified else ""
        raise SingularCaseError("no-hopf", f"no Hopf point with a predicted circle in "
                                f"[{omega_min}, {omega_max}]{where}")
    return pts[0]


def study(params, spec, quick):
    """The ``circle_check`` scene output: measured vs predicted half-widths at
    v = v_c + mu for the first Hopf point with a circle in the scene's interval, on the
    paper's model or any other.  mu is taken on the side of omega_c where the circle is
    stable; a mu whose run is lost (chatter, grazing: the circle reaches the stop) is listed
    under ``lost`` with the reason.  For the paper's model also the radius eq. (60) as
    printed would give."""
    pt = hopf_point(params, spec["omega_min"], spec["omega_max"])
    mus = spec["mu"] or [4e-4, 2e-4, 1e-4, 5e-5]
    note = ""
    if quick and spec.get("quick", True) and len(mus) > 3:
        note = f"quick mode: {3} of {len(mus)} values of μ"
        mus = sorted(mus, reverse=True)[:3]
    mus = [abs(m) * pt.circle.side for m in mus]
    c, lost = _check(params, pt, [abs(m) for m in mus] if pt.circle.side > 0 else mus, True)
    d = c.as_dict()
    k_pred = np.asarray(pt.circle.half_widths(float(pt.circle.side)))     # at |mu| = 1
    f1_paper, f1_wan = getattr(pt, "f1_paper", None), getattr(pt, "f1_wan", None)
    paper = f1_paper is not None and f1_paper > 0 and f1_wan > 0
    d.update({"quick_note": note, "lost": lost, "predicted_coefficients": k_pred.tolist(),
              "measured_coefficients": np.asarray(c.measured_coefficients).tolist(),
              "f1_paper": f1_paper, "f1_wan": f1_wan, "l1": pt.l1,
              "dmod_domega": pt.dmod_domega,
              "printed_eq60_factor": math.sqrt(f1_wan / f1_paper) if paper else None})
    return d, {"mu": np.abs(np.asarray(c.mu)), "measured": np.asarray(c.measured),
               "predicted": np.asarray(c.predicted)}
