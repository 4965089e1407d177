"""Named records that the triangle driver hands to the setup kernels (Numba takes
``collections.namedtuple`` arguments and unpacks them like tuples), instead of long
positional argument lists.
"""

from collections import namedtuple

#: The triangle records of :mod:`rasterkit.raster.kernels.face_setup`: ``xy`` (T, 6) int32 fixed-point
#: vertices, ``z`` (T, 3) float32 depths, ``box`` (T, 4) int32 clamped pixel boxes.
Records = namedtuple("Records", "xy z box")

#: Which faces need cutting: ``mask`` (M,) int8, the planes that cut each face (0: none),
#: and ``n_fan`` (M,) int8, the fan records of each cut face (0 for the others).
Cuts = namedtuple("Cuts", "mask n_fan")

#: What the setup counts: ``shift``, log2 of the rows per band; ``bands`` (N_CHUNKS, n_bands)
#: int64, drawn records per face chunk and band; ``tally`` (N_CHUNKS, N_STATUS + 1) int64,
#: faces per chunk and outcome (the last column: cut faces with something left).
Counts = namedtuple("Counts", "shift bands tally")

#: Flat Lambert colours made during the face pass (:func:`rasterkit.raster.kernels.face_setup.setup_faces`):
#: when ``on``, each face drawn or to be cut gets its colour in ``packed`` (M,) uint32 from
#: ``normals`` (M, 3) float32, ``base`` (1 or M, 3) float32 times ``scale``, the unit
#: direction ``light`` (3,) float64, ``ambient`` and ``two_sided``
#: (:func:`rasterkit.raster.kernels.shade.flat_colors`).
Lit = namedtuple("Lit", "on normals base scale light ambient two_sided packed")

#: How :func:`rasterkit.raster.kernels.bands.draw_bands` colours a visible pixel
#: (:func:`rasterkit.raster.kernels.shade.resolve_row`): the resolve ``mode`` (SHADE_*), ``n_faces``
#: M (record ``t`` is face ``t`` below M, else face ``fan_face[t - M]``), ``packed`` (M,)
#: uint32 face colours, ``faces`` (M, 3) int64, ``bary`` (M, 9) float64 perspective-correct
#: barycentric rows, and for smooth shading ``vertex_colors`` (K, 3) float32 read through
#: ``corners`` (M, 3) int64, each face corner's row (``faces`` itself for a colour per vertex).
Shading = namedtuple("Shading", "mode n_faces fan_face packed vertex_colors faces bary corners")

#: Where :func:`rasterkit.raster.kernels.bands.draw_bands` draws: ``depth`` (H, W) float32 when
#: ``keep_depth``, else a band-sized scratch per slot; the image ``height``; ``color`` (H, W,
#: C) uint8; whether to write face indices (``write_ids``) into ``ids`` (H, W) int32.
Target = namedtuple("Target", "depth keep_depth height color write_ids ids")

#: Where a draw samples each pixel: ``x, y`` int64, the sample point's offset from the pixel
#: centre in fixed point (1/256 pixel, raster x right, y down; ``0, 0`` the centre).
Sample = namedtuple("Sample", "x y")

#: The samples that :func:`rasterkit.raster.kernels.sample_bands.draw_sample_bands` averages:
#: ``offsets`` (n, 2) int64, each sample point's offset from the pixel centres in 1/256 pixel;
#: ``background`` the background's packed RGB (uint32, R in the low byte); ``scale, bias`` the
#: rounding division of the sums (:func:`rasterkit.raster.kernels.accumulate.average_samples`);
#: ``sums`` (n_slots, rows, W, 3) uint16, each slot's band of sums in its last BAND_HEIGHT rows;
#: ``exact``: the pixels whose samples saw one face and the background made exact, with
#: ``first`` and ``state`` (n_slots, rows, W) int32 the same way per slot (each pixel's first
#: face, and its samples and flags: :func:`rasterkit.raster.kernels.sample_rows.note_face`), and
#: ``corners`` (N, 4) int32 the vertex pass's rows and ``neighbours`` (M, 3) int32 the faces'
#: :func:`rasterkit.mesh.side_neighbours` for finding the outlines.
Samples = namedtuple("Samples", "offsets background scale bias sums exact first state corners neighbours")

#: Clearing a band before it is drawn: when ``on``, depth +inf, ids -1 and the band's part of
#: ``color_bytes`` (the colour buffer as 1-D uint8, empty without one) to ``pattern``, the
#: background repeated over 24 bytes (:func:`rasterkit.raster.kernels.clear.fill_bytes`).
Clear = namedtuple("Clear", "on color_bytes pattern")

#: What :func:`rasterkit.raster.kernels.maps.surface_maps` makes from a render's face ids: when
#: ``want_normals``, ``normals`` (H, W, 3) float32 from ``world_normals`` (M, 3) float32, or
#: (``smooth``) from ``vertex_normals`` (N, 3) float64 interpolated with ``bary`` (M, 9)
#: float64 and ``faces`` (M, 3) int64, all in world space, turned into camera space by
#: ``rotation`` (3, 3) float64 (C-contiguous); when ``want_objects``, ``object_ids`` (H, W)
#: int32 from ``face_object`` (M,) int32 and ``object_first`` (K,) int64, each object's
#: first face; when ``want_depth`` (made by the band worker only,
#: :func:`rasterkit.raster.kernels.maps.band_maps`), ``metric`` (H, W) float32, the distance along
#: the optical axis of each depth, for a camera with planes ``near``, ``far`` (floats),
#: ``perspective`` or not; when ``want_uv``, ``uv`` (H, W, 2) float32, the texture
#: coordinates of each face's corners ``corner_uv`` (M, 6) float64 (u0, v0, u1, v1, u2, v2;
#: NaN for a face without) interpolated perspective-correctly with ``bary``.
Maps = namedtuple("Maps", "want_normals normals smooth world_normals vertex_normals "
                          "bary faces rotation want_objects object_ids face_object object_first "
                          "want_depth metric near far perspective want_uv uv corner_uv")

#: A textured frame's resolve (:mod:`rasterkit.raster.kernels.texture_shade`): the textures'
#: arrays ``texels levels samplers transforms decode`` (:class:`rasterkit.material.sampling.TextureArgs`);
#: per face ``face_texture`` (M,) int32, its diffuse texture's row of ``samplers`` (-1: none,
#: coloured as untextured), ``corner_uv`` (M, 6) float64 its corners' (u, v) and ``tint``
#: (M, 3) float32 the colour (0..255) its texture is multiplied by; ``smooth``: the Lambert
#: factor per corner, ``intensity`` (K,) float32 read through ``corners`` (M, 3) int64, else
#: per face from the unit ``normals`` (M, 3) float32 and ``light`` (3,) float64 with
#: ``ambient`` and ``back`` (1.0: two-sided, ``|cos|``; 0.0: ``max(cos, 0)``; or (M,) per face); ``encode``
#: the sRGB table of :func:`rasterkit.raster.kernels.surface.encode_table`; per face
#: ``face_alpha`` (M,) int32 the texture whose alpha (its first channel without one) times
#: ``face_opacity`` (M,) float32 cuts it out (-1: none; :mod:`rasterkit.raster.kernels.cutout`),
#: ``face_normal_map`` (M,) int32 its normal map (-1: none), bent by ``face_bump`` (M,)
#: float32, in tangent space or (``face_normal_space`` (M,) int8 1) object space, tangent
#: space along ``tangents`` (M, 6) float32 (its unit tangent and
#: bitangent; empty when no face has a normal map); smooth, normal-mapped faces interpolate
#: ``corner_normals`` (K, 3) float64 through ``corners`` (empty otherwise). A frame with
#: lights (:mod:`rasterkit.raster.kernels.lit_shade`, L > 0) lights its textured faces (and,
#: ``phong``, every face) per pixel by Blinn-Phong: ``lights`` (L, 14) float64
#: (:func:`rasterkit.raster.lights.light_table`), the viewer at ``eye`` (3,) float64 when
#: ``perspective``, else along ``toward_viewer`` (3,) float64, the surface point from ``positions``
#: (N, 3) float64 and ``faces`` (M, 3) int64, the highlight and glow from ``specular``
#: (S, 3), ``shininess`` (S,) and ``emission`` (S, 3) float64 (S = 1 or M), and smooth
#: normals interpolated from ``corner_normals`` through ``corners``, and the lights' shadow
#: maps ``shadow_maps shadow_matrices shadow_axes softness`` (:class:`rasterkit.raster.shadows.ShadowMaps`,
#: columns 13-14 of ``lights`` say whose); L = 0 (the arrays empty): Lambert's factor as above.
Textured = namedtuple("Textured", "texels levels samplers transforms decode face_texture corner_uv tint smooth "
                                  "intensity corners normals light ambient back encode face_alpha face_opacity "
                                  "face_normal_map face_bump face_normal_space tangents corner_normals "
                                  "lights eye perspective toward_viewer positions faces specular shininess emission phong "
                                  "shadow_maps shadow_matrices shadow_axes softness")

#: An untextured frame lit per pixel (:mod:`rasterkit.raster.kernels.phong_rows`): ``lights``
#: (L, 15) float64 (:func:`rasterkit.raster.lights.light_table`, with the shadow maps' columns),
#: the viewer at ``eye`` (3,) float64 when ``perspective``, else along ``toward_viewer`` (3,) float64;
#: the surface point from ``positions`` (N, 3) float64 and ``faces`` (M, 3) int64; the
#: highlight and glow from ``specular`` (S, 3), ``shininess`` (S,) and ``emission`` (S, 3)
#: float64 (S = 1 or M, linear); the normal interpolated from ``corner_normals`` (K, 3) float64
#: through ``normal_corners`` (M, 3) int64 when ``smooth``, else each face's ``face_normals``
#: (M, 3) float32; ``two_sided`` (bool, or (M,) bool per face) faces lit on their back too;
#: ``encode`` the sRGB table of :func:`rasterkit.raster.kernels.surface.encode_table` and
#: ``decode`` (256,) float64 the linear light of each 8-bit sRGB code; ``shadows`` the lights'
#: shadow maps ``(maps, matrices, axes, softness)`` (:class:`rasterkit.raster.shadows.ShadowMaps`),
#: or None when no light has one (then the resolve compiles without the shadow lookups);
#: ``perspective_maps`` True when some of the maps are a spot's or a point light's, None when
#: all are parallel (a directional light's: the resolve then compiles only their lookups).
PixelLights = namedtuple("PixelLights", "lights eye perspective toward_viewer positions faces specular shininess emission "
                                        "smooth corner_normals normal_corners face_normals two_sided encode decode "
                                        "shadows perspective_maps")
