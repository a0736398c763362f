"""The Poincaré section x_k = b just after an impact, and its state layout (the only owner).

y = (v_k+, x_j for j != k, v_j for j != k, tau), dimension 2N, in mass order,
where k is the coordinate of the model's constraint (:attr:`symvi.model.Model.constraints`:
the stop's mass); for the paper's model this is (x1dot+, x20, x20dot, tau0)
of eq. (9).  The flow works in the stop-first order of
:attr:`symvi.flow.linear.LinearFlow.perm`, in which y is simply
(v_0+, x_1..x_{N-1}, v_1..v_{N-1}, tau).
"""
import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

@dataclass(frozen=True)
class Section:
    """Section layout of one model: names, and conversions to and from the flow state."""

    n: int
    perm: tuple          # stop-first order: perm[0] is the stop's mass (0-based)
    #: with a frame of the flow (a stop between masses, :func:`symvi.flow.linear.frame_of`):
    #: the (position, velocity) names of each flow coordinate, which perm then indexes
    labels: tuple = None

    @classmethod
    def of(cls, model):
        return _section_of(model)

    @property
    def dim(self):
        return 2 * self.n

    def _names_of(self, k):
        return self.labels[k] if self.labels is not None else (f"x{k + 1}", f"v{k + 1}")

    @functools.cached_property
    def names(self):
        """Stable names of the components of y, with 1-based mass numbers (or the names of
        the frame's coordinates: x2-x1, v2-v1)."""
        first, rest = self._names_of(self.perm[0]), [self._names_of(j) for j in self.perm[1:]]
        return (f"{first[1]}+", *(x for x, _ in rest), *(v for _, v in rest), "tau")

    def check(self, y, name="y"):
        """y as a tuple (values kept, e.g. mpf), or ParameterError naming ``name``."""
        valid = f"{self.dim} finite numbers ({', '.join(self.names)})"
        try:
            vals = tuple(y)
            ok = len(vals) == self.dim and all(math.isfinite(float(v)) for v in vals)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ParameterError(name, y, valid)
        return vals

    def state(self, y, b):
        """(z0, tau): the flow state (stop-first order) just after the impact at y."""
        n = self.n
        z = np.empty(2 * n, dtype=np.asarray(y).dtype if isinstance(y, np.ndarray) else object)
        z[0] = b
        z[1:n] = y[1:n]
        z[n] = y[0]
        z[n + 1:] = y[n:2 * n - 1]
        return z, y[2 * n - 1]

    def point(self, z, tau):
        """y of a flow state z on the section (the inverse of :meth:`state`)."""
        n = self.n
        return (z[n], *z[1:n], *z[n + 1:2 * n], tau)

    def image(self, z, reset, tau):
        """y after an impact in state z (x_k = b): v+ = R v- with R = ``reset``, the
        constraint's reset in the flow's order (:attr:`symvi.flow.linear.LinearFlow.reset`;
        v_k+ = -r v_k-, eq. (2), for the stop on mass k)."""
        n = self.n
        v = reset @ z[n:2 * n]
        return (v[0], *z[1:n], *v[1:], tau)


@functools.lru_cache(maxsize=256)
def _section_of(model):
    from ..flow.linear import frame_of
    # an elastic model's sections are its stops' (simulate's walk asks for stops on masses)
    perm, _, labels = frame_of(model if model.elastic else model.require_rigid_stops())
    return Section(model.n, perm, labels)
