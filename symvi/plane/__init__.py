"""Parameter-plane studies: the attractor of the impact map over a grid of two named
parameters, computed in compiled batches on Dask and stored as zarr (xarray).

Layers: :mod:`.grid` (axes, spec, batch inputs) -> the one classifier
:mod:`symvi.simulations.classifier` (numba: runs, Lyapunov exponent, attractor class)
-> :mod:`.engine` (Dask tasks) -> :mod:`.store` (the zarr store, resumable).  Plotting lives in :mod:`symvi.reporting.figures`.
"""
from .engine import PlaneRun as PlaneRun
from .engine import compute_block as compute_block
from .engine import compute_serial as compute_serial
from .engine import run_plane as run_plane
from .grid import Axis as Axis
from .grid import PlaneSpec as PlaneSpec
from .grid import parse_axis as parse_axis
from .store import PlaneStore as PlaneStore
