"""The one attractor classifier of symvi, and its one vocabulary (issue 24, item 5).

Every caller classifies with :func:`_judge` on the kept points of one run of the impact
map P: the parameter plane and :func:`classify_runs` (per point one run of the shared
loop :func:`symvi.flow.compiled._run_into` with its tangent map and escape test, in one
compiled serial batch; the caller runs batches in parallel processes), and
``symvi simulate --classify`` (:func:`symvi.simulations.diagnostics.classify`, on the
stored section of a run, the largest exponent's per-step logs from the QR method, whose
first column is the same tangent iteration).  The vocabulary is :data:`ATTRACTORS`
(with ``period-k``); :data:`KINDS` gives the spelling ``symvi simulate --classify``
has always printed for the same codes ("invariant circle", "doubled torus").

Per run of ``transient + n_keep`` iterations, the ``n_keep`` kept section points in
one reused (n_keep, 2N) buffer, then:

* ``lyapunov``: largest Lyapunov exponent of P, per impact (natural log): the mean
  of log |DP v| over the kept steps, v renormalised every step from
  v0 = (1, .., 1)/sqrt(2N) at the start (the transient aligns v with the leading
  direction).  NaN when the run stopped.  For a complex leading pair the finite-time
  mean oscillates by O(1 / n_keep) around log |multiplier|.
* ``max_velocity``: max |v_k-| (speed just before impact) over the kept impacts, also
  over those done by a run that stopped; NaN when none was kept.
* ``impacts_per_period``: n_keep / (kept time * omega / 2 pi).
* periodic (the one period detector, :func:`_period`): the smallest q in 1 .. Qmax,
  Qmax = min(max_period, n_keep // 4) (max_period 64 for a plane), such that
  e_j = |y_j - y_{j-q}| (tau difference wrapped to (-pi, pi]) over the last
  W = min(n_keep - q, max(4q, 64)) kept points are all <= 1e-7 s, s = 1 + max|y|
  over those points (a converged orbit: rounding-level closure), or all <= 1e-3 s
  and decaying: mean of the window's last quarter <= 0.5 x its first quarter's
  (a slow geometric approach to a stable orbit near a bifurcation, not yet closed),
  or the same over the whole kept record (the window sees only |multiplier|^48 >
  1/2 for |multiplier| > 0.986; the record reaches ~1 - 0.9 / n_keep).  Then the
  period k = round(omega (t_j - t_{j-q}) / 2 pi) >= 1 forcing periods, q impacts,
  code "period".  A periodic orbit of more than Qmax impacts is reported as what
  it looks like (a circle, with a clearly negative lyapunov).
* otherwise the last half of the kept record is judged, the first counting as more
  transient; when that half is still settling (its radial trend below grows or
  shrinks by more than 5 %, |b| m > 0.05, or the mean of log |DP v| over the first and the
  last half of the logs differ by more than half the chaos threshold below) only the
  last quarter (at least 64 points): next to a Neimark-Sacker point a run from the
  unstable focus spirals out for thousands of impacts before it settles on the
  circle, and a circle still approached by 1e-3 of its radius already looks doubled
  to the loop test below at a thousand points.
* chaos when the mean of log |DP v| over the last half of the logs exceeds max(b, 0)
  (b the radial growth rate per impact of the judged points, below) by more than
  max(2.5 / m, 1e-3), m the number of those logs (above the O(1 / m) bias of a
  finite mean on a quasi-periodic attractor).  On a spiral out of a focus of
  multipliers rho e^{+-i theta} the tangent grows as the radius, both as rho^j: the
  exponent is the spiral's, not chaos.  (Example 1 at omega = 0.738: log rho =
  2.85e-3 for the first ~2500 impacts, then a circle, exponent 0 +- 5e-4;
  tests/simulations/test_classifier.py.)
* else quasi-periodic: the judged points, tau recentred about its circular mean and
  wrapped to (-pi, pi], taken about their centre with a geometric radial trend
  removed: r_j = |y_j - centre| ~ exp(a + b j) fitted by least squares on log r_j
  and the points scaled by exp(-b j) about the centre, the centre being the mean
  weighted by exp(-b j) (two passes from the centroid).  A spiral still converging
  to a focus or growing towards a circle (|multiplier| within ~1/n_keep of 1, as
  next to a Neimark-Sacker point) becomes its closed curve; a settled attractor
  has b ~ 0 and is left as it is.  (A focus approached too slowly for the decay
  test, |multiplier| in ~(1 - 0.9 / n_keep, 1), is thus reported as a circle, its
  lyapunov ~ log |multiplier| < 0.)  Those points are projected on the plane of their
  two leading principal components and sorted by angle around the centre; L_all is
  the closed polygon through all points in that order, L_half the same through the
  first half of the points, lengths measured in the full 2N space (two strands
  that cross in the projection are still apart there).  One smooth closed curve
  around the centre: both polygons converge to its length, ratio ~ 1; a curve
  winding twice (strands alternate in angle) or a cloud: the polygon zigzags, its
  length grows with the number of points, ratio ~ 2.  L_all / L_half < 1.3:
  "circle", else "doubled-torus".  Without the trend removal a radial drift of 1 %
  over the record already gives a ratio ~ 1.6.
* ``rotation``: |mean angle increment| / 2 pi between successive kept points in
  that plane, each increment wrapped to (-pi, pi]: in [0, 1/2] (the plane's
  orientation is arbitrary, as the argument of a multiplier in [0, pi]).  Defined
  for a completed run with at least 3 distinct points (periodic with q >= 3,
  circle, doubled torus, chaos), NaN otherwise.
* stopped runs: no impact -> "no-impact"; sticking or chatter -> "sticking" (with
  ``models`` a run that sticks is run on through its sticking phases and judged on its
  impacts instead: a periodic sticking orbit is period-k, ``Classified.sticking``);
  non-finite state, or |y| > 1e6 (escape; stop code "non-finite") -> "escape";
  grazing -> "grazing".  Their period, impacts are 0 and lyapunov, rotation,
  impacts_per_period NaN.
* ``y_end``: the last section point accepted (for a stopped run the one before the
  failed step: finite), from which a caller may continue; ``k_end`` the stop whose
  section it lies on.
* several rigid stops (issue 25): each kept point lies on the section of the stop it hit
  (``hits``, in that stop's own layout).  Periodic: the joint sequence (hit, point) has
  period q: the window test above also needs hits_j = hits_{j-q} throughout, points are
  compared only on one stop, and in the whole-record decay test a pair on two stops
  counts as the scale s (first quarter: still far) or fails (last quarter).  The
  signature is the stops of the orbit's last q impacts, read from the rotation smallest
  in lexicographic order (:func:`signature`; the symmetric orbit of two stops is
  (stop1, stop2)).  Otherwise the points of the stop hit most often are judged (a
  section of the attractor by that stop, its first-return map: a closed curve stays one
  curve, a cloud a cloud) with the logs of every impact; their radial trend b is per
  judged point, b n_judged / n per impact in the chaos test, and the rotation is per
  return to that stop (likewise for a periodic orbit with >= 3 impacts on it).  With
  one stop none of this runs: the same bits as before.

``follow=True``: in each consecutive group of ``row_len`` points (a row; the whole
batch when None) a point after the first starts from the last section point of the
previous one (on the stop whose section it lies on, ``k_end``) when that run reached a
bounded attractor (period, circle, doubled torus, chaos), else from its own Y0 (on the
first stop's section).  Outputs depend only on a point's inputs (and,
with follow, on its row's earlier points): same inputs, same bits.
"""
import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..errors import ParameterError
from ..flow.compiled import (_NC, _NN, _OM, COMPLETED, STOP_CHATTER, STOP_GRAZING,
                             STOP_NO_IMPACT, STOP_STICKING, _run_into)

__all__ = ["ATTRACTORS", "KINDS", "FIELDS", "Classified", "classify_runs", "label", "kind",
           "code_of_stop", "signature", "min_kept"]

#: the vocabulary: attractor codes 0 .. 7 (code 0 is spelled period-k, k forcing periods)
ATTRACTORS = ("period", "circle", "doubled-torus", "chaos", "no-impact", "sticking", "escape",
              "grazing")
#: the same codes as ``symvi simulate --classify`` prints them (its public spelling;
#: a stopped run prints "stopped: <stop name>")
KINDS = ("period", "invariant circle", "doubled torus", "chaos", "no-impact", "sticking",
         "escape", "grazing")
FIELDS = ("code", "period", "impacts", "lyapunov", "rotation", "impacts_per_period",
          "max_velocity")

PERIOD, CIRCLE, DOUBLED, CHAOS, NOIMPACT, STICKING, ESCAPE, GRAZED = range(8)

#: closure of a converged periodic orbit, relative to 1 + max|y|
TOL_CLOSED = 1e-7
#: closure of a periodic orbit still approached slowly (with decay)
TOL_SLOW = 1e-3
#: decay over the window: mean of the last quarter / mean of the first quarter
DECAY = 0.5
#: largest number of impacts of a periodic orbit looked for in a plane
Q_MAX = 64
#: shortest comparison window
W_MIN = 64
#: chaos: exponent (less the radial growth) above max(LYAP_BIAS / m, LYAP_MIN)
LYAP_BIAS = 2.5
LYAP_MIN = 1e-3
#: L_all / L_half below this: one closed curve
RATIO_CIRCLE = 1.3
#: a judged half whose radius drifts by more than this (|b| m) is still settling: a
#: settled circle or doubled torus drifts by < 0.02 over 1000-2000 points, the approach
#: to the circle of example 1 at 0.7369 from 0.1 outside by 0.2 over 2000
SETTLING = 0.05
#: bound on |b| n of the radial trend exp(b j) removed before the loop test
DRIFT_MAX = 60.0
#: |y| beyond this: escape (the attractor code ESCAPE above is another name)
ESCAPE_MAX = 1e6

#: fewest kept impacts: the decay tests compare quarters of the kept record
MIN_KEPT = 4

_TWO_PI = 2.0 * math.pi


def label(code, period):
    """Name of attractor ``code`` (of ``ATTRACTORS``): f"period-{period}" for code 0."""
    code = int(code)
    return f"period-{int(period)}" if code == PERIOD else ATTRACTORS[code]


def kind(code, period):
    """The spelling of ``symvi simulate --classify``: :data:`KINDS`, period-k for code 0."""
    code = int(code)
    return f"period-{int(period)}" if code == PERIOD else KINDS[code]


def code_of_stop(stop):
    """Attractor code of a run stopped with code ``stop`` (symvi.flow.compiled.STOP_*)."""
    if stop == STOP_NO_IMPACT:
        return NOIMPACT
    if stop == STOP_STICKING or stop == STOP_CHATTER:
        return STICKING
    if stop == STOP_GRAZING:
        return GRAZED
    return ESCAPE


_code_of_stop = nb.njit(cache=True)(code_of_stop)


@nb.njit(cache=True, inline="always")
def _wrap(a):
    """a wrapped to (-pi, pi]."""
    a = a - _TWO_PI * math.floor(a / _TWO_PI)       # [0, 2 pi)
    return a - _TWO_PI if a > math.pi else a


@nb.njit(cache=True, inline="always")
def _dist(sec, j, k, dim):
    """|y_j - y_k|, the tau difference wrapped to (-pi, pi]."""
    e2 = 0.0
    for i in range(dim - 1):
        dd = sec[j, i] - sec[k, i]
        e2 += dd * dd
    dd = _wrap(sec[j, dim - 1] - sec[k, dim - 1])
    return math.sqrt(e2 + dd * dd)


@nb.njit(cache=True)
def _period(sec, times, hits, n, dim, omega, qmax, tol):
    """(q, k) of the periodic attractor of the n kept points, or (0, 0): the one period
    detector (module docstring; ``tol`` the closure TOL_CLOSED).  omega = 0: no times,
    (q, 0) for the first closing q.  ``hits`` (empty: one section): the stop of each
    point; the joint sequence (hit, point) must repeat, points compared only on one stop
    (a pair on two stops is as far apart as the scale s)."""
    several = hits.shape[0] > 0
    qmax = min(qmax, n // 4)
    for q in range(1, qmax + 1):
        W = min(n - q, max(4 * q, W_MIN))
        s = 0.0
        for j in range(n - W, n):
            for i in range(dim):
                s = max(s, abs(sec[j, i]))
        s = 1.0 + s
        emax = 0.0
        first = 0.0
        last = 0.0
        quarter = max(W // 4, 1)
        same = True
        for jj in range(W):
            j = n - W + jj
            if several and hits[j] != hits[j - q]:
                same = False                      # another itinerary: not period q
                break
            ej = _dist(sec, j, j - q, dim)
            emax = max(emax, ej)
            if emax > TOL_SLOW * s:
                break
            if jj < quarter:
                first += ej
            if jj >= W - quarter:
                last += ej
        if not (same and emax <= TOL_SLOW * s):
            continue
        closed = emax <= tol * s or last <= DECAY * first
        if not closed:
            # the same decay over the whole record: approaches too slow for one window
            quarter = (n - q) // 4
            first = 0.0
            last = 0.0
            for jj in range(quarter):
                if several and hits[q + jj] != hits[jj]:
                    first += s                    # still on another itinerary: far
                else:
                    first += _dist(sec, q + jj, jj, dim)
                if several and hits[n - 1 - jj] != hits[n - 1 - jj - q]:
                    last = np.inf                 # not yet on the orbit's itinerary
                else:
                    last += _dist(sec, n - 1 - jj, n - 1 - jj - q, dim)
            closed = last <= DECAY * first
        if not closed:
            continue
        if omega <= 0.0:
            return q, 0
        k = round(omega * (times[n - 1] - times[n - 1 - q]) / _TWO_PI)
        if k >= 1:
            return q, k
    return 0, 0


@nb.njit(cache=True)
def _plane(sec, j0, n, dim, pts, ang):
    """Points j0 .. j0+n-1 into pts[:n]: tau recentred about its circular mean, a
    geometric radial trend removed about the centre (module docstring); their angles
    in the plane of the two leading principal components into ang.  Returns the trend
    b (log radius per impact)."""
    sn = 0.0
    cs = 0.0
    for j in range(n):
        sn += math.sin(sec[j0 + j, dim - 1])
        cs += math.cos(sec[j0 + j, dim - 1])
    tau0 = math.atan2(sn, cs)
    centre = np.zeros(dim)
    for j in range(n):
        for i in range(dim - 1):
            pts[j, i] = sec[j0 + j, i]
        pts[j, dim - 1] = _wrap(sec[j0 + j, dim - 1] - tau0)
        for i in range(dim):
            centre[i] += pts[j, i]
    for i in range(dim):
        centre[i] /= n
    # r_j ~ exp(a + b j) fitted by least squares on log r_j; the centre of such a
    # spiral is the mean weighted by exp(-b j) (a linear spiral is an ellipse times
    # |multiplier|^j); two passes from the plain centroid
    mid = 0.5 * (n - 1)
    b = 0.0
    for _ in range(2):
        sx = sy = sxx = sxy = 0.0
        cnt = 0
        for j in range(n):
            r2 = 0.0
            for i in range(dim):
                dd = pts[j, i] - centre[i]
                r2 += dd * dd
            if r2 > 0.0:
                x = j - mid
                yv = 0.5 * math.log(r2)
                sx += x
                sy += yv
                sxx += x * x
                sxy += x * yv
                cnt += 1
        den = cnt * sxx - sx * sx
        b = (cnt * sxy - sx * sy) / den if den > 0.0 else 0.0
        b = min(max(b, -DRIFT_MAX / n), DRIFT_MAX / n)     # keep exp() finite
        wsum = 0.0
        for i in range(dim):
            centre[i] = 0.0
        for j in range(n):
            wj = math.exp(-b * (j - mid))
            wsum += wj
            for i in range(dim):
                centre[i] += wj * pts[j, i]
        for i in range(dim):
            centre[i] /= wsum
    cov = np.zeros((dim, dim))
    for j in range(n):
        wj = math.exp(-b * (j - mid))
        for i in range(dim):
            pts[j, i] = (pts[j, i] - centre[i]) * wj
        for a in range(dim):
            for c in range(a + 1):
                cov[a, c] += pts[j, a] * pts[j, c]
    for a in range(dim):
        for c in range(a):
            cov[c, a] = cov[a, c]
    _, vec = np.linalg.eigh(cov)                    # ascending eigenvalues
    for j in range(n):
        p1 = 0.0
        p2 = 0.0
        for i in range(dim):
            p1 += pts[j, i] * vec[i, dim - 1]
            p2 += pts[j, i] * vec[i, dim - 2]
        ang[j] = math.atan2(p2, p1)
    return b


@nb.njit(cache=True)
def _rotation(ang, n):
    """|mean wrapped angle increment| / 2 pi."""
    s = 0.0
    for j in range(1, n):
        s += _wrap(ang[j] - ang[j - 1])
    return abs(s / (n - 1)) / _TWO_PI


@nb.njit(cache=True)
def _loop_length(pts, ang, n, dim):
    """Length (full space) of the closed polygon through points 0 .. n-1 in angle order."""
    order = np.argsort(ang[:n], kind="mergesort")      # stable: ties keep index order
    L = 0.0
    for jj in range(n):
        a, b = order[jj], order[(jj + 1) % n]
        d2 = 0.0
        for i in range(dim):
            dd = pts[a, i] - pts[b, i]
            d2 += dd * dd
        L += math.sqrt(d2)
    return L


@nb.njit(cache=True)
def _one_section(sec, hits, n, dim):
    """(the points of the stop hit most often among the n, in order; their number; the
    stop), ties to the lower stop: with several stops each stop's points are the section of
    the attractor by that stop (its first-return map), so a closed curve stays one."""
    nc = 0
    for j in range(n):
        nc = max(nc, hits[j] + 1)
    count = np.zeros(nc, np.int64)
    for j in range(n):
        count[hits[j]] += 1
    best = 0
    for g in range(nc):
        if count[g] > count[best]:
            best = g
    sub = np.empty((count[best], dim))
    m = 0
    for j in range(n):
        if hits[j] == best:
            for i in range(dim):
                sub[m, i] = sec[j, i]
            m += 1
    return sub, m, best


@nb.njit(cache=True)
def _judge(sec, times, glog, hits, n, dim, omega, qmax, tol, lyap_min, pts, ang, out_f):
    """The classifier: attractor of the n kept points of a completed run (sec, times)
    with the per-step logs ``glog`` of the largest exponent (module docstring).
    ``hits`` (empty: one section): the stop of each point; the period is that of the
    joint sequence (hit, point), the rest is judged on the points of the stop hit most
    often (:func:`_one_section`).  Returns (code, k forcing periods, q impacts); the
    rotation into out_f[0]."""
    out_f[0] = np.nan
    q, k = _period(sec, times, hits, n, dim, omega, qmax, tol)
    per = 1.0                                     # impacts per judged point
    if hits.shape[0] > 0:
        sec, ns, best = _one_section(sec, hits, n, dim)
        per = n / ns
        if q > 0:
            qs = 0                                # the orbit's points on that stop
            for j in range(n - q, n):
                if hits[j] == best:
                    qs += 1
            if qs >= 3:
                _plane(sec, 0, ns, dim, pts, ang)
                out_f[0] = _rotation(ang, ns)
            return PERIOD, k, q
        n = ns
    if q > 0:
        if q >= 3:
            _plane(sec, 0, n, dim, pts, ang)
            out_f[0] = _rotation(ang, n)
        return PERIOD, k, q
    m = n - n // 2                                # the last half ...
    b = _plane(sec, n - m, m, dim, pts, ang)
    nl = glog.shape[0]
    ml = nl - nl // 2
    lt = 0.0                                      # mean log growth over the last half
    la = 0.0                                      # ... and over the first
    for j in range(nl):
        if j < nl // 2:
            la += glog[j]
        else:
            lt += glog[j]
    lt = lt / ml if ml > 0 else 0.0
    la = la / (nl // 2) if nl >= 2 else lt
    thr = max(LYAP_BIAS / max(ml, 1), lyap_min)
    if abs(b) * m > SETTLING or abs(la - lt) > 0.5 * thr:
        # ... or, still settling (its radius drifting, or an exponent not yet steady),
        # the last quarter
        m = max(n // 4, min(n, W_MIN))
        b = _plane(sec, n - m, m, dim, pts, ang)
    out_f[0] = _rotation(ang, m)
    # a spiral's exponent is its radial growth b (per judged point; per impact b / per):
    # chaos only beyond it
    if nl >= 2 and lt - max(b, 0.0) / per > thr:
        return CHAOS, 0, 0
    ratio = _loop_length(pts, ang, m, dim) / _loop_length(pts, ang, m // 2, dim)
    return (CIRCLE if ratio < RATIO_CIRCLE else DOUBLED), 0, 0


@nb.njit(cache=True)
def _classify_one(c, y, k, n_keep, transient, sec, times, vimp, hits, glog, v, pts, ang,
                  out_f):
    """Run the shared loop from y on constraint k's section (y left at the last section
    point) with the tangent map and the escape test, and classify.  ``hits`` (n_keep, or
    empty for one constraint): the stop of each kept point.  Returns (code, period,
    impacts, stop, the constraint of y's section at the end); floats (lyapunov, rotation,
    impacts_per_period, max_velocity) into out_f."""
    n = int(c[_NN])
    dim = 2 * n
    omega = c[_OM]
    for i in range(dim):
        v[i] = 1.0 / math.sqrt(dim)
    stop, kept, _, T0, k, _, _ = _run_into(c, y, k, n_keep, transient, sec, times, vimp, hits, v,
                                     glog, ESCAPE_MAX)
    nan = np.nan
    vmax = -1.0
    for j in range(kept):
        vmax = max(vmax, abs(vimp[j]))
    out_f[0] = nan
    out_f[1] = nan
    out_f[2] = nan
    out_f[3] = vmax if kept > 0 else nan
    if stop != COMPLETED:
        return _code_of_stop(stop), 0, 0, stop, k
    lsum = 0.0
    for j in range(n_keep):
        lsum += glog[j]
    out_f[0] = lsum / n_keep
    out_f[2] = n_keep / ((times[n_keep - 1] - T0) * omega / _TWO_PI)
    rot = np.empty(1)
    cd, kk, q = _judge(sec, times, glog, hits, n_keep, dim, omega, Q_MAX, TOL_CLOSED,
                       LYAP_MIN, pts, ang, rot)
    out_f[1] = rot[0]
    return cd, kk, q, stop, k


@nb.njit(cache=True)
def _classify_batch(C, Y0, n_keep, transient, follow, row_len, code, period, impacts, floats,
                    stop, y_end, followed, k_end, sigs):
    m = C.shape[0]
    n = int(C[0, _NN])
    dim = 2 * n
    several = sigs.shape[1] > 0               # record the stop of each kept impact
    sec = np.empty((n_keep, dim))
    times = np.empty(n_keep)
    vimp = np.empty(n_keep)
    hits = np.empty(n_keep if several else 0, np.int64)
    glog = np.empty(n_keep)
    pts = np.empty((n_keep, dim))
    ang = np.empty(n_keep)
    v = np.empty(dim)
    y = np.empty(dim)
    out_f = np.empty(4)
    for p in range(m):
        own = True
        if follow and p % row_len != 0:
            own = not (code[p - 1] == PERIOD or code[p - 1] == CIRCLE
                       or code[p - 1] == DOUBLED or code[p - 1] == CHAOS)
        followed[p] = not own
        for i in range(dim):
            y[i] = Y0[p, i] if own else y_end[p - 1, i]
        k = 0 if own else k_end[p - 1]
        cd, kk, q, st, k = _classify_one(C[p], y, k, n_keep, transient, sec, times, vimp,
                                         hits, glog, v, pts, ang, out_f)
        code[p], period[p], impacts[p], stop[p], k_end[p] = cd, kk, q, st, k
        for i in range(4):
            floats[i, p] = out_f[i]
        for i in range(dim):
            y_end[p, i] = y[i]
        if several and cd == PERIOD:
            for j in range(q):                # the stops of the orbit's last q impacts
                sigs[p, j] = hits[n_keep - q + j]


@dataclass(frozen=True)
class Classified:
    """Attractors of a batch (m points); see the module docstring for each field."""

    code: np.ndarray                 # int8, index into ATTRACTORS
    period: np.ndarray               # int32, forcing periods of a periodic attractor, else 0
    impacts: np.ndarray              # int32, impacts per orbit of a periodic attractor, else 0
    lyapunov: np.ndarray             # float64, per impact
    rotation: np.ndarray             # float64, in [0, 1/2]
    impacts_per_period: np.ndarray   # float64
    max_velocity: np.ndarray         # float64, max |v_k-|
    stop: np.ndarray                 # int8, index into symvi.flow.compiled.STOP_NAMES
    y_end: np.ndarray                # (m, 2N) float64, the last section point
    followed: np.ndarray             # bool, started from the previous point's y_end
    #: int64 (m,): the constraint whose section y_end lies on (0 with one stop)
    k_end: np.ndarray = None
    #: with several stops, per point the stops (0-based) of a periodic attractor's impacts
    #: in order (:func:`signature`), () when not periodic; None with one stop
    signature: tuple = None
    #: with an elastic stop, per point the kind of each event of :attr:`signature`
    #: ("impact", "entry", "exit"); None otherwise
    kinds: tuple = None
    #: bool (m,): the run went through sticking phases (complete chatter, the mass held on
    #: a stop, released: :mod:`symvi.flow.sticking`), its attractor judged on its impacts
    #: (a periodic one is period-k); None when not asked (no ``models``)
    sticking: np.ndarray = None

    def labels(self):
        """Names of the attractors: "period-3", "circle", ..."""
        return np.array([label(c, k) for c, k in zip(self.code, self.period)], dtype=str)

    def signature_names(self):
        """Per point ["stop1", "stop2", ...] of a periodic attractor (an elastic stop's
        events "stop1:entry", "stop1:exit", as :meth:`symvi.model.Signature.names`), None
        otherwise (and for every point with one stop)."""
        if self.signature is None:
            return [None] * len(self.code)
        kinds = self.kinds or [()] * len(self.code)
        return [[f"stop{g + 1}" + ("" if kd == "impact" else f":{kd}")
                 for g, kd in zip(sig, kind or ("impact",) * len(sig))] if sig else None
                for sig, kind in zip(self.signature, kinds)]


def signature(hits):
    """The stops of one period of a periodic attractor, ``hits`` its last q impacts'
    constraints, as a tuple read from the rotation that is smallest in lexicographic
    order (an orbit has no first impact: the symmetric orbit of two stops is (0, 1)
    whichever it was seen starting from)."""
    h = [int(g) for g in hits]
    return min((tuple(h[i:] + h[:i]) for i in range(len(h))), default=())


def min_kept(nc):
    """Fewest kept impacts a run of a model with ``nc`` stops is classified from: MIN_KEPT
    on the section judged (the stop hit most often has at least n / nc of them)."""
    return MIN_KEPT * max(int(nc), 1)


def classify_runs(C, Y0, n_keep, transient, *, follow=False, row_len=None, models=None):
    """Run and classify one batch: rows of C (:func:`symvi.flow.compiled.constants`, one
    model size and number of stops) from the start points Y0 (m, 2N), each on the first
    stop's section, in one compiled serial loop.

    ``n_keep`` (>= 4 per stop, :func:`min_kept`) kept impacts after ``transient`` dropped
    ones.  ``follow`` continues each row (``row_len`` points, the whole batch when None)
    from the previous point's attractor (module docstring).  With several stops the
    periodic attractors' signatures are in ``Classified.signature``.

    ``models`` (one :class:`symvi.model.Model` per row, a function of the row giving it,
    or one for all): a run that stops
    at sticking goes on through it (:func:`symvi.flow.sticking.run_through`, in Python,
    from the same start) and is judged on its impacts by :func:`_judge` without the
    tangent map (no exponent across a held phase: ``lyapunov`` NaN, no chaos test);
    ``Classified.sticking`` flags those points.  Without ``models`` such a run keeps the
    label "sticking".
    """
    C = np.ascontiguousarray(np.atleast_2d(C), dtype=np.float64)
    Y0 = np.ascontiguousarray(np.atleast_2d(Y0), dtype=np.float64)
    m = C.shape[0]
    if m == 0 or Y0.shape[0] != m:
        raise ParameterError("Y0", Y0.shape, f"one start point per row of C ({m})")
    n = int(C[0, _NN])
    nc = int(C[0, _NC])
    if not np.all(C[:, _NN] == n) or not np.all(C[:, _NC] == nc) or Y0.shape[1] < 2 * n:
        raise ParameterError("C", "model sizes", f"rows of one model size N and number of "
                             f"stops with Y0 of width 2N = {2 * n}")
    n_keep, transient = int(n_keep), int(transient)
    if n_keep < min_kept(nc):
        raise ParameterError("n_keep", n_keep, f"an integer >= {min_kept(nc)}"
                             + (f" ({MIN_KEPT} per stop)" if nc > 1 else ""))
    if transient < 0:
        raise ParameterError("transient", transient, "an integer >= 0")
    row_len = m if row_len is None else int(row_len)
    if row_len < 1:
        raise ParameterError("row_len", row_len, "an integer >= 1")
    code = np.zeros(m, dtype=np.int8)
    period = np.zeros(m, dtype=np.int32)
    impacts = np.zeros(m, dtype=np.int32)
    floats = np.empty((4, m))
    stop = np.zeros(m, dtype=np.int8)
    y_end = np.empty((m, 2 * n))
    followed = np.zeros(m, dtype=np.bool_)
    k_end = np.zeros(m, dtype=np.int64)
    sigs = np.full((m, Q_MAX if nc > 1 else 0), -1, dtype=np.int64)
    _classify_batch(C, Y0, n_keep, transient, bool(follow), row_len, code, period, impacts,
                    floats, stop, y_end, followed, k_end, sigs)
    sticking = None
    if models is not None:
        sticking = np.zeros(m, dtype=np.bool_)
        for p in np.flatnonzero(stop == STOP_STICKING):
            model = (models[p] if isinstance(models, (list, tuple)) else
                     models(p) if callable(models) else models)
            # the start the batch used: its own, or the previous point's end (never a
            # sticking point's, so never one changed here)
            y, k = (Y0[p, :2 * n], 0) if not followed[p] else (y_end[p - 1], k_end[p - 1])
            _through(C[p], model, y, k, n_keep, transient, p, code, period, impacts, floats,
                     stop, y_end, k_end, sigs, sticking)
    sig = None if nc == 1 else tuple(signature(row[:q]) for row, q in zip(sigs, impacts))
    return Classified(code, period, impacts, floats[0], floats[1], floats[2], floats[3], stop,
                      y_end, followed, k_end, sig, sticking=sticking)


def _through(c, model, y, k, n_keep, transient, p, code, period, impacts, floats, stop,
             y_end, k_end, sigs, sticking):
    """Point p again, through its sticking phases, judged on its impacts (row p of the
    outputs of :func:`classify_runs` replaced)."""
    from ..flow.sticking import run_through
    st, sec, t, vimp, hits, sticks, _ = run_through(model, c, y, n_keep, transient, k)
    nc = int(c[_NC])
    stop[p] = st
    sticking[p] = len(sticks) > 0
    if len(sec):
        y_end[p], k_end[p] = sec[-1], hits[-1]
        floats[3, p] = np.max(np.abs(vimp))
    if st != COMPLETED:
        code[p] = code_of_stop(st)
        return
    h = np.ascontiguousarray(hits) if nc > 1 else np.empty(0, np.int64)
    rot = np.empty(1)
    dim = sec.shape[1]
    cd, kk, q = _judge(np.ascontiguousarray(sec), np.ascontiguousarray(t), np.empty(0), h,
                       n_keep, dim, float(c[_OM]), Q_MAX, TOL_CLOSED, LYAP_MIN,
                       np.empty((n_keep, dim)), np.empty(n_keep), rot)
    code[p], period[p], impacts[p] = cd, kk, q
    floats[0, p], floats[1, p] = np.nan, rot[0]
    floats[2, p] = n_keep / ((t[-1] - t[0]) * float(c[_OM]) / _TWO_PI) if n_keep > 1 else np.nan
    if nc > 1 and cd == PERIOD:
        sigs[p, :q] = hits[n_keep - q:]


def classify_section(section, t, omega, logs, *, hits=None, max_period=Q_MAX,
                     tol=TOL_CLOSED, lyap_min=LYAP_MIN):
    """:func:`_judge` on the stored points of a completed run: (code, k, q, rotation).

    ``logs``: per-step log |DP v| of the largest exponent over the last points (any
    number, none to skip the chaos test).  ``hits``: with several stops, the stop of each
    point (each lies on that stop's section); the signature of a periodic attractor is
    then :func:`signature` of ``hits[-q:]``."""
    sec = np.ascontiguousarray(section, dtype=np.float64)
    n, dim = sec.shape
    h = np.empty(0, np.int64) if hits is None else np.ascontiguousarray(hits, dtype=np.int64)
    if hits is not None and h.shape != (n,):
        raise ParameterError("hits", h.shape, f"one stop per section point ({n})")
    least = MIN_KEPT if hits is None else min_kept(int(h.max()) + 1 if n else 1)
    if n < least:
        raise ParameterError("section", n, f"at least {least} points")
    rot = np.empty(1)
    cd, k, q = _judge(sec, np.ascontiguousarray(t, dtype=np.float64),
                      np.ascontiguousarray(logs, dtype=np.float64), h, n, dim, float(omega),
                      int(max_period), float(tol), float(lyap_min),
                      np.empty((n, dim)), np.empty(n), rot)
    return int(cd), int(k), int(q), float(rot[0])


def period_of(section, max_period=64, tol=TOL_CLOSED):
    """Smallest q (impacts) after which the points repeat, by the one detector
    :func:`_period`, or None."""
    sec = np.ascontiguousarray(section, dtype=np.float64)
    n, dim = sec.shape
    q, _ = _period(sec, np.empty(0), np.empty(0, np.int64), n, dim, 0.0, int(max_period),
                   float(tol))
    return int(q) if q > 0 else None
