"""Figures a reader understands at a glance (issue 26, item 4): a legend for the line
styles and markers, labels of nearby special points that do not overlap, tick labels
without an offset, the unit circle and |lambda| = 1 in the multiplier plot, curves in
colour-blind-safe colours that stay visible over a map."""
import numpy as np

from symvi.reporting import figures


def _texts(ax):
    fig = ax.figure
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    return [(t.get_text(), t.get_window_extent(r)) for t in ax.texts]


def test_branch_legend_labels_and_ticks():
    """Many special points within a narrow span: every drawn label is clear of the
    others, the legend names line styles and the kinds present, and an axis spanning
    2e-5 reads its values without an offset."""
    w = np.linspace(1.2, 1.2 + 2e-5, 50)
    curve = {"values": w, "Y": np.sin(w * 1e5)[:, None], "stable": w < 1.20001,
             "admissible": np.ones(50, bool),
             "special": [(k, float(w[10 + i]), [float(np.sin(w[10 + i] * 1e5))])
                         for i, k in enumerate(["flip", "grazing", "fold", "flip", "ns"])]}
    fig = figures.branches([curve], "omega", ylabel="v1+")
    ax = fig.axes[0]
    boxes = _texts(ax)
    assert boxes and all(not a[1].overlaps(b[1]) for i, a in enumerate(boxes)
                         for b in boxes[i + 1:])
    names = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {"stable", "unstable"} <= set(names) and any("PD" in n for n in names)
    assert ax.xaxis.get_offset_text().get_text() == ""
    labels = [t.get_text() for t in ax.get_xticklabels()]
    values = [float(s.replace("\u2212", "-")) for s in labels if s]
    assert values and all(1.19999 < v < 1.20003 for v in values)


def test_multiplier_plot_shows_the_crossing():
    """The complex plane with the unit circle, and |lambda| against omega with the line
    |lambda| = 1 and omega_c: where the pair crosses reads off."""
    w = np.linspace(0.7, 0.76, 40)
    r = 0.95 + (w - 0.7)                     # |lambda| through 1 at 0.75
    lam = np.column_stack([r * np.exp(1j * 1.1), r * np.exp(-1j * 1.1),
                           0.3 + 0 * w, 0.1 + 0 * w])
    fig = figures.multiplier_paths(w, lam, omega_c=0.75)
    ax, bx = fig.axes[0], fig.axes[1]
    assert any("unit circle" in t.get_text() for t in ax.get_legend().get_texts())
    assert any(np.allclose(line.get_ydata(), 1.0) for line in bx.get_lines())
    assert any("omega_c" in t.get_text() for t in bx.get_legend().get_texts())


def test_curve_colours_are_not_the_map_colours():
    """The NS, flip and fold curves are Okabe-Ito colours with a white outline, none of
    them a colour of the attractor map (the NS curve was period-1's blue)."""
    from matplotlib.colors import to_hex
    curve = {"kind": "ns", "a": [1.0, 1.1, 1.2], "b": [0.1, 0.2, 0.3],
             "subcritical": [False] * 3, "admissible": [True] * 3,
             "bifurcation": [True] * 3, "sides": [], "special": [("CH", 1.1, 0.2)]}
    fig = figures.two_parameter([curve], ("omega", "b"))
    ax = fig.axes[0]
    line = [ln for ln in ax.get_lines() if np.isfinite(ln.get_xdata()).any()][0]
    colour = to_hex(line.get_color())
    assert colour.upper() in {c.upper() for c in figures.OKABE_ITO.values()}
    maps = {c.upper() for c in list(figures._PERIOD_COLOURS) +
            list(figures._ATTRACTOR_COLOUR.values())}
    assert colour.upper() not in maps and line.get_path_effects()
    assert any("NS curve" in t.get_text() for t in ax.get_legend().get_texts())


def test_importing_figures_keeps_a_backend_the_user_chose():
    """A notebook's inline backend (or any chosen before) is not switched to Agg."""
    import subprocess
    import sys
    code = ("import matplotlib, matplotlib.pyplot; matplotlib.use('pdf'); "
            "import symvi.reporting.figures; print(matplotlib.get_backend())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "pdf", out.stderr
    code = "import symvi.reporting.figures, matplotlib; print(matplotlib.get_backend())"
    env = {k: v for k, v in __import__("os").environ.items() if k != "MPLBACKEND"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.stdout.strip().lower() == "agg", out.stderr
