"""The mesh a compiling helper renders (:mod:`rasterkit.runtime.warm`): a small sphere whose
arrays have the types the real model's will have, so that the kernels it compiles are the
variants the render runs."""

from __future__ import annotations

import numpy as np

__all__ = ["helper_mesh"]


def helper_mesh(maps, vertex_normals: bool, face_normals: bool):
    """An icosphere (80 faces) for a helper.

    ``maps``: the kinds of texture map the model has (``"diffuse"``, ``"alpha"``,
    ``"normal"``, :func:`rasterkit.formats.texture_maps`): the sphere then has texture
    coordinates and one material with a 4x4 map of each kind (an opacity map with texels
    below one half, so that the frame has cut-out faces; a normal map that is not grey, so
    that it is read as normals). ``vertex_normals``: give the sphere its own vertex normals
    (its unit vertices: the helper need not compile the kernel that sums them; this process
    compiles it for its model). ``face_normals`` False: the face normals are given too (another
    helper compiles their kernel; these are the same numbers)."""
    from rasterkit import Material, Mesh, Texture, shapes

    sphere = shapes.icosphere(1)
    vertices, faces = sphere.vertices, sphere.faces
    unit = vertices / np.linalg.norm(vertices, axis=1, keepdims=True)
    arguments = {"normals": unit} if vertex_normals else {}
    if maps:
        uv = np.stack([0.5 + np.arctan2(unit[:, 2], unit[:, 0]) / (2 * np.pi), 0.5 + np.arcsin(unit[:, 1]) / np.pi],
                      axis=1)
        texels = np.arange(48, dtype=np.uint8).reshape(4, 4, 3) * np.uint8(5)
        material = Material("warm", diffuse_map=Texture(texels) if "diffuse" in maps else None,
                            opacity_map=Texture(np.repeat(texels[..., :1] * np.uint8(2), 3, axis=2), srgb=False)
                            if "alpha" in maps else None,
                            normal_map=Texture(texels, srgb=False) if "normal" in maps else None)
        arguments.update(uv=uv, materials=[material], material_names=("warm",),
                         face_materials=np.zeros(len(faces), np.int32))
    mesh = Mesh(vertices, faces, **arguments) if arguments else sphere
    if not face_normals:
        a, b, c = (vertices[faces[:, k]] for k in range(3))
        normals = np.cross(b - a, c - a)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        normals = normals.astype(np.float32)
        normals.flags.writeable = False
        mesh.__dict__["face_normals"] = normals
    return mesh
