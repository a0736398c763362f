"""Figures 4–12 of the paper (Sec. 4) and the checks of its simulation claims.

Run:  python -m symvi.paper_figures OUTDIR      (PNG + PDF per figure, findings.json)

Computes with :mod:`symvi.simulate`, :mod:`symvi.diagnostics`,
:mod:`symvi.orbit` and :mod:`symvi.circle_check`, then draws with
:mod:`symvi.figures` (which never computes).  Every claim of Sec. 4 gets an
entry in ``findings.json`` with what the simulation finds.
"""
import json
import math
import os
import sys

import numpy as np

from . import circle_check, diagnostics, figures
from ._io import write_text
from .orbit import period1_orbits
from .params import Params
from .simulate import simulate, sweep

EX1 = Params(2, 5, 0, 1.5, 0.8)
EX2 = Params(4, 2, 0, 1.8, 0.8)


def _title(p, om, extra=""):
    return (f"mu_m={p.mu_m:g} mu_k={p.mu_k:g} f2={p.f2:g} b={p.b:g} R={p.r:g}  "
            f"v={om:g}{'  ' + extra if extra else ''}")


def multiplier_path(params, omega_min, omega_max, n=120):
    """Multipliers of the admissible period-1 orbit on a grid of omega, eq. (36)."""
    oms, lams = [], []
    for w in np.linspace(omega_min, omega_max, n):
        orbs = [o for o in period1_orbits(params, w) if o.admissible]
        if orbs:
            oms.append(w)
            lams.append([complex(z) for z in orbs[0].multipliers])
    return np.array(oms), np.array(lams)


def _describe(sim, lyap_points=4000):
    cl = diagnostics.classify(sim, lyap_points=lyap_points)
    d = {"class": cl.kind, "impacts_stored": sim.n, "transient": sim.transient, "stop": sim.stop}
    if cl.lyapunov is not None:
        d["lyapunov"] = [float(v) for v in cl.lyapunov.exponents]
        d["lyapunov_1_stderr"] = cl.lyapunov.stderr
    if cl.rotation is not None:
        d["rotation_number"] = cl.rotation
    return d


def _scan(params, omegas, transient=60000, n=4000):
    out = []
    for w in omegas:
        s = simulate(params, float(w), n_impacts=n, transient=transient)
        out.append({"omega": round(float(w), 6), **_describe(s, lyap_points=n)})
    return out


def _jump_index(sim, threshold=0.5):
    """First stored impact with |tau - tau*| > threshold (the 'large transition of phase')."""
    d = (sim.section[:, 3] - sim.fixed_point[3] + math.pi) % (2 * math.pi) - math.pi
    big = np.abs(d) > threshold
    return int(np.argmax(big)) + 1 if big.any() else None


def _save(fig, outdir, name):
    return figures.save_all(fig, os.path.join(outdir, name))


def make(outdir, *, quick=False):
    """Draw figs. 4–12, bifurcation diagrams and the circle check into ``outdir``."""
    os.makedirs(outdir, exist_ok=True)
    F = {"figures": []}
    scale = 4 if quick else 1

    # figs. 4 and 10: multipliers over the paper's omega intervals
    for name, p, lo, hi in (("fig04_multipliers", EX1, 0.7219, 0.7396),
                            ("fig10_multipliers", EX2, 0.458, 0.492)):
        oms, lam = multiplier_path(p, lo, hi, n=120 // scale)
        F["figures"] += _save(figures.multiplier_paths(oms, lam, _title(p, lo).split("  v=")[0]),
                              outdir, name)
        k = np.argmax(np.abs(lam[:, 0]) >= 1) if (np.abs(lam[:, 0]) >= 1).any() else None
        F[name] = {"omega_range": [lo, hi],
                   "first_grid_omega_with_max_modulus_ge_1": None if k is None else float(oms[k])}

    # the Hopf points and the circle check (item 6)
    F["circle_check"] = {}
    rows = []
    for key, p, lo, hi, mus in (("ex1", EX1, 0.72, 0.74, [1e-4, 2e-4, 4e-4, 8e-4, 1.6e-3]),
                                ("ex2", EX2, 0.458, 0.495, [2.5e-5, 5e-5, 1e-4, 2e-4, 4e-4])):
        try:
            pt = circle_check.hopf_point(p, lo, hi)
        except ImportError:
            F["circle_check"][key] = "symvi.hopf not available"
            continue
        res = circle_check.check(p, pt, mus[: 3 if quick else None])
        F["circle_check"][key] = res.as_dict()
        F["circle_check"][key]["table"] = res.table()
        rows.append((key, res))
        fig = figures.circle_loglog(res.mu, res.measured, res.predicted,
                                    title=f"{key}: v_c = {res.omega_c:.7f}")
        F["figures"] += _save(fig, outdir, f"circle_loglog_{key}")
    oc1 = next((r.omega_c for k, r in rows if k == "ex1"), 0.7368)

    # fig. 5: 5000 impacts from the theoretical fixed point (+ DEFAULT_PERTURBATION) at 0.7369
    s5 = simulate(EX1, 0.7369, n_impacts=5000)
    F["figures"] += _save(figures.sections(s5.section, _title(EX1, 0.7369, "5000 impacts from y*"),
                                           s5.fixed_point), outdir, "fig05_v0.7369_from_fixed_point")
    s5c = simulate(EX1, 0.7369, n_impacts=5000, transient=400000 // scale)
    F["figures"] += _save(figures.sections(s5c.section, _title(EX1, 0.7369, "after 400000"),
                                           s5c.fixed_point), outdir, "fig05b_v0.7369_converged")
    # fig. 6: 4000 impacts from a point outside the circle
    y_out = tuple(np.array(s5c.fixed_point) + 2 * (s5c.section[-1] - np.array(s5c.fixed_point)))
    s6 = simulate(EX1, 0.7369, y0=y_out, n_impacts=4000)
    F["figures"] += _save(figures.sections(s6.section, _title(EX1, 0.7369, "4000 from outside"),
                                           s6.fixed_point), outdir, "fig06_v0.7369_from_outside")
    ys = np.array(s5.fixed_point)
    F["claim_circle_0.7369"] = {
        "paper": "attracting invariant circle at v = 0.7369 (5000 impacts from the fixed point)",
        "mu": 0.7369 - oc1,
        "after_5000_from_fixed_point_max_distance": float(np.abs(
            s5.section[:, :3] - ys[:3]).max()),
        "converged": _describe(s5c),
        "converged_half_widths": (np.ptp(s5c.section, axis=0) / 2).tolist(),
        "from_outside_4000_half_widths": (np.ptp(s6.section, axis=0) / 2).tolist()}

    # torus doubling onset and figs. 7-9
    grid = np.round(np.arange(0.7430, 0.74405, 0.0001 * scale), 6)
    scan = _scan(EX1, grid, transient=60000 // scale)
    first = next((r["omega"] for r in scan if r["class"] == "doubled torus"), None)
    F["claim_torus_doubling_0.7438"] = {"paper": "single torus doubling as v passes 0.7438",
                                        "scan": scan, "first_doubled_torus": first}
    for fig, om, claim in (("fig07", 0.744, "torus doubling"), ("fig08", 0.7519, "chaos"),
                           ("fig09", 0.7555, "chaos")):
        s = simulate(EX1, om, n_impacts=8000, transient=100000 // scale)
        d = _describe(s)
        F[f"claim_{fig}_v{om}"] = {"paper": claim, **d}
        F["figures"] += _save(figures.sections(s.section, _title(EX1, om, d["class"]),
                                               s.fixed_point), outdir, f"{fig}_v{om}")

    # example 2: fig. 11, the scan up to 0.4944, fig. 12
    s11 = simulate(EX2, 0.4917, n_impacts=6000, transient=100000 // scale)
    d11 = _describe(s11)
    F["claim_fig11_v0.4917"] = {"paper": "attracting invariant circle", **d11}
    F["figures"] += _save(figures.sections(s11.section, _title(EX2, 0.4917, d11["class"]),
                                           s11.fixed_point), outdir, "fig11_v0.4917")
    grid2 = np.round(np.arange(0.4925, 0.49455, 0.0001 * scale), 6)
    scan2 = _scan(EX2, grid2, transient=60000 // scale)
    F["claim_circles_up_to_0.4943"] = {
        "paper": "single attracting invariant circles up to v = 0.4943",
        "scan": scan2,
        "last_circle": max((r["omega"] for r in scan2 if r["class"] == "invariant circle"),
                           default=None),
        "first_chaos": next((r["omega"] for r in scan2 if r["class"] == "chaos"), None)}
    jumps = {}
    for pert in (1e-4, 1e-6, 1e-8, 1e-10):
        s = simulate(EX2, 0.4944, n_impacts=6000, perturbation=(pert,) * 4)
        jumps[f"{pert:g}"] = _jump_index(s)
    s12 = simulate(EX2, 0.4944, n_impacts=4000)
    F["claim_fig12_v0.4944"] = {
        "paper": "from the fixed point: quasi-attracting circle, large phase jump after "
                 "1112 impacts, then chaos",
        "jump_impact_by_perturbation": jumps,
        "after_jump": _describe(simulate(EX2, 0.4944, n_impacts=4000, transient=20000))}
    F["figures"] += _save(figures.sections(s12.section[:1112], _title(EX2, 0.4944,
                                           "first 1112 impacts"), s12.fixed_point),
                          outdir, "fig12a_v0.4944_1112")
    F["figures"] += _save(figures.sections(s12.section, _title(EX2, 0.4944, "4000 impacts"),
                                           s12.fixed_point, highlight=(0, jumps["0.0001"] or 0)),
                          outdir, "fig12bc_v0.4944_4000")

    # bifurcation diagrams
    for name, p, lo, hi in (("bifurcation_ex1", EX1, 0.730, 0.760),
                            ("bifurcation_ex2", EX2, 0.485, 0.496)):
        sw = sweep(p, np.linspace(lo, hi, 600 // scale), n_impacts=300,
                   transient=20000 // scale)
        F["figures"] += _save(figures.bifurcation_diagram(sw.omegas, sw.section, sw.counts,
                                                          title=name), outdir, name)
    write_text(os.path.join(outdir, "findings.json"), json.dumps(F, indent=1, default=float))
    return F


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        sys.stderr.write("usage: python -m symvi.paper_figures OUTDIR [--quick]\n")
        return 2
    F = make(argv[0], quick="--quick" in argv)
    print(json.dumps({k: v for k, v in F.items() if k != "figures"}, indent=1, default=float)[:6000])
    return 0


if __name__ == "__main__":
    sys.exit(main())
