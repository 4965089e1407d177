"""Which edges a drawing shows: every polygon edge, or the feature edges of a technical drawing.

Feature edges (``edges="feature"``), found from the triangles' edge adjacency:

- **silhouette**: an edge between a face turned towards the eye and one turned away. The
  facing is the sign of the homogeneous determinant ``det[(xh, yh, w)_0, (xh, yh, w)_1,
  (xh, yh, w)_2]`` of the face's projected corners: the rasterizer's cull test
  (``rasterkit.raster.kernels.cull``) for faces in front of the eye, and still the right side of the
  plane for a face that crosses the eye's plane (it is ``w0 w1 w2`` times the raster area),
  in every projection (perspective, parallel, oblique);
- **boundary**: an edge of one face only (an open mesh's rim), and edges of three faces or
  more (non-manifold), and the segments of OBJ ``l`` elements;
- **crease**: an edge between two faces whose normals differ by ``crease_angle`` degrees
  or more (the dihedral angle's supplement: 0 for a flat pair, 90 for a cube's edge);
- **material**: an edge between two faces of different colours (``Mesh.face_colors``:
  materials, or a scene's objects) or groups.

An edge that is several of these gets the first class in the order above. Pure NumPy, no
kernels: one sort of the 3M face sides, done once per mesh (:func:`sides`, kept by the mesh
like its face normals); each camera then only tests which faces turn towards it.
"""

from __future__ import annotations

import numpy as np

from rasterkit.options import EDGES, check_choice

__all__ = ["EDGE_CLASSES", "EDGES", "feature_edges", "select_edges"]

#: Class names, indexed by the class codes :func:`select_edges` returns.
EDGE_CLASSES = ("edge", "silhouette", "boundary", "crease", "material")
EDGE, SILHOUETTE, BOUNDARY, CREASE, MATERIAL = range(5)


def check_crease_angle(crease_angle) -> float:
    """``crease_angle`` as a float in [0, 180] degrees, or ``ValueError``/``TypeError``."""
    if isinstance(crease_angle, bool) or not isinstance(crease_angle, (int, float, np.integer, np.floating)):
        raise TypeError(f"crease_angle must be a number of degrees, got {type(crease_angle).__name__}")
    angle = float(crease_angle)
    if not 0.0 <= angle <= 180.0:
        raise ValueError(f"crease_angle must be between 0 and 180 degrees, got {crease_angle!r}")
    return angle


def check_edges(edges: str) -> str:
    return check_choice("edges", edges, EDGES)


def face_facing(clip: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M,) bool: faces turned towards the eye, from their corners in homogeneous raster
    space ``clip`` (N, 4) (see the module docstring). Degenerate and non-finite faces: False."""
    c = clip[:, [0, 1, 3]]
    p0, p1, p2 = c[faces[:, 0]], c[faces[:, 1]], c[faces[:, 2]]
    with np.errstate(invalid="ignore", over="ignore"):
        det = np.einsum("ij,ij->i", p0, np.cross(p1, p2))
    return det < 0


def _adjacency(faces: np.ndarray, n_vertices: int):
    """Unique undirected face sides: ``(pairs (E, 2) int64 lo < hi, first face, second face
    (-1 for none), count of faces)``."""
    m = len(faces)
    a = faces.reshape(-1)
    b = faces[:, [1, 2, 0]].reshape(-1)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    keep = lo != hi
    n = max(int(n_vertices), 1)
    keys = (lo * n + hi)[keep]
    owner = np.repeat(np.arange(m, dtype=np.int64), 3)[keep]
    order = np.argsort(keys, kind="stable")
    keys, owner = keys[order], owner[order]
    start = np.flatnonzero(np.diff(keys, prepend=-1) != 0)
    count = np.diff(np.append(start, len(keys)))
    first = owner[start]
    second = np.where(count >= 2, owner[np.minimum(start + 1, len(owner) - 1)], -1)
    ukeys = keys[start]
    return np.stack([ukeys // n, ukeys % n], axis=1), first, second, count


def sides(mesh):
    """What the feature edges of ``mesh`` need that no camera changes, kept by the mesh
    (``Mesh._feature_sides``): ``(pairs (E, 2) int64, f1 (E,), g2 (E,) its other face or f1
    again, two (E,) bool: exactly two faces, angle (E,) float64 degrees between the faces'
    normals (NaN for a degenerate face), material (E,) bool)``."""
    pairs, f1, f2, count = _adjacency(mesh.faces, len(mesh.vertices))
    two = count == 2
    g2 = np.where(two, f2, f1)
    normals = mesh.face_normals.astype(np.float64)
    valid = (np.einsum("ij,ij->i", normals, normals) > 0.5)  # unit normals; zero or NaN: degenerate
    cos = np.clip(np.einsum("ij,ij->i", normals[f1], normals[g2]), -1.0, 1.0)
    angle = np.where(valid[f1] & valid[g2], np.degrees(np.arccos(cos)), np.nan)
    material = np.zeros(len(pairs), bool)
    if mesh.face_colors is not None:
        material |= two & np.any(mesh.face_colors[f1] != mesh.face_colors[g2], axis=1)
    if mesh.face_groups is not None:
        material |= two & (mesh.face_groups[f1] != mesh.face_groups[g2])
    for a in (pairs, f1, g2, two, angle, material):
        a.flags.writeable = False
    return pairs, f1, g2, two, angle, material


def feature_edges(mesh, clip: np.ndarray, crease_angle: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """The feature edges of ``mesh`` seen through a camera.

    Parameters
    ----------
    mesh : Mesh
        World-space mesh.
    clip : (N, 4) float64
        Its vertices in homogeneous raster space (``camera.project_h``).
    crease_angle : float
        Degrees: pairs of faces whose normals differ by this much or more meet at a crease.

    Returns
    -------
    edges : (E, 2) int64
        Vertex pairs, ``lo < hi``, sorted.
    classes : (E,) int8
        Codes into :data:`EDGE_CLASSES`.
    """
    pairs, f1, g2, two, angle, material = mesh._feature_sides  # sorted once per mesh: :func:`sides`
    facing = face_facing(clip, mesh.faces)
    silhouette = two & (facing[f1] != facing[g2])
    with np.errstate(invalid="ignore"):
        crease = two & (angle >= crease_angle - 1e-9)  # NaN (a degenerate face): never
    classes = np.full(len(pairs), -1, np.int8)
    for code, mask in ((MATERIAL, material), (CREASE, crease), (BOUNDARY, ~two), (SILHOUETTE, silhouette)):
        classes[mask] = code  # later masks win: the order of the module docstring
    chosen = classes >= 0
    edges, classes = pairs[chosen], classes[chosen]
    if len(mesh.lines):
        lines = np.sort(mesh.lines, axis=1)
        lines = lines[lines[:, 0] != lines[:, 1]]
        edges = np.concatenate([edges, lines])
        classes = np.concatenate([classes, np.full(len(lines), BOUNDARY, np.int8)])
    return np.ascontiguousarray(edges), classes


def select_edges(mesh, clip: np.ndarray, edges: str = "all",
                 crease_angle: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """``(edges (E, 2) int64, classes (E,) int8)``: ``mesh.edges`` (class ``edge``) for
    ``"all"``, :func:`feature_edges` for ``"feature"``."""
    if check_edges(edges) == "all":
        return mesh.edges, np.zeros(len(mesh.edges), np.int8)
    return feature_edges(mesh, clip, check_crease_angle(crease_angle))
