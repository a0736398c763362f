"""The numbers table and the formula audit of ``symvi reproduce``.

* :func:`numbers_table` sets every number the paper prints (Sec. 4) beside
  symvi's value, with a status (agrees / differs / not checkable) and a
  one-line reason that carries its evidence.  The printed numbers come from the
  scene file ``numbers.toml``; they are never used as expected values.
* :func:`formula_audit` evaluates each printed formula *as printed* beside an
  independent route to the same quantity, at one parameter set:

  - eqs. (11)–(16) and (21)–(24) through :mod:`symvi.paper.audit_orbit` against
    :func:`symvi.period1_orbits` and :func:`symvi.flow.motion_from`;
  - eqs. (37)–(38): the impact condition g of eq. (27) and the maps f~ of
    eq. (26) are written out literally from eqs. (21)–(29), differentiated by
    central finite differences and combined as printed, against the generated
    Jacobian (:func:`symvi.jet`);
  - eqs. (46), (54), (60), (A2)–(A17): the printed appendix formulas
    (:func:`symvi.paper.reduction.appendix_printed`, ``*_printed`` values of the
    reduction) against coefficients read off the truncated map itself by
    sampling it on a circle |z| = eps and taking Fourier modes (no derivative
    bookkeeping), against Kuznetsov's n-dimensional c1 and h20, h11, and
    against differences along the orbit branch.

Agreement means a relative discrepancy below the tolerance given in each row
(set by the accuracy of the independent route, stated in the evidence).

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, Elements
of Applied Bifurcation Theory, 3rd ed., Springer 2004, Sec. 4.7 (planar c1)
and Sec. 5.4 (n-dimensional c1).
"""
import cmath
import math
import warnings

import numpy as np

from ..errors import NearSingularWarning, SymviError

NAMES = ("x1dot+", "x20", "x20dot", "tau")


# --------------------------------------------------------------------------- formatting
def fmt(x, sig=6):
    """Compact text for a number, complex number or vector."""
    if x is None:
        return "—"
    if isinstance(x, str):
        return x
    if isinstance(x, (bool, np.bool_)):
        return "yes" if x else "no"
    a = np.asarray(x)
    if a.ndim:
        return "[" + ", ".join(fmt(v, 4) for v in a.ravel()) + "]"
    z = complex(a)
    if abs(z.imag) > 0 or np.iscomplexobj(a):
        return f"{z.real:.{sig}g}{z.imag:+.{sig}g}i"
    return f"{z.real:.{sig}g}"


def _disc(printed, value):
    """(absolute, relative) discrepancy in the 2-norm; relative to |value|."""
    p = np.asarray(printed, dtype=complex).ravel()
    v = np.asarray(value, dtype=complex).ravel()
    ab = float(np.linalg.norm(p - v))
    nv = float(np.linalg.norm(v))
    return ab, (ab / nv if nv > 0 else (0.0 if ab == 0 else math.inf))


def _row(eq, what, printed, value, *, tol, evidence, corrected="", matters="", where=""):
    """One audit row; status from the relative discrepancy against ``tol``."""
    if printed is None or value is None:
        return {"eq": eq, "what": what, "printed": fmt(printed), "symvi": fmt(value),
                "abs": None, "rel": None, "status": "not checkable", "matters": matters,
                "corrected": corrected, "evidence": evidence, "where": where}
    ab, rel = _disc(printed, value)
    ok = rel <= tol or ab <= tol * 1e-3
    return {"eq": eq, "what": what, "printed": fmt(printed), "symvi": fmt(value), "abs": ab,
            "rel": rel, "status": "agrees" if ok else "differs",
            "matters": "no: the printed formula agrees" if ok and not matters else matters,
            "corrected": "" if ok else corrected, "evidence": evidence, "where": where}


# --------------------------------------------------------------------------- orbit formulas
def _orbit_rows(params, omega, omin, omax):
    from . import audit_orbit as ao
    from .modal_flow import motion_from
    from .orbit import existence_ratio, period1_orbits
    from .params import Params, modal
    rows = []
    orbits = period1_orbits(params, omega, multipliers=False)
    if not orbits:
        return [_row("(11)–(24)", "period-1 orbit", None, None, tol=0,
                     evidence=f"no period-1 orbit exists at omega = {omega}")], None
    orb = next((o for o in orbits if o.admissible), orbits[0])
    # eq. (11): the b = 0 orbit of symvi has tan(tau0) = tan(tau0bar)
    p0 = Params(params.mu_m, params.mu_k, params.f2, 0.0, params.r)
    try:
        tan_sym = math.tan(period1_orbits(p0, omega, multipliers=False)[0].tau0)
        tan_pr = ao.tan_tau0bar_printed(params, omega)
        tan_cor = ao.tan_tau0bar_corrected(params, omega)
    except (ZeroDivisionError, IndexError, SymviError) as exc:
        rows.append(_row("(11)", "tan τ̄0", None, None, tol=0, evidence=f"not evaluable: {exc}"))
        tan_sym = None
    else:
        rows.append(_row(
            "(11)", "tan τ̄0 (phase of the b = 0 orbit)", tan_pr, tan_sym, tol=1e-9,
            evidence=f"symvi: tan τ0 of its own b = 0 orbit from conditions (10); the corrected "
                     f"formula gives {fmt(tan_cor)} (rel. diff {_disc(tan_cor, tan_sym)[1]:.1e})",
            corrected=r"\tan\bar\tau_0=\frac{(\psi_{22}\psi_{11}s_1(1-c_2)\omega_2-\psi_{12}"
                      r"\psi_{21}s_2(1-c_1)\omega_1)(1+R)\omega}{D\omega_1\omega_2(1-c_1)(1-c_2)"
                      r"(1-R)}",
            matters="yes: a factor s_2 is missing; τ̄0 feeds eq. (12), so every printed orbit "
                    "phase is wrong unless s_2 = 1"))
    # eq. (12): each printed root against the nearest symvi branch
    sym_cos = {o.branch: math.cos(o.tau0) for o in orbits}
    for sign, lab in ((1, "+"), (-1, "−")):
        pr = ao.cos_tau0_printed(params, omega, sign)
        cor = ao.cos_tau0_corrected(params, omega, sign)
        near = min(sym_cos.values(), key=lambda c: abs(c - (pr if pr is not None else cor)))
        ev = ("symvi cos τ0 of the branches: " + ", ".join(f"{b}: {fmt(c)}" for b, c in
                                                              sym_cos.items())
              + f"; the corrected formula gives {fmt(cor)}")
        if pr is None:
            rows.append(_row("(12)", f"cos τ0 ({lab} root)", None, near, tol=1e-9,
                             evidence="printed square root is imaginary here; " + ev,
                             matters="yes: the printed (12) gives no orbit where one exists"))
            continue
        rows.append(_row(
            "(12)", f"cos τ0 ({lab} root)", pr, near, tol=1e-9, evidence=ev,
            corrected=r"\cos\tau_0=\frac{b\tan\bar\tau_0\pm\sqrt{(\tan^2\bar\tau_0+1)d^2-b^2}}"
                      r"{(\tan^2\bar\tau_0+1)d},\ d(\tan\bar\tau_0\cos\tau_0-\sin\tau_0)=b",
            matters="yes: the printed numerator lacks the factor b (not even dimensionally "
                    "consistent) and the root needs the sign condition on sin τ0"))
    # eqs. (13)-(15) at symvi's tau0
    b1 = ao.b1_printed(params, omega, orb.tau0)
    rows.append(_row("(13)", f"b1 (branch {orb.branch})", b1, orb.b[0], tol=1e-9,
                     evidence="printed formula at symvi's τ0 vs symvi's b1 from conditions (10)",
                     corrected=""))
    b2 = ao.b2_printed(params, omega, orb.b[0])
    rows.append(_row("(14)", "b2", b2, orb.b[1], tol=1e-9,
                     evidence="printed formula from symvi's b1 vs symvi's b2"))
    a = ao.a_printed(params, omega, *orb.b)
    rows.append(_row("(15)", "a1, a2", a, orb.a, tol=1e-9,
                     evidence="printed formula from symvi's b1, b2 vs symvi's a1, a2"))
    # eq. (16): existence over a scan of omega
    ws = np.linspace(omin, omax, 201)
    mism, n_pr, n_sym = 0, 0, 0
    for w in ws:
        try:
            sym = abs(existence_ratio(params, float(w))) <= 1
        except SymviError:
            continue
        pr = ao.exists_printed(params, float(w), 1) or ao.exists_printed(params, float(w), -1)
        n_pr += pr
        n_sym += sym
        mism += pr != sym
    rows.append(_row(
        "(16)", f"orbit exists (201 ω in [{omin:g}, {omax:g}])", n_pr, n_sym, tol=0,
        evidence=f"printed (16) says an orbit exists at {n_pr} of 201 frequencies, symvi "
                 f"(|αb/ρ| ≤ 1, eq. 16 corrected) at {n_sym}; they disagree at {mism}",
        corrected=r"|b|\le |d|\sqrt{1+\tan^2\bar\tau_0}",
        matters="yes where they disagree: the printed condition inherits the error of (12)"))
    # eqs. (21)-(24) at a perturbation dX
    m = modal(params)
    dX = (1e-3, -2e-3, 1.5e-3, 1e-2)
    pr = ao.modal_constants_printed(params, omega, orb.y, orb.tau0, dX)
    mot = motion_from(m, omega, (params.b, orb.x20 + dX[1]),
                      (orb.v1_plus + dX[0], orb.x20_dot + dX[2]), orb.tau0 + dX[3])
    rows.append(_row("(21)–(24)", "ã1, ã2, b̃1, b̃2 at ΔX = (1e-3, -2e-3, 1.5e-3, 1e-2)",
                     pr, (mot.a[0], mot.a[1], mot.b[0], mot.b[1]), tol=1e-9,
                     evidence="symvi: ξ(0) = ψ⁻¹x(0) in symvi.flow.motion_from"))
    return rows, orb


# --------------------------------------------------------------------------- eqs. (37)-(38)
def _gtilde(params, omega, orb, dX, dth):
    """g of eq. (27) and f~ of eq. (26), written out literally from eqs. (21)–(29)."""
    from . import audit_orbit as ao
    from .modal_flow import forcing_amplitudes
    from .params import modal
    m = modal(params)
    p = m.psi
    A = forcing_amplitudes(m, omega)
    a1, a2, b1, b2 = ao.modal_constants_printed(params, omega, orb.y, orb.tau0, dX)
    te = (2 * math.pi + dth) / omega
    ph = omega * te + orb.tau0 + dX[3]
    xi, xid = [], []
    for ai, bi, wi, Ai in ((a1, b1, m.omega1, A[0]), (a2, b2, m.omega2, A[1])):
        xi.append(ai * math.cos(wi * te) + bi * math.sin(wi * te) + Ai * math.sin(ph))   # (28)
        xid.append(-ai * wi * math.sin(wi * te) + bi * wi * math.cos(wi * te)
                   + Ai * omega * math.cos(ph))                                          # (29)
    g = p[0][0] * xi[0] + p[0][1] * xi[1] - params.b                                     # (27)
    f = (-params.r * (p[0][0] * xid[0] + p[0][1] * xid[1]) - orb.v1_plus,                # (26)
         p[1][0] * xi[0] + p[1][1] * xi[1] - orb.x20,
         p[1][0] * xid[0] + p[1][1] * xid[1] - orb.x20_dot,
         dX[3] + dth)
    return g, np.array(f)


def _implicit_rows(params, omega, orb):
    from .jets import jet
    from .modal_map import fd_jacobian
    h = 1e-5
    z = np.zeros(4)

    def d(fun, k):
        e = np.zeros(5)
        e[k] = h
        up, dn = fun(z + e[:4], e[4]), fun(z - e[:4], -e[4])
        return (up[0] - dn[0]) / (2 * h), (up[1] - dn[1]) / (2 * h)

    fun = lambda dx, dth: _gtilde(params, omega, orb, dx, dth)   # noqa: E731
    parts = [d(fun, k) for k in range(5)]
    g_x = np.array([parts[i][0] for i in range(4)])
    g_th, ft_th = parts[4]
    ft_x = np.array([parts[i][1] for i in range(4)]).T           # [j, i] = df~_j/dx_i
    th_x = -g_x / g_th                                            # eq. (37)
    J_pr = ft_x + np.outer(ft_th, th_x)                           # eq. (38)
    j = jet(params, omega, order=1, orbit=orb)
    Jfd = fd_jacobian(params, omega, orb.y)
    ev = ("eqs. (21)–(29) written out literally, partial derivatives of g and f~ by central "
          f"differences (h = {h:g}, error ~1e-9), combined as printed; symvi: generated "
          "Jacobian (SymPy, eqs. 33–38)")
    return [
        _row("(37)", "∂Δθ/∂Δx_i", th_x, j.theta1, tol=1e-6, evidence=ev),
        _row("(38)", "Df(v, 0) (16 entries)", J_pr, j.jacobian, tol=1e-6,
             evidence=ev + f"; the numeric map's own finite-difference Jacobian differs from "
                           f"the generated one by {_disc(Jfd, j.jacobian)[1]:.1e} (relative)"),
    ]


# --------------------------------------------------------------------------- normal form
def _poly(AY, d2Y, d3Y, linear=True):
    """The cubic Taylor polynomial of F(Y) = P⁻¹ f(P Y), eq. (40)."""
    def F(Y):
        out = np.einsum("ijk,j,k->i", d2Y, Y, Y) / 2 + np.einsum("ijkl,j,k,l->i", d3Y, Y, Y, Y) / 6
        return out + AY @ Y if linear else out
    return F


def _modes(fun, eps, n=16):
    """Fourier modes c_k (k = -6..6) of fun(eps e^{i phi}) over n equispaced phi."""
    phi = 2 * np.pi * np.arange(n) / n
    vals = np.array([fun(eps * np.exp(1j * t)) for t in phi])
    return {k: np.tensordot(np.exp(-1j * k * phi), vals, axes=(0, 0)) / n for k in range(-6, 7)}


def _rich(fun, k, power, eps=4e-3):
    """Mode k of fun divided by eps^power, Richardson-extrapolated in eps^2."""
    a1 = _modes(fun, eps)[k] / eps ** power
    a2 = _modes(fun, eps / 2)[k] / (eps / 2) ** power
    return (4 * a2 - a1) / 3


def _W(Wd, z, cubic=True, printed=False):
    """W(z, z̄) of eq. (45) truncated at order 3 (real vector)."""
    zb = np.conj(z)
    w = Wd["W20"] * z * z / 2 + Wd["W11"] * z * zb + Wd["W02"] * zb * zb / 2
    if cubic:
        W30 = Wd["W30_printed"] if printed else Wd["W30"]
        w = w + W30 * z ** 3 / 6 + Wd["W21"] * z * z * zb / 2 \
            + np.conj(Wd["W21"]) * z * zb * zb / 2 + np.conj(W30) * zb ** 3 / 6
    return w


def printed_W(red, lam):
    """The centre-manifold coefficients exactly as printed, the errata of the reduction
    ``red`` (:class:`symvi.paper.reduction.PaperReduction`, n > 2) at lambda:
    W02 of eq. (A10), (conj(lambda) I - D) W02 = H02 (corrected: conj(lambda)^2), and W30
    of eq. (46) with -3 lambda G20 W11 where -3 lambda conj(G02) W11 belongs.  Complex
    float64; computed only here, for the audit and its tests."""
    D = np.asarray(red.D, dtype=complex)
    H = {k: np.asarray(v, dtype=complex) for k, v in red.H.items()}
    W20, W11 = (np.asarray(red.W[k], dtype=complex) for k in ("W20", "W11"))
    G20 = complex(red.G["G20"])
    lam = complex(lam)
    I = np.eye(D.shape[0])
    return {"W02_printed": np.linalg.solve(lam.conjugate() * I - D, H["H02"]),
            "W30_printed": np.linalg.solve(lam ** 3 * I - D, H["H30"] + H["H10"] @ W20 * 3
                                           - 3 * lam * G20 * W11 - 3 * lam * G20 * W20)}


def _nf_rows(params, pt, circle_evidence):
    """Eqs. (46), (54), (60), (A2)–(A17) at the Hopf point ``pt``."""
    from .jets import jet
    from ..normal_forms.normal_form import transform_jet
    from .reduction import appendix_printed, f1_eq60
    nf = pt.normal_form
    red = nf.paper
    j = jet(params, pt.omega_c, order=3, orbit=pt.orbit)
    P, Pinv = np.real(red.P), np.real(red.Pinv)
    lam = complex(nf.lam)
    lb = lam.conjugate()
    AY = Pinv @ j.jacobian @ P
    d2Y = transform_jet(Pinv, P, j.d2)
    d3Y = transform_jet(Pinv, P, j.d3)
    Fnl = _poly(AY, d2Y, d3Y, linear=False)
    F = _poly(AY, d2Y, d3Y)
    n = AY.shape[0]
    Wd = {k: np.asarray(v, dtype=complex) for k, v in red.W.items()}
    Wd.update(printed_W(red, lam))
    G, g = red.G, red.g
    pr = appendix_printed(d2Y, d3Y)
    rows = []
    norm = ("normalisation: x = P y, P = (Re r1, −Im r1, …), ‖r1‖₂ = 1, largest |r1_k| real > 0, "
            "z = y1 + i y2")

    def Y0(z):
        return np.concatenate([[z.real, z.imag], np.zeros(n - 2)])

    def G0(z):                          # G(z, z̄, 0) = F1 + i F2 - lambda z
        v = Fnl(Y0(z))
        return v[0] + 1j * v[1]

    def H0(z):                          # H(z, z̄, 0) = (F3, F4) - D W
        return Fnl(Y0(z))[2:]

    def Gw(k):                          # dG/dw_k (exact central difference of a polynomial)
        e = np.zeros(n)
        e[k] = 1e-3

        def f(z):
            v = (Fnl(Y0(z) + e) - Fnl(Y0(z) - e)) / 2e-3
            return v[0] + 1j * v[1]
        return f

    def Yw(z):
        return np.concatenate([[z.real, z.imag], np.real(_W(Wd, z, cubic=False))])

    def gz(z):                          # restricted map minus lambda z, eqs. (51)-(52)
        v = F(Yw(z))
        return v[0] + 1j * v[1] - lam * z

    ev_modes = ("symvi: read off the truncated map F(Y) = P⁻¹f(PY) sampled on |z| = ε "
                "(16 phases, Fourier modes, Richardson in ε = 4e-3, 2e-3); " + norm)
    # (A4)-(A6): g_ij = G_ij, i + j = 2
    m2 = _modes(G0, 1e-2)
    rows.append(_row("(A4)", "g11", pr["g11"], m2[0] / 1e-4, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A5)", "g02", pr["g02"], 2 * m2[-2] / 1e-4, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A6)", "g20", pr["g20"], 2 * m2[2] / 1e-4, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A7)", "G21", pr["G21"], 2 * _rich(G0, 1, 3), tol=1e-6, evidence=ev_modes
                     + "; (A7) also prints d³F1/∂y1³ with a 'd' for '∂' (typo only)"))
    mh = _modes(H0, 1e-2)
    rows.append(_row("(A8)", "H11 (vector)", pr["H11"], mh[0] / 1e-4, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A9)", "H20 (vector)", pr["H20"], 2 * mh[2] / 1e-4, tol=1e-8,
                     evidence=ev_modes))
    G10 = [_modes(Gw(k), 1e-2)[1] / 1e-2 for k in range(2, n)]
    G01 = [_modes(Gw(k), 1e-2)[-1] / 1e-2 for k in range(2, n)]
    rows.append(_row("(A11)", "G10 (vector over w)", pr["G10"], G10, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A12)", "G01 (vector over w)", pr["G01"], G01, tol=1e-8, evidence=ev_modes))
    rows.append(_row("(A14)", "G30", pr["G30"], 6 * _rich(G0, 3, 3), tol=1e-6, evidence=ev_modes))
    rows.append(_row("(A15)", "G03", pr["G03"], 6 * _rich(G0, -3, 3), tol=1e-6, evidence=ev_modes))
    rows.append(_row("(A16)", "H30 (vector)", pr["H30"], 6 * _rich(H0, 3, 3), tol=1e-6,
                     evidence=ev_modes))

    # (46): W20, W11 against Kuznetsov's h20, h11 projected on the stable subspace
    W20k = Pinv[2:] @ np.asarray(nf.h20) / 4
    W11k = Pinv[2:] @ np.asarray(nf.h11) / 4
    evk = ("symvi: Kuznetsov's h20 = (λ²I − A)⁻¹B(q,q), h11 = (I − A)⁻¹B(q,q̄) in the original "
           "coordinates, projected by the last rows of P⁻¹ and divided by 4 (z = 2 z_Kuznetsov)")
    rows.append(_row("(46)", "W20", Wd["W20"], W20k, tol=1e-8, evidence=evk))
    rows.append(_row("(46)", "W11", Wd["W11"], W11k, tol=1e-8, evidence=evk))

    # invariance residual of eq. (44), by modes, for printed and corrected W
    def resid(printed_w30=False, printed_w02=False):
        Wx = dict(Wd)
        if printed_w02:
            Wx["W02"] = Wd["W02_printed"]

        def R(z):
            w = np.real(_W(Wx, z, printed=printed_w30))
            v = F(np.concatenate([[z.real, z.imag], w]))
            z1 = v[0] + 1j * v[1]
            return v[2:] - np.real(_W(Wx, z1, printed=printed_w30))
        return R

    def rsz(R, k, p):
        return [float(np.linalg.norm(_modes(R, e)[k]) / e ** p) for e in (1e-2, 5e-3)]

    r_pr = rsz(resid(printed_w02=True), -2, 2)
    r_co = rsz(resid(), -2, 2)
    rows.append(_row(
        "(A10)", "W02", Wd["W02_printed"], np.conj(W20k), tol=1e-8,
        evidence=f"invariance eq. (44), z̄² mode of the residual / ε² at ε = 1e-2, 5e-3: printed "
                 f"{r_pr[0]:.2e}, {r_pr[1]:.2e}; corrected {r_co[0]:.1e}, {r_co[1]:.1e}; symvi "
                 "value conj(W20) from Kuznetsov",
        corrected=r"(\bar\lambda^2 I - D)W_{02} = H_{02}",
        matters="no for f1 (W02 does not enter g21); yes for g03 of eq. (A17)"))
    r_pr = rsz(resid(printed_w30=True), 3, 3)
    r_co = rsz(resid(), 3, 3)
    rows.append(_row(
        "(46)", "W30", Wd["W30_printed"], Wd["W30"], tol=1e-8,
        evidence=f"invariance eq. (44), z³ mode of the residual / ε³ at ε = 1e-2, 5e-3: printed "
                 f"{r_pr[0]:.2e}, {r_pr[1]:.2e} (does not vanish); corrected {r_co[0]:.1e}, "
                 f"{r_co[1]:.1e} (→ 0 as ε²)",
        corrected=r"W_{30}=(\lambda^3-D)^{-1}(H_{30}+3H^1_{10}W_{20}-3\lambda G_{20}W_{20}"
                  r"-3\lambda\bar G_{02}W_{11})",
        matters="no for f1 (W30 enters only quartic terms of eq. 56); yes for a reduction "
                "beyond third order"))
    r21 = rsz(resid(), 1, 3)
    ok21 = r21[1] < 1e-3 and r21[0] / max(r21[1], 1e-300) > 3
    rows.append({"eq": "(46)", "what": "W21", "printed": fmt(Wd["W21"]), "symvi": "residual → 0",
                 "abs": r21[1], "rel": None, "status": "agrees" if ok21 else "differs",
                 "matters": "no: the printed formula agrees" if ok21 else "yes",
                 "corrected": "", "where": "",
                 "evidence": f"z²z̄ mode of the residual of eq. (44) / ε³ with the printed W21: "
                             f"{r21[0]:.1e} at ε = 1e-2, {r21[1]:.1e} at 5e-3 (falls as ε²: W21 "
                             "satisfies eq. (44) to third order)"})

    # (54)/(A13)/(A17): g_ij of the restricted map
    g21m = 2 * _rich(gz, 1, 3)
    g30m = 6 * _rich(gz, 3, 3)
    g03m = 6 * _rich(gz, -3, 3)
    g20, g11, g02 = g["g20"], g["g11"], g["g02"]
    rest = (g20 * g11 * (lb - 3 + 2 * lam) / (2 * (lam * lam - lam) * (lb - 1))
            + abs(g11) ** 2 / (1 - lb) + abs(g02) ** 2 / (2 * (lam * lam - lb)))
    g21k = 2 * (complex(nf.c1) / 4 - rest)
    rows.append(_row("(54)", "g20, g11, g02 (= G_ij)", [g20, g11, g02],
                     [2 * _rich(gz, 2, 2), _rich(gz, 0, 2), 2 * _rich(gz, -2, 2)], tol=1e-6,
                     evidence="symvi: modes of the map restricted to W(z) of eq. (50); " + norm))
    rows.append(_row(
        "(54), (A13)", "g21", g["g21"], g21m, tol=1e-6,
        evidence=f"symvi: modes of the restricted map; Kuznetsov's n-dimensional c1 (no "
                 f"centre-manifold coordinates) implies g21 = {fmt(g21k)} "
                 f"(rel. diff {_disc(g['g21'], g21k)[1]:.1e}); " + norm))
    rows.append(_row("(A17)", "g30", g["g30"], g30m, tol=1e-6, evidence=ev_modes))
    g03_printed = G["G03"] + 3 * np.dot(G["G01"], Wd["W02_printed"])
    rows.append(_row(
        "(A17)", "g03 (with W02 of (A10) as printed)", g03_printed, g03m, tol=1e-6,
        evidence=f"with the corrected W02, eq. (A17) gives {fmt(g['g03'])} (rel. diff "
                 f"{_disc(g['g03'], g03m)[1]:.1e}); " + ev_modes,
        corrected=r"g_{03}=G_{03}+3\sum_l G^l_{01}W^l_{02},\ (\bar\lambda^2I-D)W_{02}=H_{02}",
        matters="no for f1; the error comes only from (A10)"))

    # (60)
    f1_pr, f1_co = float(nf.f1_printed), float(f1_eq60(lam, g20, g11, g02, g["g21"]))
    f1_k = -float(nf.l1) / 4
    same_sign = (f1_pr > 0) == (f1_k > 0)
    ratio = f1_pr / f1_k if f1_k else math.inf
    conseq = (f"sign {'agrees' if same_sign else 'differs'} ("
              + ("same stability conclusion" if same_sign else "opposite stability conclusion")
              + f"); magnitude {ratio:.3g}× the right value, so the predicted circle radius "
              + (f"is {1 / math.sqrt(abs(ratio)):.3g}× the right one" if same_sign else
                 "is meaningless"))
    rows.append(_row(
        "(60)", "f1(0)", f1_pr, f1_k, tol=1e-6,
        evidence=f"symvi: −l1/4 from Kuznetsov's n-dimensional c1 (l1 = {float(nf.l1):.6g}, "
                 f"‖q‖₂ = 1, ⟨p,q⟩ = 1); corrected (60) from the same g_ij gives {f1_co:.6g}; "
                 + circle_evidence + "; " + norm,
        corrected=r"f_1(0)=\mathrm{Re}\Big[\frac{(1-2\lambda_0)\bar\lambda_0^{2}}{2(1-\lambda_0)}"
                  r"g_{20}g_{11}\Big]+\frac12|g_{11}|^2+\frac14|g_{02}|^2-\mathrm{Re}"
                  r"\Big(\frac{\bar\lambda_0g_{21}}{2}\Big)",
        matters="yes: " + conseq))

    # (A2)-(A3)
    dlam_fd = _dlam_branch(params, pt)
    rows.append(_row("(A2)", "λ̃1 = (F11 ζ0, ζ0*) = dλ1/dω", complex(nf.dlam_dv), dlam_fd,
                     tol=1e-6, evidence="symvi: dλ1/dω by Richardson central differences of the "
                                        "multiplier along the orbit branch (h = 1e-4, 2e-4)"))
    lit = (complex(nf.dlam_dv) * cmath.exp(-1j * lam.imag)).real
    arg = (complex(nf.dlam_dv) * cmath.exp(-1j * cmath.phase(lam))).real
    dmod_fd = (lb * dlam_fd).real / abs(lam)
    rows.append(_row(
        "(A3)", "d|λ1|/dω, ω0 read as Im λ1 (the symbol ω of eq. 41)", lit, dmod_fd, tol=1e-6,
        evidence=f"with ω0 read as arg λ0 (θ0) (A3) gives {arg:.8g} (rel. diff "
                 f"{_disc(arg, dmod_fd)[1]:.1e}); symvi: Re(λ̄ dλ/dω)/|λ| from differences along "
                 "the branch",
        corrected=r"\frac{d|\lambda_1|}{d\omega}\Big|_{\omega_c}=\mathrm{Re}\big(\tilde\lambda_1"
                  r"e^{-i\theta_0}\big),\ \lambda_0=e^{i\theta_0}",
        matters="only if ω0 is read as Im λ1; the paper's symbol is ambiguous (ω is Im λ1 in "
                "eq. 41)"))
    return rows


def _dlam_branch(params, pt, h=1e-4):
    from .orbit import period1_orbits

    def lam(w):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            o = {x.branch: x for x in period1_orbits(params, w)}[pt.branch]
        return min((complex(x) for x in o.multipliers), key=lambda x: abs(x - pt.multiplier))
    w = pt.omega_c
    d1 = (lam(w + h) - lam(w - h)) / (2 * h)
    d2 = (lam(w + 2 * h) - lam(w - 2 * h)) / (4 * h)
    return (4 * d1 - d2) / 3


def _first_hopf(params, omin, omax):
    from .hopf import hopf_points
    pts = [p for p in hopf_points(params, omin, omax).points if p.normal_form is not None]
    return pts[0] if pts else None


def _circle_evidence(params, pt, f1_printed):
    """Measured circle half-width at one mu against the corrected and printed (60)."""
    try:
        from ..studies.circle_check import measure
    except ModuleNotFoundError:
        return "circle check not available"
    if pt.circle is None:
        return "no predicted circle"
    mu = 1e-4 * pt.circle.side
    try:
        m = measure(params, pt.omega_c + mu)
    except SymviError as exc:
        return f"circle not measurable ({exc})"
    if not pt.circle.stable:
        return "the predicted circle is repelling: not observable by simulation"
    k = int(np.argmax(pt.circle.q_abs))
    pred = float(pt.circle.half_widths(mu)[k])
    f1k = -pt.l1 / 4
    pr = pred * math.sqrt(f1k / f1_printed) if f1_printed > 0 else float("nan")
    return (f"simulated circle at μ = {mu:g}: half-width in {NAMES[k]} {m.half_widths[k]:.4g}; "
            f"predicted with corrected (60) {pred:.4g}, with printed (60) {pr:.4g}")


def formula_audit(params, spec):
    """Every printed formula as printed beside symvi's independent value, at ``params``."""
    omin, omax = spec["omega_min"], spec["omega_max"]
    pt = _first_hopf(params, omin, omax)
    omega_orbit = spec.get("omega_orbit") or (pt.omega_c if pt is not None else (omin + omax) / 2)
    rows, orb = _orbit_rows(params, omega_orbit, omin, omax)
    if orb is not None:
        rows += _implicit_rows(params, omega_orbit, orb)
    if pt is None:
        rows.append(_row("(46)–(60), (A2)–(A17)", "normal form", None, None, tol=0,
                         evidence=f"no Hopf point in [{omin}, {omax}]"))
    else:
        rows += _nf_rows(params, pt, _circle_evidence(params, pt, float(pt.f1_paper)))
    return {"params": params.as_dict(), "omega_orbit": omega_orbit,
            "omega_c": None if pt is None else pt.omega_c,
            "branch": None if pt is None else pt.branch, "rows": rows}


#: typographical errors and conventions recorded without a number
NOTES = [
    {"eq": "(3)", "status": "differs (typo)",
     "text": r"prints $\dot x$ in the inertia term; it must be $\ddot x$: "
             r"$M\ddot x + Kx = P\sin(\omega t+\tau)$ (symvi.params)"},
    {"eq": "(6)", "status": "differs (typo)",
     "text": r"prints $I\ddot\xi + \Lambda\dot\xi$; the stiffness term is $\Lambda\xi$: "
             r"$I\ddot\xi + \Lambda\xi = F\sin(\omega t+\tau)$"},
    {"eq": "(A7)", "status": "typo only",
     "text": r"first term printed $d^3F_1/\partial y_1^3$; it is $\partial^3F_1/\partial y_1^3$"},
    {"eq": "(58)/(60)", "status": "convention",
     "text": "f1 enters (58) as |λ|r − f1 r³, so f1 > 0 means an attracting circle; this is the "
             "opposite sign of Wan's a and of Kuznetsov's l1 (l1 < 0 attracting). symvi's "
             "corrected (60) keeps the paper's sign: f1 = −l1/4 for ‖r1‖₂ = 1 (z = 2 z_Kuznetsov)."},
]


# --------------------------------------------------------------------------- numbers table
_HOPF_MEMO = {}


def _hopf_cached(params, omin, omax):
    key = (params.key(), omin, omax)
    if key not in _HOPF_MEMO:
        from .hopf import hopf_points
        _HOPF_MEMO[key] = hopf_points(params, omin, omax)
    return _HOPF_MEMO[key]


def _unit(printed):
    """One unit in the last printed digit of a number as written in the scene file."""
    s = repr(float(printed))
    if "e" in s:
        return abs(float(printed)) * 1e-15
    dec = len(s.split(".")[1].rstrip("0")) if "." in s else 0
    return 10.0 ** -dec


def _uncertified(res):
    """What a scan that found nothing could not certify (never read as 'there is none')."""
    if res.complete:
        return ""
    from ..analysis.hopf import spans_text
    spans = spans_text(res.uncertified, 6)
    return f" found; the scan could not certify {spans}: a point there may have been missed"


def _nearest_point(params, row):
    res = _hopf_cached(params, row["omega_min"], row["omega_max"])
    if not res.points:
        return None, res
    target = row["printed"] if row["check"] == "omega_c" else None
    if target is None:
        return res.points[0], res
    return min(res.points, key=lambda p: abs(p.omega_c - target)), res


def _num_status(printed, value):
    u = _unit(printed)
    d = abs(value - printed)
    return ("agrees" if d <= u * (1 + 1e-9) else "differs"), d / u


def _check_omega_c(params, row, quick):
    pt, res = _nearest_point(params, row)
    if pt is None:
        return "differs", None, (f"no Hopf point in [{row['omega_min']}, {row['omega_max']}]"
                                 + _uncertified(res))
    st, units = _num_status(row["printed"], pt.omega_c)
    dec = len(repr(float(row["printed"])).split(".")[1])
    return st, pt.omega_c, (
        f"Hopf point located to 1e-12 (H1 {'holds' if pt.h1 else 'FAILS'}, H2 "
        f"{'holds' if pt.h2 else 'FAILS'}, H3 {'holds' if pt.h3 else 'FAILS'}); rounds to "
        f"{round(pt.omega_c, dec):.{dec}f}, truncates to {math.floor(pt.omega_c * 10 ** dec) / 10 ** dec:.{dec}f}; "
        f"|Δ| = {units:.2f} units of the last printed digit"
        + (f"; {len(res.points)} Hopf points in the interval" if len(res.points) > 1 else ""))


def _check_dmod(params, row, quick):
    pt, res = _nearest_point(params, row)
    if pt is None:
        return "differs", None, "no Hopf point" + _uncertified(res)
    st, units = _num_status(row["printed"], pt.dmod_domega)
    rel = abs(pt.dmod_domega - pt.dmod_domega_branch) / abs(pt.dmod_domega)
    return st, pt.dmod_domega, (
        f"at ω_c = {pt.omega_c:.9f}: {pt.dmod_domega:.6g} by eqs. (A1)–(A3), "
        f"{pt.dmod_domega_branch:.6g} by differences of |λ1| along the branch (rel. diff "
        f"{rel:.1e}); printed/symvi = {row['printed'] / pt.dmod_domega:.4g}; d|λ1|/dω "
        "depends on no normalisation, so this is not a convention")


def _check_f1(params, row, quick):
    pt, res = _nearest_point(params, row)
    if pt is None:
        return "differs", None, "no Hopf point" + _uncertified(res)
    same = (row["printed"] > 0) == (pt.f1_wan > 0)
    return "not checkable", pt.f1_wan, (
        f"f1 depends on the normalisation of r1, which the paper does not state. symvi with "
        f"‖r1‖₂ = 1, largest component real: eq. (60) corrected {pt.f1_wan:.6g} (= −l1/4, "
        f"l1 = {pt.l1:.6g} Kuznetsov ‖q‖₂ = 1), eq. (60) as printed {pt.f1_paper:.6g}. Sign "
        + ("agrees: attracting circle, supercritical" if same else
           "DIFFERS: the stability conclusion is opposite"))


def _check_interval(params, row, quick):
    from .orbit import multiplier_path
    a, b = row["printed"]
    res = _hopf_cached(params, row["omega_min"], row["omega_max"])
    inside = [p for p in res.points if a <= p.omega_c <= b]
    ws = np.linspace(a, b, row["steps"])
    M = np.abs(multiplier_path(params, ws)[0])      # |lambda| descending, NaN: no orbit
    bad = int(np.isnan(M[:, 0]).sum())
    facts, good = [], True
    if bad:
        facts.append(f"no admissible orbit at {bad} of {len(ws)} frequencies")
        good = False
    if len(inside) != 1:
        facts.append(f"{len(inside)} Hopf points in the interval")
        good = False
    else:
        vc = inside[0].omega_c
        before = M[ws < vc]
        inside_ok = bool(np.all(before < 1))
        others_ok = bool(np.all(M[:, 2:] < 1))
        d = np.diff(M, axis=0)
        inc12 = bool(np.all(d[:, 0] > 0))
        dec34 = bool(np.all(d[:, 2] < 0))
        facts.append(f"one Hopf point, ω_c = {vc:.6f}; all |λ| < 1 on [{a}, ω_c): "
                     f"{'yes' if inside_ok else 'no'}; |λ3|, |λ4| < 1 throughout: "
                     f"{'yes' if others_ok else 'no'}; |λ1,2| increasing: "
                     f"{'yes' if inc12 else 'no'}; |λ3,4| decreasing: {'yes' if dec34 else 'no'}")
        facts.append(f"|λ1| from {M[0, 0]:.4f} to {M[-1, 0]:.4f}, |λ3| from {M[0, 2]:.4f} to "
                     f"{M[-1, 2]:.4f} ({len(ws)} frequencies)")
        good = good and inside_ok and others_ok and inc12 and dec34
    return ("agrees" if good else "differs"), f"[{a}, {b}]", "; ".join(facts)


def _sim_counts(row, quick):
    from ..simulations.simulation import quick_counts
    return quick_counts(row, quick, default_impacts=2000, default_transient=row["transient"])


def _classify_at(params, omega, n, tr, pert):
    from ..simulations.diagnostics import classify
    from ..simulations.simulation import simulate
    kw = {"perturbation": tuple(pert)} if pert else {}
    sim = simulate(params, omega, n_impacts=n, transient=tr, **kw)
    return sim, classify(sim)


def _describe(c):
    bits = [c.kind]
    if c.lyapunov is not None:
        bits.append(f"largest Lyapunov exponent {c.lyapunov.largest:+.2e}/impact "
                    f"(over {c.lyapunov.n} impacts)")
    if c.rotation is not None:
        bits.append(f"rotation number {c.rotation:.4f}")
    return ", ".join(bits)


def _check_attractor(params, row, quick):
    n, tr, note = _sim_counts(row, quick)
    sim, c = _classify_at(params, row["omega"], n, tr, row["perturbation"])
    kind = c.kind if not c.kind.startswith("period-") else c.kind
    st = "agrees" if kind == row["expect"] else "differs"
    why = f"symvi: {_describe(c)}; {n} impacts after a transient of {tr} from y* + perturbation"
    if row.get("omega_min") is not None and c.kind == "invariant circle":
        try:
            pt, _ = _nearest_point(params, {**row, "check": "circle"})
            mu = row["omega"] - pt.omega_c
            if pt.circle is not None and pt.circle.exists(mu):
                hw = pt.circle.half_widths(mu)
                sec = np.asarray(sim.section)
                k = int(np.argmax(hw[:3]))
                meas = (sec[:, k].max() - sec[:, k].min()) / 2
                why += (f"; μ = ω − ω_c = {mu:.3g}: half-width in {NAMES[k]} simulated "
                        f"{meas:.3g}, normal form {hw[k]:.3g}")
        except SymviError:
            pass
    if note:
        why += f" ({note})"
    return st, kind, why


def _check_onset(params, row, quick):
    from ..simulations.diagnostics import branch_count
    from ..simulations.simulation import sweep
    steps = row["steps"]
    tr = row["transient"]
    if quick:
        steps = row["quick_steps"] or min(steps, 13)
        tr = row["quick_transient"] if row["quick_transient"] is not None else tr
    ws = np.linspace(row["omega_min"], row["omega_max"], steps)
    sw = sweep(params, ws, n_impacts=row["impacts"], transient=tr)
    kinds = []
    for i in range(len(ws)):
        if sw.stops[i] != "completed":
            kinds.append(0)
            continue
        kinds.append(branch_count(sw.section[i, :sw.counts[i]]))
    want = 2 if row["expect"] == "doubled torus" else 1
    first = next((ws[i] for i in range(len(ws)) if kinds[i] == want), None)
    # the onset proper: from here on every grid frequency shows it
    stay = next((ws[i] for i in range(len(ws)) if all(k == want for k in kinds[i:])), None)
    step = ws[1] - ws[0]
    seq = "".join(str(k) for k in kinds)
    if stay is None:
        return "differs", None, (f"no persistent {row['expect']} on [{ws[0]}, {ws[-1]}] "
                                 f"({steps} frequencies; sheets per ω: {seq})")
    u = max(_unit(row["printed"]), step)
    st = "agrees" if abs(stay - row["printed"]) <= u * (1 + 1e-9) else "differs"
    return st, float(f"{stay:.6g}"), (
        f"{row['expect']} (2 sheets, diagnostics.branch_count) at every ω ≥ {stay:.5g} on a grid "
        f"of step {step:.2g} (first seen at {first:.5g}); sheets per ω from {ws[0]:g} to "
        f"{ws[-1]:g}: {seq}; {row['impacts']} impacts after {tr} each"
        + (" (quick mode: coarser grid)" if quick and steps != row["steps"] else ""))


def _check_escape(params, row, quick):
    from ..simulations.simulation import fixed_point, simulate
    ys = fixed_point(params, row["omega"])
    if ys is None:
        return "not checkable", None, "no admissible period-1 orbit to start from"
    counts = []
    for d in row["offsets"]:
        sim = simulate(params, row["omega"], n_impacts=row["impacts"], perturbation=(d,) * 4)
        dt = (np.asarray(sim.section)[:, 3] - ys[3] + math.pi) % (2 * math.pi) - math.pi
        big = np.nonzero(np.abs(dt) > row["threshold"])[0]
        counts.append(int(big[0]) + 1 if len(big) else None)
    txt = ", ".join(f"δ = {d:g}: {c if c is not None else '> ' + str(row['impacts'])}"
                    for d, c in zip(row["offsets"], counts))
    have = [c for c in counts if c is not None]
    lo, hi = (min(have), max(have)) if have else (None, None)
    inside = have and lo <= row["printed"] <= hi
    return "not checkable", (f"{lo}–{hi}" if have else None), (
        f"impacts until |τ − τ*| first exceeds {row['threshold']:g} rad, starting at y* + δ(1,1,1,1): "
        f"{txt}. The count grows like log(1/δ) and the paper does not give its start offset"
        + ("; the printed value lies within this range" if inside else ""))


_CHECKS = {"omega_c": _check_omega_c, "dmod_domega": _check_dmod, "f1": _check_f1,
           "interval": _check_interval, "attractor": _check_attractor, "onset": _check_onset,
           "escape": _check_escape}


def numbers_table(rows, paramsets, quick=False):
    """Every printed number of the scene's rows beside symvi's value, with status and reason."""
    out = []
    for r in rows:
        params = paramsets[r["params"]]
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", NearSingularWarning)
                status, value, why = _CHECKS[r["check"]](params, r, quick)
        except ModuleNotFoundError as exc:
            status, value, why = "not available", None, f"{exc.name} is not in this checkout"
        except SymviError as exc:
            status, value, why = "differs", None, f"symvi could not compute it: {exc}"
        out.append({"label": r["label"], "params": r["params"], "where": r["where"],
                    "quote": r["quote"], "printed": r["printed"],
                    "symvi": value if not isinstance(value, float) else float(f"{value:.8g}"),
                    "status": status, "reason": why, "check": r["check"]})
    return {"rows": out, "quick": bool(quick)}


# --------------------------------------------------------------------------- circle check
