"""Known-answer maps for the normal-form tests: jets built by exact composition.

A base map in coordinates u, whose centre part is z -> lambda z (1 + c |z|^2)
(z = u1 + i u2) and whose stable part is linear, is conjugated by a
near-identity polynomial change of variables T (which curves the centre
manifold and couples z to w) and a linear change M.  The cubic normal-form
coefficient is invariant under the near-identity change, so with
q_u = (1, -i, 0, ...)/sqrt(2):

    c1 = 2 lambda c / ||M q_u||^2,   l1 = 2 Re(c) / ||M q_u||^2.
"""
import numpy as np


def compose(f, g):
    """Jet (A, d2, d3) of f o g at 0 from the jets of f and g (raw derivatives)."""
    fA, f2, f3 = f
    gA, g2, g3 = g
    A = fA @ gA
    d2 = np.einsum("iab,aj,bk->ijk", f2, gA, gA) + np.einsum("ia,ajk->ijk", fA, g2)
    t = np.einsum("iab,ajk,bl->ijkl", f2, g2, gA)
    d3 = (np.einsum("iabc,aj,bk,cl->ijkl", f3, gA, gA, gA)
          + t + t.transpose(0, 1, 3, 2) + t.transpose(0, 3, 2, 1)
          + np.einsum("ia,ajkl->ijkl", fA, g3))
    return A, d2, d3


def inverse(T):
    """Jet of T^{-1} at 0."""
    A = np.linalg.inv(T[0])
    n = A.shape[0]
    z2, z3 = np.zeros((n,) * 3), np.zeros((n,) * 4)
    d2 = -np.einsum("ia,ajk->ijk", A, compose(T, (A, z2, z3))[1])
    d3 = -np.einsum("ia,ajkl->ijkl", A, compose(T, (A, d2, z3))[2])
    return A, d2, d3


def linear(M):
    n = M.shape[0]
    return np.asarray(M, float), np.zeros((n,) * 3), np.zeros((n,) * 4)


def random_sym(rng, n, order, scale=1.0):
    """A random tensor symmetric in its lower ``order`` indices."""
    t = rng.normal(scale=scale, size=(n,) * (order + 1))
    if order == 2:
        return (t + t.transpose(0, 2, 1)) / 2
    perms = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 1, 3), (0, 2, 3, 1), (0, 3, 1, 2), (0, 3, 2, 1)]
    return sum(t.transpose(p) for p in perms) / 6


def polar3(F, n):
    """Symmetric third-derivative tensor of a cubic form u -> F(u) = C(u, u, u) / 6."""
    E = np.eye(n)
    C = np.zeros((n, n, n, n))
    for j in range(n):
        for k in range(n):
            for l in range(n):
                x, y, z = E[j], E[k], E[l]
                C[:, j, k, l] = (F(x + y + z) - F(x + y) - F(x + z) - F(y + z)
                                 + F(x) + F(y) + F(z))   # 6 c(u) polarised, / 6 * 6
    return C


def base(theta, c, D0=None, rate=0.0):
    """Jet of z -> (1 + rate) e^{i theta} z (1 + c |z|^2), w -> D0 w (n = 2 + dim D0)."""
    lam = (1 + rate) * np.exp(1j * theta)
    m = 0 if D0 is None else np.asarray(D0).shape[0]
    n = 2 + m
    A = np.zeros((n, n))
    A[:2, :2] = [[lam.real, -lam.imag], [lam.imag, lam.real]]
    if m:
        A[2:, 2:] = D0

    def cubic(u):
        z = u[0] + 1j * u[1]
        v = lam * c * z * z * np.conj(z)
        out = np.zeros(n)
        out[0], out[1] = v.real, v.imag
        return out

    return A, np.zeros((n,) * 3), polar3(cubic, n)


def conjugated(theta, c, D0=None, *, seed=0, quad=0.7, cub=0.4, M=None, rate=0.0):
    """Jet of M T f0 T^{-1} M^{-1} and the exact c1 (see module docstring).

    ``rate`` multiplies the centre eigenvalue by (1 + rate); the family's
    dA = d/d(rate) A = M [[cos, -sin], [sin, cos]] M^{-1} (d|lambda|/d rate = 1)
    is returned as ``f_dA(M, theta, n)``.
    """
    f0 = base(theta, c, D0, rate)
    n = f0[0].shape[0]
    rng = np.random.default_rng(seed)
    T = (np.eye(n), random_sym(rng, n, 2, quad), random_sym(rng, n, 3, cub))
    if M is None:
        M = np.eye(n) + 0.4 * rng.normal(size=(n, n))
    Mj = linear(M)
    f = compose(Mj, compose(T, compose(f0, compose(inverse(T), linear(np.linalg.inv(M))))))
    qu = np.zeros(n, complex)
    qu[0], qu[1] = 1 / np.sqrt(2), -1j / np.sqrt(2)
    s2 = np.linalg.norm(M @ qu) ** 2
    lam = np.exp(1j * theta)
    return f, 2 * lam * c / s2, M


def eval_poly(jet, x):
    """f(x) = A x + B(x, x)/2 + C(x, x, x)/6 for a jet (works on object arrays too)."""
    A, d2, d3 = jet
    return A @ x + np.dot(np.dot(d2, x), x) / 2 + np.dot(np.dot(np.dot(d3, x), x), x) / 6


def family_dA(M, theta):
    """d/d(rate) of the Jacobian of ``conjugated(..., rate)``: d|lambda1|/d rate = 1."""
    n = M.shape[0]
    dR = np.zeros((n, n))
    dR[:2, :2] = [[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]]
    return M @ dR @ np.linalg.inv(M)
