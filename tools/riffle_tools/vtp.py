"""Read riffle's ParaView output (engine/output/vtk_output.cpp) into numpy arrays. numpy only.

riffle writes PolyData (.vtp), header_type="UInt32", little endian, no compression; each array one block, a
UInt32 byte count followed by the raw values, either raw in the AppendedData section after the XML at the offset its
DataArray names (format="appended", `[output] vtk_encoding = "appended"`, the default) or base64 inside its
DataArray (format="binary", `vtk_encoding = "inline"`). Types used: Float32 or Float64 for real values (`[output]
vtk_precision`, "single" by default), Int32, Int64, UInt64. Points are the particle centres; point data are the
component's output fields. A .pvd collection lists (time, file) pairs. A
run over MPI ranks writes each frame in pieces, one .vtp per rank, named by a .pvtp (PPolyData); read_vtp reads a
.pvtp as the whole frame, its pieces joined and ordered by id (a whole frame of water has its fluid particles first,
then walls and dummies: match particles by id or kind, not by index, across the two).

    from riffle_tools import vtp
    frames = vtp.read_pvd("out/run/solids.pvd")    # [(time_s, Path), ...] sorted by time
    frame = vtp.read_vtp(frames[0][1])              # {"points": (N, 3), "velocity": (N, 3), "radius": (N,), ...}
                                                    # (real arrays as float64, whatever the frame's precision)
    scene, named = vtp.run_scene("out/run")         # the scene file riffle.log names (None if not found)
"""
import base64
import pathlib
import re
import sys
import tomllib
import xml.etree.ElementTree as ElementTree

import numpy as np

from . import ROOT

_TYPES = {
    "Float64": "<f8", "Float32": "<f4",
    "Int8": "<i1", "Int16": "<i2", "Int32": "<i4", "Int64": "<i8",
    "UInt8": "<u1", "UInt16": "<u2", "UInt32": "<u4", "UInt64": "<u8",
}


class VtpError(RuntimeError):
    """A file that is not riffle's VTP/PVD format (the message says what is wrong and where)."""


def _parse(path):
    """The XML root of a .vtp/.pvtp/.pvd file and its raw appended bytes (None without an AppendedData section).
    The appended bytes are not XML: the text before them is parsed, closed by the file's end tag."""
    try:
        data = pathlib.Path(path).read_bytes()
    except OSError as error:
        raise VtpError(f"{path}: {error}") from error
    marker = data.find(b"<AppendedData")
    appended = None
    text = data
    if marker >= 0:
        tag_end = data.find(b">", marker)
        if tag_end < 0 or b'encoding="raw"' not in data[marker:tag_end]:
            raise VtpError(f"{path}: only raw AppendedData is supported")
        start = data.find(b"_", tag_end)
        if start < 0:
            raise VtpError(f"{path}: AppendedData without its '_' mark")
        appended = memoryview(data)[start + 1:]
        text = data[:marker] + b"</VTKFile>"
    try:
        return ElementTree.fromstring(text), appended
    except ElementTree.ParseError as error:
        raise VtpError(f"{path}: {error}") from error


def decode_array(element, path="?", appended=None):
    """One <DataArray> (format "binary", base64 inside it, or "appended", raw at its offset into `appended`) as a
    numpy array, shape (n,) or (n, components)."""
    name = element.get("Name", "?")
    kind = element.get("type")
    if kind not in _TYPES:
        raise VtpError(f"{path}: array {name}: type {kind!r} is not supported")
    form = element.get("format")
    if form == "appended":
        if appended is None:
            raise VtpError(f"{path}: array {name}: format 'appended' but the file has no AppendedData")
        offset = int(element.get("offset", "-1"))
        if offset < 0 or offset + 4 > len(appended):
            raise VtpError(f"{path}: array {name}: offset {offset} outside the appended data ({len(appended)} bytes)")
        count = int(np.frombuffer(appended[offset:offset + 4], dtype="<u4")[0])
        if offset + 4 + count > len(appended):
            raise VtpError(f"{path}: array {name}: {count} bytes at offset {offset} run past the appended data")
        raw = bytes(appended[offset:offset + 4 + count])
    elif form == "binary":
        raw = base64.b64decode("".join((element.text or "").split()))
    else:
        raise VtpError(f"{path}: array {name}: format {form!r}, expected 'binary' or 'appended'")
    if len(raw) < 4:
        raise VtpError(f"{path}: array {name}: no UInt32 size header")
    count = int(np.frombuffer(raw[:4], dtype="<u4")[0])
    if count != len(raw) - 4:
        raise VtpError(f"{path}: array {name}: header says {count} bytes, the block holds {len(raw) - 4}")
    values = np.frombuffer(raw[4:], dtype=_TYPES[kind]).copy()
    if kind == "Float32":  # the tools compute in double whatever precision the frame was written in
        values = values.astype(np.float64)
    components = int(element.get("NumberOfComponents", "1"))
    if components > 1:
        if values.size % components:
            raise VtpError(f"{path}: array {name}: {values.size} values are not a multiple of {components}")
        values = values.reshape(-1, components)
    return values


def read_vtp(path, fields=None):
    """The points and point data of one riffle .vtp file as {"points": (N, 3), field: array, ...}.

    fields: optional iterable of point-data names to decode (others are skipped, which is faster); None = all.
    Cell data (walls.vtp) is returned under "cell:<name>"."""
    path = pathlib.Path(path)
    fields = None if fields is None else tuple(fields)  # an iterator is read once
    root, appended = _parse(path)
    if root.get("type") == "PPolyData":
        return _read_pieces(path, root, fields)
    if root.get("type") != "PolyData":
        raise VtpError(f"{path}: VTKFile type {root.get('type')!r}, expected 'PolyData'")
    if root.get("byte_order", "LittleEndian") != "LittleEndian" or root.get("header_type", "UInt32") != "UInt32":
        raise VtpError(f"{path}: only little-endian files with UInt32 headers are supported")
    piece = root.find("PolyData/Piece")
    if piece is None:
        raise VtpError(f"{path}: no PolyData/Piece")
    wanted = None if fields is None else set(fields)
    out = {}
    points = piece.find("Points/DataArray")
    if points is None:
        raise VtpError(f"{path}: no Points")
    out["points"] = decode_array(points, path, appended).reshape(-1, 3)
    for element in piece.findall("PointData/DataArray"):
        name = element.get("Name")
        if wanted is None or name in wanted:
            out[name] = decode_array(element, path, appended)
    for element in piece.findall("CellData/DataArray"):
        name = element.get("Name")
        if wanted is None or name in wanted:
            out["cell:" + name] = decode_array(element, path, appended)
    count = int(piece.get("NumberOfPoints", len(out["points"])))
    if len(out["points"]) != count:
        raise VtpError(f"{path}: {len(out['points'])} points, the piece says {count}")
    if wanted:
        missing = wanted - set(out)
        if missing:
            raise VtpError(f"{path}: missing point data {sorted(missing)}")
    return out


def _read_pieces(path, root, fields):
    """A .pvtp frame: its pieces (Source paths relative to the .pvtp's folder) read and joined, sorted by id."""
    sources = [element.get("Source") for element in root.findall("PPolyData/Piece")]
    if not sources or None in sources:
        raise VtpError(f"{path}: a PPolyData without pieces, or a Piece without Source")
    wanted = None if fields is None else set(fields) | {"id"}
    pieces = [read_vtp(path.parent / source, wanted) for source in sources]
    names = set(pieces[0])
    for source, piece in zip(sources, pieces):
        if set(piece) != names:
            raise VtpError(f"{path}: piece {source} holds other arrays than {sources[0]}")
    out = {name: np.concatenate([piece[name] for piece in pieces]) for name in names}
    if "id" in out:
        order = np.argsort(out["id"], kind="stable")
        out = {name: values[order] for name, values in out.items()}
    if fields is not None and "id" not in set(fields):
        out.pop("id", None)
    return out


def read_pvd(path):
    """The (time_s, absolute path) pairs of a .pvd collection, sorted by time; a later entry of the same time wins
    (a resumed run may rewrite a frame)."""
    path = pathlib.Path(path)
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, OSError) as error:
        raise VtpError(f"{path}: {error}") from error
    frames = {}
    for element in root.iter("DataSet"):
        frames[float(element.get("timestep"))] = path.parent / element.get("file")
    return sorted(frames.items())


def run_scene(out_dir):
    """The scene a run used: (path, named), named the scene file of the last 'starting' or 'resuming' line of
    OUT_DIR/riffle.log (None if it names none). path is OUT_DIR/scene_as_run.toml where the run wrote it (the scene
    as the run read it, --set overrides applied), else the first existing of the name as written, relative to the
    run's grandparent (out/<run> lies in the repository) and relative to the repository holding this file; None when
    none exists. Relative paths inside the scene are relative to the named file's folder."""
    out_dir = pathlib.Path(out_dir)
    log = out_dir / "riffle.log"
    named = None
    if log.exists():
        for line in open(log, errors="replace"):
            found = re.search(r"(?:starting|resuming) '[^']*' from (.+?\.toml):", line)
            if found:
                named = found.group(1)
    as_run = out_dir / "scene_as_run.toml"
    if as_run.exists():
        return as_run, named
    if named is None:
        return None, None
    for candidate in (pathlib.Path(named), out_dir.resolve().parent.parent / named,
                      ROOT / named):
        if candidate.exists():
            return candidate, named
    return None, named


def fluid_scene(out_dir, tool):
    """The scene a run with the MPS water used, parsed (run_scene's file): `tool` exits naming the run when no scene
    is found or it has no [fluid] spacing."""
    scene, named = run_scene(out_dir)
    if scene is None:
        sys.exit(f"{tool}: no scene found for {out_dir} (riffle.log names {named})")
    with open(scene, "rb") as handle:
        data = tomllib.load(handle)
    if "spacing" not in data.get("fluid", {}):
        sys.exit(f"{tool}: {scene} has no [fluid] spacing: not a run with the MPS water")
    return data
