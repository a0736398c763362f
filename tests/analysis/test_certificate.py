"""The Hopf scan's certificate (issue 23, defects 2 and 3): what the scan could not certify
is listed (HopfResult.uncertified, JSON 'uncertified' / 'complete') and said in the
headline, never turned into "no pair crosses"; the singular frequencies omega_j / n,
which accumulate at 0, are counted before any work and only the largest are cut."""
import json
import math
from unittest import mock

import pytest

from symvi import Params
from symvi.analysis import hopf
from symvi.errors import ParameterError

from ..fuzz._cli import assert_bad_input, cli

EX1 = Params(2, 5, 0, 1.5, 0.8)
BASE = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
WC = 0.73687692209059288        # example 1 (test_hopf_points.REF)


def test_complete_scan_says_so():
    res = hopf.hopf_points(EX1, 0.70, 0.76)
    assert res.complete and res.uncertified == () and res.uncertified_reasons == ()
    d = res.as_dict()
    assert d["complete"] is True and d["uncertified"] == []


def test_budget_that_runs_out_is_no_negative_statement():
    """A budget far too small: the spans left are declared, in the result, the JSON and the
    headline; the text never says that nothing crosses."""
    with mock.patch.object(hopf, "MAX_SAMPLES", 3):
        res = hopf.hopf_points(EX1, 0.70, 0.76)
        rc, out, err = cli("hopf", *BASE, "--range", "omega=0.70:0.76")
        rcj, outj, _ = cli("hopf", *BASE, "--range", "omega=0.70:0.76",
                           "--json")
    assert not res.complete and res.uncertified
    assert "orbit-evaluation budget ran out" in res.uncertified_reasons
    # the point the full scan finds is missing here, and its place is declared
    assert not any(abs(p.omega_c - WC) < 1e-9 for p in res.points)
    assert any(lo <= WC <= hi for lo, hi in res.uncertified)
    spans = res.uncertified
    assert all(lo < hi for lo, hi in spans)
    assert all(h0 < l1 for (_, h0), (l1, _) in zip(spans, spans[1:]))     # merged, sorted
    assert rc == 0 and "Traceback" not in err
    assert "NOT certified on" in out and "no complex pair" not in out
    obj = json.loads(outj)
    assert rcj == 0 and obj["complete"] is False
    assert obj["uncertified"] == [[lo, hi] for lo, hi in spans]


def test_singular_frequencies_are_counted_before_any_work():
    """omega_j / n for omega in (a, b): at most MAX_SINGULAR of them, the largest, and the
    count of the rest, in closed form even where they are innumerable."""
    sysm = hopf._system(EX1)
    w1, w2 = sysm.undamped_frequencies()
    sing, floor = hopf._singular_frequencies(sysm, 0.40, 0.80)
    assert [w for w, _ in sing] == sorted([w1 / 2, w2 / 3, w2 / 4]) and floor is None
    sing, floor = hopf._singular_frequencies(sysm, 1e-300, 0.76, cap=5)
    assert len(sing) == 5 and floor is not None
    w, count = floor
    assert w < min(x for x, _ in sing) and count > 1e299
    # every omega_j / n above the floor is listed
    expect = sorted(x for x in [w1 / n for n in range(2, 12)] + [w2 / n for n in range(3, 12)]
                    if w < x < 0.76)
    assert [x for x, _ in sing] == expect


def test_below_the_last_cut_is_uncertified():
    """Only the MAX_SINGULAR largest omega_j / n are cut: below them the interval is
    declared uncertified, with the reason, and the scan above is unchanged."""
    with mock.patch.object(hopf, "MAX_SINGULAR", 2):
        res = hopf.hopf_points(EX1, 0.40, 0.62)
    (lo, hi) = res.uncertified[0]
    assert lo == 0.40 and hi == pytest.approx(0.4402428672 * (1 + 1e-7), rel=1e-9)
    assert "singular frequencies omega_j / n accumulate" in res.uncertified_reasons
    assert [e.kind for e in res.events].count("singular") == 2
    # the point above the floor is found, the one below it not claimed
    assert any(abs(p.omega_c - 0.5932345384615) < 1e-9 for p in res.points)
    assert all(p.omega_c > hi for p in res.points)


@pytest.mark.parametrize("lo", ["1e-300", "5e-5", "0", "-1"])
def test_omega_range_checked_first(lo):
    """Below the orbit code's range (1e-4): refused at once, naming the flag's parameter
    (1e-300 used to enumerate ~1e300 singular frequencies)."""
    assert_bad_input(cli("hopf", *BASE, "--omega-min", lo, "--omega-max", "0.76"),
                     "--omega-min", "0.0001")
    with pytest.raises(ParameterError):
        hopf.hopf_points(EX1, float(lo), 0.76)


def test_repeated_events_are_summarised(capsys):
    """Many events of one kind: one line for them in the text (all in the JSON)."""
    with mock.patch("symvi.cli.hopf.EVENT_LINES", 1):
        rc, out, _ = cli("hopf", *BASE, "--range", "omega=0.40:0.62")
    assert rc == 0
    assert "3 events 'singular' between omega = 0.4402428672 and 0.5985858215" in out
    assert "omega_1 / omega = 2" not in out


@pytest.mark.slow
def test_paper_example_from_0_001():
    """The issue's reproduction: example 1 on [0.001, 0.76] finds omega_c = 0.7369 (it used
    to print "no complex pair ... crosses" after its budget ran out), and the region where
    the omega_j / n accumulate is declared uncertified in the headline."""
    rc, out, _ = cli("hopf", *BASE, "--range", "omega=0.001:0.76", "--json")
    obj = json.loads(out)
    assert rc == 0 and not obj["complete"]
    assert any(abs(p["omega_c"] - WC) < 1e-12 for p in obj["points"])
    lo, hi = obj["uncertified"][0]
    assert lo == 0.001 and 0.005 < hi < 0.01
    assert len(obj["events"]) < 3000 and obj["samples"] < hopf.MAX_SAMPLES + \
        2 * hopf.SAMPLES_PER_CUT * hopf.MAX_SINGULAR
    assert not math.isnan(obj["points"][-1]["dmod_domega_branch"])
