"""The maps layer: the section layout (its only owner) and the impact map P of any model."""
from .section import Section as Section
