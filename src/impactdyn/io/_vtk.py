"""HydroGrid <-> VTK XML RectilinearGrid (``.vtr``), for ParaView.

meshio (5.3) reads and writes unstructured meshes only — no ``.vtr`` — so this
module writes the XML itself (VTK file formats, "Serial XML: RectilinearGrid").
Cell data arrays are named after the HydroGrid fields (units in the file's
comment, see :data:`impactdyn.debris._grid.UNITS`); ``velocity`` has 3
components.  FieldData holds ``TimeValue`` (µs, the name ParaView reads as the
time) and ``staggered`` (0/1; absent means cell-centred).  Arrays are written
inline as base64 ``binary`` (header and data encoded separately, as VTK does,
UInt64 header), which round-trips exactly; the reader also takes header and
data encoded as one stream (meshio), ``ascii`` arrays and UInt32 headers.  Compressed or appended data are not read.
"""

from __future__ import annotations

import base64
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn._runfolder import atomic_output
from impactdyn.hydrogrid import CELL_FIELDS, UNITS, HydroGrid
from impactdyn.io._registry import in_file, register_format

_HEADER_TYPES = {"UInt32": np.dtype("<u4"), "UInt64": np.dtype("<u8")}
_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1", "Int8": "i1"}


def write_vtr(path: str | Path, grid: HydroGrid) -> None:
    nx, ny, nz = grid.shape
    extent = f"0 {nx} 0 {ny} 0 {nz}"
    root = ET.Element("VTKFile", type="RectilinearGrid", version="1.0", byte_order="LittleEndian",
                      header_type="UInt64")
    root.append(ET.Comment(" impactdyn HydroGrid; units: "
                           + ", ".join(f"{k} {v}" for k, v in UNITS.items()) + " "))
    rg = ET.SubElement(root, "RectilinearGrid", WholeExtent=extent)
    fd = ET.SubElement(rg, "FieldData")
    _data_array(fd, "TimeValue", np.array([grid.time]))
    _data_array(fd, "staggered", np.array([grid.staggered], dtype=np.uint8), "UInt8")
    piece = ET.SubElement(rg, "Piece", Extent=extent)
    cd = ET.SubElement(piece, "CellData", Scalars="density", Vectors="velocity")
    for name in CELL_FIELDS:
        a = getattr(grid, name)
        # VTK orders cells x fastest: (nx, ny, nz[, 3]) -> (nz, ny, nx[, 3]) in C order
        _data_array(cd, name, a.transpose(2, 1, 0, *range(3, a.ndim)), components=3 if a.ndim == 4 else 1)
    coords = ET.SubElement(piece, "Coordinates")
    for name in ("x", "y", "z"):
        _data_array(coords, name, getattr(grid, name))
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)


def read_vtr(path: str | Path) -> HydroGrid:
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        raise InputError(f"{path}: not an XML file ({err})") from None
    if root.tag != "VTKFile" or root.get("type") != "RectilinearGrid":
        raise InputError(f"{path}: not a VTK RectilinearGrid file")
    if root.get("compressor") or root.find(".//AppendedData") is not None:
        raise InputError(f"{path}: compressed or appended VTK data is not supported; "
                         "save with ascii or uncompressed inline binary data")
    big = root.get("byte_order", "LittleEndian") == "BigEndian"
    header = _HEADER_TYPES.get(root.get("header_type", "UInt32"))
    if header is None:
        raise InputError(f"{path}: unknown header_type {root.get('header_type')!r}")
    pieces = root.findall("./RectilinearGrid/Piece")
    if len(pieces) != 1:
        raise InputError(f"{path}: expected one Piece, found {len(pieces)}")
    piece = pieces[0]
    x0, x1, y0, y1, z0, z1 = (int(v) for v in piece.get("Extent").split())
    shape = (x1 - x0, y1 - y0, z1 - z0)

    def array(parent: ET.Element | None, name: str, required: bool = True) -> np.ndarray | None:
        el = None if parent is None else parent.find(f"./DataArray[@Name='{name}']")
        if el is None:
            if required:
                raise InputError(f"{path}: data array {name!r} missing")
            return None
        return _decode(path, el, header, big)

    coords = piece.find("Coordinates")
    cd = piece.find("CellData")
    fields = {}
    for name in CELL_FIELDS:
        a = array(cd, name)
        want = shape[::-1] + ((3,) if name == "velocity" else ())
        if a.size != int(np.prod(want)):
            raise InputError(f"{path}: array {name!r} has {a.size} values, expected {int(np.prod(want))}")
        a = a.reshape(want)
        fields[name] = a.transpose(2, 1, 0, *range(3, a.ndim))
    fd = root.find("./RectilinearGrid/FieldData")
    time = array(fd, "TimeValue", required=False)
    staggered = array(fd, "staggered", required=False)
    with in_file(path):
        return HydroGrid(x=array(coords, "x"), y=array(coords, "y"), z=array(coords, "z"), **fields,
                         staggered=bool(staggered[0]) if staggered is not None else False,
                         time=float(time[0]) if time is not None else 0.0)


def _data_array(parent: ET.Element, name: str, a: np.ndarray, vtk_type: str = "Float64",
                components: int = 1) -> None:
    data = np.ascontiguousarray(a, dtype=_TYPES[vtk_type]).tobytes()
    el = ET.SubElement(parent, "DataArray", type=vtk_type, Name=name, format="binary")
    if components > 1:
        el.set("NumberOfComponents", str(components))
    if parent.tag == "FieldData":
        el.set("NumberOfTuples", str(a.size))
    size = np.array([len(data)], dtype=_HEADER_TYPES["UInt64"]).tobytes()
    el.text = (base64.b64encode(size) + base64.b64encode(data)).decode("ascii")


def _decode(path: Path, el: ET.Element, header: np.dtype, big: bool) -> np.ndarray:
    vtk_type, fmt, name = el.get("type"), el.get("format"), el.get("Name")
    if vtk_type not in _TYPES:
        raise InputError(f"{path}: array {name!r}: unsupported type {vtk_type!r}")
    order = ">" if big else "<"
    dtype = np.dtype(_TYPES[vtk_type]).newbyteorder(order)
    text = (el.text or "").strip()
    try:
        if fmt == "ascii":
            return np.array(text.split(), dtype=np.float64)
        if fmt == "binary":
            head = text[:4 * -(-header.itemsize // 3)]  # base64 characters of a separately encoded header
            if head.endswith("="):  # header and data encoded separately (VTK, this writer)
                raw = base64.b64decode(head) + base64.b64decode(text[len(head):])
            else:  # one stream (meshio)
                raw = base64.b64decode(text)
            nbytes = int(np.frombuffer(raw[:header.itemsize], dtype=header.newbyteorder(order))[0])
            data = raw[header.itemsize:header.itemsize + nbytes]
            return np.frombuffer(data, dtype=dtype).astype(np.float64)
    except (ValueError, TypeError) as err:
        raise InputError(f"{path}: array {name!r}: cannot decode ({err})") from None
    raise InputError(f"{path}: array {name!r}: unsupported format {fmt!r}")


register_format("vtk-rectilinear", (".vtr",), reader=read_vtr, writer=write_vtr)


def write_mesh(path: str | Path, mesh, **options) -> None:
    """Write a :class:`meshio.Mesh` atomically, format from the suffix of ``path`` (``.vtu``, ``.vtk`` …);
    ``options`` go to meshio's writer of the format (``compression="lzma"`` for a ``.vtu``)."""
    import meshio

    path = Path(path)
    with atomic_output(path) as tmp:
        meshio.write(tmp, mesh, file_format=meshio.extension_to_filetypes[path.suffix.lower()][0], **options)
