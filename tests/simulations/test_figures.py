"""symvi.figures: files written atomically as PNG and PDF, from finished results."""
import numpy as np
import pytest

from symvi.reporting import figures


def _check(paths):
    for p in paths:
        data = open(p, "rb").read()
        assert data[:4] in (b"\x89PNG", b"%PDF")
        assert len(data) > 1000


def test_all_figures_png_and_pdf(tmp_path):
    rng = np.random.default_rng(0)
    th = rng.uniform(0, 2 * np.pi, 500)
    sec = np.column_stack([-1.5 + 0.1 * np.cos(th), 0.3 + 0.2 * np.sin(th),
                           0.1 * np.cos(th), 1.5 + 0.05 * np.sin(th)])
    om = np.linspace(0.72, 0.74, 20)
    lam = np.exp(1j * np.outer(om, [3, -3, 2, -2])) * np.linspace(0.9, 1.01, 20)[:, None]
    mu = np.array([1e-4, 4e-4, 1.6e-3])
    hw = np.sqrt(mu)[:, None] * np.array([0.8, 6.3, 7.1, 2.4])
    figs = {"mult": figures.multiplier_paths(om, lam, "test", omega_c=0.7368),
            "sec": figures.sections(sec, "test", fixed_point=sec.mean(axis=0), highlight=(0, 50)),
            "bif": figures.bifurcation_diagram(om, np.repeat(sec[None, :40], 20, axis=0)),
            "loglog": figures.circle_loglog(mu, hw * 1.01, hw)}
    for name, fig in figs.items():
        _check(figures.save_all(fig, str(tmp_path / name)))
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".tmp-")]


def test_save_rejects_unknown_suffix(tmp_path):
    fig = figures.sections(np.zeros((3, 4)))
    with pytest.raises(ValueError):
        figures.save(fig, tmp_path / "x.gif")
    assert not list(tmp_path.iterdir())


