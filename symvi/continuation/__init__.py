"""Continuation of n-p orbits in any named parameter, with their special points located:
one pseudo-arclength engine (:mod:`symvi.continuation.engine`), one result family and one
event vocabulary (:mod:`symvi.continuation.result`)."""
from .result import EVENT_KINDS as EVENT_KINDS
from .result import Result as Result
from .points import Branch as Branch
from .points import BranchPoint as BranchPoint
from .points import SpecialPoint as SpecialPoint
from .branch import continue_branch as continue_branch
from .branch import switch_at_flip as switch_at_flip
from .branch import period1_branches as period1_branches
from .branch import same_branch as same_branch
from .branch import diagram_branches as diagram_branches
from .start import continue_orbits as continue_orbits
