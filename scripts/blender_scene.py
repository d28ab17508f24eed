"""A Blender scene from an aquaform run folder: the water surface over time in a glass tank.

    blender -P scripts/blender_scene.py -- RUNDIR [options]             # opens the scene to look at
    blender -b -P scripts/blender_scene.py -- RUNDIR --render PREFIX [--resolution WxH] [--frames A:B]
                                                                       # renders PREFIX0000.png ...
options:
    --domain x0,y0,z0,x1,y1,z1  the tank (the scene's "domain", in the simulation's y-up axes, each
                                min below its max); by default RUNDIR/run.json's (aquaform run
                                writes it), else the box around every exported surface
    --up y|z                    the run's --up (default: RUNDIR/run.json's, else y, aquaform's
                                default; the exports themselves do not record it); a
                                y-up run's files are turned (x, y, z) -> (x, -z, y) so its up is
                                Blender's z, a z-up run's files are already turned
    --render PREFIX             render the frames with Cycles (CPU) to PREFIX####.png and quit
    --resolution WxH            the pictures' size, 16..8192 per side as aquaform's --resolution
                                (default 640x360; --size WxH, its old name, still works and
                                says so)
    --frames A:B[:S]            the Blender frames to render, every S-th, within the run's exported
                                frames (default: the whole run)
    --samples N                 Cycles samples, 1..4096 (default 16)
    --whitewater on|off         draw the run's whitewater (its whitewater_NNNN.ply files, from
                                `aquaform run --whitewater-every K`) as small white spheres (default on)

Exit status, as the aquaform command's: 0 done; 2 bad input (a flag, a missing or unreadable run
folder, a corrupt run.json or one whose "up" or "domain" is wrong, an exported file that is not of
its kind, a solid's file that run.json lists missing or not a mesh), one line on stderr naming it and
the fix, checked before Blender imports or renders anything; 1 a failure at run time (Blender cannot import a file); 130 Ctrl-C while rendering
(Blender's first Ctrl-C finishes the frame it is on; the frames rendered stay; a second one is
Blender's own and ends it at once, with Blender's status 2). Without run.json, the up axis y and
the tank round the surfaces are assumed, and a line on stderr says so.

The surface: the run's surface_NNNN.obj / .ply meshes, one object per exported frame, each shown
only from its frame until the next one (keyframed hide_render / hide_viewport). Where the run has
no meshes, its density_NNNN.vdb volumes as one volume sequence with a Volume to Mesh surface at
the volume's iso value (the aquaform_iso metadata). Blender frame F is simulation frame F
(through exports.csv's frame column where the run wrote one, else the number in the file name);
the frame rate is the run's (stats.csv's time step between frames).

The whitewater: the run's whitewater_NNNN.ply files (diffuse_NNNN.ply, their old name, in a run
written before), one object per file shown from its frame until the next as the surfaces are,
each a mesh of points that a Geometry Nodes modifier turns into a point cloud (Cycles draws each
point as a sphere) with a white material. A point's radius follows its kind, as a fraction of the
run's particle spacing (run.json): spray 0.2, foam 0.3, bubbles 0.15 (the spray's drops are finer
than the foam's clumps; the bubbles are seen through the water).
"""
import csv
import glob
import json
import math
import os
import re
import struct
import sys
import tempfile

import bpy
from mathutils import Matrix, Vector

USAGE = ("usage: blender [-b] -P blender_scene.py -- RUNDIR [--render PREFIX] [--resolution WxH] [--frames A:B[:S]] "
         "[--samples N] [--domain x0,y0,z0,x1,y1,z1] [--up y|z] [--whitewater on|off]")
# A value for each flag, as the refusals' examples.
EXAMPLES = {"--domain": "0,0,0,1.6,0.8,0.8", "--up": "z", "--render": "out/cycles_", "--resolution": "640x360",
            "--size": "640x360",
            "--frames": "0:60", "--samples": "16", "--whitewater": "off"}
# The aquaform command's picture sizes (render/picture_size.h: kMinPictureSide, kMaxPictureSide;
# tests/test_script_fuzz.cpp checks that the two agree).
MIN_SIDE, MAX_SIDE = 16, 8192
MAX_SAMPLES = 4096
EXIT_RUNTIME, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 1, 2, 130


# A frame without water (a scene whose nozzles have not started, or whose sinks took it all): the
# surface export writes its header alone, and the frame shows no surface.
EMPTY_SURFACE = re.compile(rb"# aquaform [^\n]*: 0 vertices, 0 triangles\s*$")

def leave(message, status):
    """One line on stderr and Blender's exit status: os._exit, since in Blender's window a
    SystemExit only ends the script (blender -b would pass sys.exit's status on; this does both)."""
    sys.stderr.write("blender_scene: " + message + "\n")
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def fail(message):
    """A failure at run time (an import Blender cannot do): exit 1."""
    leave(message, EXIT_RUNTIME)


def refuse(message):
    """Bad input (a flag, the run folder or one of its files), found before any work: exit 2."""
    leave(message, EXIT_BAD_INPUT)


def note(message):
    sys.stderr.write("blender_scene: " + message + "\n")


def parse_domain(text, where, fix):
    """Six finite numbers x0,y0,z0,x1,y1,z1 (a list or a comma-separated string), each min below its max."""
    try:
        numbers = [float(x) for x in (text.split(",") if isinstance(text, str) else text)]
    except (TypeError, ValueError):
        numbers = []
    if len(numbers) != 6 or not all(math.isfinite(x) for x in numbers) or \
            any(numbers[k] >= numbers[k + 3] for k in range(3)):
        refuse("%s must be six numbers x0,y0,z0,x1,y1,z1 with each min below its max, got %s; %s"
               % (where, json.dumps(text) if not isinstance(text, str) else '"%s"' % text, fix))
    return numbers[:3], numbers[3:]


def parse_size(text, flag="--resolution"):
    match = re.fullmatch(r"(\d{1,6})[xX](\d{1,6})", text)
    if not match or not all(MIN_SIDE <= int(side) <= MAX_SIDE for side in match.groups()):
        refuse('%s must look like 640x360 (%d..%d per side), got "%s"' % (flag, MIN_SIDE, MAX_SIDE, text))
    return int(match.group(1)), int(match.group(2))


def parse_old_size(text):
    """--size, the old name of --resolution (as `aquaform view` keeps it): still works, and
    parse_args says so once every flag has passed (a refusal stays one line)."""
    return parse_size(text, "--size")


def parse_frames(text):
    """A:B[:S] with A <= B and S >= 1 (the run's range is checked once the folder is read)."""
    match = re.fullmatch(r"(\d{1,9}):(\d{1,9})(?::(\d{1,9}))?", text)
    if not match:
        refuse('--frames must look like A:B or A:B:S (whole frames from 0, every S-th), got "%s"; e.g. --frames 0:60'
               % text)
    a, b, step = int(match.group(1)), int(match.group(2)), int(match.group(3) or 1)
    if a > b:
        refuse('--frames %s starts after it ends; give A <= B, e.g. --frames %d:%d' % (text, b, a))
    if step < 1:
        refuse('--frames %s steps by %d; give a step S of 1 or more, e.g. --frames %d:%d:1' % (text, step, a, b))
    return a, b, step


def parse_samples(text):
    if not re.fullmatch(r"\d{1,9}", text) or not 1 <= int(text) <= MAX_SAMPLES:
        refuse('--samples must be a whole number from 1 to %d, got "%s"; e.g. --samples 16' % (MAX_SAMPLES, text))
    return int(text)


def parse_up(text):
    if text not in ("y", "z"):
        refuse('--up must be y or z (the run\'s own --up), got "%s"' % text)
    return text


def parse_on_off(text):
    if text not in ("on", "off"):
        refuse('--whitewater must be on or off, got "%s"' % text)
    return text == "on"


PARSERS = {"--domain": lambda v: parse_domain(v, "--domain", "e.g. --domain " + EXAMPLES["--domain"]),
           "--up": parse_up, "--render": lambda v: v, "--resolution": parse_size, "--size": parse_old_size,
           "--frames": parse_frames,
           "--samples": parse_samples, "--whitewater": parse_on_off}


def parse_args(argv):
    """The flags after Blender's "--", each checked; any fault is refused before any work."""
    if not argv or argv[0].startswith("-"):
        refuse("the run folder comes first%s; %s" % (", not " + argv[0] if argv else "", USAGE))
    given = {}
    i = 1
    while i < len(argv):
        key = argv[i]
        if key not in PARSERS:
            refuse("unknown argument %s; %s" % (key, USAGE))
        if key in given:
            refuse("%s is given twice; give it once" % key)
        if i + 1 >= len(argv) or argv[i + 1] == "" or argv[i + 1].startswith("--"):
            refuse("%s needs a value; e.g. %s %s" % (key, key, EXAMPLES[key]))
        given[key] = PARSERS[key](argv[i + 1])
        i += 2
    if "--size" in given and "--resolution" in given:
        refuse("--size is the old name of --resolution; give --resolution alone")
    for key in ("--resolution", "--size", "--frames", "--samples"):
        if key in given and "--render" not in given:
            refuse("%s is for rendering; add --render PREFIX, or leave %s out to open the scene" % (key, key))
    if "--size" in given:
        note("--size is the old name of --resolution; it still works")
    return {"run": argv[0], "domain": given.get("--domain"), "up": given.get("--up"), "render": given.get("--render"),
            "size": given.get("--resolution", given.get("--size", (640, 360))), "frames": given.get("--frames"),
            "samples": given.get("--samples", 16), "whitewater": given.get("--whitewater", True)}


def number_of(path):
    match = re.search(r"_(\d+)\.\w+$", os.path.basename(path))
    return int(match.group(1)) if match else None


def read_csv(path):
    if not os.path.isfile(path):
        return []
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as error:
        refuse("cannot read %s (%s); write the run again or remove the file" % (path, error))


def frames_of(run, files):
    """Simulation frame of each exported file: exports.csv's frame column where the run wrote
    that table, else the file's number (older runs numbered files by frame)."""
    table = {row.get("file"): row for row in read_csv(os.path.join(run, "exports.csv"))}
    frames = {}
    for f in files:
        row = table.get(os.path.basename(f))
        text = row.get("frame") if row else None
        if text not in (None, ""):
            if not re.fullmatch(r"\d{1,9}", text.strip()):
                refuse('%s gives %s the frame "%s", not a whole number; write the run again'
                       % (os.path.join(run, "exports.csv"), os.path.basename(f), text))
            frames[f] = int(text)
        elif number_of(f) is not None:
            frames[f] = number_of(f)
        else:
            refuse("cannot tell the frame of %s (no exports.csv row, no number in its name); rename it NAME_NNNN or "
                   "remove it" % f)
    return frames


def frame_rate(run):
    """Frames per second from stats.csv (the time between consecutive frames); 60 otherwise."""
    times = []
    for row in read_csv(os.path.join(run, "stats.csv")):
        text = row.get("time_s")
        if not text:
            continue
        try:
            times.append(float(text))
        except ValueError:
            times.append(math.nan)
        if not math.isfinite(times[-1]):
            refuse('%s has the time_s "%s", not a number; write the run again or remove stats.csv (60 fps is then assumed)'
                   % (os.path.join(run, "stats.csv"), text))
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


def read_run_json(run):
    """run.json (aquaform run writes it): {"up", "domain"}, each None where absent. A corrupt file,
    a key of the wrong type or an unknown up axis is refused: guessing turns the water the wrong way."""
    path = os.path.join(run, "run.json")
    if not os.path.isfile(path):
        return {"up": None, "domain": None, "found": False, "obstacles": [], "particle_spacing": None}
    fix = "write the run again with `aquaform run`, or remove run.json and give --up and --domain"
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, UnicodeDecodeError, ValueError) as error:
        refuse("%s is not readable JSON (%s); %s" % (path, str(error).splitlines()[0], fix))
    if not isinstance(data, dict):
        refuse("%s holds a %s, not an object; %s" % (path, type(data).__name__, fix))
    up = data.get("up")
    if "up" in data and up not in ("y", "z"):
        refuse('%s: "up" is %s, not "y" or "z"; %s' % (path, json.dumps(up), fix))
    domain = None
    if "domain" in data:
        box = data["domain"]
        if not (isinstance(box, dict) and isinstance(box.get("min"), list) and isinstance(box.get("max"), list)
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in box["min"] + box["max"])):
            refuse('%s: "domain" is %s, not {"min": [x, y, z], "max": [x, y, z]}; %s' % (path, json.dumps(box), fix))
        domain = parse_domain(box["min"] + box["max"], '%s: "domain"' % path, fix)
    for key in ("frame_dt", "particle_spacing"):
        value = data.get(key)
        if key in data and not (isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0):
            refuse('%s: "%s" is %s, not a number above 0; %s' % (path, key, json.dumps(value), fix))
    # The solids beside the run: [{"name", "file"} or {"name", "files": "obstacle_x_%04u.obj", "moves": true}].
    obstacles = data.get("obstacles", [])
    shape = 'a list of {"name": ..., "file": ...} or {"name": ..., "files": ..., "moves": true}'
    if not isinstance(obstacles, list) or not all(
            isinstance(o, dict) and isinstance(o.get("name"), str)
            and (isinstance(o.get("file"), str) or (isinstance(o.get("files"), str) and "%" in o["files"]))
            for o in obstacles):
        refuse('%s: "obstacles" is %s, not %s; %s' % (path, json.dumps(obstacles)[:200], shape, fix))
    for o in obstacles:
        name = o.get("file") or o["files"]
        if "file" not in o:  # a printf pattern of the frame: it must make a name of a number
            try:
                name = o["files"] % 0
            except (TypeError, ValueError, OverflowError):
                refuse('%s: obstacle %s\'s "files" %s is not a pattern of one frame number (such as %s); %s'
                       % (path, json.dumps(o["name"]), json.dumps(o["files"]), json.dumps("obstacle_x_%04u.obj"), fix))
        if os.path.basename(name) != name or name in ("", ".", ".."):
            refuse('%s: obstacle file %s is not a file name in the run folder; %s' % (path, json.dumps(name), fix))
    return {"up": up, "domain": domain, "found": True, "obstacles": obstacles,
            "particle_spacing": data.get("particle_spacing")}


# The first bytes of each file kind the scene reads: OpenVDB's magic number (int64 0x56444220,
# little-endian), PLY's header word; an OBJ is text (no NUL byte) with vertex lines.
VDB_MAGIC = struct.pack("<q", 0x56444220)


def check_file_kind(path):
    """Refuses an exported file that is empty or not of the kind its name says."""
    try:
        with open(path, "rb") as f:
            head = f.read(1 << 16)
    except OSError as error:
        refuse("cannot read %s (%s); make it readable or remove it" % (path, error.strerror or error))
    name = os.path.basename(path)
    kind = path.rsplit(".", 1)[-1].lower()
    if not head:
        problem = "is empty"
    elif kind == "vdb" and not head.startswith(VDB_MAGIC):
        problem = "is not an OpenVDB file"
    elif kind == "ply" and not re.match(rb"ply\r?\n", head):
        problem = "is not a PLY file"
    elif kind == "obj" and (b"\0" in head or not (re.search(rb"(^|\n)v\s", head) or EMPTY_SURFACE.match(head))):
        problem = "is not an OBJ mesh (no vertex lines)"
    else:
        return
    refuse("%s %s; export it again with `aquaform run` or remove %s from %s" % (path, problem, name, os.path.dirname(path)))


# The OBJ keywords Blender's importer reads or skips; any other first word is not OBJ.
OBJ_KEYWORDS = {b"v", b"vn", b"vt", b"vp", b"f", b"l", b"p", b"o", b"g", b"s", b"usemtl", b"mtllib", b"cstype", b"deg",
                b"curv", b"curv2", b"surf", b"parm", b"end", b"mg", b"bevel", b"c_interp", b"d_interp", b"lod",
                b"shadow_obj", b"trace_obj"}


def obj_problem(path):
    """Why the OBJ mesh at `path` cannot be drawn (a line that is not OBJ, a vertex that is not three
    finite numbers, a face with fewer than three corners or a corner with no vertex, no face), or
    None. Read whole: an obstacle's file is small, and Blender's importer would otherwise fail, or
    draw nothing, after the scene has been started."""
    vertices = faces = 0
    try:
        with open(path, "rb") as f:
            for number, line in enumerate(f, 1):
                words = line.split()
                if not words or words[0].startswith(b"#"):
                    continue
                if words[0] not in OBJ_KEYWORDS or b"\0" in line:
                    shown = re.sub(r"[^\x20-\x7e]", "?", line[:40].decode("ascii", "replace").strip())
                    return "line %d is not OBJ (%s)" % (number, shown)
                if words[0] == b"v":
                    try:
                        xyz = [float(w) for w in words[1:4]]
                    except ValueError:
                        xyz = []
                    if len(xyz) != 3 or not all(math.isfinite(x) for x in xyz):
                        return "line %d: a vertex is three finite numbers" % number
                    vertices += 1
                elif words[0] == b"f":
                    if len(words) < 4:
                        return "line %d: a face has at least three corners" % number
                    for corner in words[1:]:
                        try:
                            index = int(corner.split(b"/")[0])
                        except ValueError:
                            index = 0
                        if index < 0:
                            index += vertices + 1
                        if not 1 <= index <= vertices:
                            return "line %d: a face's corner %s names no vertex before it" % (
                                number, corner.decode("ascii", "replace"))
                    faces += 1
    except OSError as error:
        return "cannot be read (%s)" % (error.strerror or error)
    return None if faces else "has no faces"


def obstacle_files(run, obstacles, first, last):
    """Each solid's files (run.json's "obstacles"), checked before any work: [(name, frame or None,
    path)]. A still one has one file; a moving one a file at every frame of the surfaces'
    first..last, as `aquaform run` writes them. A file missing or not a mesh is refused: drawn
    without its solids, the scene would be wrong without a word."""
    fix = "write the run again with `aquaform run` (it writes the solids' files beside the surfaces)"
    files = []
    for o in obstacles:
        shown = [(None, o["file"])] if "file" in o else [(f, o["files"] % f) for f in range(first, last + 1)]
        for frame, name in shown:
            path = os.path.join(run, name)
            at = "" if frame is None else " at frame %d" % frame
            if not os.path.isfile(path):
                refuse('%s lists the obstacle %s, but its file %s%s is missing; %s, or remove the entry from run.json'
                       % (os.path.join(run, "run.json"), json.dumps(o["name"]), path, at, fix))
            if not path.lower().endswith(".obj"):
                check_file_kind(path)
            problem = obj_problem(path) if path.lower().endswith(".obj") else None
            if problem:
                refuse("%s (the obstacle %s%s) is not a mesh Blender can draw: %s; %s"
                       % (path, json.dumps(o["name"]), at, problem, fix))
            files.append((o["name"], frame, path))
    return files


# The whitewater's PLY (sim/particle_io.cpp, write_whitewater_ply): binary little-endian vertices of
# x, y, z, vx, vy, vz (float), kind (uchar: 0 spray, 1 foam, 2 bubble), life (float), 29 bytes each.
WHITEWATER_PROPERTIES = [("float", "x"), ("float", "y"), ("float", "z"), ("float", "vx"), ("float", "vy"), ("float", "vz"),
                         ("uchar", "kind"), ("float", "life")]
WHITEWATER_VERTEX_BYTES = 29
WHITEWATER_RADIUS = (0.2, 0.3, 0.15)  # spray, foam, bubble: in particle spacings (see the docstring)


def whitewater_header(path):
    """(vertices, header bytes) of a whitewater PLY; refuses a file of another layout or cut short."""
    fix = "export it again with `aquaform run --whitewater-every K` or remove it"
    with open(path, "rb") as f:
        head = f.read(4096)
    end = head.find(b"end_header\n")
    lines = head[:end].decode("ascii", "replace").split("\n") if end >= 0 else []
    vertices = None
    properties = []
    for line in lines:
        words = line.split()
        if words[:1] == ["element"]:
            if words[1:2] != ["vertex"] or len(words) != 3 or not words[2].isdigit():
                refuse('%s has the element "%s", not aquaform\'s whitewater layout (its vertices alone); %s'
                       % (path, " ".join(words[1:]), fix))
            vertices = int(words[2])
        elif words[:1] == ["property"]:
            properties.append(tuple(words[1:]))
    if end < 0 or "format binary_little_endian 1.0" not in lines or vertices is None or properties != WHITEWATER_PROPERTIES:
        refuse("%s is not aquaform's whitewater PLY (binary x y z vx vy vz kind life); %s" % (path, fix))
    header = end + len(b"end_header\n")
    size = os.path.getsize(path)
    if size != header + vertices * WHITEWATER_VERTEX_BYTES:
        refuse("%s is cut short or padded: %d bytes where %d vertices take %d; %s"
               % (path, size, vertices, header + vertices * WHITEWATER_VERTEX_BYTES, fix))
    return vertices, header


def read_whitewater(path):
    """Positions (n x 3) and kinds (n) of a whitewater PLY, as numpy arrays (a million particles
    read in one call, not one by one)."""
    import numpy
    vertices, header = whitewater_header(path)
    layout = numpy.dtype([("p", "<f4", 3), ("v", "<f4", 3), ("kind", "u1"), ("life", "<f4")])
    assert layout.itemsize == WHITEWATER_VERTEX_BYTES
    data = numpy.fromfile(path, dtype=layout, count=vertices, offset=header)
    return data["p"], data["kind"]


def check_render_prefix(prefix):
    """PREFIX's folder exists or can be made, and can be written (the pictures would be lost)."""
    folder = os.path.dirname(os.path.abspath(prefix))
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".blender_scene_probe"):
            pass
    except OSError as error:
        refuse("--render %s: its folder %s cannot be written (%s); give a PREFIX in a folder you can write"
               % (prefix, folder, error.strerror or error))


def read_run(args):
    """Everything the scene takes from the run folder, checked before any work: the surfaces
    (meshes, else volumes, and the volumes' iso level) and their frames, the up axis, the tank,
    the solids' files, the whitewater's, the frame rate."""
    run = args["run"]
    if not os.path.isdir(run):
        refuse("no run folder %s; give the --out folder of an `aquaform run` with --mesh-every or --vdb-every" % run)
    meshes = sorted(glob.glob(os.path.join(run, "surface_*.obj")) + glob.glob(os.path.join(run, "surface_*.ply")))
    volumes = sorted(glob.glob(os.path.join(run, "density_*.vdb")))
    files = meshes or volumes
    if not files:
        refuse("no surface_*.obj/.ply or density_*.vdb in " + run + " (run with --mesh-every or --vdb-every)")
    for path in files:
        check_file_kind(path)
    frames = frames_of(run, files)
    files.sort(key=lambda f: frames[f])
    first, last = frames[files[0]], frames[files[-1]]
    if args["frames"]:
        a, b, _ = args["frames"]
        if a < first or b > last:
            refuse("--frames %d:%d is outside the run's frames %d..%d (its exported surfaces); e.g. --frames %d:%d"
                   % (a, b, first, last, first, last))
    described = read_run_json(run)
    if not described["found"]:
        assumed = [what for flag, what in (("up", "up y (aquaform's default)"), ("domain", "the tank round the surfaces"))
                   if not args[flag]]
        if assumed:
            note("no run.json in %s: assuming %s; give %s to say otherwise"
                 % (run, " and ".join(assumed), " and ".join("--" + f for f in ("up", "domain") if not args[f])))
    # The whitewater's files, checked as the surfaces are (their frames from exports.csv); a run
    # written before aquaform named them whitewater_NNNN.ply has them as diffuse_NNNN.ply.
    whitewater = sorted(glob.glob(os.path.join(run, "whitewater_*.ply"))) if args["whitewater"] else []
    if args["whitewater"] and not whitewater:
        whitewater = sorted(glob.glob(os.path.join(run, "diffuse_*.ply")))
        if whitewater:
            note("%s has the whitewater as diffuse_NNNN.ply, the old name of whitewater_NNNN.ply; drawn all the same"
                 % run)
    for path in whitewater:
        check_file_kind(path)
        whitewater_header(path)
    frames.update(frames_of(run, whitewater))
    whitewater.sort(key=lambda f: frames[f])
    solids = obstacle_files(run, described["obstacles"], first, last)
    iso = None
    if not meshes:  # the volumes' surface level, read now rather than after the scene is started
        try:
            iso = vdb_float_metadata(volumes[0], "aquaform_iso")
        except (OSError, struct.error) as error:
            refuse("%s: its aquaform_iso metadata cannot be read (%s); export it again with `aquaform run --vdb-every K` "
                   "or remove it" % (volumes[0], error))
        if iso is not None and not math.isfinite(iso):
            refuse("%s: its aquaform_iso metadata is %s, not a number; export it again with `aquaform run --vdb-every K`"
                   % (volumes[0], iso))
    fps = frame_rate(run)
    if args["render"]:  # last: the only check that makes something (PREFIX's folder)
        check_render_prefix(args["render"])
    return {"meshes": meshes, "volumes": volumes, "frames": frames, "first": first, "last": last,
            "up": args["up"] or described["up"] or "y", "domain": args["domain"] or described["domain"], "fps": fps,
            "obstacles": solids, "dir": run, "whitewater": whitewater, "iso": iso,
            "spacing": described["particle_spacing"]}


# The run's coordinates to Blender's: a y-up run turned +90 degrees about x ((x, y, z) ->
# (x, -z, y)), as Blender's OBJ importer turns a y-up file; a z-up run kept as it is.
Y_UP_TO_Z_UP = Matrix.Rotation(math.radians(90.0), 4, "X")


def to_blender(up):
    return Y_UP_TO_Z_UP if up == "y" else Matrix.Identity(4)


def import_mesh(path):
    with open(path, "rb") as f:
        if EMPTY_SURFACE.match(f.read(4096)):  # no water that frame: an empty mesh keeps its place
            name = os.path.splitext(os.path.basename(path))[0]
            obj = bpy.data.objects.new(name, bpy.data.meshes.new(name))
            bpy.context.scene.collection.objects.link(obj)
            return obj
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


def shown_until(files, frames, k):
    """The frame the k-th of a kind's files (in frame order) stops showing: the next file's, or
    one export interval after the last (a single file: the next frame)."""
    start = frames[files[k]]
    if k + 1 < len(files):
        return frames[files[k + 1]]
    return start + max(1, start - frames[files[k - 1]] if k else 1)


def whitewater_material():
    """Matte white with a little sheen: foam and spray scatter light, they do not refract it."""
    return principled_material("aquaform whitewater", (0.95, 0.97, 1.0, 1.0), 0.0, 0.45, 1.33)


def points_node_group(material):
    """Geometry Nodes: the mesh's vertices as a point cloud, each point's radius its "radius"
    attribute, with `material` (Cycles draws the points as spheres)."""
    group = bpy.data.node_groups.new("aquaform whitewater points", "GeometryNodeTree")
    group.inputs.new("NodeSocketGeometry", "Geometry")
    group.outputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    given, result = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    to_points = nodes.new("GeometryNodeMeshToPoints")
    radius = nodes.new("GeometryNodeInputNamedAttribute")
    radius.data_type = "FLOAT"
    radius.inputs["Name"].default_value = "radius"
    set_material = nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = material
    links.new(given.outputs[0], to_points.inputs["Mesh"])
    links.new(radius.outputs["Attribute"], to_points.inputs["Radius"])
    links.new(to_points.outputs["Points"], set_material.inputs["Geometry"])
    links.new(set_material.outputs["Geometry"], result.inputs[0])
    return group


def add_whitewater(run, turn):
    """An object per whitewater file, shown at its frames; returns the most particles in one."""
    if not run["whitewater"]:
        return 0
    spacing = run["spacing"] or 0.01
    if not run["spacing"]:
        note("run.json gives no particle_spacing; the whitewater's spheres are sized for 1 cm")
    group = points_node_group(whitewater_material())
    import numpy
    radii = numpy.array(WHITEWATER_RADIUS, dtype=numpy.float32) * spacing
    most = 0
    files = run["whitewater"]
    for k, path in enumerate(files):
        positions, kinds = read_whitewater(path)
        most = max(most, len(positions))
        mesh = bpy.data.meshes.new("whitewater %04d" % run["frames"][path])
        mesh.vertices.add(len(positions))
        mesh.vertices.foreach_set("co", positions.ravel())
        radius = mesh.attributes.new("radius", "FLOAT", "POINT")
        radius.data.foreach_set("value", radii[numpy.minimum(kinds, 2)])
        obj = bpy.data.objects.new(mesh.name, mesh)
        bpy.context.scene.collection.objects.link(obj)
        obj.matrix_world = turn
        obj.modifiers.new("points", "NODES").node_group = group
        key_visibility(obj, run["frames"][path], shown_until(files, run["frames"], k))
    print("blender_scene: whitewater from %d files, up to %d particles in one" % (len(files), most))
    return most


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
    args = parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    run = read_run(args)
    turn = to_blender(run["up"])
    meshes, volumes, frames = run["meshes"], run["volumes"], run["frames"]
    first, last = run["first"], run["last"]

    scene = bpy.context.scene
    for obj in list(bpy.data.objects):  # the factory scene's cube, camera and light
        bpy.data.objects.remove(obj)

    water = water_material()
    surfaces = []
    if meshes:
        for k, path in enumerate(meshes):
            obj = import_mesh(path)
            obj.matrix_world = turn @ obj.matrix_world
            obj.data.materials.clear()
            obj.data.materials.append(water)
            for polygon in obj.data.polygons:
                polygon.use_smooth = True
            key_visibility(obj, frames[path], shown_until(meshes, frames, k))
            surfaces.append(obj)
    else:
        # One volume object playing the files as a sequence (Blender numbers them itself).
        bpy.ops.object.volume_import(filepath=os.path.abspath(volumes[0]), directory=os.path.dirname(os.path.abspath(volumes[0])),
                                     files=[{"name": os.path.basename(f)} for f in volumes])
        volume = bpy.context.active_object
        volume.matrix_world = turn
        volume.data.frame_start = frames[volumes[0]]
        volume.hide_render = True
        iso = run["iso"] or 0.5
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

    add_whitewater(run, turn)

    # The solids (run.json's "obstacles", their files checked in read_run): a still one once, a
    # moving one a file per frame shown at its frame.
    solid = principled_material("solid", (0.75, 0.33, 0.10, 1.0), 0.0, 0.6, 1.45)  # a warm colour, apart from water and glass
    for name, frame, path in run["obstacles"]:
        obj = import_mesh(path)
        obj.name = "obstacle " + name
        obj.matrix_world = turn @ obj.matrix_world
        obj.data.materials.clear()
        obj.data.materials.append(solid)
        if frame is not None:
            key_visibility(obj, frame, frame + 1)

    # The tank: --domain, else run.json's, else the box round every surface.
    domain = run["domain"]
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
    fps = run["fps"]
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
        # Blender's first Ctrl-C stops the animation after the frame it is on and calls render_cancel.
        interrupted = []
        bpy.app.handlers.render_cancel.append(lambda *_: interrupted.append(True))
        bpy.ops.render.render(animation=True)
        if interrupted:
            leave("stopped by Ctrl-C; the frames rendered before it are in %s####.png" % args["render"], EXIT_INTERRUPTED)
        print("blender_scene: rendered frames %d..%d to %s####.png" % (a, b, args["render"]))


if __name__ == "__main__":  # blender -P runs it as __main__; tests/tools/blender_check.py imports it
    try:
        main()
    except KeyboardInterrupt:
        leave("stopped by Ctrl-C", EXIT_INTERRUPTED)
    except Exception as error:  # an exception leaves Blender's exit status 0: make it 1
        import traceback
        where = traceback.extract_tb(error.__traceback__)[-1]
        fail("%s: %s (line %d)" % (type(error).__name__, str(error).splitlines()[0] if str(error) else "", where.lineno))
