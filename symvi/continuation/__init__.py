"""Continuation of n-p orbits in any named parameter, with their special points located."""
from .branch import Branch as Branch
from .branch import BranchPoint as BranchPoint
from .branch import SpecialPoint as SpecialPoint
from .branch import continue_branch as continue_branch
from .branch import switch_at_flip as switch_at_flip
