"""The defining system of a codimension-one curve of n-p orbits in two named parameters.

Unknowns X = (u, a, b): u the shooting unknowns of :mod:`symvi.orbits.periodic`, a and b
the two parameters.  Equations (m + 1 of them in m + 2 unknowns, a curve)::

    G(u; a, b) = 0                      the orbit (multiple shooting)
    g(u; a, b) = 0                      one bordered test function of the monodromy M

with, for the matrix B(M) that is singular on the curve,

    fold:  B = M - I          flip:  B = M + I
    NS:    B = M (.) M - I    the second compound (bialternate) matrix, eigenvalues
                              mu_i mu_j (i < j): singular when a pair has product 1

and g the last component of the solution of [[B, w0], [v0^T, 0]] (v, g) = (0, 1)
(minimally augmented system, Govaerts; Kuznetsov & Meijer for maps).  With w from
the transposed system, dg = -w^T dB v: its derivatives need dM only, which come
exactly from the generated jets at each impact, M = J_{p-1} ... J_0 and

    dM/dy_i[j] = L_i d2_i[:, :, j] R_i,   dM/da = sum_i L_i (dJ_i/da) R_i,

L_i = J_{p-1} ... J_{i+1}, R_i = J_{i-1} ... J_0, dJ_i/da the explicit derivative at
fixed y_i (generated parameter slot, never finite differences).  The time unknowns
enter g only through the y_i (the generated jets eliminate the time, eq. (30)).

The system is presented as a one-parameter problem in b with unknowns v = (u, a), so
the pseudo-arclength corrector of :mod:`symvi.continuation.points` serves it unchanged.
"""
import math

import numpy as np

from ..codegen.jets import evaluate as jet_values
from ..codegen.jets import flight_jet
from ..errors import ParameterError
from ..orbits.periodic import Problem

KINDS = ("ns", "flip", "fold")


def compound2(M):
    """The second compound matrix of M (rows/columns indexed by pairs i > j)."""
    ix = _pairs(M.shape[0])
    return M[ix["PP"]] * M[ix["QQ"]] - M[ix["PQ"]] * M[ix["QP"]]


_PAIRS = {}


def _pairs(d):
    """Index grids of the pairs (i > j) of d, built once per d."""
    if d not in _PAIRS:
        P, Q = np.tril_indices(d, -1)
        _PAIRS[d] = {"PP": np.ix_(P, P), "QQ": np.ix_(Q, Q), "PQ": np.ix_(P, Q),
                     "QP": np.ix_(Q, P), "P": P, "Q": Q,
                     "flat": [(np.ravel_multi_index((r[:, None], c[None, :]), (d, d)).ravel())
                              for r, c in ((P, P), (Q, Q), (P, Q), (Q, P))]}
    return _PAIRS[d]


class CurveSystem:
    """G(u; a, b) = 0 and g = 0 for the ``kind`` of curve (ns, flip, fold) of n-p orbits of
    ``model`` in the parameters ``names`` = (a, b) (names or
    :class:`symvi.model.parameters.Parameter`, parsed here once: :attr:`params`); ``omega``
    is the forcing frequency when neither is omega."""

    #: the kinds of curve this system defines
    KINDS = KINDS

    def __init__(self, model, n, p, names, kind, omega=None, signature=None):
        if kind not in self.KINDS:
            raise ParameterError("kind", kind, "ns, flip or fold")
        pa, pb = (model.parameter(nm) for nm in names)   # names the parameter or raises
        if pa == pb:
            raise ParameterError("params", tuple(str(nm) for nm in names),
                                 "two different parameter names")
        on_omega = pa.is_forcing_frequency or pb.is_forcing_frequency
        if not on_omega and omega is None:
            raise ParameterError("omega", None, "a fixed forcing frequency when neither "
                                 "parameter is omega")
        self.model, self.n, self.p, self.kind = model, n, p, kind
        self.signature = signature              # the constraint of each impact (None: stop 1)
        self.params, self.names = (pa, pb), (pa.name, pb.name)
        self.omega = None if on_omega else float(omega)
        self._pr = None
        self.border = None
        self.size = None
        pr = self.problem(pb.get(model, 1.0))
        self.m = pr.size
        self.size = pr.size + 1
        self.d = pr.d

    # ---- the one-parameter problem at fixed b -------------------------------------
    def problem(self, bval):
        """The orbit problem continued in a, at b = bval (cached for the last bval)."""
        bval = float(bval)
        if self._pr is not None and self._pr[0] == bval:
            return self._pr[1]
        pa, pb = self.params
        model, omega = pb.set(self.model, self.omega, bval)
        pr = Problem(model, self.n, self.p, omega=None if pa.is_forcing_frequency else omega,
                     param=pa, signature=self.signature)
        self._pr = (bval, pr)
        return pr

    def at(self, bval, check=True):
        """Validates b (the corrector calls it once per solve)."""
        return self.problem(bval)

    def orbit_data(self, X):
        """(problem, G, G_u, M) at a curve point X = (u, a, b), from the last evaluation
        when it was at X (the point just corrected is asked for again at once)."""
        m = self.m
        c = getattr(self, "_orbit_cache", None)
        pr = self.problem(X[-1])
        if c is not None and c[0] == np.asarray(X[:-1], float).tobytes() and c[1] == float(X[-1]):
            return pr, c[2], c[3], c[4]
        G, Gu, _ = pr.evaluate(X[:m], X[m], check=False)
        return pr, G, Gu, pr.monodromy(X[:m], Gu)[1]

    # ---- the test function ---------------------------------------------------------
    def matrix(self, M):
        d = M.shape[0]
        if self.kind == "fold":
            return M - np.eye(d)
        if self.kind == "flip":
            return M + np.eye(d)
        C = compound2(M)
        return C - np.eye(C.shape[0])

    def set_border(self, M):
        """Border vectors: the singular vectors of B(M) of its smallest singular value."""
        U, s, Vt = np.linalg.svd(self.matrix(M))
        self.border = (Vt[-1].copy(), U[:, -1].copy())

    def test(self, M, grad=False):
        """g, and with ``grad`` the matrix K = dg/dM (dg = sum K * dM)."""
        B = self.matrix(M)
        k = B.shape[0]
        v0, w0 = self.border
        A = np.zeros((k + 1, k + 1))
        A[:k, :k], A[:k, k], A[k, :k] = B, w0, v0
        rhs = np.zeros(k + 1)
        rhs[k] = 1.0
        x = np.linalg.solve(A, rhs)
        if not grad:
            return float(x[k]), None
        y = np.linalg.solve(A.T, rhs)
        v, w = x[:k], y[:k]
        W = -np.outer(w, v)                    # dg/dB
        if self.kind != "ns":
            return float(x[k]), W
        ix = _pairs(M.shape[0])
        d = M.shape[0]
        # B_ab = M[P_a,P_b] M[Q_a,Q_b] - M[P_a,Q_b] M[Q_a,P_b]: dg/dM by the chain rule
        parts = (W * M[ix["QQ"]], W * M[ix["PP"]], -W * M[ix["QP"]], -W * M[ix["PQ"]])
        K = np.zeros(d * d)
        for flat, part in zip(ix["flat"], parts):
            K += np.bincount(flat, weights=part.ravel(), minlength=d * d)
        K = K.reshape(d, d)
        return float(x[k]), K

    # ---- the system ----------------------------------------------------------------
    def evaluate(self, v, lam, jac=True, dparam=False, check=True):
        """(F, dF/dv, dF/db) at v = (u, a), b = lam; F = (G, g)."""
        m = self.m
        u, a = v[:m], float(v[m])
        pr = self.problem(lam)
        G, Gu, Ga = pr.evaluate(u, a, jac=True, dparam=jac, check=check)
        mats, M = pr.monodromy(u, Gu)
        self._orbit_cache = (np.asarray(v, float).tobytes(), float(lam), G, Gu, M)
        g, K = self.test(M, grad=jac)
        F = np.append(G, g)
        if not jac:
            return F, None, None
        Gb = pr.derivative(u, a, self.params[1])
        gu, ga, gb = self._grad(pr, u, a, K)
        DF = np.zeros((m + 1, m + 1))
        DF[:m, :m], DF[:m, m] = Gu, Ga
        DF[m, :m], DF[m, m] = gu, ga
        return F, DF, np.append(Gb, gb) if dparam else None

    def _grad(self, pr, u, a, K):
        """dg/du (zero on the times), dg/da, dg/db from the generated jets."""
        fl, (model, flow, F) = pr.flights(u, a, check=False)
        Y, T = pr.split(u)
        names = self.names
        jets = []
        tans = [None if par.is_forcing_frequency or pr.nonlinear else par.tangent(model)
                for par in self.params]
        phases = pr.phase_flows(model, flow, F)       # each flight's contact phase
        for i in range(self.p):
            y, te = tuple(Y[i]), float(T[i])
            if pr.nonlinear:          # the series of the flight, one per parameter
                from ..flow.nljet import map_jet
                ends = (int(pr.sig[i]), int(pr.sig[(i + 1) % self.p]))
                vs = [map_jet(phases[i][0], F.omega, y, te, 2, *ends, param=par)
                      for par in self.params]
                jets.append((vs[0]["J"], vs[0]["d2"], [v["dpJ"] for v in vs]))
                continue
            if pr.several:            # a flight between two constraints' sections
                ends = (int(pr.sig[i]), int(pr.sig[(i + 1) % self.p]))

                def jet(tan, y=y, te=te, ends=ends, fF=phases[i]):
                    return flight_jet(*fF, y, te, 2, *ends, tan)
            else:
                def jet(tan, y=y, te=te):
                    return jet_values(flow, F, y, te, 2, tan)
            first = next((t for t in tans if t is not None), None)
            vals = jet(first)
            dJ = []
            for nm, tan in zip(names, tans):
                if tan is None:
                    dJ.append(vals["dwJ"])
                elif tan is first:
                    dJ.append(vals["dpJ"])
                else:
                    dJ.append(jet(tan)["dpJ"])
            jets.append((vals["J"], vals["d2"], dJ))
        d, p = self.d, self.p
        # prefix and suffix products: R_i = J_{i-1}..J_0, L_i = J_{p-1}..J_{i+1}
        R = [np.eye(d)]
        for J, _, _ in jets[:-1]:
            R.append(J @ R[-1])
        L = [np.eye(d)] * p
        acc = np.eye(d)
        for i in range(p - 1, -1, -1):
            L[i] = acc
            acc = acc @ jets[i][0]
        gu = np.zeros(self.m, dtype=K.dtype)      # complex K: an eigenvalue's gradient
        gab = [0.0, 0.0]
        for i, (J, d2, dJ) in enumerate(jets):
            Ki = L[i].T @ K @ R[i].T
            gu[i * d:(i + 1) * d] = np.einsum("ab,abj->j", Ki, d2)
            for k in range(2):
                gab[k] += np.sum(Ki * dJ[k])
        return gu, gab[0].real if K.dtype.kind == "f" else gab[0], \
            gab[1].real if K.dtype.kind == "f" else gab[1]


def kappa_pair(mu, prev=None):
    """The critical pair of an NS curve: the two multipliers whose product is nearest 1
    (nearest ``prev`` when given, for continuity), and kappa = (mu_i + mu_j) / 2, real on
    the curve: cos(theta) on the NS part (|kappa| < 1), a neutral saddle beyond."""
    mu = np.asarray(mu)
    best = None
    for i in range(len(mu)):
        for j in range(i + 1, len(mu)):
            dist = abs(mu[i] * mu[j] - 1)
            if prev is not None:
                dist = min(abs(mu[i] - prev[0]) + abs(mu[j] - prev[1]),
                           abs(mu[j] - prev[0]) + abs(mu[i] - prev[1])) + dist
            if best is None or dist < best[0]:
                best = (dist, i, j)
    _, i, j = best
    a, b = (mu[i], mu[j]) if mu[i].imag >= mu[j].imag else (mu[j], mu[i])
    return (i, j), (complex(a), complex(b)), float(((a + b) / 2).real)


def theta_of(pair):
    """The angle of the upper multiplier of a complex critical pair (0 or pi when real)."""
    z = pair[0]
    if abs(z.imag) > 1e-12:
        return float(abs(math.atan2(z.imag, z.real)))
    return 0.0 if z.real > 0 else math.pi
