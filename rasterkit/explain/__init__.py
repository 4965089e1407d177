"""The lecture made visible: ``rasterkit explain`` as pure functions.

- :mod:`.chain`: the camera transformation factor by factor (:func:`chain_steps`, with a
  world point carried through to its pixel) and its text (:func:`format_chain`);
- :mod:`.line`: brute force, DDA and Bresenham pixel grids for a segment and Bresenham's
  decision variable at each step (:func:`line_steps`, :func:`line_grids`,
  :func:`format_line`).

The functions return data or text and print nothing; the command line prints. Importing
this package loads NumPy but not Numba: only :func:`line_grids` (and so
:func:`format_line`) runs kernels, through :func:`rasterkit.draw.line`.
"""

from rasterkit.explain.chain import ChainSteps, Factor, chain_steps, format_chain
from rasterkit.explain.line import MAX_GRID, BresenhamStep, LineSteps, check_segment, format_line, line_grids, line_steps

__all__ = ["MAX_GRID", "BresenhamStep", "ChainSteps", "Factor", "LineSteps", "chain_steps",
           "check_segment", "format_chain", "format_line", "line_grids", "line_steps"]
