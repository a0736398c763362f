"""The walk's event vocabulary (:mod:`symvi.flow.contact`): what a phase's finder meets and
how a walk ends, shared by the exact phases and the Taylor ones
(:mod:`symvi.flow.nlcontact`), which the walk imports: here, so neither imports the other
back."""
from dataclasses import dataclass

#: event kinds: a rigid impact, the entry into and the exit from an elastic contact
IMPACT, ENTRY, EXIT = "impact", "entry", "exit"
#: how a walk ends: a tangency (h'' <= 0 there) or a contact the motion does not leave
#: (h'' > 0: the stop holds the mass), no event within t_max of a phase, or t_end reached
GRAZING, STICKING, NO_EVENT, TIME = "grazing", "sticking", "no-event", "time"
#: a phase whose field is not finite along the motion (a force like sqrt(x1) at x1 = 0)
NONFINITE = "non-finite"


@dataclass(frozen=True)
class Hit:
    """What the finder met: ``status`` "event", GRAZING, NO_EVENT or NONFINITE, the time,
    the guard's index, and h'' there (> 0 at a tangency: the motion stays on the stop)."""

    status: str
    t: float
    guard: int
    h2: float
    steps: int
