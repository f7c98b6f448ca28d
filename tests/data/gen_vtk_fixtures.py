#!/usr/bin/python3
"""Writes the .vtu fixtures with VTK's own vtkXMLUnstructuredGridWriter (Debian's python3-vtk9;
these were made with VTK 9.1.0): run `/usr/bin/python3 gen_vtk_fixtures.py` in this folder.

quad_*.vtu: 2x2 unit quads (z = 0), point data `u` (Float64, 2 components), cell data `region`.
mixed3d_*.vtu: a unit cube (hexahedron), a pyramid on its top, a wedge on its x = 1 side and a
tetrahedron on its x = 0 side, point data `displacement` (3 components), cell data `region`.

Modes: `appended` is what ParaView writes by default (appended data, raw encoding, zlib
compression, UInt32 header); `binary` is inline base64 with zlib and a UInt64 header; `raw` is
appended raw data without compression; `base64` is the VTK writer's own default (appended data
in base64, zlib). The Points arrays carry an
<InformationKey> (their L2 norm range is computed before writing, as ParaView does).
"""
import vtk


def grid(points, cells, point_name, point_comps):
    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(*p)
    g.SetPoints(pts)
    for ty, conn in cells:
        ids = vtk.vtkIdList()
        for v in conn:
            ids.InsertNextId(v)
        g.InsertNextCell(ty, ids)
    u = vtk.vtkDoubleArray()
    u.SetName(point_name)
    u.SetNumberOfComponents(point_comps)
    for i, p in enumerate(points):
        u.InsertNextTuple([0.5 * i + 0.25 * k for k in range(point_comps)])
    g.GetPointData().AddArray(u)
    r = vtk.vtkIntArray()
    r.SetName("region")
    for c in range(len(cells)):
        r.InsertNextValue(c + 1)
    g.GetCellData().AddArray(r)
    pts.GetData().GetRange(-1)  # stores L2_NORM_RANGE: written as an <InformationKey>
    return g


def write(g, name, mode):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(name)
    w.SetInputData(g)
    w.SetEncodeAppendedData(mode == "base64")
    if mode == "binary":
        w.SetDataModeToBinary()
        w.SetHeaderTypeToUInt64()
    elif mode == "raw":
        w.SetCompressorTypeToNone()
    assert w.Write() == 1


quad = grid(
    [(x, y, 0.0) for y in range(3) for x in range(3)],
    [(vtk.VTK_QUAD, [3 * j + i, 3 * j + i + 1, 3 * j + i + 4, 3 * j + i + 3]) for j in range(2) for i in range(2)],
    "u",
    2,
)
mixed = grid(
    [
        (0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),  # 0-3: the cube's bottom
        (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),  # 4-7: its top
        (0.5, 0.5, 1.5),  # 8: the pyramid's apex
        (2, 0, 0), (2, 1, 0),  # 9, 10: the wedge's outer edge
        (-1, 0, 0),  # 11: the tetrahedron's apex
    ],
    [
        (vtk.VTK_HEXAHEDRON, [0, 1, 2, 3, 4, 5, 6, 7]),
        (vtk.VTK_PYRAMID, [4, 5, 6, 7, 8]),
        (vtk.VTK_WEDGE, [1, 9, 5, 2, 10, 6]),
        (vtk.VTK_TETRA, [0, 4, 3, 11]),
    ],
    "displacement",
    3,
)
for mode in ["appended", "binary"]:
    write(quad, f"quad_{mode}.vtu", mode)
for mode in ["appended", "binary", "raw", "base64"]:
    write(mixed, f"mixed3d_{mode}.vtu", mode)

