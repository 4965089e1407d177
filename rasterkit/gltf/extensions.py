"""glTF extensions: which are read, which refuse a file, which are ignored.

- Read: ``KHR_mesh_quantization`` (attributes of integer types, normalized or not: the
  accessors read every component type anyway) and ``KHR_lights_punctual`` (the lights the
  default scene's nodes place light the Scene, :mod:`rasterkit.gltf.lights`).
- Refused when the file lists them in ``extensionsRequired``, in one line naming the
  extension: those that change the geometry, without which the file has none or the wrong
  one (:data:`GEOMETRY`: Draco and meshopt compression, GPU instancing). When such an
  extension is only used (``extensionsUsed``), the file carries uncompressed fallback data,
  which is read, with a warning.
- Any other extension, required or used, is ignored with one warning naming it (the file is
  drawn without what it adds: texture transforms, other material models, KTX2 or WebP
  images...).
"""

from __future__ import annotations

from rasterkit.gltf.document import Document, shown

__all__ = ["GEOMETRY", "READ", "check_extensions"]

#: Extensions read (see the module documentation).
READ = ("KHR_mesh_quantization", "KHR_lights_punctual")

#: Extensions that change the geometry: a file that requires one is refused.
GEOMETRY = {
    "KHR_draco_mesh_compression": "Draco-compressed geometry",
    "EXT_meshopt_compression": "meshopt-compressed buffers",
    "KHR_meshopt_compression": "meshopt-compressed buffers",
    "EXT_mesh_gpu_instancing": "instanced meshes",
}


def check_extensions(doc: Document) -> None:
    """Refuse a file that requires an extension of :data:`GEOMETRY`; warn about the others
    it uses that are not read."""
    required = _names(doc, "extensionsRequired")
    for name in required:
        if name in GEOMETRY:
            raise doc.error("extensionsRequired", f"requires extension {name} ({GEOMETRY[name]}), which rasterkit "
                                                  "does not read")
    for name in dict.fromkeys(required + _names(doc, "extensionsUsed")):
        if name in READ:
            continue
        if name in GEOMETRY:
            doc.warn("extensionsUsed", f"extension {name} ({GEOMETRY[name]}) is not read: its fallback data are")
        else:
            what = "requires" if name in required else "uses"
            doc.warn("extensionsUsed", f"{what} extension {shown(name)}, which rasterkit ignores")


def _names(doc: Document, key: str) -> list:
    names = doc.root.list(key, [])
    for k, name in enumerate(names):
        if not isinstance(name, str):
            raise doc.error(f"{key}[{k}]", f"must be an extension's name, got {shown(name)}")
    return names
