"""Known-answer maps for the codimension-two normal forms: exact jets by truncated
polynomial arithmetic in mpmath (60 digits).

A map is built in normal-form coordinates v = (u, w): u the critical coordinates with
a chosen critical normal form N_c(u) (z = u1 + i u2 for a complex pair), w two strongly
contracting coordinates.  The couplings keep {w = 0} invariant (every term of w' has a
factor w; u' = N_c(u) + linear and nonlinear terms in w), so the restricted map is N_c.
It is then disguised:

    F = L o Phi o N o Phi^{-1} o L^T,

Phi = S_1 o ... o S_m a product of *shears* y_i -> y_i + s(y_others) (s of degree 2..3,
so Phi is near-identity and Phi^{-1} = S_m^{-1} o ... o S_1^{-1} is exact), L a rational
orthogonal matrix.  The critical eigenvectors of F are L times those of N (norms and
orthogonality kept), and the normal-form coefficients are those of N_c:

* exactly, when the coefficient is invariant under near-identity changes
  (``disguise="generic"``);
* for coefficients that depend on the normalising transformation (resonant quadratic
  terms: R3's Im part, LPNS, LPPD cubic terms), exactly when Phi has no resonant
  quadratic terms on the centre subspace (``disguise="plain"``): the u-shears then
  carry quadratic monomials with a factor w only, and the w-shears no pure-u
  quadratic monomial, so <p_i, D^2 Phi(q_j, q_k)> = 0 and the bordered normalisation
  <p, h> = 0 of the algorithm is met by Phi itself.

Shears cannot put every quadratic monomial in every component (y_i's shear does not
depend on y_i); :func:`build_general` (order 3) uses a general Phi = id + Q + K with
Phi^{-1} by fixed-point iteration, for the plain disguise with *non-resonant* pure-u
quadratic terms (they make h20, h02, h11 of the fold-flip nonzero, which MatContM's
sign error needs in order to show).

Polynomials are dicts {exponent tuple: coefficient}; products are truncated at the
map's order (3 or 5).
"""
import itertools
import math

import mpmath
import numpy as np

DPS = 60


# --------------------------------------------------------------------------- polynomials
class Poly:
    """Truncated polynomial in ``n`` variables: {exponents: coefficient}."""

    __slots__ = ("n", "order", "c")

    def __init__(self, n, order, c=None):
        self.n, self.order, self.c = n, order, (c or {})

    @classmethod
    def var(cls, n, order, i):
        e = [0] * n
        e[i] = 1
        return cls(n, order, {tuple(e): mpmath.mpf(1)})

    @classmethod
    def const(cls, n, order, x):
        return cls(n, order, {(0,) * n: mpmath.mpmathify(x)})

    def __add__(self, o):
        if not isinstance(o, Poly):
            o = Poly.const(self.n, self.order, o)
        c = dict(self.c)
        for k, v in o.c.items():
            c[k] = c[k] + v if k in c else v
        return Poly(self.n, self.order, c)

    __radd__ = __add__

    def __neg__(self):
        return Poly(self.n, self.order, {k: -v for k, v in self.c.items()})

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if not isinstance(o, Poly):
            o = mpmath.mpmathify(o)
            return Poly(self.n, self.order, {k: v * o for k, v in self.c.items()})
        c = {}
        order = self.order
        deg = sum
        items = [(k, deg(k), v) for k, v in o.c.items()]
        for k1, v1 in self.c.items():
            d1 = deg(k1)
            for k2, d2, v2 in items:
                if d1 + d2 > order:
                    continue
                k = tuple(a + b for a, b in zip(k1, k2))
                c[k] = c[k] + v1 * v2 if k in c else v1 * v2
        return Poly(self.n, order, c)

    __rmul__ = __mul__

    def real(self):
        return Poly(self.n, self.order, {k: mpmath.mpf(mpmath.mpc(v).real)
                                         for k, v in self.c.items()})

    def imag(self):
        return Poly(self.n, self.order, {k: mpmath.mpf(mpmath.mpc(v).imag)
                                         for k, v in self.c.items()})


def monomial(K, exps):
    """prod K[i]^exps[i] for a list K of polynomials."""
    out = None
    for i, e in enumerate(exps):
        for _ in range(e):
            out = K[i] if out is None else out * K[i]
    return out


def apply_linear(M, K):
    return [sum((K[j] * M[i][j] for j in range(len(K)) if M[i][j] != 0),
                Poly(K[0].n, K[0].order)) for i in range(len(M))]


def apply_shear(K, i, terms, sign):
    """K_i += sign * sum coeff * prod K^exps (exps[i] = 0)."""
    K = list(K)
    add = Poly(K[0].n, K[0].order)
    for exps, coeff in terms:
        assert exps[i] == 0
        add = add + monomial(K, exps) * coeff
    K[i] = K[i] + add * sign
    return K


def jets(K, order):
    """Raw derivative tensors (A, d2, ..., d_order) at 0 of the polynomial map K (mpf)."""
    n = len(K)
    out = []
    for k in range(1, order + 1):
        T = np.empty((n,) + (n,) * k, dtype=object)
        for idx in itertools.product(range(n), repeat=k):
            e = [0] * n
            for j in idx:
                e[j] += 1
            e = tuple(e)
            fac = math.prod(math.factorial(m) for m in e)
            for i in range(n):
                T[(i,) + idx] = K[i].c.get(e, mpmath.mpf(0)) * fac
        out.append(T)
    return out


# --------------------------------------------------------------------------- the disguise
#: a rational orthogonal matrix (Cayley transform of a skew matrix with rational entries)
def cayley(n, seed):
    rng = np.random.default_rng(seed)
    S = [[mpmath.mpf(0)] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            v = mpmath.mpf(int(rng.integers(-3, 4))) / 4
            S[i][j], S[j][i] = v, -v
    S = mpmath.matrix(S)
    I = mpmath.eye(n)
    Q = (I - S) * mpmath.inverse(I + S)
    return [[Q[i, j] for j in range(n)] for i in range(n)]


def shears(n, ncrit, seed, generic, resonant=None):
    """Shears (i, terms) of Phi, first-applied last.  ``resonant(i, exps)`` tells whether
    a pure-u quadratic monomial is resonant in component i (kept out unless generic)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        terms = []
        others = [j for j in range(n) if j != i]
        for deg in (2, 3):
            for combo in itertools.combinations_with_replacement(others, deg):
                e = [0] * n
                for j in combo:
                    e[j] += 1
                pure_u = all(e[j] == 0 for j in range(ncrit, n))
                if deg == 2 and pure_u and not generic:
                    if i >= ncrit or resonant is None or resonant(i, tuple(e)):
                        continue
                if rng.random() < 0.5:
                    continue
                c = mpmath.mpf(int(rng.integers(-6, 7))) / 10
                if c:
                    terms.append((tuple(e), c))
        out.append((i, terms))
    rng.shuffle(out)
    return out


def build(n, ncrit, normal, order, *, seed=0, generic=True, resonant=None):
    """Jets (mpf, at DPS digits) of L o Phi o N o Phi^{-1} o L^T and L.

    ``normal(V)`` maps the list of polynomials V = (u..., w...) to N(V)."""
    with mpmath.workdps(DPS):
        L = cayley(n, seed + 100)
        LT = [[L[j][i] for j in range(n)] for i in range(n)]
        X = [Poly.var(n, order, i) for i in range(n)]
        K = apply_linear(LT, X)
        sh = shears(n, ncrit, seed, generic, resonant)
        for i, terms in sh:                       # Phi^{-1} = S_m^{-1} o ... o S_1^{-1}
            K = apply_shear(K, i, terms, -1)
        K = normal(K)
        for i, terms in reversed(sh):             # Phi = S_1 o ... o S_m
            K = apply_shear(K, i, terms, +1)
        K = apply_linear(L, K)
        return jets(K, order), np.array(L, dtype=object)


def to_float(jet):
    return [np.array(t.tolist(), dtype=float) for t in jet]


# --------------------------------------------------------------------------- the stable part
D2 = [["0.2", "-0.15"], ["0.1", "0.25"]]   # strings: made mpf at the working precision


def stable_part(V, ncrit, order):
    """(du, w') for the two contracting coordinates w = V[ncrit:]: w' = D2 w + terms with a
    factor w; du: terms added to the critical components (linear and nonlinear in w)."""
    u, w = V[:ncrit], V[ncrit:]
    w1, w2 = w
    u1 = u[0]
    u2 = u[1] if ncrit > 1 else u[0]
    D = [[mpmath.mpf(x) for x in row] for row in D2]
    wn = [w1 * D[0][0] + w2 * D[0][1] + u1 * w1 * mpmath.mpf("0.3") + w2 * w2 * mpmath.mpf("-0.2")
          + u2 * u2 * w2 * mpmath.mpf("0.4"),
          w1 * D[1][0] + w2 * D[1][1] + u2 * w1 * mpmath.mpf("-0.35")
          + u1 * u1 * w1 * mpmath.mpf("0.1")
          + w1 * w2 * mpmath.mpf("0.15")]
    if order >= 5:
        wn[0] = wn[0] + u1 * u1 * u2 * u2 * w2 * mpmath.mpf("0.3")
        wn[1] = wn[1] + u2 * u2 * u2 * w1 * mpmath.mpf("-0.2")
    du = []
    for k in range(ncrit):
        s = mpmath.mpf(k + 1) / 10
        t = w1 * s + w2 * (-s / 2) + w1 * w1 * mpmath.mpf("0.25") + u[k] * w2 * mpmath.mpf("-0.3") \
            + u1 * w1 * w2 * mpmath.mpf("0.2")
        if order >= 5:
            t = t + u1 * u1 * u1 * w2 * mpmath.mpf("0.15") + w1 * w1 * w1 * w1 * mpmath.mpf("0.1")
        du.append(t)
    return du, wn


def with_stable(crit, ncrit, order):
    """N(V) = (crit(u) + du, w') for a critical normal form crit(u) -> list."""
    def normal(V):
        du, wn = stable_part(V, ncrit, order)
        cu = crit(V[:ncrit])
        return [cu[k] + du[k] for k in range(ncrit)] + wn
    return normal


def complex_z(u):
    """z = u1 + i u2 as a complex polynomial."""
    return u[0] + u[1] * mpmath.mpc(0, 1)


def conj_z(u):
    return u[0] - u[1] * mpmath.mpc(0, 1)


# --------------------------------------------------------------------------- general disguise
def build_general(n, ncrit, normal, *, seed=0, resonant=lambda i, e: True, scale="0.5"):
    """Like :func:`build` with order 3 and a general Phi = id + Q + K (Q quadratic, K cubic,
    random), Phi^{-1} by fixed-point iteration.  Q has no pure-u monomial in the w
    components and, in the u components, only the pure-u monomials for which
    ``resonant(i, exps)`` is False (the plain disguise with non-resonant centre terms)."""
    order = 3
    with mpmath.workdps(DPS):
        rng = np.random.default_rng(seed)
        terms = []
        for i in range(n):
            ti = []
            for deg in (2, 3):
                for combo in itertools.combinations_with_replacement(range(n), deg):
                    e = [0] * n
                    for j in combo:
                        e[j] += 1
                    e = tuple(e)
                    pure_u = all(e[j] == 0 for j in range(ncrit, n))
                    if deg == 2 and pure_u and (i >= ncrit or resonant(i, e)):
                        continue
                    c = mpmath.mpf(int(rng.integers(-5, 6))) / 10 * mpmath.mpf(scale)
                    if c:
                        ti.append((e, c))
            terms.append(ti)

        def phi_nl(K):
            return [sum((monomial(K, e) * c for e, c in terms[i]), Poly(n, order))
                    for i in range(n)]

        L = cayley(n, seed + 100)
        LT = [[L[j][i] for j in range(n)] for i in range(n)]
        X = [Poly.var(n, order, i) for i in range(n)]
        Y = apply_linear(LT, X)
        K = list(Y)
        for _ in range(3):                        # K = Y - (Phi - id)(K)
            nl = phi_nl(K)
            K = [Y[i] - nl[i] for i in range(n)]
        K = normal(K)
        nl = phi_nl(K)
        K = apply_linear(L, [K[i] + nl[i] for i in range(n)])
        return jets(K, order), np.array(L, dtype=object)
