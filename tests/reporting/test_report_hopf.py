"""The report's Hopf table never turns an uncertified scan into "no Hopf point" (issue 23,
item 2): the spans the scan could not certify, and each point's caveats, are printed."""
import pytest

from symvi.reporting import report
from symvi.reporting.scenes import parse_scene, run_scene

SCENE = """[scene]
name = "h"
title = "h"

[params]
mu_m = 2
mu_k = 5
f2 = 0
b = 1.5
r = 0.8

[[output]]
kind = "hopf"
omega_min = 0.736
omega_max = 0.738
"""


def test_no_point_with_uncertified_spans_is_not_a_negative_statement():
    r = {"points": [], "events": [], "uncertified": [[0.665125, 0.76]],
         "uncertified_reasons": ["budget of 20000 orbit evaluations <used up>"]}
    text = "\n".join(report._hopf_table(r))
    assert "No Hopf point in the interval" not in text
    assert "Not certified" in text and "[0.665125, 0.76]" in text
    assert "&lt;used up&gt;" in text                       # the reason, as text
    assert "No Hopf point in the interval" in "\n".join(report._hopf_table(
        {"points": [], "events": [], "uncertified": []}))


def test_scene_hopf_carries_the_certificate(tmp_path):
    """The cached result of a hopf output holds the scan's uncertified spans (empty here:
    the paper's example certified on [0.736, 0.738]) and each point's caveats."""
    [p] = run_scene(parse_scene(SCENE, "h.toml"), tmp_path)
    r = p.result
    assert r["uncertified"] == [] and r["points"][0]["omega_c"] == pytest.approx(0.736877,
                                                                                 abs=1e-6)
    text = "\n".join(report._hopf_table(r))
    assert "Not certified" not in text and "Caution" not in text
    q = dict(r["points"][0], circle_caveat="(H1) fails: a multiplier <outside>")
    text = "\n".join(report._hopf_table(dict(r, points=[q])))
    assert "Caution at ω_c = 0.7368" in text and "&lt;outside&gt;" in text
