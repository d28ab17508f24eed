#!/usr/bin/python3
"""Reads aquaform's VTK exports with VTK itself and prints what it found as JSON, for
tests/test_exports.cpp to check. Run with Debian's /usr/bin/python3 and whichever VTK it has:
ParaView's (python3-paraview, which scripts/setup.sh --tools installs) or python3-vtk9.

  read_vtk.py FILE.vtu   -> {"points", "cells", "cell_types", "positions", "arrays": {name: {type, components, values}}}
  read_vtk.py FILE.vtp   -> the same, and "polys": every poly's point ids, "normals": the name of
                            the point data VTK takes as normals ("" when none)
  read_vtk.py FILE.pvd   -> {"datasets": [{"timestep", "file", "grid": <as above>}]}

A .vtu is read with vtkXMLUnstructuredGridReader, a .vtp with vtkXMLPolyDataReader. A .pvd is
parsed as XML (VTK 9.1's Python has no collection reader) and every file it lists is read by its
extension. Exits 1 when VTK cannot read a file.
"""
import json
import os
import sys
import xml.etree.ElementTree as ElementTree

# Both packages ship VTK's modules as vtkmodules (the umbrella "vtk" module is python3-vtk9's only).
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdList, vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader


def read_dataset(path):
    reader = vtkXMLPolyDataReader() if path.endswith(".vtp") else vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0 or reader.GetOutput() is None:
        raise RuntimeError("VTK could not read " + path)
    grid = reader.GetOutput()
    points = grid.GetPoints()
    result = {
        "points": grid.GetNumberOfPoints(),
        "cells": grid.GetNumberOfCells(),
        "cell_types": sorted({grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}),
        "positions": vtk_to_numpy(points.GetData()).astype(float).ravel().tolist() if points else [],
        "position_type": points.GetData().GetDataTypeAsString() if points else "",
        "arrays": {},
    }
    point_data = grid.GetPointData()
    for i in range(point_data.GetNumberOfArrays()):
        array = point_data.GetArray(i)
        result["arrays"][array.GetName()] = {
            "type": array.GetDataTypeAsString(),
            "components": array.GetNumberOfComponents(),
            "values": vtk_to_numpy(array).ravel().tolist(),
        }
    if path.endswith(".vtp"):
        ids = vtkIdList()
        result["polys"] = []
        for i in range(grid.GetNumberOfCells()):
            grid.GetCellPoints(i, ids)
            result["polys"].append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
        normals = point_data.GetNormals()
        result["normals"] = normals.GetName() if normals else ""
    return result


def read_pvd(path):
    root = ElementTree.parse(path).getroot()
    if root.get("type") != "Collection":
        raise RuntimeError(path + " is not a VTK collection")
    datasets = []
    for dataset in root.iter("DataSet"):
        file = dataset.get("file")
        datasets.append({"timestep": float(dataset.get("timestep")), "file": file,
                         "grid": read_dataset(os.path.join(os.path.dirname(path), file))})
    return {"datasets": datasets}


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: read_vtk.py FILE.vtu|FILE.vtp|FILE.pvd")
    path = sys.argv[1]
    # VTK reports read errors on its output window, not as exceptions: make them fatal.
    errors = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(errors)
    try:
        result = read_pvd(path) if path.endswith(".pvd") else read_dataset(path)
    except (RuntimeError, ElementTree.ParseError, OSError) as e:
        sys.exit(str(e))
    if "ERROR" in errors.GetOutput():
        sys.exit("VTK reported: " + errors.GetOutput())
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
