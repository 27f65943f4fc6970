"""Reads tsuchi's binary .vtu particle frames (appended raw, UInt64 headers) into numpy arrays.

    frame = read_vtu("results/particles_000010.vtu")
    frame["points"]          # (n, 3) positions
    frame["stress"]          # (n, 6) XX, YY, ZZ, XY, YZ, XZ
"""
import struct
import xml.etree.ElementTree as ET

import numpy as np

_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}
_MARK = b'<AppendedData encoding="raw">'


def read_vtu(path):
    with open(path, "rb") as f:
        data = f.read()
    start = data.index(_MARK)
    blob_start = data.index(b"_", start) + 1
    end = data.rindex(b"</AppendedData>")
    root = ET.fromstring(data[:start].decode() + "</VTKFile>")
    blob = data[blob_start:end]
    out = {}
    for section in ("PointData", "Points", "Cells"):
        for arr in root.iter(section):
            for d in arr.iter("DataArray"):
                off = int(d.get("offset"))
                (nbytes,) = struct.unpack("<Q", blob[off:off + 8])
                if off + 8 + nbytes > len(blob):
                    raise ValueError(f"{path}: array {d.get('Name')} is truncated")
                a = np.frombuffer(blob[off + 8:off + 8 + nbytes], dtype=_TYPES[d.get("type")])
                ncomp = int(d.get("NumberOfComponents", "1"))
                name = d.get("Name") or ("points" if section == "Points" else "?")
                out[name] = a.reshape(-1, ncomp) if ncomp > 1 else a
    # The body names in index order (the field "body" holds the index): a String array, each name
    # as its character codes followed by 0.
    for d in root.iter("DataArray"):
        if d.get("Name") == "body_names":
            codes = [int(v) for v in d.text.split()]
            names, word = [], []
            for c in codes:
                if c == 0:
                    names.append(bytes(word).decode())
                    word = []
                else:
                    word.append(c)
            out["body_names"] = names
    return out


def read_pvd(path):
    """(time, file) pairs of a .pvd collection, file paths relative to the .pvd's folder."""
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
