"""A batch's record (``OUTDIR/manifest.jsonl``) and what ``--resume`` may skip.

The manifest has one JSON object per line, one per model, appended as its result arrives,
each line with one ``write`` to a file opened for appending: a run that is killed leaves
every finished model's line and no half line (a reader skips a line that does not parse,
in case the disk filled up in the middle of one; the line after a failed write starts on a
line of its own, so it is not spoilt too). Fields: ``input``, ``output``,
``status`` (``"ok"``, ``"error"``, or ``"skipped"`` by ``--resume``), ``error`` (the
one-line message, or null; the command line prints it after ``rasterkit: error:``, or
``rasterkit: internal error:`` for a bug of rasterkit or a worker that died),
``seconds`` (the model's own time in its worker), ``triangles`` (null when it did not load
or was skipped), ``warnings`` (the loader's warning lines).
A new run starts a new manifest; a ``--resume`` run appends to the old one, a line for every
model, ``"skipped"`` for those whose image was complete and newer than the model: a run that
was killed may have written an image and not its line, so the last line of each model
says what it is now.

File names are bytes on POSIX and stay so: a name that is not UTF-8 has its undecodable
bytes as ``\\udcXX`` escapes in the JSON (the ``surrogateescape`` code points Python gives
them, so ``os.fsencode`` of the ``input`` a reader gets is the file's name again); the rest
of the file is UTF-8.

Pure standard library.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

__all__ = ["Manifest", "complete_image", "read_manifest", "up_to_date"]

MANIFEST = "manifest.jsonl"

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_PNG_END = b"\x00\x00\x00\x00IEND\xaeB`\x82"  # an empty IEND chunk and its CRC


class Manifest:
    """``OUTDIR/manifest.jsonl``, open for appending records (truncated first unless ``append``)."""

    def __init__(self, folder: Path, append: bool):
        self.path = Path(folder) / MANIFEST
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | (0 if append else os.O_TRUNC)
        self._fd = os.open(self.path, flags, 0o666)  # the umask decides the permissions
        self._torn = False  # the last write failed, perhaps in the middle of its line

    def write(self, record: dict) -> None:
        """Append ``record`` as one line. An ``OSError`` (a full disk) names the manifest;
        the line after a failed one starts on a line of its own."""
        # json.dumps leaves a name's surrogate escapes as they are; "backslashreplace"
        # writes each as the JSON escape \udcXX, which json.loads turns back into it
        line = (json.dumps(record, ensure_ascii=False) + "\n").encode("utf-8", "backslashreplace")
        if self._torn:
            line = b"\n" + line
        try:
            while line:
                line = line[os.write(self._fd, line):]  # a full disk may write part of it
            self._torn = False
        except OSError as e:
            self._torn = True
            raise OSError(e.errno, e.strerror or str(e), str(self.path)) from None

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> Manifest:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def read_manifest(path: str | os.PathLike) -> list[dict]:
    """The records of a manifest, in order; lines that do not parse are left out."""
    records = []
    with open(path, encoding="utf-8", errors="surrogateescape") as f:
        for line in f:
            try:
                record = json.loads(line)
            except ValueError:
                continue
            if isinstance(record, dict):
                records.append(record)
    return records


def complete_image(path: Path) -> bool:
    """Whether ``path`` is a whole image file as rasterkit writes them: a PNG (or APNG) from
    its signature to its end chunk, or a GIF from its header to its trailer byte."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):  # a FIFO would block, a device never end
            return False
        with open(path, "rb") as f:
            head = f.read(8)
            f.seek(0, os.SEEK_END)
            size = f.tell()
            if size < 20:
                return False
            f.seek(size - len(_PNG_END))
            tail = f.read()
    except OSError:
        return False
    if head == _PNG_SIGNATURE:
        return tail == _PNG_END
    return head[:6] in (b"GIF87a", b"GIF89a") and tail[-1:] == b";"


def up_to_date(source: Path, output: Path) -> bool:
    """Whether ``output`` is a complete image newer than its model ``source``."""
    try:
        if output.stat().st_mtime_ns <= source.stat().st_mtime_ns:
            return False
    except OSError:
        return False
    return complete_image(output)
