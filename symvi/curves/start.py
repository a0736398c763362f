"""Where a curve starts: the fold, flip or NS points that one-parameter continuation in
omega locates over [omega_min, omega_max] (period-1 branches and the period-doubled
branches born at their flips, :func:`symvi.continuation.period1_branches`)."""
from ..errors import ParameterError, SingularCaseError
from .curve import continue_curve

_BRANCH_KIND = {"ns": "ns", "flip": "flip", "fold": "fold"}


def parse_params(text):
    """The two curve parameters from "NAME,NAME" (the CLI's --params, a scene's plane)."""
    names = tuple(s.strip() for s in str(text).split(","))
    if len(names) != 2 or not all(names) or names[0] == names[1]:
        raise ParameterError("--params", text, "two different names separated by a comma, "
                             "e.g. omega,b")
    return names


def start_points(model, omega_min, omega_max, kind):
    """The admissible located points of ``kind`` on the branches over the interval, those of
    the primary (fewest-impact) orbits first, then by omega: [(SpecialPoint, Branch)]."""
    from ..continuation import period1_branches
    if kind not in _BRANCH_KIND:
        raise ParameterError("kind", kind, "ns, flip or fold")
    out = []
    for br in period1_branches(model, omega_min, omega_max):
        for sp in br.special:
            if sp.kind == kind and sp.orbit.admissible:
                if not any(abs(sp.value - o.value) < 1e-9 and o.orbit.p == sp.orbit.p
                           for o, _ in out):
                    out.append((sp, br))
    return sorted(out, key=lambda x: (x[0].orbit.p, x[0].value))


def curve_from_interval(model, omega_min, omega_max, names, *, kind="ns", index=1, **kw):
    """The ``kind`` curve in ``names`` through the ``index``-th (1-based, by omega) point of
    that kind found in [omega_min, omega_max]; keywords as :func:`continue_curve`."""
    pts = start_points(model, omega_min, omega_max, kind)
    if not pts:
        raise SingularCaseError("no-start", f"no admissible {kind} point in omega = "
                                f"[{omega_min:g}, {omega_max:g}]: no {kind} curve to start")
    if not 1 <= index <= len(pts):
        raise ParameterError("index", index, f"an integer from 1 to {len(pts)} (the {kind} "
                             f"points found: omega = "
                             + ", ".join(f"{sp.value:.9g}" for sp, _ in pts) + ")")
    sp, br = pts[index - 1]
    fixed = {}
    if "omega" not in names:
        fixed["omega"] = sp.value
    return continue_curve(model, kind, names, sp.orbit, **fixed, **kw), sp
