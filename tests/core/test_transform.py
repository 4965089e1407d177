"""Tests of rasterkit.transform against hand-written matrices, Rodrigues' formula and the
lecture's algebraic properties of affine maps."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rasterkit import transform as tf

PROPERTY = settings(deadline=None, max_examples=50)

E_X, E_Y, E_Z = np.eye(3)
AXIS_ROTATIONS = [(tf.rotate_x, E_X), (tf.rotate_y, E_Y), (tf.rotate_z, E_Z)]
ROTATION_IDS = ["x", "y", "z"]

# A pinhole projection onto the plane z = -1 (camera looking down -z): w = -z.
PINHOLE = np.array(
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, -1.0, 0.0]]
)


# ---------------------------------------------------------------- strategies

angles = st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False)
coords = st.floats(-10.0, 10.0, allow_nan=False)
vec3 = st.tuples(coords, coords, coords).map(np.array)
unit_range = st.floats(-1.0, 1.0, allow_nan=False)
# Directions comfortably away from zero, so that normalising them is well conditioned.
directions = st.tuples(unit_range, unit_range, unit_range).filter(
    lambda v: math.hypot(*v) > 1e-3
).map(np.array)
factors = st.floats(0.2, 5.0) | st.floats(-5.0, -0.2)
shear_names = st.sampled_from(["xy", "xz", "yx", "yz", "zx", "zy"])

# Single elementary maps from the library; a single shear coefficient keeps det = 1, so every
# composition stays well conditioned and invertible.
elementary = st.one_of(
    st.builds(tf.translate, coords, coords, coords),
    st.builds(tf.rotate_x, angles),
    st.builds(tf.rotate_y, angles),
    st.builds(tf.rotate_z, angles),
    st.builds(tf.rotate_axis, angles, directions, vec3),
    st.builds(tf.scale, factors),
    st.builds(tf.scale, factors, factors, factors),
    st.builds(tf.reflect, st.sampled_from("xyz")),
    st.builds(tf.reflect_plane, vec3, directions),
    st.builds(lambda name, k: tf.shear(**{name: k}), shear_names, st.floats(-2.0, 2.0)),
)
affine_maps = st.lists(elementary, min_size=1, max_size=4).map(lambda ms: tf.compose(*ms))


def rodrigues(theta, axis):
    """R = cos θ I + sin θ [k]x + (1 - cos θ) k kᵀ, as a 4x4 matrix about the origin."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    m = np.eye(4)
    m[:3, :3] = (
        math.cos(theta) * np.eye(3) + math.sin(theta) * cross + (1 - math.cos(theta)) * np.outer(k, k)
    )
    return m


def homogeneous_apply(m, p):
    """One point through a 4x4 matrix, written out by hand."""
    h = m @ np.append(p, 1.0)
    return h[:3] / h[3]


def assert_close(actual, expected, atol=1e-12):
    np.testing.assert_allclose(actual, expected, rtol=0, atol=atol)


# ---------------------------------------------------------------- exact matrices


def test_identity():
    assert_close(tf.identity(), np.eye(4), atol=0)


def test_translate_matrix():
    expected = np.array([[1, 0, 0, 1], [0, 1, 0, -2], [0, 0, 1, 3.5], [0, 0, 0, 1]], float)
    assert_close(tf.translate(1, -2, 3.5), expected, atol=0)


@PROPERTY
@given(angles)
def test_rotation_matrices(theta):
    c, s = math.cos(theta), math.sin(theta)
    rx = [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]]
    ry = [[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]]
    rz = [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    assert_close(tf.rotate_x(theta), rx, atol=1e-15)
    assert_close(tf.rotate_y(theta), ry, atol=1e-15)
    assert_close(tf.rotate_z(theta), rz, atol=1e-15)


@pytest.mark.parametrize(
    "rotation, source, target",
    [
        (tf.rotate_z, E_X, E_Y),
        (tf.rotate_z, E_Y, -E_X),
        (tf.rotate_x, E_Y, E_Z),
        (tf.rotate_x, E_Z, -E_Y),
        (tf.rotate_y, E_Z, E_X),
        (tf.rotate_y, E_X, -E_Z),
    ],
)
def test_rotations_are_right_handed(rotation, source, target):
    assert_close(tf.apply_vectors(rotation(math.pi / 2), source[None]), target[None], atol=1e-15)


def test_scale_uniform_and_per_axis():
    assert_close(tf.scale(2.5), np.diag([2.5, 2.5, 2.5, 1.0]), atol=0)
    assert_close(tf.scale(2, -3, 0.5), np.diag([2.0, -3.0, 0.5, 1.0]), atol=0)
    assert_close(tf.apply_points(tf.scale(2, 3, 4), [[1.0, 1.0, 1.0]]), [[2.0, 3.0, 4.0]], atol=0)


@pytest.mark.parametrize("args", [(2.0, 3.0), (2.0, None, 3.0)])
def test_scale_with_two_factors_is_a_type_error(args):
    with pytest.raises(TypeError):
        tf.scale(*args)


@pytest.mark.parametrize("axis, index", [("x", 0), ("y", 1), ("z", 2)])
def test_reflect_mirrors_one_coordinate(axis, index):
    expected = np.eye(4)
    expected[index, index] = -1.0
    assert_close(tf.reflect(axis), expected, atol=0)


def test_reflect_z_is_the_lectures_mz():
    assert_close(tf.apply_points(tf.reflect("z"), [[1.0, 2.0, 3.0]]), [[1.0, 2.0, -3.0]], atol=0)


@pytest.mark.parametrize("axis", ["w", "X", "", "xy", 0, None])
def test_reflect_rejects_bad_axis(axis):
    with pytest.raises(ValueError):
        tf.reflect(axis)


@PROPERTY
@given(vec3, directions, st.floats(-5, 5), st.floats(-5, 5), st.floats(-5, 5))
def test_reflect_plane_geometry(q, normal, a, b, d):
    m = tf.reflect_plane(q, normal)
    n = normal / np.linalg.norm(normal)
    # Two tangents spanning the plane.
    t1 = np.cross(n, E_X if abs(n[0]) < 0.9 else E_Y)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    on_plane = q + a * t1 + b * t2
    assert_close(homogeneous_apply(m, on_plane), on_plane, atol=1e-11)
    assert_close(homogeneous_apply(m, on_plane + d * n), on_plane - d * n, atol=1e-11)
    assert_close(tf.apply_vectors(m, n[None]), -n[None])
    assert_close(m @ m, np.eye(4), atol=1e-11)
    assert np.linalg.det(m[:3, :3]) == pytest.approx(-1.0)


@pytest.mark.parametrize("point, normal", [((0, 0, 0), (0, 0, 1)), ((3, -4, 0), (0, 0, -5))])
def test_reflect_plane_xy_is_reflect_z(point, normal):
    assert_close(tf.reflect_plane(point, normal), tf.reflect("z"), atol=0)


@pytest.mark.parametrize(
    "point, normal",
    [
        ((0, 0, 0), (0, 0, 0)),
        ((0, 0, 0), (0, 1)),
        ((0, 0), (0, 0, 1)),
        ((0, 0, 0), (0, np.nan, 1)),
        ((np.inf, 0, 0), (0, 0, 1)),
    ],
)
def test_reflect_plane_rejects_bad_arguments(point, normal):
    with pytest.raises(ValueError):
        tf.reflect_plane(point, normal)


@pytest.mark.parametrize(
    "name, index", [("xy", (0, 1)), ("xz", (0, 2)), ("yx", (1, 0)), ("yz", (1, 2)), ("zx", (2, 0)), ("zy", (2, 1))]
)
def test_shear_single_coefficient(name, index):
    expected = np.eye(4)
    expected[index] = 0.75
    assert_close(tf.shear(**{name: 0.75}), expected, atol=0)


def test_shear_formula_with_all_coefficients():
    xy, xz, yx, yz, zx, zy = 1.0, 2.0, 3.0, 4.0, 5.0, 6.0
    x, y, z = 0.5, -1.0, 2.0
    expected = [x + xy * y + xz * z, y + yx * x + yz * z, z + zx * x + zy * y]
    m = tf.shear(xy, xz, yx, yz, zx, zy)
    assert_close(tf.apply_points(m, [[x, y, z]]), [expected], atol=0)


def test_shear_rejects_unknown_coefficient():
    with pytest.raises(TypeError):
        tf.shear(xx=1.0)


# ---------------------------------------------------------------- lecture properties


@pytest.mark.parametrize("rotation, _axis", AXIS_ROTATIONS, ids=ROTATION_IDS)
@PROPERTY
@given(theta=angles)
def test_rotation_inverse_is_negative_angle_and_transpose(rotation, _axis, theta):
    r = rotation(theta)
    assert_close(tf.invert(r), rotation(-theta))
    assert_close(r.T, rotation(-theta), atol=0)
    assert_close(r @ r.T, np.eye(4))


@pytest.mark.parametrize("rotation, _axis", AXIS_ROTATIONS, ids=ROTATION_IDS)
@PROPERTY
@given(theta=angles, phi=angles)
def test_rotations_about_one_axis_add_and_commute(rotation, _axis, theta, phi):
    assert_close(rotation(theta) @ rotation(phi), rotation(theta + phi))
    assert_close(rotation(theta) @ rotation(phi), rotation(phi) @ rotation(theta))


def test_rotations_about_different_axes_do_not_commute():
    rx, ry = tf.rotate_x(math.pi / 2), tf.rotate_y(math.pi / 2)
    # x -> (Rx) x -> (Ry) -z, but x -> (Ry) -z -> (Rx) y.
    assert_close(tf.apply_vectors(tf.compose(rx, ry), E_X[None]), -E_Z[None], atol=1e-15)
    assert_close(tf.apply_vectors(tf.compose(ry, rx), E_X[None]), E_Y[None], atol=1e-15)


@PROPERTY
@given(vec3, vec3)
def test_translations_add_commute_and_invert(a, b):
    assert_close(tf.compose(tf.translate(*a), tf.translate(*b)), tf.translate(*(a + b)), atol=0)
    assert_close(tf.translate(*a) @ tf.translate(*b), tf.translate(*b) @ tf.translate(*a), atol=0)
    assert_close(tf.invert(tf.translate(*a)), tf.translate(*(-a)), atol=0)
    assert_close(tf.translate(*a) @ tf.translate(*(-a)), np.eye(4), atol=0)


@PROPERTY
@given(affine_maps, affine_maps, affine_maps)
def test_composition_is_associative(a, b, c):
    expected = tf.compose(a, b, c)
    assert_close(tf.compose(tf.compose(a, b), c), expected, atol=1e-9)
    assert_close(tf.compose(a, tf.compose(b, c)), expected, atol=1e-9)


def test_composition_is_not_commutative():
    t, r = tf.translate(1, 0, 0), tf.rotate_z(math.pi / 2)
    origin = np.zeros((1, 3))
    # Move, then turn: (1, 0, 0) turns to (0, 1, 0). Turn, then move: the origin stays, moves.
    assert_close(tf.apply_points(tf.compose(t, r), origin), [[0.0, 1.0, 0.0]], atol=1e-15)
    assert_close(tf.apply_points(tf.compose(r, t), origin), [[1.0, 0.0, 0.0]], atol=1e-15)


@PROPERTY
@given(st.lists(coords, min_size=32, max_size=32))
def test_compose_is_reversed_matrix_product(values):
    a = np.reshape(values[:16], (4, 4))
    b = np.reshape(values[16:], (4, 4))
    assert_close(tf.compose(a, b), b @ a, atol=0)
    assert_close(tf.compose(a), a, atol=0)


def test_compose_of_nothing_is_identity():
    assert_close(tf.compose(), np.eye(4), atol=0)


@PROPERTY
@given(affine_maps)
def test_invert_matches_numpy(m):
    inverse = tf.invert(m)
    np.testing.assert_allclose(inverse, np.linalg.inv(m), rtol=1e-9, atol=1e-9)
    assert_close(inverse @ m, np.eye(4), atol=1e-9)
    assert_close(inverse[3], [0.0, 0.0, 0.0, 1.0], atol=0)


@pytest.mark.parametrize(
    "m",
    [PINHOLE, np.diag([1.0, 1.0, 1.0, 2.0]), np.eye(3), np.eye(4)[:3], tf.scale(1.0, 0.0, 1.0)],
    ids=["perspective", "w-scale", "3x3", "3x4", "singular"],
)
def test_invert_rejects_non_invertible_affine(m):
    with pytest.raises(ValueError):
        tf.invert(m)


# ---------------------------------------------------------------- rotation about an axis


@PROPERTY
@given(angles, directions)
def test_rotate_axis_is_rodrigues(theta, axis):
    assert_close(tf.rotate_axis(theta, axis), rodrigues(theta, axis))


@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("rotation, axis", AXIS_ROTATIONS, ids=ROTATION_IDS)
@pytest.mark.parametrize("theta", [0.3, math.pi / 2, -2.0, math.pi])
def test_rotate_axis_about_coordinate_axes(theta, rotation, axis, sign):
    m = tf.rotate_axis(theta, sign * axis)
    assert_close(m, rodrigues(theta, sign * axis))
    assert_close(m, rotation(sign * theta))


@PROPERTY
@given(angles, directions, vec3, st.floats(-5, 5))
def test_rotate_axis_off_origin(theta, axis, origin, t):
    m = tf.rotate_axis(theta, axis, origin)
    expected = tf.translate(*origin) @ rodrigues(theta, axis) @ tf.translate(*(-origin))
    assert_close(m, expected, atol=1e-11)
    on_axis = origin + t * axis
    assert_close(homogeneous_apply(m, on_axis), on_axis, atol=1e-11)


@PROPERTY
@given(angles, directions)
def test_rotate_axis_direction_is_fixed_eigenvector(theta, axis):
    linear = tf.rotate_axis(theta, axis)[:3, :3]
    assert_close(linear @ axis, axis)
    assert np.linalg.det(linear) == pytest.approx(1.0)


@pytest.mark.parametrize("magnitude", [1e-200, 1e-100, 1e100, 1e200])
def test_rotate_axis_ignores_axis_length(magnitude):
    # The docstring promises any non-zero length; a huge axis must not turn into the z axis,
    # a tiny one must not be mistaken for zero.
    axis = np.array([1.0, 2.0, -0.5])
    assert_close(tf.rotate_axis(0.7, magnitude * axis), rodrigues(0.7, axis))


@pytest.mark.parametrize("magnitude", [1e-200, 1e200])
def test_reflect_plane_ignores_normal_length(magnitude):
    assert_close(tf.reflect_plane((0, 0, 1), (0, 0, magnitude)), tf.reflect_plane((0, 0, 1), (0, 0, 1)))


@pytest.mark.parametrize(
    "axis, origin",
    [((0, 0, 0), (0, 0, 0)), ((1, 0), (0, 0, 0)), ((1, 0, 0), (0, 0)), ((np.nan, 0, 1), (0, 0, 0)), ((0, 0, 1), (0, np.inf, 0))],
)
def test_rotate_axis_rejects_bad_arguments(axis, origin):
    with pytest.raises(ValueError):
        tf.rotate_axis(1.0, axis, origin)


# ---------------------------------------------------------------- homogeneous helpers


@PROPERTY
@given(st.lists(vec3, min_size=0, max_size=8), st.floats(0.1, 10) | st.floats(-10, -0.1))
def test_homogeneous_round_trip(points, w):
    p = np.reshape(points, (-1, 3))
    h = tf.to_homogeneous(p)
    assert h.shape == (len(p), 4)
    assert_close(h[:, 3], np.ones(len(p)), atol=0)
    assert_close(tf.from_homogeneous(h), p, atol=0)
    # Any non-zero multiple of a homogeneous point is the same point.
    assert_close(tf.from_homogeneous(w * h), p, atol=1e-12)
    assert_close(tf.to_homogeneous(p, 0.0)[:, 3], np.zeros(len(p)), atol=0)


def test_from_homogeneous_w_zero_gives_inf_and_nan_silently():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = tf.from_homogeneous([[1.0, -2.0, 0.0, 0.0]])
    assert out[0, 0] == np.inf
    assert out[0, 1] == -np.inf
    assert np.isnan(out[0, 2])


@pytest.mark.parametrize(
    "func, array",
    [
        (tf.to_homogeneous, np.zeros(3)),
        (tf.to_homogeneous, np.zeros((2, 4))),
        (tf.from_homogeneous, np.zeros(4)),
        (tf.from_homogeneous, np.zeros((2, 3))),
        (tf.apply_normals, np.zeros((2, 4))),
    ],
)
def test_homogeneous_helpers_reject_bad_shapes(func, array):
    with pytest.raises(ValueError):
        if func is tf.apply_normals:
            func(np.eye(4), array)
        else:
            func(array)


@PROPERTY
@given(st.lists(vec3, min_size=1, max_size=8), vec3)
def test_apply_points_moves_points_by_translation(points, d):
    p = np.array(points)
    assert_close(tf.apply_points(tf.translate(*d), p), p + d)


@PROPERTY
@given(affine_maps, vec3, st.lists(vec3, min_size=1, max_size=8))
def test_apply_vectors_ignores_translation(m, d, vectors):
    v = np.array(vectors)
    moved = tf.compose(m, tf.translate(*d))
    assert_close(tf.apply_vectors(moved, v), v @ m[:3, :3].T, atol=1e-9)
    assert_close(tf.apply_vectors(tf.translate(*d), v), v, atol=0)


def test_apply_vectors_breaks_normals_under_non_uniform_scale():
    # The plane x + y = 0: normal (1, 1, 0), tangent (1, -1, 0).
    m = tf.scale(1.0, 2.0, 1.0)
    tangent = tf.apply_vectors(m, [[1.0, -1.0, 0.0]])[0]
    normal = np.array([[1.0, 1.0, 0.0]])
    assert np.dot(tf.apply_vectors(m, normal)[0], tangent) == pytest.approx(-3.0)
    assert_close(tf.apply_normals(m, normal), [[2 / math.sqrt(5), 1 / math.sqrt(5), 0.0]])


def test_apply_vectors_breaks_normals_under_shear():
    # The plane y = 0 is mapped onto itself by an xy shear, so its normal must stay +y.
    m = tf.shear(xy=1.0)
    normal = np.array([[0.0, 1.0, 0.0]])
    assert_close(tf.apply_vectors(m, normal), [[1.0, 1.0, 0.0]], atol=0)
    assert_close(tf.apply_normals(m, normal), normal)


@PROPERTY
@given(affine_maps, directions, directions)
def test_apply_normals_stay_perpendicular_to_tangents(m, t1, t2):
    normal = np.cross(t1, t2)
    assume(np.linalg.norm(normal) > 1e-3)
    tangents = tf.apply_vectors(m, np.array([t1, t2]))
    n = tf.apply_normals(m, normal[None])[0]
    assert np.linalg.norm(n) == pytest.approx(1.0)
    assert_close(tangents @ n, np.zeros(2), atol=1e-9)


def test_apply_normals_ignores_translation_and_keeps_zero():
    m = tf.compose(tf.scale(1, 3, 0.5), tf.translate(4, 5, 6))
    out = tf.apply_normals(m, [[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]])
    assert_close(out, [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


# ---------------------------------------------------------------- what affine maps keep


@PROPERTY
@given(affine_maps, vec3, vec3, st.floats(-3, 3))
def test_affine_maps_keep_affine_combinations(m, p1, p2, a1):
    a2 = 1.0 - a1
    image = tf.apply_points(m, np.array([p1, p2, a1 * p1 + a2 * p2]))
    assert_close(image[2], a1 * image[0] + a2 * image[1], atol=1e-8)


@PROPERTY
@given(affine_maps, vec3, vec3, vec3, st.floats(0, 1), st.floats(0, 1))
def test_affine_maps_keep_barycentric_coordinates(m, p1, p2, p3, u, v):
    a = np.array([u, (1 - u) * v, (1 - u) * (1 - v)])  # sums to 1
    corners = np.array([p1, p2, p3])
    image = tf.apply_points(m, np.vstack([corners, a @ corners]))
    assert_close(image[3], a @ image[:3], atol=1e-8)


@PROPERTY
@given(affine_maps, vec3, directions, st.floats(-3, 3))
def test_affine_maps_keep_collinearity_and_ratios(m, p, d, t):
    image = tf.apply_points(m, np.array([p, p + d, p + t * d]))
    along = image[1] - image[0]
    assert_close(np.cross(along, image[2] - image[0]), np.zeros(3), atol=1e-8)
    assert_close(image[2] - image[0], t * along, atol=1e-8)


@PROPERTY
@given(affine_maps, vec3, vec3, directions)
def test_affine_maps_keep_parallel_lines_parallel(m, p, q, d):
    image = tf.apply_points(m, np.array([p, p + d, q, q + d]))
    assert_close(image[1] - image[0], image[3] - image[2], atol=1e-8)


def test_perspective_does_not_keep_ratios():
    a, b = np.array([0.0, 0.0, -1.0]), np.array([2.0, 0.0, -3.0])
    image = tf.apply_points(PINHOLE, np.array([a, b, (a + b) / 2]))
    assert_close(image[:2], [[0.0, 0.0, -1.0], [2 / 3, 0.0, -1.0]], atol=1e-15)
    # The midpoint (1, 0, -2) lands at x = 1/2, not at the image midpoint x = 1/3.
    assert_close(image[2], [0.5, 0.0, -1.0], atol=1e-15)
    assert not np.allclose(image[2], (image[0] + image[1]) / 2)
