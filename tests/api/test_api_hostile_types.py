"""Nonsense through the Python API is refused, not converted on the quiet (issue 14, item 10).

Every public function that takes numbers (vertices, faces, edges, colours, normals, points,
matrices, camera vectors and scalars, a light, segments) refuses booleans, complex numbers,
strings, dates, objects and None with a one-line ``TypeError`` naming the argument and the
dtype; integers where floats are expected stay accepted and give what the floats give.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh, Scene, draw, shapes, transform
from rasterkit.mesh import polygon_edges, unique_edges

CUBE = shapes.cube()
N, M = len(CUBE.vertices), len(CUBE.faces)

#: Arrays of nonsense of the shape ``shape``: their dtype, and how the message names it.
NONSENSE = {
    "complex": lambda shape: np.ones(shape, complex),
    "bool": lambda shape: np.ones(shape, bool),
    "datetime": lambda shape: np.ones(shape, "datetime64[s]"),
    "timedelta": lambda shape: np.ones(shape, "timedelta64[s]"),
    "str": lambda shape: np.full(shape, "1"),
    "bytes": lambda shape: np.full(shape, b"1"),
    "object": lambda shape: np.full(shape, 1.0, dtype=object),
    "None inside": lambda shape: np.full(shape, None),
}
DTYPE_WORDS = {"complex": "complex128", "bool": "bool", "datetime": "datetime64", "timedelta": "timedelta64",
               "str": "<U1", "bytes": "|S1", "object": "object", "None inside": "object"}


def _camera(**kwargs):
    return Camera.look_at((0, 0, 5), (0, 0, 0), width=32, height=24, **kwargs)


#: (argument name, the call with the argument replaced by ``x``, the argument's shape)
CALLS = [
    ("vertices", lambda x: Mesh(x, CUBE.faces), (N, 3)),
    ("faces", lambda x: Mesh(CUBE.vertices, x), (M, 3)),
    ("edges", lambda x: Mesh(CUBE.vertices, CUBE.faces, edges=x), (4, 2)),
    ("lines", lambda x: Mesh(CUBE.vertices, CUBE.faces, lines=x), (4, 2)),
    ("vertex_colors", lambda x: Mesh(CUBE.vertices, CUBE.faces, vertex_colors=x), (N, 3)),
    ("face_colors", lambda x: Mesh(CUBE.vertices, CUBE.faces, face_colors=x), (M, 3)),
    ("normals", lambda x: Mesh(CUBE.vertices, CUBE.faces, normals=x), (N, 3)),
    ("texcoords", lambda x: Mesh(CUBE.vertices, CUBE.faces, texcoords=x), (N, 2)),
    ("face_groups", lambda x: Mesh(CUBE.vertices, CUBE.faces, face_groups=x, group_names=("a",)), (M,)),
    ("vertices", lambda x: rasterkit.render((x, CUBE.faces), _camera()), (N, 3)),
    ("eye", lambda x: Camera.look_at(x, (0, 0, 0)), (3,)),
    ("target", lambda x: Camera.look_at((0, 0, 5), x), (3,)),
    ("up", lambda x: Camera.look_at((0, 0, 5), (0, 0, 0), up=x), (3,)),
    ("shift", lambda x: Camera.look_at((0, 0, 5), (0, 0, 0), shift=x), (2,)),
    ("center", lambda x: Camera.frame(x, 1.0), (3,)),
    ("points", lambda x: _camera().project(x), (2, 3)),
    ("x", lambda x: _camera().ray(x, 0.0), (2,)),
    ("light", lambda x: rasterkit.render(CUBE, _camera(), mode="solid", light=x), (3,)),
    ("segments", lambda x: draw.lines(np.zeros((4, 4, 3), np.uint8), x), (2, 4)),
    ("a model matrix", lambda x: Scene().add(CUBE, x), (4, 4)),
    ("points", lambda x: transform.apply_points(np.eye(4), x), (2, 3)),
    ("matrix", lambda x: transform.apply_points(x, np.zeros((2, 3))), (4, 4)),
    ("vectors", lambda x: transform.apply_vectors(np.eye(4), x), (2, 3)),
    ("normals", lambda x: transform.apply_normals(np.eye(4), x), (2, 3)),
    ("points", lambda x: transform.to_homogeneous(x), (2, 3)),
    ("homogeneous points", lambda x: transform.from_homogeneous(x), (2, 4)),
    ("matrices[0]", lambda x: transform.compose(x), (4, 4)),
    ("matrix", lambda x: transform.invert(x), (4, 4)),
    ("axis", lambda x: transform.rotate_axis(1.0, x), (3,)),
    ("normal", lambda x: transform.reflect_plane((0, 0, 0), x), (3,)),
    ("pairs", lambda x: unique_edges(x, 8), (4, 2)),
    ("polygons[0]", lambda x: polygon_edges([x]), (4,)),
]


@pytest.mark.parametrize("kind", list(NONSENSE))
@pytest.mark.parametrize("name, call, shape", CALLS, ids=[f"{c[0]}-{i}" for i, c in enumerate(CALLS)])
def test_nonsense_arrays_are_a_type_error_naming_the_argument_and_dtype(name, call, shape, kind):
    value = NONSENSE[kind](shape)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning on the way either
        with pytest.raises(TypeError) as error:
            call(value)
    message = str(error.value)
    assert "\n" not in message and name in message and DTYPE_WORDS[kind] in message, message


#: Arguments for which None means "the default" (no edges given, a headlight, the identity).
OPTIONAL = {"edges", "lines", "vertex_colors", "face_colors", "normals", "texcoords", "face_groups", "light",
            "a model matrix", "pairs", "polygons[0]"}
REQUIRED = [c for c in CALLS if c[0] not in OPTIONAL]


@pytest.mark.parametrize("name, call, shape", REQUIRED, ids=[f"{c[0]}-{i}" for i, c in enumerate(REQUIRED)])
def test_none_where_numbers_are_required_is_a_type_error_naming_the_argument(name, call, shape):
    with pytest.raises(TypeError) as error:
        call(None)
    message = str(error.value)
    assert "\n" not in message and name in message and "None" in message, message


@pytest.mark.parametrize("value", [None, "cube.obj", 3, [1, 2, 3], (None, None)])
def test_none_or_nonsense_as_a_mesh_or_scene_is_a_type_error(value):
    with pytest.raises(TypeError):
        rasterkit.render(value, _camera())
    with pytest.raises(TypeError):
        Scene(_camera()).add(value)


def test_scene_objects_appended_by_hand_are_checked():
    scene = Scene(_camera()).add(CUBE)
    scene.objects.append(None)
    with pytest.raises(TypeError, match="SceneObjects"):
        rasterkit.render(scene)


@pytest.mark.parametrize("call", [
    lambda: Camera.look_at((0, 0, 5), (0, 0, 0), fov_y="45"),
    lambda: Camera.look_at((0, 0, 5), (0, 0, 0), near=True),
    lambda: Camera.look_at((0, 0, 5), (0, 0, 0), far=100j),
    lambda: Camera.frame((0, 0, 0), "1"),
    lambda: Camera.frame((0, 0, 0), None),
    lambda: Camera.preset("perspective", (0, 0, 0), 1.0, distance="3"),
    lambda: transform.translate("1", 0, 0),
    lambda: transform.scale(True),
    lambda: transform.rotate_x("0.5"),
    lambda: transform.shear(xy=1j),
    lambda: shapes.torus(rings=8.5),
    lambda: shapes.grid(nx="3"),
    lambda: shapes.icosphere(True),
    lambda: shapes.cube("1"),
])
def test_nonsense_scalars_are_a_type_error(call):
    with pytest.raises(TypeError) as error:
        call()
    assert "\n" not in str(error.value)


def test_integers_where_floats_are_expected_stay_accepted_and_equal_the_floats():
    as_int = CUBE.vertices.astype(np.int64) * 2
    a, b = Mesh(as_int, CUBE.faces), Mesh(as_int.astype(float), CUBE.faces)
    assert a.vertices.dtype == np.float64 and np.array_equal(a.vertices, b.vertices)
    camera = Camera.look_at([0, 0, 5], np.array([0, 0, 0], np.int32), up=np.array([0, 1, 0], np.uint8),
                            width=32, height=24)
    assert camera == _camera()
    for mode in ("wire", "solid"):
        assert np.array_equal(rasterkit.render(a, camera, mode=mode, light=[1, 2, 3]).color,
                              rasterkit.render(b, camera, mode=mode, light=[1.0, 2.0, 3.0]).color)
    assert np.array_equal(transform.apply_points(np.eye(4, dtype=int), [[1, 2, 3]]), [[1.0, 2.0, 3.0]])
    image_int, image_float = np.zeros((4, 4, 3), np.uint8), np.zeros((4, 4, 3), np.uint8)
    draw.lines(image_int, np.array([[0, 0, 3, 3]], np.int16), color="white")
    draw.lines(image_float, [[0.5, 0.5, 3.5, 3.5]], color="white")
    assert np.array_equal(image_int, image_float) and image_int.any()


def test_messages_describe_large_arrays_by_shape_never_by_their_values():
    with pytest.raises(ValueError) as error:
        Camera.look_at(np.zeros(1000), (0, 0, 0))
    assert "\n" not in str(error.value) and "(1000,)" in str(error.value)
    with pytest.raises(ValueError) as error:
        transform.rotate_axis(1.0, np.full(3, np.nan))
    assert str(error.value) == "axis must be 3 finite numbers, got (nan, nan, nan)"
