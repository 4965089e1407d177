"""The STL reader's Numba kernels: ``text`` (the facets of ASCII STL text) and ``mesh``
(welding corners, finite rows, facet normals, the edges of the welded triangles)."""
