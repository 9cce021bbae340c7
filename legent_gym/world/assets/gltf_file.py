"""A glTF/GLB file checked before it is converted: the bounds on what one file may hold
(:data:`MAX_GLTF_BYTES`, :data:`MAX_VERTICES`, :data:`MAX_IMAGES`, :data:`MAX_GLTF_ITEMS`),
the container (a GLB's header and chunks, the JSON, glTF 2.0, required extensions), the
files and URIs it refers to (only base64 data URIs and regular files beside it) and its
images. :func:`read_document` returns the checked glTF JSON or raises
:class:`AssetImportError` naming the file and what is wrong;
:mod:`legent_gym.world.assets.gltf` converts what it accepts."""

from __future__ import annotations

import base64
import io
import json
import os
import re
import stat
import struct
import warnings
from pathlib import Path
from urllib.parse import unquote

#: Bounds on what one file may hold, so that a hostile file fails with a message naming
#: the file and the bound rather than exhausting memory: the .gltf/.glb file and each
#: buffer file it refers to (bytes), the vertices over every node instance (the declared
#: POSITION counts are checked before anything is decoded), the images, and the nodes,
#: meshes, accessors and primitives.
MAX_GLTF_BYTES = 256 * 1024 * 1024
MAX_VERTICES = 2_000_000
MAX_IMAGES = 64
MAX_GLTF_ITEMS = 100_000
#: Required glTF extensions whose geometry trimesh cannot decode.
_UNSUPPORTED_EXTENSIONS = {"EXT_meshopt_compression": "meshopt-compressed geometry"}

_GLB_MAGIC = b"glTF"
_GLB_JSON = 0x4E4F534A  # b"JSON"
_GLB_BIN = 0x004E4942  # b"BIN\0"


class AssetImportError(ValueError):
    """A glTF/GLB file or an import argument that cannot be turned into an asset."""


class AssetImportWarning(UserWarning):
    """An import that works but deserves attention (slow to render, no collision)."""


def read_document(path: Path) -> dict:
    """The glTF JSON of ``path``, after checking the container is whole and readable.

    Doing this before trimesh turns its varied failures (struct errors, KeyErrors, JSON
    errors deep in a loader) into precise messages for the common problems.
    """
    suffix = path.suffix.lower()
    if suffix not in (".gltf", ".glb"):
        raise AssetImportError(f"{path}: not a glTF file (expected a .gltf or .glb extension)")
    data = _read_bounded(path, path, "the file")
    if suffix == ".gltf" and data[:4] == _GLB_MAGIC:
        raise AssetImportError(f"{path}: this is a binary GLB file; give it the .glb extension")
    text, binary = _glb_chunks(path, data) if suffix == ".glb" else (data, None)
    try:
        document = json.loads(text)
    except (UnicodeDecodeError, json.JSONDecodeError) as err:
        raise AssetImportError(f"{path}: the glTF JSON is corrupt: {err}") from err
    except RecursionError:
        raise AssetImportError(f"{path}: the glTF JSON is nested too deeply") from None
    if not isinstance(document, dict):
        raise AssetImportError(f"{path}: the glTF JSON is not an object")
    asset = document.get("asset")
    version = str(asset.get("version", "")) if isinstance(asset, dict) else ""
    if not version.startswith("2"):
        raise AssetImportError(f"{path}: only glTF 2.0 is supported (asset.version is {version!r})")
    for ext in document.get("extensionsRequired", []) or []:
        if ext in _UNSUPPORTED_EXTENSIONS:
            raise AssetImportError(f"{path}: requires {ext} ({_UNSUPPORTED_EXTENSIONS[ext]}), "
                                   "which cannot be decoded")
    _check_counts(path, document)
    _check_external_files(path, document)
    _check_images(path, document, binary)
    return document


def _check_file(path: Path, target: Path, what: str) -> None:
    """``target`` (the file itself or one it refers to) must be a regular file of at most
    ``MAX_GLTF_BYTES``; errors name ``path`` and ``what``. Asked before opening: opening a
    FIFO would wait for a writer, and reading a device may not end."""
    try:
        info = os.stat(target)
    except OSError as err:
        raise AssetImportError(f"{path}: cannot read {what}: {err.strerror or err}") from err
    if not stat.S_ISREG(info.st_mode):
        raise AssetImportError(f"{path}: {what} is not a regular file (a directory, device or pipe)")
    if info.st_size > MAX_GLTF_BYTES:
        raise AssetImportError(f"{path}: {what} is {info.st_size} bytes, more than the "
                               f"{MAX_GLTF_BYTES} an asset may have (MAX_GLTF_BYTES)")


def _read_bounded(path: Path, target: Path, what: str) -> bytes:
    """The bytes of ``target``, checked by :func:`_check_file` first."""
    _check_file(path, target, what)
    try:
        with open(target, "rb") as file:
            data = file.read(MAX_GLTF_BYTES + 1)
    except OSError as err:
        raise AssetImportError(f"{path}: cannot read {what}: {err.strerror or err}") from err
    if len(data) > MAX_GLTF_BYTES:  # grew since the check
        raise AssetImportError(f"{path}: {what} is more than the {MAX_GLTF_BYTES} bytes an asset may "
                               "have (MAX_GLTF_BYTES)")
    return data


def _check_counts(path: Path, document: dict) -> None:
    """Refuse documents over the item, image and declared-vertex bounds, by name."""
    for key in ("nodes", "meshes", "accessors", "bufferViews", "buffers", "materials", "textures",
                "images", "scenes"):
        items = document.get(key)
        if items is None:
            continue
        if not isinstance(items, list):
            raise AssetImportError(f"{path}: the glTF {key!r} is not a list")
        limit = MAX_IMAGES if key in ("images", "textures") else MAX_GLTF_ITEMS
        if len(items) > limit:
            bound = "MAX_IMAGES" if limit == MAX_IMAGES else "MAX_GLTF_ITEMS"
            raise AssetImportError(f"{path}: {len(items)} {key}, more than the {limit} an asset may "
                                   f"have ({bound})")
    accessors = document.get("accessors") or []
    declared = primitives = 0
    for mesh in document.get("meshes") or []:
        prims = mesh.get("primitives") if isinstance(mesh, dict) else None
        for prim in prims if isinstance(prims, list) else []:
            primitives += 1
            attributes = prim.get("attributes") if isinstance(prim, dict) else None
            index = attributes.get("POSITION") if isinstance(attributes, dict) else None
            if isinstance(index, int) and 0 <= index < len(accessors) and isinstance(accessors[index], dict):
                count = accessors[index].get("count", 0)
                declared += count if isinstance(count, int) and count > 0 else 0
    if primitives > MAX_GLTF_ITEMS:
        raise AssetImportError(f"{path}: {primitives} mesh primitives, more than the {MAX_GLTF_ITEMS} "
                               "an asset may have (MAX_GLTF_ITEMS)")
    if declared > MAX_VERTICES:
        raise AssetImportError(f"{path}: its meshes declare {declared} vertices, more than the "
                               f"{MAX_VERTICES} an asset may have (MAX_VERTICES)")


def _glb_chunks(path: Path, data: bytes) -> tuple[bytes, bytes | None]:
    """The JSON and BIN chunks of a GLB, checking the header against the real length."""
    if len(data) < 20:
        raise AssetImportError(f"{path}: truncated GLB ({len(data)} bytes, shorter than its header)")
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != _GLB_MAGIC:
        raise AssetImportError(f"{path}: not a GLB file (bad magic {magic!r})")
    if version != 2:
        raise AssetImportError(f"{path}: GLB version {version} is not supported (only 2)")
    if length > len(data):
        raise AssetImportError(f"{path}: truncated GLB: the header declares {length} bytes "
                               f"but the file has {len(data)}")
    chunks: list[tuple[int, bytes]] = []
    offset = 12
    while offset + 8 <= length:
        chunk_length, chunk_type = struct.unpack_from("<II", data, offset)
        if offset + 8 + chunk_length > length:
            raise AssetImportError(f"{path}: truncated GLB: chunk {len(chunks)} runs past the end "
                                   "of the file")
        chunks.append((chunk_type, data[offset + 8:offset + 8 + chunk_length]))
        offset += 8 + chunk_length
    if not chunks or chunks[0][0] != _GLB_JSON:
        raise AssetImportError(f"{path}: corrupt GLB: the first chunk is not JSON")
    binary = next((chunk for kind, chunk in chunks[1:] if kind == _GLB_BIN), None)
    return chunks[0][1], binary


def _check_external_files(path: Path, document: dict) -> None:
    """Every buffer and image URI must be a base64 data URI or a relative path to a regular
    file inside the file's own folder; buffer files must exist and be within
    ``MAX_GLTF_BYTES``. Anything else (``http:``, ``file:`` or other URLs, absolute paths,
    ``..`` or symbolic links out of the folder, devices) is refused."""
    folder = path.parent.resolve()
    for kind in ("buffers", "images"):
        for index, entry in enumerate(document.get(kind) or []):
            uri = entry.get("uri") if isinstance(entry, dict) else None
            if uri is None:
                continue
            what = f"{kind[:-1]} {index}"
            if not isinstance(uri, str) or not uri:
                raise AssetImportError(f"{path}: {what} has a uri that is not a non-empty string")
            if uri.startswith("data:"):
                if ";base64," not in uri.partition(",")[0] + ",":
                    raise AssetImportError(f"{path}: {what} has a data URI that is not base64 "
                                           "(glTF embeds data as data:<type>;base64,...)")
                continue
            if re.match(r"^[A-Za-z][A-Za-z0-9+.\-]*:", uri) or "://" in uri:
                raise AssetImportError(f"{path}: {what} refers to the URL {uri[:80]!r}; only files "
                                       "beside the asset are read")
            name = unquote(uri)
            if "\0" in name or name.startswith(("/", "\\")):
                raise AssetImportError(f"{path}: {what} refers to the absolute path {uri[:80]!r}; only "
                                       "files beside the asset are read")
            try:
                target = (folder / name).resolve()
                exists = target.exists()
            except (OSError, RuntimeError) as err:  # RuntimeError: a symbolic link loop
                raise AssetImportError(f"{path}: {what} uri {uri[:80]!r} cannot be resolved: {err}") from err
            if not target.is_relative_to(folder):
                raise AssetImportError(f"{path}: {what} refers to {uri[:80]!r}, outside the asset's folder")
            if not exists:
                if kind == "images":
                    continue  # a missing image is a warning (see _check_images)
                raise AssetImportError(f"{path}: refers to a missing buffer file {uri!r}")
            _check_file(path, target, f"{kind[:-1]} file {uri[:80]!r}")


def _check_images(path: Path, document: dict, binary: bytes | None) -> None:
    """Warn about texture images that cannot be decoded.

    trimesh logs and drops an image it cannot read (missing file, corrupt data, a format
    PIL lacks), which would silently turn a textured asset plain. A bad image is not fatal
    (the parts keep their base colour) so that files with, say, a KTX2 texture and a PNG
    fallback still import.
    """
    # start-up time: only for a textured glTF
    from PIL import Image

    for index, image in enumerate(document.get("images", []) or []):
        label = f"image {index}"
        try:
            if isinstance(image, dict) and image.get("name"):
                label += f" ({image['name']!r})"
            data = _image_bytes(path, document, image, binary)
            with Image.open(io.BytesIO(data)) as decoded:
                decoded.verify()
        except Exception as err:  # PIL, base64 and malformed-JSON errors alike
            warnings.warn(f"{path}: {label} cannot be decoded ({type(err).__name__}: {err}); the "
                          "parts using it keep only their base colour", AssetImportWarning,
                          stacklevel=5)


def _image_bytes(path: Path, document: dict, image: dict, binary: bytes | None) -> bytes:
    """The encoded bytes of a glTF image (data URI, file, or buffer view)."""
    if "uri" in image:
        return _uri_bytes(path, image["uri"])
    view = document["bufferViews"][image["bufferView"]]
    buffer = document["buffers"][view["buffer"]]
    data = _uri_bytes(path, buffer["uri"]) if "uri" in buffer else binary
    if data is None:
        raise ValueError("the GLB has no binary chunk")
    start = view.get("byteOffset", 0)
    return data[start:start + view["byteLength"]]


def _uri_bytes(path: Path, uri: str) -> bytes:
    """The bytes a buffer or image URI points at (base64 data URI or a relative file)."""
    if uri.startswith("data:"):
        header, _, payload = uri.partition(",")
        return base64.b64decode(payload) if header.endswith(";base64") else unquote(payload).encode()
    if "://" in uri:
        raise ValueError(f"remote URI {uri!r} is not supported")
    return _read_bounded(path, path.parent / unquote(uri), f"file {uri[:80]!r}")
