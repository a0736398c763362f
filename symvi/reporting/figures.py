"""Figures from finished results; matplotlib (Agg) only, nothing is computed here.

* :func:`multiplier_paths` -- multipliers of the period-1 orbit over omega on
  the unit circle (paper, figs. 4 and 10);
* :func:`sections` -- projected Poincaré sections (figs. 5–9, 11–12).  The
  paper does not name its axes; we use three projections of the section
  point (x1dot+, x2, x2dot, tau): (x2, x1dot+), (tau, x1dot+) and (x2dot, x2);
* :func:`bifurcation_diagram` -- section coordinate against omega;
* :func:`circle_loglog` -- measured and predicted circle half-widths against mu;
* :func:`branches` -- continued branches; :func:`two_parameter` -- fold, flip and NS
  curves in a parameter plane with their codimension-two points.

Every figure is written as PNG or PDF (from the file suffix) through a
temporary file renamed into place.
"""
import os

import sys

import matplotlib

# files only, no window: Agg, unless the user chose a backend already (a notebook's inline
# one, MPLBACKEND, or pyplot imported), which must not be switched under them
if "matplotlib.pyplot" not in sys.modules and not os.environ.get("MPLBACKEND"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .._io import FIGURE_SUFFIXES, atomic_path  # noqa: E402

#: the projections drawn by :func:`sections`: (x index, y index) into the section point
PROJECTIONS = ((1, 0), (3, 0), (2, 1))
LABELS = (r"$\dot x_{1+}$", r"$x_2$", r"$\dot x_2$", r"$\tau$")

#: the Okabe-Ito palette (colour-blind safe) for lines and markers [Okabe & Ito, Color
#: Universal Design, 2008]; maps use the light colours of :data:`_MAP_COLOURS` so that
#: every line, drawn with a white outline, stays visible over them
OKABE_ITO = {"black": "#000000", "orange": "#E69F00", "sky": "#56B4E9", "green": "#009E73",
             "yellow": "#F0E442", "blue": "#0072B2", "vermillion": "#D55E00",
             "purple": "#CC79A7"}
_BRANCH = OKABE_ITO["blue"]


def save(fig, path, *more, dpi=150):
    """Write ``fig`` to ``path`` and to each of ``more`` (PNG or PDF by suffix, every name
    checked first) atomically and close it; returns ``path``."""
    paths = [os.fspath(p) for p in (path, *more)]
    for p in paths:
        if os.path.splitext(p)[1].lower() not in FIGURE_SUFFIXES:
            from ..errors import ParameterError      # a ValueError: one line on the CLI
            raise ParameterError("figure path", p, "a file name ending in .png or .pdf")
    try:
        for p in paths:
            with atomic_path(p) as tmp:
                fig.savefig(tmp, dpi=dpi, format=os.path.splitext(p)[1].lower()[1:])
    finally:
        plt.close(fig)          # also when the write is refused: no figure left open
    return paths[0]


def save_all(fig, stem, formats=("png", "pdf")):
    """Write ``fig`` as ``stem.png`` and ``stem.pdf``; returns the paths."""
    paths = [f"{stem}.{f}" for f in formats]
    save(fig, *paths)
    return paths


def multiplier_paths(omegas, multipliers, title="", omega_c=None):
    """Multipliers lambda_i(omega) in the complex plane with the unit circle, figs. 4, 10,
    and beside it |lambda_i| against omega with the line |lambda| = 1, so that where a pair
    crosses the circle reads off (``omega_c`` marked on both).

    ``multipliers`` is (m, 4) complex, one row per omega.
    """
    lam = np.asarray(multipliers, dtype=complex)
    om = np.asarray(omegas, dtype=float)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.4, 4.8),
                                 gridspec_kw={"width_ratios": (1.1, 1.0)})
    th = np.linspace(0, 2 * np.pi, 400)
    ax.plot(np.cos(th), np.sin(th), color="0.3", lw=1.0, label="unit circle")
    for i in range(lam.shape[1]):
        sc = ax.scatter(lam[:, i].real, lam[:, i].imag, c=om, s=6, cmap="viridis")
    fig.colorbar(sc, ax=ax, label=r"$\omega$")
    # where the pair crosses: |lambda| against omega beside it, the crossing marked
    for i in range(lam.shape[1]):
        bx.plot(om, np.abs(lam[:, i]), ".", ms=2, color="0.35")
    bx.axhline(1.0, color="0.3", lw=1.0, label=r"$|\lambda| = 1$ (the unit circle)")
    if omega_c is not None:
        j = int(np.argmin(np.abs(om - omega_c)))
        ax.plot(lam[j].real, lam[j].imag, "o", mfc="none", mec=OKABE_ITO["vermillion"],
                ms=9, label=r"multipliers at $\omega_c$")
        bx.axvline(omega_c, color=OKABE_ITO["vermillion"], ls="--", lw=1.0,
                   label=r"$\omega_c$" + f" = {omega_c:.6g}")
    bx.set_xlabel(r"$\omega$")
    bx.set_ylabel(r"$|\lambda|$")
    bx.legend(fontsize=7, loc="best")
    ax.legend(fontsize=7, loc="upper right")
    if title:
        fig.suptitle(title, fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlabel(r"Re $\lambda$")
    ax.set_ylabel(r"Im $\lambda$")
    ax.axhline(0, color="0.85", lw=0.5)
    ax.axvline(0, color="0.85", lw=0.5)
    _plain_ticks(bx)
    fig.tight_layout()
    return fig


def sections(section, title="", fixed_point=None, projections=PROJECTIONS, marker_size=0.6,
             highlight=None, labels=LABELS):
    """Projected Poincaré sections, one panel per projection (figs. 5–9, 11–12).

    ``highlight`` = (start, stop) draws that slice of points in a second colour
    (e.g. the first 1112 impacts of fig. 12a).
    """
    sec = np.asarray(section, dtype=float)
    fig, axes = plt.subplots(1, len(projections), figsize=(4.2 * len(projections), 4))
    axes = np.atleast_1d(axes)
    for ax, (ix, iy) in zip(axes, projections):
        ax.scatter(sec[:, ix], sec[:, iy], s=marker_size, color="k", lw=0, rasterized=True)
        if highlight is not None:
            a, b = highlight
            ax.scatter(sec[a:b, ix], sec[a:b, iy], s=marker_size * 2, color="tab:red", lw=0,
                       rasterized=True)
        if fixed_point is not None:
            ax.plot(fixed_point[ix], fixed_point[iy], "+", color="tab:blue", ms=8)
        ax.set_xlabel(labels[ix])
        ax.set_ylabel(labels[iy])
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def bifurcation_diagram(omegas, section, counts=None, component=0, title="", kinds=None,
                        labels=LABELS, curves=None):
    """Section coordinate ``component`` of the stored points against omega.

    ``section`` is (m, n, 4) as in :class:`symvi.simulations.simulation.Sweep`.
    """
    om = np.asarray(omegas, dtype=float)
    sec = np.asarray(section, dtype=float)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    n = sec.shape[1]
    X = np.repeat(om, n)
    Y = sec[:, :, component].ravel()
    ok = np.isfinite(Y)
    ax.scatter(X[ok], Y[ok], s=0.3, color="k", lw=0, rasterized=True)
    if curves:                     # continued branches over the brute-force diagram
        branches(curves, "omega", ax=ax)
        ax.set_xlim(om.min(), om.max())
        if ok.any():               # keep the diagram's scale; branches may run far off
            lo, hi = Y[ok].min(), Y[ok].max()
            pad = 0.15 * (hi - lo) + 1e-3 * (1 + abs(hi))
            ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel(r"$\omega$")
    ax.set_ylabel(labels[component])
    if title:
        ax.set_title(title)
    fig.tight_layout()
    return fig


def circle_loglog(mu, measured, predicted=None, names=LABELS, title=""):
    """Circle half-widths against mu on log-log axes, with the sqrt(mu) law.

    ``measured`` and ``predicted`` are (k, 4): one row per mu.
    """
    mu = np.asarray(mu, dtype=float)
    M = np.asarray(measured, dtype=float)
    fig, ax = plt.subplots(figsize=(5.6, 4.4))
    for i in range(M.shape[1]):
        line, = ax.loglog(mu, M[:, i], "o", label=f"{names[i]} simulated")
        if predicted is not None:
            ax.loglog(mu, np.asarray(predicted, dtype=float)[:, i], "-", color=line.get_color(),
                      label=f"{names[i]} normal form")
    ref = M[0].max() * np.sqrt(mu / mu[0])
    ax.loglog(mu, ref, ":", color="0.5", label=r"$\propto\sqrt{\mu}$")
    ax.set_xlabel(r"$\mu = \omega - \omega_c$")
    ax.set_ylabel("half-width of the invariant circle")
    if title:
        ax.set_title(title)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def _axes(ax, figsize):
    """(axes, own): ``ax``, or the axes of a new figure of ``figsize`` (own: this call made
    it, and returns the figure)."""
    if ax is not None:
        return ax, False
    return plt.subplots(figsize=figsize)[1], True


def _done(ax, own, title):
    """``ax`` titled, with plain ticks; its figure, laid out, when this call made it
    (``own``), else ``ax``."""
    if title:
        ax.set_title(title, fontsize=9)
    _plain_ticks(ax)
    if own:
        ax.figure.tight_layout()
        return ax.figure
    return ax


def _plain_ticks(ax):
    """Tick labels as the values themselves, never an offset or a factor beside the axis
    (a flip curve spanning 2e-5 read "+1.2" and unreadable ticks), at most 6 a side."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter
    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() != "linear":
            continue
        fmt = ScalarFormatter(useOffset=False)
        fmt.set_scientific(False)
        axis.set_major_formatter(fmt)
        axis.set_major_locator(MaxNLocator(nbins=6))


def _axis_label(name):
    """A parameter's axis label: omega as its symbol (one symbol for one quantity)."""
    return name if name != "omega" else r"$\omega$"


#: marker, colour and short label of each special-point kind (one set in every figure)
_SPECIAL_STYLE = {"fold": ("s", OKABE_ITO["green"]), "flip": ("D", OKABE_ITO["vermillion"]),
                  "ns": ("o", OKABE_ITO["purple"]), "grazing": ("v", OKABE_ITO["orange"]),
                  "admissibility": ("x", "0.45"), "branch-point": ("P", OKABE_ITO["sky"]),
                  "unlocated": ("x", "k"), "symmetry-breaking": ("P", OKABE_ITO["black"])}
_SPECIAL_LABEL = {"ns": "NS", "flip": "PD", "fold": "LP", "grazing": "G",
                  "branch-point": "BP", "symmetry-breaking": "SB", "admissibility": "A",
                  "unlocated": "?"}


def _place_labels(ax, items, fontsize=7):
    """Annotate each (text, (x, y), colour) beside its point, trying offsets round it in
    turn and keeping the first whose box overlaps no label placed before (labels of
    nearby points, PD/G/LP, no longer print over each other); where every place is taken
    the point keeps its marker alone (the legend names the kinds)."""
    offsets = ((4, 4), (4, -11), (-16, 4), (-16, -11), (4, 14), (-16, 14))
    ax.autoscale_view()                   # the final limits: where the points will be
    renderer = ax.figure.canvas.get_renderer()
    placed = []
    for text, xy, col in items:
        for off in offsets:
            a = ax.annotate(text, xy, textcoords="offset points", xytext=off,
                            fontsize=fontsize, color=col)
            box = a.get_window_extent(renderer)
            if not any(box.overlaps(b) for b in placed):
                placed.append(box)
                break
            a.remove()


def _style_legend(ax, styles, kinds, loc="best"):
    """A legend of the line styles used (``styles``: (label, kwargs)) and of the markers
    of the special kinds present (``kinds``)."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], **kw, label=lab) for lab, kw in styles]
    for kind in kinds:
        mk, col = _SPECIAL_STYLE.get(kind, ("*", "k"))
        handles.append(Line2D([], [], ls="", marker=mk, color=col, mfc="none", ms=6,
                              label=f"{_SPECIAL_LABEL.get(kind, kind)}: {kind}"))
    if handles:
        ax.legend(handles=handles, fontsize=7, loc=loc, framealpha=0.85)


def branches(curves, param, ylabel=None, title="", ax=None):
    """Continued branches (the plain data of :meth:`symvi.continuation.Branch.curve`):
    each impact point's coordinate against the parameter; stable solid, unstable
    dashed, inadmissible dotted grey; special points marked and labelled."""
    ax, own = _axes(ax, (7, 4.2))
    styles = (("stable", dict(ls="-", color=_BRANCH, lw=1.4)),
              ("unstable", dict(ls="--", color=_BRANCH, lw=1.0)),
              ("not admissible", dict(ls=":", color="0.6", lw=0.8)))
    used, kinds, labels = set(), [], []
    for c in curves:
        lam = np.asarray(c["values"], dtype=float)
        Y = np.asarray(c["Y"], dtype=float).reshape(len(lam), -1)
        stab = np.asarray(c["stable"], dtype=bool)
        adm = np.asarray(c["admissible"], dtype=bool)
        for j in range(Y.shape[1]):
            for (name, style), mask in zip(styles, (adm & stab, adm & ~stab, ~adm)):
                if mask.any():
                    used.add(name)
                ax.plot(lam, np.where(mask, Y[:, j], np.nan), **style)
        for kind, value, ys in c["special"]:
            mk, col = _SPECIAL_STYLE.get(kind, ("*", "k"))
            for y in ys:
                ax.plot(value, y, mk, color=col, ms=6, mfc="none")
            if kind not in kinds:
                kinds.append(kind)
            labels.append((_SPECIAL_LABEL.get(kind, kind), (value, ys[0]), col))
    ax.set_xlabel(_axis_label(param))
    ax.set_ylabel(ylabel or "")
    _plain_ticks(ax)
    _place_labels(ax, labels)
    _style_legend(ax, [s for s in styles if s[0] in used], kinds)
    return _done(ax, own, title)


_CURVE_COLOUR = {"ns": OKABE_ITO["purple"], "flip": OKABE_ITO["vermillion"],
                 "fold": OKABE_ITO["green"], "grazing": OKABE_ITO["orange"]}
_CURVE_NAME = {"ns": "NS", "flip": "flip (PD)", "fold": "fold (LP)", "grazing": "grazing (G)"}


def two_parameter(curves, names, title="", ax=None):
    """A two-parameter bifurcation diagram from the plain data of
    :meth:`symvi.curves.Curve.plot_data`: each curve in the plane of ``names``
    (NS purple, flip vermillion, fold green, grazing orange, each with a white outline so that it stays
    visible over a map; solid where the bifurcation is supercritical or the fold is
    simple, dashed where subcritical, dotted on neutral-saddle stretches, grey where the
    orbit is not admissible), short ticks on the side where the orbit is stable, the
    codimension-two points labelled, and a legend of colours and line styles."""
    from matplotlib import patheffects
    halo = [patheffects.Stroke(linewidth=3.2, foreground="white"), patheffects.Normal()]
    ax, own = _axes(ax, (6.4, 4.6))
    kinds, used, labels = [], set(), []
    spans = [np.ptp(np.concatenate([np.asarray(c["a"], float) for c in curves])) or 1.0,
             np.ptp(np.concatenate([np.asarray(c["b"], float) for c in curves])) or 1.0]
    for c in curves:
        a, b = np.asarray(c["a"], float), np.asarray(c["b"], float)
        col = _CURVE_COLOUR.get(c["kind"], "k")
        sub = np.asarray(c["subcritical"], dtype=bool)
        adm = np.asarray(c["admissible"], dtype=bool)
        bif = np.asarray(c["bifurcation"], dtype=bool)
        if c["kind"] not in kinds:
            kinds.append(c["kind"])
        for name, mask, style in (
                ("supercritical / simple", adm & bif & ~sub, dict(ls="-", lw=1.5)),
                ("subcritical", adm & bif & sub, dict(ls="--", lw=1.2)),
                ("neutral saddle", adm & ~bif, dict(ls=":", lw=0.9))):
            if mask.any() and c["kind"] != "grazing":     # a grazing curve has no sides
                used.add((name, style["ls"], style["lw"]))
            ax.plot(np.where(mask, a, np.nan), np.where(mask, b, np.nan), color=col,
                    path_effects=halo, **style)
        if (~adm).any():
            used.add(("not admissible", ":", 0.8))
        ax.plot(np.where(~adm, a, np.nan), np.where(~adm, b, np.nan), ls=":", color="0.6",
                lw=0.8)
        for i, side in c["sides"]:
            if side is None:
                continue
            da, db = side[0] * spans[0] * 0.025, side[1] * spans[1] * 0.025
            ax.plot([a[i], a[i] + da], [b[i], b[i] + db], "-", color=col, lw=0.8)
        for kind, va, vb in c["special"]:
            # a point two curves share (an RG on the grazing and the fold curve) once
            if any(k == kind and abs(p[0] - va) <= 1e-9 * spans[0] and
                   abs(p[1] - vb) <= 1e-9 * spans[1] for k, p, _ in labels):
                continue
            ax.plot(va, vb, "o", color="k", ms=4, mfc="w")
            labels.append((kind, (va, vb), "k"))
    ax.set_xlabel(_axis_label(names[0]))
    ax.set_ylabel(_axis_label(names[1]))
    _plain_ticks(ax)
    _place_labels(ax, labels)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=_CURVE_COLOUR.get(k, "k"), lw=1.5, path_effects=halo,
                      label=f"{_CURVE_NAME.get(k, k)} curve") for k in kinds]
    handles += [Line2D([], [], color="0.3" if n != "not admissible" else "0.6", ls=ls,
                       lw=lw, label=n) for n, ls, lw in sorted(used)]
    old = ax.get_legend()                 # a map's own legend (plane_maps) stays the axes'
    leg = ax.legend(handles=handles, fontsize=7, loc="best", framealpha=0.85)
    if old is not None:
        ax.add_artist(leg)
        ax.legend_ = old
    return _done(ax, own, title)


def codim2_evidence(result, arrays, axes=(1, 2), title=""):
    """The runs of :mod:`symvi.curves.evidence` in one projection (section coordinates
    ``axes``): for a CH result the circle run, the fixed-point run (first and last block)
    and the predicted inner/outer circles; for an R3/R4 result the basin runs and the
    period-m orbits found, the fixed point marked.  The verdict is the caption."""
    i, j = axes
    fig, ax = plt.subplots(figsize=(6.0, 5.0))
    ys = np.asarray(arrays["fixed_point"], dtype=float)
    if result.get("kind") == "CH":
        for key, style, label in (("predicted_outer", dict(color="tab:green", lw=1.0),
                                   r"predicted outer circle $\rho_+$ (stable)"),
                                  ("predicted_inner", dict(color="tab:red", lw=1.0, ls="--"),
                                   r"predicted inner circle $\rho_-$ (unstable)")):
            r = np.asarray(arrays[key], dtype=float)
            ax.plot(r[:, i], r[:, j], **style, label=label)
        c = np.asarray(arrays["circle"], dtype=float)
        ax.plot(c[:, i], c[:, j], ",", color="tab:blue")
        ax.plot([], [], ".", color="tab:blue", label="run from outside: invariant circle")
        for key, col, label in (("fixed_first", "0.5", "run from x*: first block"),
                                ("fixed_last", "k", "run from x*: last block")):
            f = np.asarray(arrays[key], dtype=float)
            ax.plot(f[:, i], f[:, j], ".", color=col, ms=1, label=label)
    else:
        for key in sorted(k for k in arrays if k.startswith("run_")):
            r = np.asarray(arrays[key], dtype=float)
            ax.plot(r[:, i], r[:, j], ".", ms=1.5, alpha=0.6,
                    label=f"run from {key[4:]} x the orbit's offset")
        for key in sorted(k for k in arrays if k.startswith("orbit_")):
            o = np.asarray(arrays[key], dtype=float)
            ax.plot(o[:, i], o[:, j], "x", color="tab:red", ms=7,
                    label=f"period-{result.get('m')} orbit (full map)")
    ax.plot(ys[i], ys[j], "o", color="k", mfc="w", ms=5, label="fixed point x*")
    names = result.get("variables") or [str(k) for k in range(len(ys))]
    if len(names) > max(i, j):
        ax.set_xlabel(names[i])
        ax.set_ylabel(names[j])
    if result.get("kind") != "CH":
        # the basin runs may leave far away: frame the neighbourhood of x*
        o = [np.asarray(arrays[k], dtype=float) for k in arrays if k.startswith("orbit_")]
        if o:
            span = 3 * max(np.abs(a[:, [i, j]] - ys[[i, j]]).max() for a in o)
            ax.set_xlim(ys[i] - span, ys[i] + span)
            ax.set_ylim(ys[j] - span, ys[j] + span)
    par = ", ".join(f"{k} = {v:.9g}" for k, v in result.get("params", {}).items())
    ax.set_title((title + "\n" if title else "") + f"{result.get('kind')} evidence at {par}",
                 fontsize=8)
    ax.legend(fontsize=6, loc="best")
    import textwrap
    fig.text(0.01, 0.005, "\n".join(textwrap.wrap(result.get("verdict", ""), 130)), fontsize=5)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


#: attractor colours: light ones (Paul Tol's colour-blind safe "light" scheme, 2021) so
#: that the curves drawn over a map in the Okabe-Ito colours, outlined, stay visible
_MAP_COLOURS = {"light blue": "#77AADD", "light cyan": "#99DDFF", "mint": "#44BB99",
                "pear": "#BBCC33", "olive": "#AAAA00", "light yellow": "#EEDD88",
                "orange": "#EE8866", "pink": "#FFAABB", "pale grey": "#DDDDDD"}
_ATTRACTOR_COLOUR = {"circle": _MAP_COLOURS["light yellow"],
                     "doubled-torus": _MAP_COLOURS["orange"], "chaos": _MAP_COLOURS["pink"],
                     "no-impact": "#ffffff", "sticking": _MAP_COLOURS["pale grey"],
                     "escape": "#555555", "grazing": "#CCBBEE"}
_PERIOD_COLOURS = (_MAP_COLOURS["light blue"], _MAP_COLOURS["mint"],
                   _MAP_COLOURS["light cyan"], _MAP_COLOURS["pear"], _MAP_COLOURS["olive"],
                   "#B4D7F0", "#A8DDCC", "#DDE899")


def plane_maps(ds, curves=(), title=""):
    """The attractor map (categorical colours, legend) and the Lyapunov map (diverging,
    centred on 0) of a plane store's Dataset (:mod:`symvi.plane.store`), with the
    two-parameter curves of :func:`symvi.curves.curves_in_box` over both."""
    from matplotlib.colors import ListedColormap, TwoSlopeNorm
    from matplotlib.patches import Patch
    xn, yn = ds.attrs["x"], ds.attrs["y"]
    x, y = np.asarray(ds[xn]), np.asarray(ds[yn])
    lab = np.asarray(ds["attractor"]).astype(str)
    # long periods share one colour: a legend of dozens of periods says nothing
    many = f"period > {len(_PERIOD_COLOURS)}"
    per = np.char.startswith(lab, "period-")
    k = np.where(per, np.char.lstrip(np.where(per, lab, "period-0"), "period-"), "0").astype(int)
    lab = np.where(per & (k > len(_PERIOD_COLOURS)), many, lab)
    present = sorted({s for s in lab.ravel() if s}, key=_label_order)
    periodic = [s for s in present if s.startswith("period-")]
    colours = {s: _PERIOD_COLOURS[i % len(_PERIOD_COLOURS)] for i, s in enumerate(periodic)}
    colours.update({s: _ATTRACTOR_COLOUR[s] for s in present if s in _ATTRACTOR_COLOUR})
    colours[many] = "#6699CC"
    code = np.full(lab.shape, np.nan)
    for i, s in enumerate(present):
        code[lab == s] = i
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 5.0), constrained_layout=True)
    ax = axes[0]
    if present:
        cmap = ListedColormap([colours[s] for s in present])
        ax.pcolormesh(x, y, np.ma.masked_invalid(code), cmap=cmap, vmin=-0.5,
                      vmax=len(present) - 0.5, shading="nearest")
    ax.legend(handles=[Patch(facecolor=colours[s], edgecolor="0.5", label=s) for s in present],
              loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    ax.set_title("attractor")
    lam = np.asarray(ds["lyapunov"], float)
    ax = axes[1]
    finite = lam[np.isfinite(lam)]
    lim = float(np.percentile(np.abs(finite), 99)) if finite.size else 1.0
    lim = lim if lim > 0 else 1.0
    im = ax.pcolormesh(x, y, np.ma.masked_invalid(lam), cmap="RdBu_r", shading="nearest",
                       norm=TwoSlopeNorm(vcenter=0.0, vmin=-lim, vmax=lim))
    fig.colorbar(im, ax=ax, label="largest Lyapunov exponent (per impact)", extend="both")
    ax.set_title("Lyapunov exponent")
    for ax in axes:
        if curves:
            names = (xn, yn)
            two_parameter(list(curves), names, ax=ax)     # curves made in (x, y) order
        ax.set_xlim(x.min(), x.max())
        ax.set_ylim(y.min(), y.max())
        ax.set_xlabel(_axis_label(xn))
        ax.set_ylabel(_axis_label(yn))
        _plain_ticks(ax)
    if title:
        fig.suptitle(title)
    return fig


def _label_order(s):
    if s.startswith("period-"):
        return (0, int(s.split("-")[1]), s)
    if s.startswith("period >"):
        return (0, 10 ** 9, s)
    order = ("circle", "doubled-torus", "chaos", "grazing", "sticking", "no-impact", "escape")
    return (1, order.index(s) if s in order else len(order), s)
