"""Constraints and signatures: the interfaces every layer above the model reads.

A constraint acts on one coordinate s = c^T x of the masses (c, the *guard
normal*, N numbers in mass order), with a gap g and a side:

* ``side = "upper"``: s <= g, the stop is above; the guard h = s - g < 0 off it;
* ``side = "lower"``: s >= g; h = g - s < 0 off it.

A constraint is of one of two kinds:

* **rigid** (``restitution`` 0 < r <= 1): at a contact (h = 0, moving towards the stop)
  the velocities jump by an impulse along a direction q (velocity space), below;
* **elastic** (``stiffness`` k_s > 0, optional ``damping`` c_s >= 0): while the stop is
  penetrated (h > 0) the force -sign (k_s h + c_s h') acts along c; no jump, no reset.

The rigid reset::

    v+ = v- - (1 + r) q (c^T v-) / (c^T q) = R v-,   R = (I - Q) - r Q,  Q = q c^T / (c^T q),

which sends c^T v to -r c^T v and leaves every velocity with c^T v = 0 alone.  For a
rigid contact q = M^-1 c (the impulse of a force along c; momentum is conserved
along any direction orthogonal to c).  :class:`symvi.model.Stop`, today's stop on
mass k, builds the constraint c = e_k with the rigid impulse q = M^-1 c: for a
diagonal M, q = e_k / m_k and Q = e_k e_k^T exactly (m_k^-1 / m_k^-1 = 1 in floating
point), Newton's law v_k+ = -r v_k- (eq. (2) generalised) with every other velocity
unchanged.  R is written as (I - Q) - r Q so that its entries are then exactly 1, 0 and
-r: the reset applied as a matrix gives the paper's numbers bit for bit.

A signature says which constraint (an index into ``model.constraints``) each
impact of an orbit hits: with one stop, an n-p orbit has the signature (0,)*p.

References: COCO's ``hspo`` toolbox (a hybrid orbit as segments, events and resets,
with a signature naming them) [Dankowicz & Schilder, Recipes for Continuation, ch. 4].
"""
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

SIDES = ("upper", "lower")


KINDS = ("rigid", "elastic")


@dataclass(frozen=True)
class Constraint:
    """One contact on s = c^T x (see the module docstring).

    ``normal`` is c (N numbers, mass order), ``gap`` g, ``side`` "upper" or "lower".
    A rigid contact has ``restitution`` r with 0 < r <= 1 and ``impulse`` the direction
    q of the velocity jump (None: M^-1 c, the rigid contact); an elastic one has
    ``restitution`` None, ``stiffness`` k_s > 0 and ``damping`` c_s >= 0, and no reset.
    Built by :meth:`symvi.model.Stop.constraint`; the numbers are checked there.
    """

    normal: tuple
    gap: float
    restitution: float = None
    side: str = "upper"
    impulse: tuple = None
    stiffness: float = None
    damping: float = None

    def __post_init__(self):
        c = tuple(float(x) for x in self.normal)
        if not c or not all(math.isfinite(x) for x in c) or not any(c):
            raise ParameterError("constraint.normal", self.normal, "N finite numbers, not all 0")
        object.__setattr__(self, "normal", c)
        if self.side not in SIDES:
            raise ParameterError("constraint.side", self.side, '"upper" or "lower"')
        if self.impulse is not None:
            q = tuple(float(x) for x in self.impulse)
            if len(q) != len(c) or not math.isfinite(sum(a * b for a, b in zip(c, q))) \
                    or sum(a * b for a, b in zip(c, q)) == 0:
                raise ParameterError("constraint.impulse", self.impulse,
                                     f"{len(c)} finite numbers q with c^T q != 0")
            object.__setattr__(self, "impulse", q)
        if (self.restitution is None) == (self.stiffness is None):
            raise ParameterError("constraint.kind", (self.restitution, self.stiffness),
                                 "a restitution (rigid) or a stiffness (elastic), not both")
        if self.stiffness is None and self.damping is not None:
            raise ParameterError("constraint.damping", self.damping,
                                 "none for a rigid contact (an elastic one has a stiffness)")
        if self.stiffness is not None and self.impulse is not None:
            raise ParameterError("constraint.impulse", self.impulse,
                                 "none for an elastic contact (it has no jump)")

    @property
    def kind(self):
        """"rigid" (a reset) or "elastic" (a contact phase, no reset)."""
        return "rigid" if self.stiffness is None else "elastic"

    def with_values(self, gap, restitution, stiffness=None, damping=None):
        """This constraint at other numbers (gap and restitution, or gap, stiffness and
        damping), checked by the caller (the Stop); the normal and impulse, checked once,
        are kept as they are: a curve in the gap or r builds one constraint per corrector
        step."""
        new = object.__new__(Constraint)
        for name in ("normal", "side", "impulse"):
            object.__setattr__(new, name, getattr(self, name))
        object.__setattr__(new, "gap", float(gap))
        for name, v in (("restitution", restitution), ("stiffness", stiffness),
                        ("damping", damping)):
            object.__setattr__(new, name, None if v is None else float(v))
        return new

    @property
    def n(self):
        """Number of masses N the constraint is written for."""
        return len(self.normal)

    @property
    def sign(self):
        """+1 for an upper stop (s <= g), -1 for a lower one (s >= g)."""
        return 1.0 if self.side == "upper" else -1.0

    @property
    def coordinate(self):
        """k (0-based) where c = e_k, the stop acts on one mass's coordinate; else None."""
        c = self.normal
        nz = [i for i, x in enumerate(c) if x != 0.0]
        return nz[0] if len(nz) == 1 and c[nz[0]] == 1.0 else None

    def s(self, x):
        """The constrained coordinate s = c^T x."""
        return sum(ci * xi for ci, xi in zip(self.normal, x) if ci != 0.0)

    def guard(self, x):
        """h(x) = sign (c^T x - g): < 0 off the stop, 0 at contact."""
        return self.sign * (self.s(x) - self.gap)

    def approach(self, v):
        """sign c^T v: > 0 when the motion goes towards the stop."""
        return self.sign * self.s(v)

    def direction(self, Minv=None):
        """The impulse direction q: ``impulse``, or M^-1 c (``Minv`` is M^-1, float64 or
        mpmath object array; q keeps its type)."""
        if self.stiffness is not None:
            raise ParameterError("constraint.kind", "elastic",
                                 "a rigid contact (an elastic contact has no impulse or reset)")
        if self.impulse is not None:
            return np.array(self.impulse)
        if Minv is None:
            raise ParameterError("Minv", None, "M^-1: a rigid contact's impulse is along M^-1 c")
        return np.asarray(Minv) @ np.array(self.normal)

    def projector(self, Minv=None):
        """Q = q c^T / (c^T q) (N x N, mass order): the part of v the reset acts on."""
        c = np.array(self.normal)
        q = self.direction(Minv)
        return np.outer(q, c) / (c @ q)

    def reset_matrix(self, Minv=None, order=None, r=None):
        """R = (I - Q) - r Q (N x N): v+ = R v- (module docstring), in mass order or in
        the order ``order`` (a permutation of the masses: R[order][:, order]); ``r``
        overrides the restitution (an mpmath r gives an object array)."""
        Q = self.projector(Minv)
        R = (np.eye(self.n) - Q) - (self.restitution if r is None else r) * Q
        if order is not None:
            R = R[np.ix_(order, order)]
        return R

    def reset(self, v, Minv=None):
        """v+ = R v- (mass order)."""
        return self.reset_matrix(Minv) @ np.asarray(v, dtype=float)


@dataclass(frozen=True)
class Signature:
    """Which constraint each event of an orbit meets: ``hits[i]`` indexes
    ``model.constraints`` for event i (i = 0..p-1): a rigid impact, or the entry into or
    the exit from an elastic contact.  ``contact``: the elastic constraints in contact
    during flight 0 (after event 0); each elastic event toggles its constraint, so the
    phase of every flight follows (:meth:`phases`).  With the default () event 0 on an
    elastic constraint is its exit: point 0 leaves the stop, as after a rigid impact."""

    hits: tuple
    contact: tuple = ()

    def __post_init__(self):
        h = self.hits
        if isinstance(h, (str, bytes)) or not hasattr(h, "__len__") or len(h) == 0 or any(
                isinstance(i, bool) or not isinstance(i, (int, np.integer)) or i < 0 for i in h):
            raise ParameterError("signature", h, "a non-empty sequence of constraint indices >= 0")
        object.__setattr__(self, "hits", tuple(int(i) for i in h))
        c = self.contact
        if isinstance(c, (str, bytes)) or not hasattr(c, "__iter__") or any(
                isinstance(i, bool) or not isinstance(i, (int, np.integer)) or i < 0 for i in c):
            raise ParameterError("signature.contact", c, "a set of constraint indices >= 0")
        object.__setattr__(self, "contact", tuple(sorted(set(int(i) for i in c))))

    def phases(self, model):
        """The elastic constraints in contact during each flight (p tuples), or
        ParameterError where the events cannot close an orbit: ``contact`` names a rigid
        constraint, or an elastic constraint is met an odd number of times (its entries
        and exits alternate)."""
        cs = self.check(model).constraints(model)
        bad = [i for i in self.contact if i >= len(model.constraints) or
               model.constraints[i].kind != "elastic"]
        if bad:
            raise ParameterError("signature.contact", self.contact,
                                 "indices of elastic constraints")
        for k in set(self.hits):
            if model.constraints[k].kind == "elastic" and self.hits.count(k) % 2:
                raise ParameterError("signature", self.hits, "an even number of events on "
                                     f"each elastic stop (stop {k + 1}: its entries and "
                                     "exits alternate)")
        S, out = set(self.contact), []
        for i, con in enumerate(cs):
            if i and con.kind == "elastic":
                S ^= {self.hits[i]}
            out.append(tuple(sorted(S)))
        return tuple(out)

    def kinds(self, model):
        """The kind of each event: "impact", "entry" or "exit" (:meth:`phases`)."""
        ph = self.phases(model)
        return tuple("impact" if model.constraints[k].kind != "elastic" else
                     "entry" if k in ph[i] else "exit" for i, k in enumerate(self.hits))

    def names(self, model):
        """["stop1", "stop2:entry", "stop2:exit", ...]: each event, stops 1-based; an
        elastic event names its kind."""
        return [f"stop{k + 1}" + ("" if kind == "impact" else f":{kind}")
                for k, kind in zip(self.hits, self.kinds(model))]

    @classmethod
    def single(cls, p):
        """The signature of p impacts on the one stop: (0,) * p."""
        return cls((0,) * int(p))

    @property
    def p(self):
        """Number of impacts."""
        return len(self.hits)

    def check(self, model):
        """``self``, or ParameterError where an index names no constraint of ``model``."""
        m = len(model.constraints)
        bad = [i for i in self.hits if i >= m]
        if bad:
            raise ParameterError("signature", self.hits,
                                 f"constraint indices from 0 to {m - 1} (the model has {m})")
        return self

    def constraints(self, model):
        """The constraint of each impact."""
        cs = model.constraints
        return tuple(cs[i] for i in self.check(model).hits)
