"""Hostile use of the Python API: no array a user can reach makes a kernel read or write
outside memory (issue 14, item 4).

A Mesh's arrays are immutable (read-only views of ``bytes``): NumPy cannot make them
writeable again, on the array or on any base or view of it, nor resize them. What NumPy does
let anyone change in place (``shape``, ``dtype``, ``strides``) and attributes replaced behind
the frozen dataclass are caught by ``Mesh.check_intact`` before a kernel runs. Every case
that could crash runs in a child process (:mod:`support.hostile`): a segfault fails its test instead
of ending the session.
"""

from __future__ import annotations

import copy
import pickle
import warnings

import numpy as np
import pytest

import rasterkit
from rasterkit import shapes
from rasterkit.mesh import immutable
from support.hostile import run_python

MODES = ("wire", "hidden", "solid", "solid+wire")

#: The arrays of a Mesh (all set on the mesh that ``_full_mesh`` makes) and what is cached.
ARRAYS = ("vertices", "faces", "edges", "lines", "vertex_colors", "normals", "texcoords", "face_colors",
          "face_groups", "face_normals")


def _full_mesh():
    cube = shapes.cube()
    n, m = len(cube.vertices), len(cube.faces)
    mesh = rasterkit.Mesh(cube.vertices, cube.faces, edges=cube.edges, lines=[[0, 7]],
                          vertex_colors=np.full((n, 3), 0.5), normals=np.array(cube.vertices),
                          texcoords=np.zeros((n, 2)), face_colors=np.full((m, 3), 0.25),
                          face_groups=np.zeros(m, np.int32), group_names=("all",))
    mesh.face_normals  # noqa: B018 - cached now: an array of the Mesh too
    return mesh


def _camera(mesh, size=(64, 48)):
    return rasterkit.Camera.frame(*mesh.bounding_sphere(), width=size[0], height=size[1])


# --- in process: what NumPy offers cannot reach a Mesh's memory ----------------------------


@pytest.mark.parametrize("name", ARRAYS)
def test_no_numpy_call_makes_a_mesh_array_writeable_or_resizes_it(name):
    mesh = _full_mesh()
    arr = getattr(mesh, name)
    before = arr.copy()
    assert immutable(arr)
    chain, base = [arr], arr.base
    while isinstance(base, np.ndarray):
        chain.append(base)
        base = base.base
    assert type(base) is bytes
    for a in chain + [arr.view(), arr[::-1], arr.reshape(-1)]:
        with pytest.raises(ValueError, match="WRITEABLE"):
            a.flags.writeable = True
        with pytest.raises(ValueError, match="WRITEABLE"):
            a.setflags(write=True)
        with pytest.raises(ValueError):
            a.resize(2 * a.size + 1, refcheck=False)
    strided = np.lib.stride_tricks.as_strided(arr, writeable=True)  # documented: read-only stays so
    with pytest.raises(ValueError, match="read-only"):
        strided.reshape(-1)[0] = 1
    with pytest.raises(ValueError, match="read-only"):
        np.frombuffer(base, dtype=np.uint8)[0] = 1
    assert np.array_equal(getattr(mesh, name), before)


def test_a_mesh_shares_only_immutable_arrays_and_copies_everything_else():
    cube = shapes.cube()
    v = np.array(cube.vertices)
    mesh = rasterkit.Mesh(v, cube.faces, edges=cube.edges)
    assert not np.shares_memory(mesh.vertices, v) and v.flags.writeable  # the caller's array untouched
    again = rasterkit.Mesh(mesh.vertices, mesh.faces, edges=mesh.edges)  # another Mesh's: shared, immutable
    assert again.vertices is mesh.vertices and again.faces is mesh.faces
    foreign = np.frombuffer(bytearray(v.tobytes()), np.float64).reshape(-1, 3)
    foreign.flags.writeable = False  # over a bytearray: writeable again at will, so copied
    assert not np.shares_memory(rasterkit.Mesh(foreign, cube.faces).vertices, foreign)


@pytest.mark.parametrize("copier", [copy.copy, copy.deepcopy, lambda m: pickle.loads(pickle.dumps(m))])
def test_copies_and_pickles_of_a_mesh_are_immutable_and_render_the_same(copier):
    mesh = _full_mesh()
    twin = copier(mesh)
    for name in ARRAYS:
        assert immutable(getattr(twin, name)), name
        np.testing.assert_array_equal(getattr(twin, name), getattr(mesh, name))
    camera = _camera(mesh)
    for mode in MODES:
        assert np.array_equal(rasterkit.render(twin, camera, mode=mode).color,
                              rasterkit.render(mesh, camera, mode=mode).color)


def _changed_shape(mesh, name):
    getattr(mesh, name).shape = (-1, 1)


def _changed_dtype(mesh, name):
    getattr(mesh, name).dtype = np.int32 if getattr(mesh, name).dtype.itemsize == 8 else np.int16


def _byte_swapped(mesh, name):
    arr = getattr(mesh, name)
    arr.dtype = arr.dtype.newbyteorder()


def _changed_strides(mesh, name):
    arr = getattr(mesh, name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # NumPy 2.4 deprecates it, still allows it
        arr.strides = (0, *arr.strides[1:])


def _replaced(mesh, name):
    object.__setattr__(mesh, name, np.full_like(getattr(mesh, name), 10**6 if name != "vertices" else 0))


@pytest.mark.parametrize("change", [_changed_shape, _changed_dtype, _byte_swapped, _changed_strides, _replaced])
@pytest.mark.parametrize("name", ["vertices", "faces", "edges", "vertex_colors", "face_colors", "normals"])
def test_an_array_changed_in_place_or_replaced_is_refused_before_any_kernel(change, name):
    mesh = _full_mesh()
    change(mesh, name)
    with pytest.raises(ValueError, match=rf"^Mesh\.{name} was changed after the Mesh was made") as error:
        rasterkit.render(mesh, _camera(shapes.cube()), mode="solid+wire")
    assert "\n" not in str(error.value)


def test_a_cached_face_normals_array_of_the_wrong_shape_is_refused():
    mesh = _full_mesh()
    mesh.__dict__["face_normals"] = np.zeros((1, 3), np.float32)
    with pytest.raises(ValueError, match="normals must have shape"):
        rasterkit.render(mesh, _camera(mesh), mode="solid")


def test_framebuffer_size_follows_its_colour_buffer_and_a_stale_depth_recipe_is_refused():
    mesh = shapes.cube()
    fb = rasterkit.render(mesh, _camera(mesh, (40, 30)), mode="solid")
    with pytest.raises(AttributeError):
        fb.height = 10**9  # a depth buffer made from it would be 40 GB
    fb.color = np.zeros((10, 20, 3), np.uint8)
    assert (fb.width, fb.height) == (20, 10)
    with pytest.raises(ValueError, match=r"^the depth buffer of this 40x30 render cannot be made"):
        fb.depth  # noqa: B018


def test_faces_in_the_memory_of_a_buffer_drawn_into_are_refused():
    from rasterkit.raster.triangles import rasterize_triangles

    ids = np.full((8, 8), -1, np.int32)
    faces = ids.reshape(-1).view(np.int64)[:3].reshape(1, 3)
    faces[:] = [[0, 1, 2]]
    clip = np.array([[0, 0, 0.5, 1], [8, 0, 0.5, 1], [0, 8, 0.5, 1]], float)
    with pytest.raises(ValueError, match="faces must not share memory with ids"):
        rasterize_triangles(None, np.full((8, 8), np.inf, np.float32), clip, faces, ids=ids)


# --- in child processes: the reproduction and its relatives neither crash nor draw wrong -------

_CHILD_PRELUDE = """
import copy, sys, warnings
import numpy as np
import rasterkit
from rasterkit import shapes

def full_mesh():
    cube = shapes.cube()
    n, m = len(cube.vertices), len(cube.faces)
    mesh = rasterkit.Mesh(cube.vertices, cube.faces, edges=cube.edges, vertex_colors=np.full((n, 3), 0.5),
                          normals=np.array(cube.vertices), face_colors=np.full((m, 3), 0.25))
    mesh.face_normals
    return mesh

camera = rasterkit.Camera.frame(*shapes.cube().bounding_sphere(), width=64, height=48)
STYLES = [dict(mode=m) for m in ("wire", "hidden", "solid", "solid+wire")] + [
    dict(mode="solid", shading="smooth"), dict(mode="solid+wire", aa=True, ids=True), dict(mode="wire", aa=True)]
expected = [rasterkit.render(full_mesh(), camera, **s).color for s in STYLES]

def attempt(label, attack):
    for style, image in zip(STYLES, expected):
        mesh = full_mesh()
        try:
            attack(mesh)
        except (ValueError, TypeError) as e:  # refused by NumPy: the mesh is untouched
            pass
        try:
            color = rasterkit.render(mesh, camera, **style).color
        except (ValueError, TypeError) as e:
            assert "\\n" not in str(e), (label, str(e))
            print(label, style, "refused:", type(e).__name__, flush=True)
            continue
        assert np.array_equal(color, image), (label, style, "drew a different image")
        print(label, style, "same image", flush=True)
"""

_ATTACKS = {
    "issue: edges made writeable, index 10**9": "m.edges.flags.writeable = True; m.edges[0, 0] = 10**9",
    "faces made writeable, index 10**9": "m.faces.flags.writeable = True; m.faces[0, 0] = 10**9",
    "faces made writeable through the base": "m.faces.base.flags.writeable = True; m.faces.base[0] = -10**9",
    "faces made writeable, negative index": "m.faces.setflags(write=True); m.faces[0, 0] = -10**6",
    "edges written through as_strided": (
        "np.lib.stride_tricks.as_strided(m.edges, writeable=True)[0, 1] = 2**62"),
    "vertices resized to one row": "m.vertices.resize((1, 3), refcheck=False)",
    "edges resized": "m.edges.resize((10**6, 2), refcheck=False)",
    "colours made writeable": "m.vertex_colors.flags.writeable = True; m.vertex_colors[:] = np.nan",
    "normals made writeable": "m.normals.flags.writeable = True; m.normals[:] = np.inf",
    "face normals made writeable": "m.face_normals.flags.writeable = True; m.face_normals[:] = np.nan",
    "edges reshaped to one column": "m.edges.shape = (-1, 1)",
    "faces reinterpreted as int32": "m.faces.dtype = np.int32",
    "edges byte-swapped": "m.edges.dtype = m.edges.dtype.newbyteorder()",
    "edges with stride 0": ("warnings.simplefilter('ignore'); m.edges.strides = (0, 8)"),
    "edges replaced by object.__setattr__": "object.__setattr__(m, 'edges', np.array([[0, 10**9]]))",
    "faces replaced by immutable bad indices": (
        "object.__setattr__(m, 'faces', np.frombuffer(np.full((12, 3), 10**9).tobytes(), np.int64).reshape(12, 3))"),
    "deep copy changed": ("c = copy.deepcopy(m); c.faces.flags.writeable = True"),
}


def test_attacks_on_a_mesh_give_an_error_or_the_same_image_never_a_crash():
    """Every attack in one child (a child's start-up and its seven expected renders cost more
    than an attack): each attack prints its label when it has ended, so a crash or a hang is
    named by the last label printed."""
    code = _CHILD_PRELUDE
    for k, (label, attack) in enumerate(_ATTACKS.items()):
        body = "\n    ".join(attack.split("; "))
        code += f"\ndef attack_{k}(m):\n    {body}\n\nattempt({label!r}, attack_{k})\nprint('ended', {label!r}, flush=True)\n"
    outcome = run_python(code, timeout=400)  # the first attack compiles every mode: a minute on a busy machine
    ended = [line[len("ended "):] for line in outcome.stdout.splitlines() if line.startswith("ended ")]
    after = f"after the attacks {ended}" if ended else "before the first attack ended"
    assert not outcome.crashed and not outcome.timed_out, f"{outcome.describe()} ({after})"
    assert outcome.code == 0, f"{outcome.describe()} ({after})"
    assert ended == list(_ATTACKS), outcome.describe()


def test_out_of_range_indices_are_refused_when_a_mesh_is_made():
    v = shapes.cube().vertices
    for faces in ([[0, 1, 8]], [[0, 1, -1]], [[0, 1, 10**9]], np.array([[0, 1, 2**64 - 1]], np.uint64)):
        with pytest.raises(ValueError, match=r"faces index out of range \[0, 8\)"):
            rasterkit.Mesh(v, faces)
    for edges in ([[0, 8]], [[-1, 0]], [[0, 2**63 - 1]]):
        with pytest.raises(ValueError, match=r"edges index out of range \[0, 8\)"):
            rasterkit.Mesh(v, [[0, 1, 2]], edges=edges)


def test_hostile_kernel_inputs_through_rasterize_triangles_and_lines_end_cleanly():
    outcome = run_python("""
        import numpy as np
        from rasterkit.draw import lines
        from rasterkit.raster.triangles import rasterize_triangles
        clip = np.array([[0, 0, 0.5, 1], [8, 0, 0.5, 1], [0, 8, 0.5, 1]], float)
        for faces in ([[0, 1, 10**9]], [[0, -1, 2]], [[-2**63, 0, 1]]):
            try:
                rasterize_triangles(np.zeros((8, 8, 3), np.uint8), np.full((8, 8), np.inf, np.float32), clip,
                                    np.array(faces, np.int64), face_colors=np.ones((1, 3), np.float32))
            except ValueError as e:
                print("refused:", e)
        image = np.zeros((8, 8, 3), np.uint8)
        lines(image, [[0, 0, 1e308, -1e308], [np.nan, 0, 3, 3], [-2**62, 3, 2**62, 3]], color="white")
        assert image[3].all() and not image[[0, 1, 2, 4, 5, 6, 7]].any()
        for bad in (np.zeros((8, 8, 3), np.uint8)[:, :, :0], np.zeros((0, 8, 3), np.uint8)):
            try:
                lines(bad, [[0, 0, 7, 7]])
            except ValueError as e:
                print("refused:", e)
        print("done")
    """, timeout=60)
    assert outcome.code == 0 and outcome.stdout.count("refused: faces must index vertices") == 3, outcome.describe()
    assert outcome.stdout.rstrip().endswith("done"), outcome.describe()
