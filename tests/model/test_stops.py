"""Several stops (issue 25, items 1-2, the model layer): Stop's coordinates, sides and
kinds, Model(stops=[...]), their checks, the [[stop]] tables of a model file, the stop[k]
parameters, and the one capability check of the dynamics (one rigid stop on one mass)."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.flow.linear import LinearFlow
from symvi.maps import Section
from symvi.model import Model, ModelFileError, Stop, dumps, loads
from tests.zoo import PAPER_EX1

MATS = dict(mass=[1.0, 2.0, 0.5], stiffness=[[2.0, -1.0, 0.0], [-1.0, 3.0, -1.0],
                                             [0.0, -1.0, 2.0]], forcing=[1.0, 0.2, 0.0])
UP = Stop(mass=1, gap=0.5, restitution=0.8)
LOW = Stop(mass=1, gap=-0.4, side="lower", restitution=0.7)
PAIR = Stop(between=(1, 2), gap=0.3, stiffness=50.0, damping=0.1)
THREE = Model(**MATS, stops=[UP, LOW, PAIR])

FILE = """[model]
mass = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.5]]
stiffness = [[2.0, -1.0, 0.0], [-1.0, 3.0, -1.0], [0.0, -1.0, 2.0]]
forcing = [1.0, 0.2, 0.0]

[[stop]]
mass = 1
gap = 0.5
side = "upper"
restitution = 0.8

[[stop]]
mass = 1
gap = -0.4
side = "lower"
restitution = 0.7

[[stop]]
between = [1, 2]
gap = 0.3
side = "upper"
stiffness = 50.0
damping = 0.1
"""


# ---- Stop ------------------------------------------------------------------------
def test_old_stop_calls_keep_working():
    s = Stop(2, 0.3, 0.9)
    assert (s.mass, s.gap, s.restitution, s.side, s.kind, s.between) == (2, 0.3, 0.9, "upper",
                                                                          "rigid", None)
    assert s == Stop(mass=2, gap=0.3, restitution=0.9) and s.plain
    assert repr(s) == "Stop(mass=2, gap=0.3, restitution=0.9)"


def test_stop_kinds_and_their_constraints():
    c = PAIR.constraint(3)
    assert c.normal == (-1.0, 1.0, 0.0) and c.kind == "elastic" and c.restitution is None
    assert (c.stiffness, c.damping, c.side, c.gap) == (50.0, 0.1, "upper", 0.3)
    with pytest.raises(ParameterError, match="elastic"):
        c.reset_matrix(np.eye(3))                   # an elastic contact has no reset
    lo = LOW.constraint(3)
    assert lo.sign == -1.0 and lo.kind == "rigid" and lo.impulse is None
    assert lo.guard([-0.5, 0.0, 0.0]) == pytest.approx(0.1)          # s = -0.5 < g: inside
    assert Stop(between=[3, 1], gap=0.1, restitution=1).between == (3, 1)
    assert not PAIR.plain and not LOW.plain and PAIR.kind == "elastic"


@pytest.mark.parametrize("kw,field,words", [
    (dict(gap=0.1, restitution=0.5), "stop.mass", "exactly one of mass=k"),
    (dict(mass=1, between=(1, 2), gap=0.1, restitution=0.5), "stop.mass", "both given"),
    (dict(between=(2, 2), gap=0.1, restitution=0.5), "stop.between", "two different"),
    (dict(between=(1, 9), gap=0.1, restitution=0.5), "stop.between", "from 1 to 8"),
    (dict(between=1, gap=0.1, restitution=0.5), "stop.between", "two different"),
    (dict(mass=1, restitution=0.5), "stop.gap", "required"),
    (dict(mass=1, gap=0.1, restitution=0.5, side="left"), "stop.side", '"upper" or "lower"'),
    (dict(mass=1, gap=0.1), "stop.restitution", "or a stiffness > 0"),
    (dict(mass=1, gap=0.1, restitution=0.5, stiffness=3.0), "stop.stiffness",
     "none for a rigid stop"),
    (dict(mass=1, gap=0.1, restitution=0.5, damping=0.1), "stop.damping", "only with a stiffness"),
    (dict(mass=1, gap=0.1, stiffness=0.0), "stop.stiffness", "0 < stiffness"),
    (dict(mass=1, gap=0.1, stiffness=2.0, damping=-1.0), "stop.damping", "0 <= damping"),
    (dict(mass=1, gap=0.1, stiffness="2"), "stop.stiffness", "not a number"),
])
def test_bad_stops_name_the_field_and_the_range(kw, field, words):
    with pytest.raises(ParameterError) as e:
        Stop(**kw)
    assert e.value.name == field and words in str(e.value) and "\n" not in str(e.value)


# ---- Model(stops=[...]) -------------------------------------------------------------
def test_model_with_several_stops():
    m = THREE
    assert m.stops == (UP, LOW, PAIR) and m.stop is UP
    assert m.constraints == tuple(s.constraint(3) for s in (UP, LOW, PAIR))
    assert [c.kind for c in m.constraints] == ["rigid", "rigid", "elastic"]
    one = Model(**MATS, stops=[UP])
    assert one == Model(**MATS, stop=UP) and hash(one) == hash(Model(**MATS, stop=UP))
    assert one.key() == Model(**MATS, stop=UP).key()
    other = Model(**MATS, stops=[UP, LOW.replaced(gap=-0.3), PAIR])
    assert other != m and len({m, other, Model(**MATS, stops=[UP, LOW, PAIR])}) == 2
    assert eval(repr(m), {"Model": Model, "Stop": Stop}) == m
    assert not m.conservative


def test_as_dict_keeps_todays_form_for_one_plain_stop():
    assert Model(**MATS, stop=UP).as_dict()["stop"] == {"mass": 1, "gap": 0.5, "restitution": 0.8}
    d = THREE.as_dict()["stop"]
    assert d == [{"mass": 1, "gap": 0.5, "side": "upper", "restitution": 0.8},
                 {"mass": 1, "gap": -0.4, "side": "lower", "restitution": 0.7},
                 {"between": [1, 2], "gap": 0.3, "side": "upper", "stiffness": 50.0,
                  "damping": 0.1}]
    assert isinstance(Model(**MATS, stop=LOW).as_dict()["stop"], list)


@pytest.mark.parametrize("stops,field,words", [
    ([UP, Stop(mass=4, gap=0.1, restitution=0.5)], "stop[2].mass", "from 1 to 3"),
    ([UP, Stop(between=(2, 4), gap=0.1, restitution=0.5)], "stop[2].between", "from 1 to 3"),
    ([UP, Stop(mass=1, gap=0.9, restitution=0.5)], "stop[2].side", "at most one upper"),
    ([UP, Stop(mass=1, gap=0.5, side="lower", restitution=0.5)], "stop[2].gap", "free space"),
    ([Stop(mass=1, gap=0.6, side="lower", restitution=0.5), UP], "stop[2].gap", "free space"),
    # an upper stop on x1 - x2 at -0.2 is a lower stop on x2 - x1 at 0.2: above 0.1
    ([Stop(between=(1, 2), gap=0.1, restitution=0.5),
      Stop(between=(2, 1), gap=-0.2, restitution=0.5)], "stop[2].gap", "free space"),
    ([Stop(between=(1, 2), gap=0.1, restitution=0.5),
      Stop(between=(2, 1), gap=0.2, side="lower", restitution=0.5)], "stop[2].side",
     "at most one upper"),
    ([], "stops", "non-empty"),
    ([UP, "stop"], "stop[2]", "symvi.Stop"),
])
def test_bad_stop_sets_name_the_stop(stops, field, words):
    with pytest.raises(ParameterError) as e:
        Model(**MATS, stops=stops)
    assert e.value.name == field and words in str(e.value) and "\n" not in str(e.value)


def test_a_two_sided_stop_between_two_masses_is_accepted():
    m = Model(**MATS, stops=[Stop(between=(1, 2), gap=0.1, restitution=0.5),
                             Stop(between=(2, 1), gap=0.2, restitution=0.5)])
    assert [c.normal for c in m.constraints] == [(-1.0, 1.0, 0.0), (1.0, -1.0, 0.0)]


def test_one_stop_messages_are_unchanged():
    with pytest.raises(ParameterError, match=r"^stop.mass = 4 is invalid; valid range: a mass "
                       r"index from 1 to 3$"):
        Model(**MATS, stop=Stop(mass=4, gap=0.1, restitution=0.5))
    for kw in ({}, {"stop": UP, "stops": [UP]}):
        with pytest.raises(ParameterError, match="exactly one of stop="):
            Model(**MATS, **kw)


# ---- model files ----------------------------------------------------------------------
def test_stop_tables_round_trip():
    m = loads(FILE)
    assert m == THREE and m.stops == THREE.stops
    assert dumps(m) == FILE
    assert loads(dumps(m)) == m
    # one plain stop keeps the single [stop] table, as [[stop]] or [stop] in the file
    one = loads(FILE.split("\n[[stop]]\nmass = 1\ngap = -0.4")[0])
    assert one == Model(**MATS, stop=UP) and "[stop]\nmass = 1\n" in dumps(one)
    assert "[[stop]]" not in dumps(one)


def _bad(edit):
    with pytest.raises(ModelFileError) as e:
        loads(edit(FILE), "f.toml")
    assert "\n" not in str(e.value)
    return str(e.value)


@pytest.mark.parametrize("edit,words", [
    (lambda s: s.replace("stiffness = 50.0", "stiffnes = 50.0"),
     ["f.toml: [[stop]] #3 stiffnes: unknown key", "between, damping"]),
    (lambda s: s.replace("gap = -0.4\n", ""), ["[[stop]] #2 gap: missing"]),
    (lambda s: s.replace("stiffness = 50.0\n", ""), ["[[stop]] #3 restitution: missing",
                                                      "stiffness > 0"]),
    (lambda s: s.replace("between = [1, 2]", ""), ["[[stop]] #3 mass: missing", "between"]),
    (lambda s: s.replace("restitution = 0.7", "restitution = 0.7\nstiffness = 3.0"),
     ["[[stop]] #2 stiffness: invalid", "none for a rigid stop"]),
    (lambda s: s.replace("mass = 1\ngap = -0.4", "mass = 4\ngap = -0.4"),
     ["[[stop]] #2 mass: invalid", "from 1 to 3"]),
    (lambda s: s.replace("between = [1, 2]", "between = [1, 1]"),
     ["[[stop]] #3 between: invalid", "two different"]),
    (lambda s: s.replace("gap = -0.4", "gap = 0.6"), ["[[stop]] #2 gap: invalid", "free space"]),
    (lambda s: s.replace('side = "lower"', 'side = "upper"'),
     ["[[stop]] #2 side: invalid", "at most one upper"]),
    (lambda s: s.replace('side = "lower"', 'side = "down"'),
     ["[[stop]] #2 side: invalid", '"upper" or "lower"']),
    (lambda s: s + "\n[stop]\nmass = 1\ngap = 0.1\nrestitution = 0.5\n",
     ["[stop]: both [stop] and [[stop]] given"]),
    (lambda s: s.split("[[stop]]")[0], ["[stop]: missing table", "[[stop]]"]),
    (lambda s: "stop = []\n" + s.split("[[stop]]")[0], ["[[stop]]: 0 tables"]),
])
def test_bad_stop_tables_name_the_key(edit, words):
    msg = _bad(edit)
    for w in words:
        assert w in msg


def test_single_stop_table_takes_the_new_keys():
    text = FILE.split("[[stop]]")[0] + '[stop]\nmass = 2\ngap = -0.1\nside = "lower"\n' \
        'stiffness = 9.0\n'
    m = loads(text)
    assert m.stops == (Stop(mass=2, gap=-0.1, side="lower", stiffness=9.0),)
    assert loads(dumps(m)) == m and "[[stop]]" in dumps(m)
    with pytest.raises(ModelFileError, match=r"\[stop\] stiffness: invalid"):
        loads(text.replace("stiffness = 9.0", "stiffness = 9.0\nrestitution = 0.5"))


# ---- parameters -------------------------------------------------------------------------
def test_parameter_names_of_several_stops():
    names = THREE.parameter_names()
    assert names[:9] == ["gap", "restitution", "stop[1].gap", "stop[1].restitution",
                         "stop[2].gap", "stop[2].restitution", "stop[3].gap",
                         "stop[3].stiffness", "stop[3].damping"]
    for name in names:
        assert THREE.with_(**{name: THREE.value(name)}) == THREE
    # one plain stop: today's names
    assert Model(**MATS, stop=UP).parameter_names()[:3] == ["gap", "restitution", "mass[1,1]"]


def test_stop_parameters_get_and_set():
    m = THREE
    assert m.value("gap") == m.value("stop[1].gap") == 0.5
    assert m.value("stop[2].gap") == -0.4 and m.value("stop[3].stiffness") == 50.0
    m2 = m.with_(**{"stop[2].gap": -0.2})
    assert m2.stops[1] == LOW.replaced(gap=-0.2) and m2.stops[0] is UP and m2.stops[2] is PAIR
    m3 = m.with_(**{"stop[3].stiffness": 80.0, "stop[3].damping": 0.0})
    assert (m3.stops[2].stiffness, m3.stops[2].damping) == (80.0, 0.0)
    # a mixed change: matrices and a stop
    m4 = m.with_(**{"forcing[2]": 0.5, "stop[2].restitution": 0.3})
    assert m4.forcing[1] == 0.5 and m4.stops[1].restitution == 0.3
    par = m.parameter("stop[2].gap")
    assert par.set(m, 1.1, -0.2) == (m2, 1.1)


def test_stop_parameters_carry_the_constraints_over():
    m = THREE
    m.constraints                                        # built, then carried over
    for name, v in (("stop[2].gap", -0.1), ("stop[3].damping", 0.3), ("restitution", 0.6)):
        new = m.with_(**{name: v})
        assert "constraints" in new._arrays
        fresh = Model(**MATS, stops=list(new.stops))
        assert new.constraints == fresh.constraints and new == fresh


@pytest.mark.parametrize("name,value,field,words", [
    ("stop[2].gap", 0.6, "stop[2].gap", "free space"),
    ("gap", -0.5, "gap", "free space"),                  # the first stop, below the lower
    ("stop[1].gap", -0.5, "stop[1].gap", "free space"),
    ("stop[2].restitution", 1.5, "stop[2].restitution", "0 < restitution <= 1"),
    ("stop[3].stiffness", -1.0, "stop[3].stiffness", "0 < stiffness"),
    ("restitution", 0.0, "stop.restitution", "0 < restitution <= 1"),
    ("stop[4].gap", 0.1, "parameter", "1 <= k <= 3"),
    ("stop[1].stiffness", 1.0, "parameter", "stop 1 is rigid"),
    ("stop[3].restitution", 0.5, "parameter", "stop 3 is elastic"),
    ("stop[0].gap", 0.1, "parameter", "k >= 1"),
])
def test_bad_stop_parameters(name, value, field, words):
    with pytest.raises(ParameterError) as e:
        THREE.with_(**{name: value})
    assert e.value.name == field and words in str(e.value)


def test_stop_tangents():
    """The Tangent holds a rigid stop's gap or restitution and names the stop (Tangent.stop,
    0-based); an elastic stop's stiffness and damping are its dk and dc."""
    t, t1 = THREE.tangent("gap"), THREE.tangent("stop[1].gap")
    assert (t.db, t.dr, t1.db, t1.dr, t.stop) == (1.0, 0.0, 1.0, 0.0, 0)
    assert THREE.tangent("stop[1].restitution").dr == 1.0
    t2 = THREE.tangent("stop[2].gap")
    assert (t2.db, t2.dr, t2.stop) == (1.0, 0.0, 1)
    assert THREE.tangent("mass[1]").stop == 0
    t3 = THREE.tangent("stop[3].stiffness")
    assert (t3.dk, t3.dc, t3.db, t3.stop, t3.zero) == (1.0, 0.0, 0.0, 2, False)


def test_preset_stop_parameters():
    m = PAPER_EX1
    assert m.value("stop[1].gap") == m.value("b") == 1.5
    new = m.with_(**{"stop[1].gap": 1.2})
    assert new == m.with_(b=1.2) and new.preset["b"] == 1.2
    with pytest.raises(ParameterError, match="1 <= k <= 1"):
        m.parameter("stop[2].gap")


# ---- what the dynamics take: the flow rigid stops on masses, the orbits one stop ---------
def test_the_flow_refuses_an_elastic_stop():
    """An elastic stop runs in simulate's walk through contact phases (flow/contact.py),
    on the section of its mass; the flow and the orbit analyses refuse it in one line."""
    assert Section.of(Model(**MATS, stops=[Stop(mass=2, gap=0.3, stiffness=50.0)])).dim == 6
    m = Model(**MATS, stops=[PAIR])
    for enter in (LinearFlow.of, Model.require_rigid_stops, Model.require_one_rigid_stop):
        with pytest.raises(ParameterError) as e:
            enter(m)
        msg = str(e.value)
        assert "an elastic stop" in msg and "\n" not in msg
        assert ("simulate, orbit" in msg) != (enter is Model.require_one_rigid_stop)


def test_a_stop_between_masses_is_a_coordinate_of_the_flow_s_frame():
    """s = x2 - x1 becomes the flow's first coordinate (q = T x): its section is named in
    it, the flow's M, K and P are the congruent ones, the rigid reset conserves momentum and
    sends s' to -r s'; the period-1 analyses still refuse it in one line."""
    m = Model(**MATS, stops=[Stop(between=(1, 2), gap=0.3, restitution=0.5)])
    flow = LinearFlow.of(m)
    assert Section.of(m).names == ("v2-v1+", "x1", "x3", "v1", "v3", "tau")
    T, Ti = flow.T, flow.Tinv
    assert np.allclose(flow.M, Ti.T @ m.mass @ Ti) and np.allclose(flow.P, Ti.T @ m.forcing)
    v = np.array([0.3, -0.7, 0.2])                 # mass velocities
    vplus = Ti @ (flow.reset @ (T @ v))
    c = np.array([-1.0, 1.0, 0.0])
    assert np.isclose(c @ vplus, -0.5 * (c @ v))
    assert np.isclose(m.mass.diagonal() @ vplus, m.mass.diagonal() @ v)   # momentum
    assert vplus[2] == v[2]
    with pytest.raises(ParameterError) as e:
        m.require_one_rigid_stop()
    assert "a stop between two masses" in str(e.value) and "\n" not in str(e.value)


@pytest.mark.parametrize("stops,words", [
    ([UP, LOW], "stops = 2 is invalid"),
    ([LOW], "a lower stop"),
])
def test_the_orbit_analyses_take_one_upper_stop(stops, words):
    """Several rigid stops on masses (or a lower one) enter the flow and the compiled run;
    the orbit analyses (period-1 orbits, shooting, the Python map, the jets) refuse them
    in one line."""
    from symvi.orbits import period1_orbits
    m = Model(**MATS, stops=stops)
    assert LinearFlow.of(m).n == 3 and Section.of(m).dim == 6
    assert m.require_rigid_stops() is m
    for enter in (Model.require_one_rigid_stop, lambda m: period1_orbits(m, 1.1)):
        with pytest.raises(ParameterError) as e:
            enter(m)
        msg = str(e.value)
        assert words in msg and "closed form" in msg and "\n" not in msg
    plain = Model(**MATS, stops=[UP])
    assert plain.require_one_rigid_stop() is plain and LinearFlow.of(plain).n == 3
