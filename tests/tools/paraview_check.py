#!/usr/bin/env pvpython
"""What ParaView makes of an aquaform run folder (issue 29).

    pvpython tests/tools/paraview_check.py RUNDIR [--png PATH] [--size WxH]
    xvfb-run -a pvbatch tests/tools/paraview_check.py RUNDIR --png PATH   # the render needs a display

Opens RUNDIR/particles.pvd as one time series (ParaView's PVD reader, as File > Open does) and,
where they exist, RUNDIR/surface.pvd and RUNDIR/whitewater.pvd; prints one JSON
object on stdout:

    {"particles": {"file": ..., "time_steps": [t0, t1, ...],
                   "steps": [{"time": t, "points": n, "cells": n, "point_arrays": [names],
                              "ranges": {one-component array: [min, max]}, "bounds": [...]}, ...]},
     "surface": {... the same ...} or null,
     "whitewater": {... the same ...} or null,
     "picture": {"path": ..., "width": w, "height": h, "colour": array} or null}

--png renders the particles at the last time step as points coloured by their speed (the
velocity array's magnitude) with the surface, where there is one, drawn over them, and saves the
picture. Anything that cannot be read ends the script with exit status 1 and one line on stderr.
"""
import json
import os
import sys


def fail(message):
    sys.stderr.write("paraview_check: " + message + "\n")
    sys.exit(1)


def parse_args(argv):
    if not argv or argv[0].startswith("-"):
        fail("usage: paraview_check.py RUNDIR [--png PATH] [--size WxH]")
    args = {"run": argv[0], "png": None, "size": (320, 180)}
    i = 1
    while i < len(argv):
        if argv[i] == "--png" and i + 1 < len(argv):
            args["png"] = argv[i + 1]
        elif argv[i] == "--size" and i + 1 < len(argv):
            try:
                w, h = argv[i + 1].lower().split("x")
                args["size"] = (int(w), int(h))
            except ValueError:
                fail("--size wants WxH, got " + argv[i + 1])
        else:
            fail("unknown argument " + argv[i])
        i += 2
    return args


args = parse_args(sys.argv[1:])

# paraview.simple is imported after the arguments are checked (it takes a second to load).
from paraview import servermanager  # noqa: E402
from paraview.simple import (  # noqa: E402
    ColorBy, CreateView, Delete, GetActiveViewOrCreate, OpenDataFile, ResetCamera, SaveScreenshot, Show,
    UpdatePipeline)


def read_series(pvd_path):
    """Opens a .pvd collection and describes it per time step (None when the file is absent)."""
    if not os.path.isfile(pvd_path):
        return None, None
    reader = OpenDataFile(pvd_path)  # a PVDReader: the collection's datasets as one time series
    if reader is None:
        fail("ParaView has no reader for " + pvd_path)
    # TimestepValues is the reader's list of the collection's "timestep" attributes (sorted); a
    # single step comes back as a plain float.
    # (a property object: list() gives its values).
    values = reader.TimestepValues
    try:
        times = [float(t) for t in values]
    except TypeError:
        times = [float(values)]
    if not times:
        fail(pvd_path + " holds no time steps")
    steps = []
    for t in times:
        UpdatePipeline(time=t, proxy=reader)
        # Fetch brings the reader's output for that time to this (client) process.
        data = servermanager.Fetch(reader)
        if data is None:
            fail("ParaView read nothing from " + pvd_path + " at time " + repr(t))
        # A PVD file's output is a vtkMultiBlockDataSet when the collection has parts or groups;
        # aquaform writes one part, but descend into blocks to be safe.
        if data.IsA("vtkMultiBlockDataSet"):
            if data.GetNumberOfBlocks() < 1 or data.GetBlock(0) is None:
                fail(pvd_path + ": empty block at time " + repr(t))
            data = data.GetBlock(0)
        point_data = data.GetPointData()
        names = [point_data.GetArrayName(k) for k in range(point_data.GetNumberOfArrays())]
        # The range of each one-component array (the whitewater's kind and life).
        ranges = {point_data.GetArrayName(k): list(point_data.GetArray(k).GetRange())
                  for k in range(point_data.GetNumberOfArrays())
                  if point_data.GetArray(k).GetNumberOfComponents() == 1 and data.GetNumberOfPoints() > 0}
        steps.append({"time": t, "points": int(data.GetNumberOfPoints()),
                      "cells": int(data.GetNumberOfCells()), "point_arrays": names,
                      "ranges": ranges, "bounds": list(data.GetBounds())})
    return reader, {"file": pvd_path, "time_steps": times, "steps": steps}


run = args["run"]
if not os.path.isdir(run):
    fail("no run folder " + run)
particles_path = os.path.join(run, "particles.pvd")
if not os.path.isfile(particles_path):
    fail("no particles.pvd in " + run + " (run with --vtk-every K)")

try:
    particles_reader, particles = read_series(particles_path)
    surface_reader, surface = read_series(os.path.join(run, "surface.pvd"))
    _, whitewater = read_series(os.path.join(run, "whitewater.pvd"))
except SystemExit:
    raise
except Exception as error:  # a reader's exception (a malformed file) is one line, not a trace
    fail("cannot read " + run + ": " + (str(error).splitlines()[0] if str(error) else repr(error)))

picture = None
if args["png"]:
    width, height = args["size"]
    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    # 5.11 takes the background from the colour palette unless told to use the view's own.
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 0
    last = particles["time_steps"][-1]
    view.ViewTime = last  # the view's time picks the step every reader shows
    shown = Show(particles_reader, view)
    shown.SetRepresentationType("Points")
    shown.PointSize = 3.0
    colour = "velocity" if "velocity" in particles["steps"][-1]["point_arrays"] else None
    if colour:
        # Colour by the velocity's magnitude with a lookup table fitted to the data's range.
        ColorBy(shown, ("POINTS", colour, "Magnitude"))
        shown.RescaleTransferFunctionToDataRange(True, False)
    if surface_reader is not None:
        surface_shown = Show(surface_reader, view)
        surface_shown.DiffuseColor = [0.2, 0.45, 0.9]
        surface_shown.Opacity = 0.6
    # Look at the fluid from the front and above (the scene's y is up unless the run said otherwise).
    view.CameraPosition = [0.8, 1.5, 3.0]
    view.CameraFocalPoint = [0.8, 0.3, 0.4]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    ResetCamera(view)
    SaveScreenshot(args["png"], view, ImageResolution=[width, height])
    if not os.path.isfile(args["png"]):
        fail("ParaView wrote no picture at " + args["png"])
    picture = {"path": args["png"], "width": width, "height": height, "colour": colour,
               "bytes": os.path.getsize(args["png"])}
    Delete(view)

print(json.dumps({"particles": particles, "surface": surface, "whitewater": whitewater, "picture": picture}, indent=1))
