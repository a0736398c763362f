"""Where a curve starts: the fold, flip or NS points that one-parameter continuation in
omega locates over [omega_min, omega_max] (period-1 branches and the period-doubled
branches born at their flips, :func:`symvi.continuation.period1_branches`)."""
from ..errors import ParameterError, SingularCaseError
from .curve import continue_curve

_BRANCH_KIND = {"ns": "ns", "flip": "flip", "fold": "fold", "grazing": "grazing"}


def parse_params(text, flag="--params"):
    """The two curve parameters from "NAME,NAME" (the CLI's --params, a scene's plane).
    Commas inside brackets belong to a name: ``omega,stiffness[1,2]``."""
    names, depth, cur = [], 0, ""
    for ch in str(text):
        depth += {"[": 1, "]": -1}.get(ch, 0)
        if depth < 0 or depth > 1:
            break
        if ch == "," and depth == 0:
            names.append(cur)
            cur = ""
        else:
            cur += ch
    names = tuple(n.strip() for n in names + [cur])
    if depth != 0 or len(names) != 2 or not all(names) or names[0] == names[1]:
        raise ParameterError(flag, text, "two different names separated by a comma, "
                             "e.g. omega,b or omega,stiffness[1,2]")
    return names


def curve_params(model, text, flag="--params"):
    """The two curve parameters of "NAME,NAME" (:func:`parse_params`) as names of ``model``:
    each one of its parameters, not the same one twice (``b`` and ``gap``, ``mass[1,2]`` and
    ``mass[2,1]`` are one parameter: the same tangent), with nonlinear forces one the
    series take (:func:`symvi.flow.nljet.check_parameter`); an error names ``flag``.
    Nothing is computed: a front end asks this first."""
    names = parse_params(text, flag)
    check_pair(model, names, flag, text)
    return names


def check_pair(model, names, flag="names", shown=None):
    """Refuse (ParameterError naming ``flag``) two curve parameters ``names`` that are not
    two different parameters of ``model`` that its curves take (:func:`curve_params`)."""
    import numpy as np
    from ..model.parameters import NamedParameter
    pars = []
    for nm in names:
        try:
            pars.append(model.parameter(nm))
        except ParameterError as exc:
            raise ParameterError(flag, nm, exc.valid) from None
    # a nonlinear force's parameter has no tangent: it is one parameter per name
    if not any(par.is_forcing_frequency or isinstance(par, NamedParameter) for par in pars):
        ta, tb = (par.tangent(model) for par in pars)
        if all(np.array_equal(getattr(ta, f), getattr(tb, f))
               for f in ("dM", "dK", "dC", "dP", "db", "dr", "dk", "dc", "stop")):
            raise ParameterError(flag, names if shown is None else shown, "two different "
                                 "parameters (these two names are one parameter)")
    if model.nonlinear is not None:
        from ..flow.nljet import check_parameter
        for nm, par in zip(names, pars):
            try:
                check_parameter(model, par)
            except ParameterError as exc:
                raise ParameterError(flag, nm, exc.valid) from None


def start_points(model, omega_min, omega_max, kind, *, branches=None):
    """The admissible located points of ``kind`` on the branches over the interval, those of
    the primary (fewest-impact) orbits first, then by omega: [(SpecialPoint, Branch)].
    ``branches``: those of :func:`symvi.continuation.period1_branches` over the interval,
    when already computed."""
    if kind not in _BRANCH_KIND:
        raise ParameterError("kind", kind, "ns, flip, fold or grazing")
    out = []
    if branches is None:
        branches = omega_branches(model, omega_min, omega_max)
    for br in branches:
        for sp in br.special:
            # a grazing point is inadmissible by nature: an impact velocity through 0 or a
            # flight touching a stop (an elastic contact's edge starts no curve)
            if sp.kind == kind and (sp.orbit.admissible if kind != "grazing" else
                                    ("impact" in sp.coefficients or "flight" in
                                     sp.coefficients) and not sp.coefficients.get("exit")):
                if not any(abs(sp.value - o.value) < 1e-9 and o.orbit.p == sp.orbit.p
                           for o, _ in out):
                    out.append((sp, br))
    return sorted(out, key=lambda x: (x[0].orbit.p, x[0].value))


def omega_branches(model, omega_min, omega_max):
    """The branches in omega over the interval where curves start: the period-1 branches
    and their period-doubled ones (:func:`symvi.continuation.period1_branches`) where the
    closed form exists (one rigid stop), else the branch of the attractor a run settles on
    at the middle of the interval, both ways, with the branches switched to at its flips
    and branch points (:func:`symvi.continuation.continue_orbits`)."""
    from ..continuation import continue_orbits, period1_branches
    from ..model import Model
    model = Model.of(model)
    if model.one_rigid_stop:
        return period1_branches(model, omega_min, omega_max)
    return continue_orbits(model, "omega", omega_min, omega_max,
                           start_omega=0.5 * (omega_min + omega_max), switch=True)


def curve_from_interval(model, omega_min, omega_max, names, *, kind="ns", index=1, **kw):
    """The ``kind`` curve in ``names`` through the ``index``-th (1-based, by omega) point of
    that kind found in [omega_min, omega_max]; keywords as :func:`continue_curve`.  The
    parameters are checked before anything is computed (:func:`check_pair`)."""
    from ..model import Model
    check_pair(Model.of(model), tuple(names))
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
    if kind == "grazing":
        from .grazing import continue_grazing
        kw.pop("locate", None)
        return continue_grazing(model, names, sp, **fixed, **kw), sp
    return continue_curve(model, kind, names, sp.orbit, **fixed, **kw), sp


def curves_of_plane(spec, **kw):
    """The fold, flip and NS curves over the plane of ``spec`` (a
    :class:`symvi.plane.PlaneSpec`; ``symvi plot``): :func:`curves_in_box` of its two axes,
    (curves, notes); none, with a note saying why, when neither axis is omega."""
    if "omega" not in (spec.x.name, spec.y.name):
        return [], ["no curves: neither axis is omega"]
    box = {spec.x.name: (spec.x.lo, spec.x.hi), spec.y.name: (spec.y.lo, spec.y.hi)}
    return curves_in_box(spec.model, (spec.x.name, spec.y.name), box, **kw)


def curves_in_box(model, names, box, *, kinds=("ns", "flip", "fold"), rows=3, omega=None,
                  max_points=400):
    """The fold, flip and NS curves that cross the box of a parameter plane.

    ``names`` = (x, y) with ``omega`` one of them; ``box`` = {name: (lo, hi)}.  Start points
    are the points of each kind that one-parameter continuation in omega locates at
    ``rows`` evenly spaced values of the other parameter; a start already on a found curve
    (within 1e-3 of the box) is skipped.  Returns (curves, notes): the curves as
    :meth:`Curve.plot_data`, and one line per start that could not be continued.
    """
    import numpy as np

    from ..errors import SymviError
    from ..model import Model
    model = Model.of(model)
    pars = [model.parameter(nm) for nm in names]
    if not any(par.is_forcing_frequency for par in pars):
        raise ParameterError("names", names, "omega and one named parameter")
    omega_first = pars[0].is_forcing_frequency
    other = names[1] if omega_first else names[0]
    other_par = pars[1] if omega_first else pars[0]
    (wlo, whi), (plo, phi) = box["omega"], box[other]
    span = np.array([whi - wlo, phi - plo])
    found, notes = [], []
    for v in np.linspace(plo, phi, rows + 2)[1:-1]:
        m = other_par.apply(model, float(v))
        try:
            branches = omega_branches(m, wlo, whi)        # once per row, for every kind
        except SymviError as exc:
            notes.append(f"{other} = {v:.6g}: {exc}")
            continue
        for kind in kinds:
            pts = start_points(m, wlo, whi, kind, branches=branches)
            for sp, _ in pts:
                xy = np.array([sp.value, v])
                if any(_near(c, xy, span, omega_first) for c in found if c["kind"] == kind):
                    continue
                try:
                    cv = continue_curve(m, kind, names, sp, bounds=box, max_points=max_points)
                except SymviError as exc:
                    notes.append(f"{kind} from omega = {sp.value:.6g}, {other} = {v:.6g}: {exc}")
                    continue
                found.append(cv.plot_data())
    return found, notes


def _near(curve, xy, span, omega_first):
    """The point xy = (omega, other) lies on the polyline of ``curve`` (within 1e-3 of
    the box); ``omega_first``: the curve's a is omega."""
    import numpy as np
    a, b = np.asarray(curve["a"], float), np.asarray(curve["b"], float)
    P = np.column_stack([a, b] if omega_first else [b, a]) / span
    q = xy / span
    if len(P) == 1:
        return np.linalg.norm(P[0] - q) < 1e-3
    A, B = P[:-1], P[1:]
    d = B - A
    t = np.clip(np.einsum("ij,ij->i", q - A, d) / np.maximum(np.einsum("ij,ij->i", d, d),
                                                            1e-300), 0, 1)
    return bool(np.min(np.linalg.norm(A + t[:, None] * d - q, axis=1)) < 1e-3)
