"""Deprecated: the plane's classifier is the one classifier of symvi,
:mod:`symvi.simulations.classifier`, whose batch entry ``classify`` is now
``classify_runs``; the names below warn (DeprecationWarning naming the new home) and are
removed in the next release (issue 24, item 5)."""
from .._deprecated import moved_call as _moved_call
from .._deprecated import moved_names as _moved_names

#: the names of the old module that live on in symvi.simulations.classifier
_NAMES = ("ATTRACTORS", "FIELDS", "Classified", "label", "PERIOD", "CIRCLE", "DOUBLED",
          "CHAOS", "NOIMPACT", "STICKING", "ESCAPE", "GRAZED", "TOL_CLOSED", "TOL_SLOW",
          "DECAY", "Q_MAX", "W_MIN", "LYAP_BIAS", "LYAP_MIN", "RATIO_CIRCLE", "DRIFT_MAX",
          "ESCAPE_MAX", "MIN_KEPT")
_get = _moved_names(__name__, "symvi.simulations.classifier", _NAMES)


def __getattr__(name):
    if name == "classify":
        return _moved_call("symvi.plane.kernel.classify", "symvi.simulations.classifier",
                           "classify_runs")
    return _get(name)
