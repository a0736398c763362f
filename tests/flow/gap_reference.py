"""Reference helpers of the compiled-flow tests: the gap function h(t) of a flight, random
and tangent section states (numpy, through :mod:`symvi.flow.linear`, never the kernels).
The models are in :mod:`tests.zoo`."""
import numpy as np

from symvi.flow.linear import LinearFlow


def z0_of(model, ys):
    """Flow states (stop-first order) and tau of section points ys (k, 2N)."""
    n = model.n
    ys = np.atleast_2d(np.asarray(ys, dtype=float))
    z = np.empty((len(ys), 2 * n))
    z[:, 0] = model.stop.gap
    z[:, 1:n] = ys[:, 1:n]
    z[:, n] = ys[:, 0]
    z[:, n + 1:] = ys[:, n:2 * n - 1]
    return z, ys[:, -1]


class Gap:
    """h(t) = x_k(t) - b of the flights from many section points, vectorised.

    h = Re(sum_j d_j e^{lambda_j t}) + Re(f e^{i omega t}) - b, with d_j = W[0, j] c_j
    and f = (U_k sin tau + V_k cos tau) - i (U_k cos tau - V_k sin tau).
    """

    def __init__(self, model, omega, ys):
        flow = LinearFlow.of(model)
        fo = flow.forcing(omega)
        z, tau = z0_of(model, ys)
        s, c = np.sin(tau)[:, None], np.cos(tau)[:, None]
        zp = np.hstack([fo.U * s + fo.V * c, omega * (fo.U * c - fo.V * s)])
        self.d = ((z - zp) @ flow.Winv.T) * flow.W[0]
        U, V = fo.U[0], fo.V[0]
        self.f = (U * s[:, 0] + V * c[:, 0]) - 1j * (U * c[:, 0] - V * s[:, 0])
        self.lam, self.omega, self.b = flow.lam, omega, model.stop.gap

    def at(self, t, deriv=0, rows=slice(None)):
        """h^(deriv) at one time per row."""
        t = np.asarray(t, dtype=float)[:, None]
        d, f = self.d[rows], self.f[rows]
        hom = (d * self.lam ** deriv * np.exp(self.lam * t)).sum(axis=1).real
        forced = (f * (1j * self.omega) ** deriv * np.exp(1j * self.omega * t[:, 0])).real
        return hom + forced - (self.b if deriv == 0 else 0.0)

    def grid(self, t, rows):
        """h on a time grid for some rows: (rows, len(t))."""
        E = np.exp(np.outer(self.lam, t))
        d, f = self.d[rows], self.f[rows]
        F = np.exp(1j * self.omega * t)
        return (d.real @ E.real - d.imag @ E.imag + np.outer(f.real, F.real)
                - np.outer(f.imag, F.imag) - self.b)

    def first_crossing(self, t_grid, dt):
        """First sign change of h on a grid of step dt up to t_grid, refined by
        bisection; inf if none."""
        t = np.arange(1, int(t_grid / dt) + 1) * dt
        k = len(self.d)
        out = np.full(k, np.inf)
        for lo in range(0, k, 200):
            rows = np.arange(lo, min(k, lo + 200))
            pos = self.grid(t, rows) >= 0
            has = pos.any(axis=1)
            i = np.argmax(pos, axis=1)
            a = np.where(i > 0, t[np.maximum(i - 1, 0)], 0.0)
            b = t[i]
            for _ in range(60):
                mid = 0.5 * (a + b)
                hm = self.at(mid, rows=rows)
                a, b = np.where(hm < 0, mid, a), np.where(hm < 0, b, mid)
            out[rows] = np.where(has, b, np.inf)
        return out


def random_states(model, n, rng):
    """Section points with v_k+ < 0, other coordinates O(1), tau in [0, 2 pi)."""
    dim = model.dim
    ys = np.empty((n, dim))
    ys[:, 0] = rng.uniform(-2.0, -1e-3, n)
    ys[:, 1:dim - 1] = rng.uniform(-1.0, 1.0, (n, dim - 2))
    ys[:, -1] = rng.uniform(0.0, 2 * np.pi, n)
    return ys


DELTAS = (1e-2, 1e-5, 1e-8, 1e-11, 1e-13, 0.0, -1e-13, -1e-11, -1e-8, -1e-5)


def tangent_states(model, omega, base, rng, t_lo=0.3, t_hi=8.0, deltas=DELTAS):
    """From random states, states whose flight has a local max of h at a chosen t*
    with height -delta (delta cycling through ``deltas``): Newton on (v_k+, tau) for
    h(t*) = -delta, h'(t*) = 0.  Returns (states, t*) of the converged ones."""
    k = len(base)
    ts = rng.uniform(t_lo, t_hi, k)
    delta = np.array([deltas[i % len(deltas)] for i in range(k)])
    y = base.copy()
    rows = np.arange(k)

    def F(y):
        g = Gap(model, omega, y)
        return np.column_stack([g.at(ts) + delta, g.at(ts, 1)])

    for _ in range(40):
        f0 = F(y)
        y1, y2 = y.copy(), y.copy()
        y1[:, 0] += 1.0                  # h is affine in v_k+
        y2[:, -1] += 1e-6
        J = np.stack([F(y1) - f0, (F(y2) - f0) / 1e-6], axis=2)
        ok = np.abs(np.linalg.det(J)) > 1e-12
        step = np.zeros_like(f0)
        step[ok] = np.linalg.solve(J[ok], f0[ok][:, :, None])[:, :, 0]
        y[:, 0] -= step[:, 0]
        y[:, -1] -= step[:, 1]
    res = np.abs(F(y)).max(axis=1)
    good = (res < 1e-14) & (y[:, 0] < -1e-3) & (y[:, 0] > -5) & np.all(np.isfinite(y), axis=1)
    y[:, -1] %= 2 * np.pi
    return y[rows[good]], ts[good]
