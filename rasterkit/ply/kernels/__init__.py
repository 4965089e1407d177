"""The PLY reader's kernels: the numbers of an ASCII body (``tokens``) and the rows of an
element whose lists differ in length from row to row (``rows``). Imported only by the
modules of :mod:`rasterkit.ply`; each is compiled on first use (``rows`` only for a file
whose lists differ in length)."""
