"""``read_gltf(path) -> GltfScene``: glTF 2.0 files (``.gltf`` JSON with external or ``data:``
buffers and images, and binary ``.glb``) read as a :class:`rasterkit.Scene`.

The package, one part per module, in the order the reader uses them: ``errors``
(:class:`GltfError`, :class:`GltfLimitError`), ``document`` (typed access to the JSON, every
value checked with its JSON path), ``container`` (the GLB chunks or the JSON text, and
:func:`sniff`), ``extensions`` (what is read, refused or ignored), ``uris`` (``data:`` URIs
and files beside the model), ``buffers`` (buffers and buffer views, range-checked),
``accessors`` (typed, strided NumPy views; normalized integers; sparse accessors),
``primitives`` (attributes and the triangles, lines and points of each mode), ``materials``
(:class:`rasterkit.Material` and :class:`rasterkit.Texture` of the glTF materials),
``meshes`` (a glTF mesh as one :class:`rasterkit.Mesh`), ``nodes`` (the default scene's
hierarchy and world matrices), ``cameras`` (:class:`GltfCamera`, :func:`camera_of`),
``lights`` (``KHR_lights_punctual``: :class:`GltfLight` and the :class:`rasterkit.Light` of
it) and ``reader`` (:func:`read_gltf`, :class:`GltfScene`).

Coordinates: glTF's are right-handed, +Y up, metres, as rasterkit's world is (right-handed,
any up; the framing works from the bounding sphere): no conversion is applied. Texture
coordinates are flipped once (``v' = 1 - v``: glTF's ``v`` runs down the image, rasterkit's
up). Colours are linear in glTF and sRGB in rasterkit: they are encoded once (a light's
brightness above 1 goes into its intensity).

``docs/formats-gltf.md`` says what is read and what is refused.
"""

from rasterkit.gltf.cameras import GltfCamera, camera_of
from rasterkit.gltf.container import sniff
from rasterkit.gltf.errors import GltfError, GltfLimitError
from rasterkit.gltf.lights import GltfLight, light_of
from rasterkit.gltf.reader import GltfScene, read_gltf

__all__ = ["GltfCamera", "GltfError", "GltfLight", "GltfLimitError", "GltfScene", "camera_of", "light_of", "read_gltf",
           "sniff"]
