"""What Blender makes of an aquaform run folder's surface mesh and density volumes (issue 29).

    blender -b --factory-startup --python tests/tools/blender_check.py -- RUNDIR [options]

options:
    --mesh FILE          the surface mesh to import (.obj or .ply; default: the first surface_*.obj
                         or surface_*.ply in RUNDIR, if any)
    --obj-axes blender|file
                         blender (the default): the OBJ importer's own axes (the file's y is up and
                         becomes Blender's z, as File > Import does); file: the file's coordinates
                         kept as they are (forward y, up z), the frame the density volumes sit in
    --volume FILE        the density volume for the Volume to Mesh surface (default: the
                         density_*.vdb of the mesh's frame (exports.csv, else the number in the
                         names), else the first)
    --iso V              the Volume to Mesh threshold (default: the volume's aquaform_iso metadata)
    --png PATH           render the Volume to Mesh surface with Cycles on the CPU to PATH
    --size WxH           the picture's size (default 64x36)
    --samples N          Cycles samples (default 4)

Prints one JSON object on stdout between the lines AQUAFORM_JSON_BEGIN and AQUAFORM_JSON_END
(Blender prints its own lines around it):

    "mesh":   {"file", "vertices", "bbox": [[xmin, ymin, zmin], [xmax, ymax, zmax]]}  (Blender's world)
    "volume": {"files", "is_sequence", "frame_start", "frame_duration", "frame_offset",
               "sequence_mode", "frames": [{"frame", "file", "loaded", "grids", "bbox"}, ...]}
               every Blender frame from frame_start - 1 to frame_start + frame_duration, with the
               file Blender resolves there (null where it resolves none)
    "volume_to_mesh": {"volume", "iso", "voxel_size", "vertices", "bbox"}
    "picture": {"path", "width", "height", "samples"}

Exits 1 with one line on stderr when a file cannot be imported.
"""
import glob
import json
import os
import re
import struct
import sys

import bpy
from mathutils import Matrix, Vector

# The .vdb metadata reader (Blender's Python has no pyopenvdb) is the scene script's.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from blender_scene import vdb_float_metadata  # noqa: E402


def fail(message):
    sys.stderr.write("blender_check: " + message + "\n")
    sys.stdout.flush()
    # sys.exit inside Blender's --python only ends the script; os._exit ends Blender with the status.
    os._exit(1)


def parse_args():
    # Blender passes its own arguments too; ours follow the "--".
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv or argv[0].startswith("-"):
        fail("usage: blender -b --factory-startup --python blender_check.py -- RUNDIR [options]")
    args = {"run": argv[0], "mesh": None, "obj_axes": "blender", "volume": None, "iso": None,
            "png": None, "size": (64, 36), "samples": 4}
    i = 1
    while i < len(argv):
        key = argv[i]
        if i + 1 >= len(argv):
            fail(key + " wants a value")
        value = argv[i + 1]
        if key == "--mesh":
            args["mesh"] = value
        elif key == "--obj-axes" and value in ("blender", "file"):
            args["obj_axes"] = value
        elif key == "--volume":
            args["volume"] = value
        elif key == "--iso":
            args["iso"] = float(value)
        elif key == "--png":
            args["png"] = value
        elif key == "--size":
            w, h = value.lower().split("x")
            args["size"] = (int(w), int(h))
        elif key == "--samples":
            args["samples"] = int(value)
        else:
            fail("unknown argument " + key + " " + value)
        i += 2
    return args


def world_bbox(obj):
    """The axis-aligned box of an object's evaluated geometry in Blender's world (None if empty).
    bound_box is the box in the object's own space: its 8 corners go through matrix_world."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    corners = [evaluated.matrix_world @ Vector(c) for c in evaluated.bound_box]
    lo = [min(c[k] for c in corners) for k in range(3)]
    hi = [max(c[k] for c in corners) for k in range(3)]
    if lo == hi:
        return None  # Blender reports an all-zero box for an empty object
    return [lo, hi]


def import_mesh(path, obj_axes):
    before = set(bpy.data.objects)
    if path.lower().endswith(".obj"):
        if obj_axes == "file":
            # forward y, up z: Blender's own axes, so the importer turns nothing.
            axes = {"forward_axis": "Y", "up_axis": "Z"}
        else:
            axes = {}  # the importer's defaults: forward -z, up y (the OBJ convention)
        if hasattr(bpy.ops.wm, "obj_import"):  # the C++ importer (3.2 and later)
            result = bpy.ops.wm.obj_import(filepath=path, **axes)
        else:  # the legacy Python add-on
            legacy = {"axis_forward": axes.get("forward_axis", "-Z"), "axis_up": axes.get("up_axis", "Y")}
            result = bpy.ops.import_scene.obj(filepath=path, **legacy)
    elif path.lower().endswith(".ply"):
        # 3.4's PLY importer (an add-on) keeps the file's coordinates: no axis conversion.
        result = bpy.ops.import_mesh.ply(filepath=path)
    else:
        fail("not a mesh Blender imports here: " + path)
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if "FINISHED" not in result or not new:
        fail("Blender could not import " + path)
    return new[0]


def import_volume(files):
    """Imports files as one volume object, as File > Import > OpenVDB does with several files
    selected: Blender then detects the number in the names and makes it a sequence."""
    before = set(bpy.data.objects)
    directory = os.path.dirname(os.path.abspath(files[0]))
    result = bpy.ops.object.volume_import(filepath=os.path.abspath(files[0]), directory=directory,
                                          files=[{"name": os.path.basename(f)} for f in files])
    new = [o for o in bpy.data.objects if o not in before and o.type == "VOLUME"]
    if "FINISHED" not in result or not new:
        fail("Blender could not import " + files[0])
    return new[0]


def frame_mapping(obj):
    """Which file the volume shows at each Blender frame around its sequence."""
    volume = obj.data
    scene = bpy.context.scene
    first = volume.frame_start - 1
    last = volume.frame_start + volume.frame_duration if volume.is_sequence else volume.frame_start + 1
    frames = []
    for frame in range(first, last + 1):
        scene.frame_set(frame)
        # grids.load() reads the file the volume resolves at the scene's current frame;
        # grids.frame is the sequence frame it resolved (a huge number when none) and
        # grids.frame_filepath that frame's file name, whether or not the file exists.
        loaded = volume.grids.load()
        path = volume.grids.frame_filepath if volume.grids.frame_filepath else None
        frames.append({"frame": frame, "file": os.path.basename(path) if path else None,
                       "loaded": bool(loaded and volume.grids.is_loaded and len(volume.grids) > 0),
                       "grids": [g.name for g in volume.grids],
                       "error": volume.grids.error_message or None,
                       "bbox": world_bbox(obj) if len(volume.grids) > 0 else None})
    return frames


def number_of(path):
    match = re.search(r"_(\d+)\.\w+$", os.path.basename(path))
    return int(match.group(1)) if match else None


def frames_of(run):
    """exports.csv's file -> simulation frame, where the run wrote that table."""
    path = os.path.join(run, "exports.csv")
    if not os.path.isfile(path):
        return {}
    import csv
    with open(path, newline="") as f:
        return {row["file"]: int(row["frame"]) for row in csv.DictReader(f)}


def frame_of(path, frames):
    """A file's simulation frame: exports.csv's, else the number in its name (runs that numbered by frame)."""
    return frames.get(os.path.basename(path), number_of(path))


def point_camera(camera, target_lo, target_hi):
    """Places the camera in front of and above the box, looking at its centre, far enough to see it."""
    centre = (Vector(target_lo) + Vector(target_hi)) / 2
    size = (Vector(target_hi) - Vector(target_lo)).length
    camera.location = centre + Vector((0.6, -1.6, 0.9)).normalized() * size * 1.6
    camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
    camera.data.clip_end = size * 10


def main():
    args = parse_args()
    run = args["run"]
    if not os.path.isdir(run):
        fail("no run folder " + run)

    # The factory scene's cube is not ours.
    for obj in list(bpy.data.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)

    report = {"mesh": None, "volume": None, "volume_to_mesh": None, "picture": None}

    mesh_path = args["mesh"]
    if mesh_path is None:
        candidates = sorted(glob.glob(os.path.join(run, "surface_*.obj")) + glob.glob(os.path.join(run, "surface_*.ply")))
        mesh_path = candidates[0] if candidates else None
    mesh_obj = None
    if mesh_path:
        mesh_obj = import_mesh(mesh_path, args["obj_axes"])
        report["mesh"] = {"file": os.path.basename(mesh_path), "vertices": len(mesh_obj.data.vertices),
                          "bbox": world_bbox(mesh_obj)}

    volume_files = sorted(glob.glob(os.path.join(run, "density_*.vdb")))
    if volume_files:
        sequence = import_volume(volume_files)
        v = sequence.data
        report["volume"] = {"files": [os.path.basename(f) for f in volume_files], "is_sequence": bool(v.is_sequence),
                            "frame_start": v.frame_start, "frame_duration": v.frame_duration,
                            "frame_offset": v.frame_offset, "sequence_mode": v.sequence_mode,
                            "frames": frame_mapping(sequence)}
        sequence.hide_render = True  # the picture shows the Volume to Mesh surface

        # Volume to Mesh from one file on its own (a second, single-file volume object, so that this
        # does not depend on how the sequence plays).
        single = args["volume"]
        if single is None:
            frames = frames_of(run)
            same = [f for f in volume_files if mesh_path and frame_of(f, frames) == frame_of(mesh_path, frames)]
            single = same[0] if same else volume_files[0]
        iso = args["iso"] if args["iso"] is not None else vdb_float_metadata(single, "aquaform_iso")
        if iso is None:
            fail(single + " has no aquaform_iso metadata; pass --iso")
        volume_obj = import_volume([single])
        volume_obj.data.is_sequence = False
        volume_obj.hide_render = True
        volume_obj.data.grids.load()
        if len(volume_obj.data.grids) == 0:
            fail("Blender read no grid from " + single + ": " + volume_obj.data.grids.error_message)
        grid = volume_obj.data.grids[0]
        # matrix_object maps the grid's index space to the object's space: its columns' lengths are
        # the voxel's edges.
        voxel = [Vector(grid.matrix_object.col[k][:3]).length for k in range(3)]
        # Volume to Mesh is a modifier on a mesh object (its own geometry is replaced): an empty mesh.
        surface = bpy.data.objects.new("volume_to_mesh", bpy.data.meshes.new("volume_to_mesh"))
        bpy.context.scene.collection.objects.link(surface)
        modifier = surface.modifiers.new("VolumeToMesh", "VOLUME_TO_MESH")
        modifier.object = volume_obj
        modifier.grid_name = grid.name
        modifier.threshold = iso
        modifier.resolution_mode = "GRID"  # the grid's own voxels
        modifier.adaptivity = 0.0
        evaluated = surface.evaluated_get(bpy.context.evaluated_depsgraph_get())
        report["volume_to_mesh"] = {"volume": os.path.basename(single), "iso": iso, "voxel_size": voxel,
                                    "vertices": len(evaluated.data.vertices), "bbox": world_bbox(surface)}

        if args["png"]:
            scene = bpy.context.scene
            scene.render.engine = "CYCLES"
            scene.cycles.device = "CPU"
            scene.cycles.samples = args["samples"]
            scene.cycles.use_denoising = False
            scene.render.resolution_x, scene.render.resolution_y = args["size"]
            scene.render.resolution_percentage = 100
            scene.render.image_settings.file_format = "PNG"
            scene.render.filepath = os.path.abspath(args["png"])
            material = bpy.data.materials.new("water")
            material.diffuse_color = (0.2, 0.45, 0.9, 1.0)
            material.use_nodes = True
            # The node tree built here rather than found (what use_nodes puts there varies).
            nodes = material.node_tree.nodes
            nodes.clear()
            principled = nodes.new("ShaderNodeBsdfPrincipled")
            principled.inputs["Base Color"].default_value = (0.2, 0.45, 0.9, 1.0)
            output = nodes.new("ShaderNodeOutputMaterial")
            material.node_tree.links.new(principled.outputs["BSDF"], output.inputs["Surface"])
            surface.data.materials.append(material)
            if mesh_obj is not None:
                mesh_obj.hide_render = True
            box = report["volume_to_mesh"]["bbox"] or [[0, 0, 0], [1, 1, 1]]
            point_camera(scene.camera, box[0], box[1])
            light = bpy.data.objects.get("Light")
            if light is not None:  # the factory point light, turned into a sun so the distance does not matter
                light.data.type = "SUN"
                light.data.energy = 3.0
            bpy.ops.render.render(write_still=True)
            if not os.path.isfile(args["png"]):
                fail("Cycles wrote no picture at " + args["png"])
            report["picture"] = {"path": args["png"], "width": args["size"][0], "height": args["size"][1],
                                 "samples": args["samples"]}

    print("AQUAFORM_JSON_BEGIN")
    print(json.dumps(report, indent=1))
    print("AQUAFORM_JSON_END")
    sys.stdout.flush()


# An exception in a --python script leaves Blender's exit status 0: turn it into status 1.
try:
    main()
except Exception as error:  # noqa: BLE001
    import traceback
    where = traceback.extract_tb(error.__traceback__)[-1]
    fail("%s: %s (line %d)" % (type(error).__name__, str(error).splitlines()[0] if str(error) else "", where.lineno))
