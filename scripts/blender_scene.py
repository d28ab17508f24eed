"""A Blender scene from an aquaform run folder: the water surface over time in a glass tank.

    blender -P scripts/blender_scene.py -- RUNDIR [options]             # opens the scene to look at
    blender -b -P scripts/blender_scene.py -- RUNDIR --render PREFIX [--size WxH] [--frames A:B]
                                                                       # renders PREFIX0000.png ...
options:
    --domain x0,y0,z0,x1,y1,z1  the tank (the scene's "domain", in the simulation's y-up axes); by
                                default taken from a scene .json in RUNDIR when there is one, else
                                the box around every exported surface
    --up y|z                    the run's --up (default: a run.json in RUNDIR where it says, else y,
                                aquaform's default; the exports themselves do not record it); a
                                y-up run's files are turned (x, y, z) -> (x, -z, y) so its up is
                                Blender's z, a z-up run's files are already turned
    --render PREFIX             render the frames with Cycles (CPU) to PREFIX####.png and quit
    --size WxH                  the pictures' size (default 640x360)
    --frames A:B[:S]            the Blender frames to render, every S-th (default: the whole run)
    --samples N                 Cycles samples (default 16)

The surface: the run's surface_NNNN.obj / .ply meshes, one object per exported frame, each shown
only from its frame until the next one (keyframed hide_render / hide_viewport). Where the run has
no meshes, its density_NNNN.vdb volumes as one volume sequence with a Volume to Mesh surface at
the volume's iso value (the aquaform_iso metadata). Blender frame F is simulation frame F
(through exports.csv's frame column where the run wrote one, else the number in the file name);
the frame rate is the run's (stats.csv's time step between frames).
"""
import csv
import glob
import math
import os
import re
import struct
import sys

import bpy
from mathutils import Matrix, Vector


def fail(message):
    sys.stderr.write("blender_scene: " + message + "\n")
    sys.stdout.flush()
    os._exit(1)  # sys.exit inside Blender's -P only ends the script


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv or argv[0].startswith("-"):
        fail("usage: blender [-b] -P blender_scene.py -- RUNDIR [--render PREFIX] [--size WxH] [--frames A:B]")
    args = {"run": argv[0], "domain": None, "up": None, "render": None, "size": (640, 360), "frames": None,
            "samples": 16}
    i = 1
    while i < len(argv):
        key = argv[i]
        if i + 1 >= len(argv):
            fail(key + " wants a value")
        value = argv[i + 1]
        try:
            if key == "--domain":
                numbers = [float(x) for x in value.split(",")]
                if len(numbers) != 6:
                    raise ValueError
                args["domain"] = (numbers[:3], numbers[3:])
            elif key == "--up" and value in ("y", "z"):
                args["up"] = value
            elif key == "--render":
                args["render"] = value
            elif key == "--size":
                w, h = value.lower().split("x")
                args["size"] = (int(w), int(h))
            elif key == "--frames":
                parts = [int(x) for x in value.split(":")]
                if len(parts) not in (2, 3) or (len(parts) == 3 and parts[2] < 1):
                    raise ValueError
                args["frames"] = (parts[0], parts[1], parts[2] if len(parts) == 3 else 1)
            elif key == "--samples":
                args["samples"] = int(value)
            else:
                fail("unknown argument " + key)
        except ValueError:
            fail("bad value for " + key + ": " + value)
        i += 2
    return args


def number_of(path):
    match = re.search(r"_(\d+)\.\w+$", os.path.basename(path))
    return int(match.group(1)) if match else None


def read_csv(path):
    if not os.path.isfile(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def frames_of(run, files):
    """Simulation frame of each exported file: exports.csv's frame column where the run wrote
    that table, else the file's number (older runs numbered files by frame)."""
    table = {row.get("file"): row for row in read_csv(os.path.join(run, "exports.csv"))}
    frames = {}
    for f in files:
        row = table.get(os.path.basename(f))
        frames[f] = int(row["frame"]) if row and row.get("frame") not in (None, "") else number_of(f)
    return frames


def frame_rate(run):
    """Frames per second from stats.csv (the time between consecutive frames); 60 otherwise."""
    rows = read_csv(os.path.join(run, "stats.csv"))
    times = [float(r["time_s"]) for r in rows if r.get("time_s")]
    if len(times) >= 2 and times[-1] > times[0]:
        return (len(times) - 1) / (times[-1] - times[0])
    return 60.0


def vdb_float_metadata(path, name):
    """A float entry of a .vdb file's grid metadata, read without OpenVDB (Blender's Python has
    no pyopenvdb). An entry is written as: uint32 name length, name, uint32 type-name length, type
    name ("float"), uint32 value size (4), the value (little-endian float32); metadata is never
    compressed (only the tree's buffers are)."""
    with open(path, "rb") as f:
        data = f.read()
    key = struct.pack("<I", len(name)) + name.encode()
    at = data.find(key)
    if at < 0:
        return None
    at += len(key)
    (type_len,) = struct.unpack_from("<I", data, at)
    at += 4 + type_len
    return struct.unpack_from("<f", data, at + 4)[0]


def run_up(run):
    """The run's up axis where a run.json / scene.json in the folder says it, else None."""
    for name in ("run.json", "scene.json"):
        path = os.path.join(run, name)
        if os.path.isfile(path):
            import json
            try:
                with open(path) as f:
                    data = json.load(f)
                if data.get("up") in ("y", "z"):
                    return data["up"]
            except (OSError, ValueError, AttributeError):
                pass
    return None


def run_domain(run):
    """The tank from a scene .json in the run folder, when the run left one there."""
    import json
    for path in sorted(glob.glob(os.path.join(run, "*.json"))):
        try:
            with open(path) as f:
                data = json.load(f)
            domain = data.get("domain") if isinstance(data, dict) else None
            if domain and "min" in domain and "max" in domain:
                return list(map(float, domain["min"])), list(map(float, domain["max"]))
        except (OSError, ValueError, TypeError):
            continue
    return None


# The run's coordinates to Blender's: a y-up run turned +90 degrees about x ((x, y, z) ->
# (x, -z, y)), as Blender's OBJ importer turns a y-up file; a z-up run kept as it is.
Y_UP_TO_Z_UP = Matrix.Rotation(math.radians(90.0), 4, "X")


def to_blender(up):
    return Y_UP_TO_Z_UP if up == "y" else Matrix.Identity(4)


def import_mesh(path):
    before = set(bpy.data.objects)
    if path.lower().endswith(".obj"):
        # Keep the file's coordinates (forward y, up z is no turn); the run's turn is applied below.
        if hasattr(bpy.ops.wm, "obj_import"):
            bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
        else:
            bpy.ops.import_scene.obj(filepath=path, axis_forward="Y", axis_up="Z")
    else:
        bpy.ops.import_mesh.ply(filepath=path)  # 3.4's PLY importer keeps the coordinates
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if not new:
        fail("Blender could not import " + path)
    return new[0]


def principled_material(name, color, transmission, roughness, ior):
    """A material of one Principled BSDF (the water and the tank's glass)."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = color
    bsdf.inputs["Transmission"].default_value = transmission
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["IOR"].default_value = ior
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    return material


def water_material():
    """Glass-like water: full transmission and water's index."""
    return principled_material("aquaform water", (0.55, 0.8, 1.0, 1.0), 1.0, 0.02, 1.33)


def glass_material():
    return principled_material("aquaform tank glass", (0.95, 0.97, 1.0, 1.0), 1.0, 0.0, 1.5)


def floor_material():
    material = bpy.data.materials.new("aquaform floor")
    material.use_nodes = True
    bsdf = [n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED"]
    if bsdf:
        bsdf[0].inputs["Base Color"].default_value = (0.35, 0.33, 0.3, 1.0)
    material.diffuse_color = (0.35, 0.33, 0.3, 1.0)
    return material


def box_object(name, lo, hi, material):
    """A box from lo to hi (Blender's world) as a mesh object."""
    mesh = bpy.data.meshes.new(name)
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    verts = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
             (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.data.materials.append(material)
    return obj


def build_tank(lo, hi):
    """Four glass walls (thin boxes just outside the domain) and a floor below it, open at the top."""
    t = 0.01 * max(hi[k] - lo[k] for k in range(3))  # wall thickness
    glass = glass_material()
    walls = [
        ((lo[0] - t, lo[1] - t, lo[2]), (lo[0], hi[1] + t, hi[2])),  # -x
        ((hi[0], lo[1] - t, lo[2]), (hi[0] + t, hi[1] + t, hi[2])),  # +x
        ((lo[0], lo[1] - t, lo[2]), (hi[0], lo[1], hi[2])),          # -y
        ((lo[0], hi[1], lo[2]), (hi[0], hi[1] + t, hi[2])),          # +y
    ]
    for k, (a, b) in enumerate(walls):
        box_object("tank wall %d" % k, a, b, glass)
    # The floor reaches past the tank so the picture has ground around it.
    margin = 0.5 * max(hi[0] - lo[0], hi[1] - lo[1])
    box_object("floor", (lo[0] - margin, lo[1] - margin, lo[2] - t), (hi[0] + margin, hi[1] + margin, lo[2]),
               floor_material())


def key_visibility(obj, visible_from, visible_until):
    """obj shows on frames visible_from .. visible_until - 1 only (constant keys: no blending)."""
    for frame, hidden in ((visible_from - 1, True), (visible_from, False), (visible_until, True)):
        obj.hide_render = hidden
        obj.hide_viewport = hidden
        obj.keyframe_insert("hide_render", frame=frame)
        obj.keyframe_insert("hide_viewport", frame=frame)
    for curve in obj.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "CONSTANT"


def box_of(objects):
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for obj in objects:
        for corner in obj.bound_box:
            c = obj.matrix_world @ Vector(corner)
            lo = [min(lo[k], c[k]) for k in range(3)]
            hi = [max(hi[k], c[k]) for k in range(3)]
    return lo, hi


def main():
    args = parse_args()
    run = args["run"]
    if not os.path.isdir(run):
        fail("no run folder " + run)
    up = args["up"] or run_up(run) or "y"
    turn = to_blender(up)

    scene = bpy.context.scene
    for obj in list(bpy.data.objects):  # the factory scene's cube, camera and light
        bpy.data.objects.remove(obj)

    meshes = sorted(glob.glob(os.path.join(run, "surface_*.obj")) + glob.glob(os.path.join(run, "surface_*.ply")))
    volumes = sorted(glob.glob(os.path.join(run, "density_*.vdb")))
    water = water_material()
    surfaces = []
    if meshes:
        frames = frames_of(run, meshes)
        meshes.sort(key=lambda f: frames[f])
        for k, path in enumerate(meshes):
            obj = import_mesh(path)
            obj.matrix_world = turn @ obj.matrix_world
            obj.data.materials.clear()
            obj.data.materials.append(water)
            for polygon in obj.data.polygons:
                polygon.use_smooth = True
            start = frames[path]
            end = frames[meshes[k + 1]] if k + 1 < len(meshes) else start + max(1, start - frames[meshes[k - 1]] if k else 1)
            key_visibility(obj, start, end)
            surfaces.append(obj)
        first, last = frames[meshes[0]], frames[meshes[-1]]
    elif volumes:
        frames = frames_of(run, volumes)
        volumes.sort(key=lambda f: frames[f])
        # One volume object playing the files as a sequence (Blender numbers them itself).
        bpy.ops.object.volume_import(filepath=os.path.abspath(volumes[0]), directory=os.path.dirname(os.path.abspath(volumes[0])),
                                     files=[{"name": os.path.basename(f)} for f in volumes])
        volume = bpy.context.active_object
        volume.matrix_world = turn
        volume.data.frame_start = frames[volumes[0]]
        volume.hide_render = True
        iso = vdb_float_metadata(volumes[0], "aquaform_iso") or 0.5
        obj = bpy.data.objects.new("water", bpy.data.meshes.new("water"))
        scene.collection.objects.link(obj)
        modifier = obj.modifiers.new("VolumeToMesh", "VOLUME_TO_MESH")
        modifier.object = volume
        modifier.threshold = iso
        modifier.resolution_mode = "GRID"
        modifier.use_smooth_shade = True
        obj.matrix_world = turn
        obj.data.materials.append(water)
        surfaces.append(obj)
        first, last = frames[volumes[0]], frames[volumes[-1]]
    else:
        fail("no surface_*.obj/.ply or density_*.vdb in " + run + " (run with --mesh-every or --vdb-every)")

    # The tank: --domain, else a scene .json in the run folder, else the box round every surface.
    domain = args["domain"] or run_domain(run)
    if domain:
        # The domain is the scene's, in the simulation's (y-up) axes whatever --up the run used.
        corners = [Y_UP_TO_Z_UP @ Vector((x, y, z)) for x in (domain[0][0], domain[1][0]) for y in (domain[0][1], domain[1][1])
                   for z in (domain[0][2], domain[1][2])]
        lo = [min(c[k] for c in corners) for k in range(3)]
        hi = [max(c[k] for c in corners) for k in range(3)]
    else:
        bpy.context.view_layer.update()
        lo, hi = box_of(surfaces)
        print("blender_scene: no domain given or found; the tank is the box round the surfaces")
    build_tank(lo, hi)

    # Camera: in front of the tank (Blender's -y side) and above it, looking at its centre.
    centre = (Vector(lo) + Vector(hi)) / 2
    size = (Vector(hi) - Vector(lo)).length
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.location = centre + Vector((0.35, -1.4, 0.8)).normalized() * size * 1.3
    camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
    camera.data.lens = 35
    camera.data.clip_end = size * 20
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 4.0
    sun.rotation_euler = (math.radians(40), math.radians(15), math.radians(30))
    scene.collection.objects.link(sun)
    if scene.world is None:
        scene.world = bpy.data.worlds.new("world")
    scene.world.use_nodes = True
    background = [n for n in scene.world.node_tree.nodes if n.type == "BACKGROUND"]
    if background:
        background[0].inputs["Color"].default_value = (0.8, 0.85, 0.9, 1.0)

    # The run's frames and frame rate (fps as a whole number over fps_base, e.g. 60 / 1.0).
    fps = frame_rate(run)
    scene.render.fps = max(1, round(fps))
    scene.render.fps_base = scene.render.fps / fps
    scene.frame_start, scene.frame_end = first, last
    scene.frame_set(first)

    if args["render"]:
        a, b, step = args["frames"] or (first, last, 1)
        scene.frame_start, scene.frame_end, scene.frame_step = a, b, step
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = args["samples"]
        scene.cycles.use_denoising = False
        scene.cycles.max_bounces = 8
        scene.cycles.transmission_bounces = 8
        scene.render.resolution_x, scene.render.resolution_y = args["size"]
        scene.render.resolution_percentage = 100
        scene.render.image_settings.file_format = "PNG"
        # PREFIX####: Blender puts the frame number, four digits, where the #s are.
        scene.render.filepath = os.path.abspath(args["render"]) + "####"
        bpy.ops.render.render(animation=True)
        print("blender_scene: rendered frames %d..%d to %s####.png" % (a, b, args["render"]))


if __name__ == "__main__":  # blender -P runs it as __main__; tests/tools/blender_check.py imports it
    try:
        main()
    except Exception as error:  # an exception leaves Blender's exit status 0: make it 1
        import traceback
        where = traceback.extract_tb(error.__traceback__)[-1]
        fail("%s: %s (line %d)" % (type(error).__name__, str(error).splitlines()[0] if str(error) else "", where.lineno))
