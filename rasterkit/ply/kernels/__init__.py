"""The PLY reader's kernels: the numbers of an ASCII body (``tokens``), the rows of an element
whose lists vary in length from row to row (``rows``) and the polygons' sides as sorted keys
(``edges``). Imported only by the modules of :mod:`rasterkit.ply`."""
