#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into tests/fuzz/corpus/<target>/.

Seeds are small valid files of each format (a few hundred bytes: libFuzzer mutates
small inputs fastest) covering the features the readers handle, plus the fixtures of
data/ that are small enough. Run it again after changing it; the files are committed.
"""
import json
import shutil
import struct
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "tests" / "fuzz" / "corpus"
FIXTURES = ROOT / "data" / "fixtures"


def put(target, name, content):
    d = OUT / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(content.encode() if isinstance(content, str) else content)


def lzf_literal(data):
    """LZF data made of literal runs only (valid, uncompressed): our decoder (and PCL's) reads it."""
    out = bytearray()
    for i in range(0, len(data), 32):
        chunk = data[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def pcd():
    t = "pcd_cloud"
    put(t, "ascii_xyz.pcd",
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH 4\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
        "1 2 3\n0.5 -0.25 1e-3\nnan nan nan\n4 5 6\n")
    put(t, "organized_ascii.pcd",
        "VERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
        "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
        "0 0 1 1\nnan nan nan 0\n1 1 1 2\n0 1 inf 3\n")
    put(t, "double_and_count.pcd",
        "VERSION 0.7\nFIELDS x y z normal\nSIZE 8 8 8 4\nTYPE F F F F\nCOUNT 1 1 1 3\n"
        "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 0 0 1\n4 5 6 1 0 0\n")
    header = ("VERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F U\n"
              "COUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n")
    points = [(0.0, 0.0, 0.0, 1), (1.0, 0.5, -2.0, 2), (3.0, 4.0, 5.0, 7)]
    body = b"".join(struct.pack("<fffI", *p) for p in points)
    put(t, "binary_xyzl.pcd", header.encode() + b"DATA binary\n" + body)
    # binary_compressed stores the fields one after the other (x x x y y y ...).
    soa = b"".join(struct.pack("<" + ("f" if f < 3 else "I") * 3, *[p[f] for p in points])
                   for f in range(4))
    packed = lzf_literal(soa)
    put(t, "binary_compressed.pcd", header.encode() + b"DATA binary_compressed\n" +
        struct.pack("<II", len(packed), len(soa)) + packed)
    put(t, "int_types.pcd",
        "VERSION 0.7\nFIELDS x y z label\nSIZE 2 1 8 2\nTYPE I U I U\nCOUNT 1 1 1 1\n"
        "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n-3 200 7 9\n1 2 3 4\n")


def ply_header(fmt, elements):
    lines = ["ply", "format %s 1.0" % fmt, "comment seed"]
    for name, count, props in elements:
        lines.append("element %s %d" % (name, count))
        lines += ["property " + p for p in props]
    return ("\n".join(lines) + "\nend_header\n").encode()


def ply():
    c = "ply_cloud"
    xyz = ["float x", "float y", "float z"]
    put(c, "ascii_xyz.ply", ply_header("ascii", [("vertex", 3, xyz)]) +
        b"0 0 0\n1 2 3\n-1 0.5 nan\n")
    put(c, "binary_le_xyzl.ply",
        ply_header("binary_little_endian", [("vertex", 2, xyz + ["uint label"])]) +
        struct.pack("<fffIfffI", 0, 0, 0, 1, 1, 2, 3, 4))
    put(c, "binary_be_double.ply",
        ply_header("binary_big_endian",
                   [("vertex", 2, ["double x", "double y", "double z", "uchar red"])]) +
        struct.pack(">dddBdddB", 1, 2, 3, 255, 4, 5, 6, 0))
    put(c, "with_faces.ply",
        ply_header("ascii", [("vertex", 3, xyz), ("face", 1, ["list uchar int vertex_indices"])])
        + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    put(c, "normals_colors.ply",
        ply_header("ascii", [("vertex", 2, xyz + ["float nx", "float ny", "float nz",
                                                  "uchar red", "uchar green", "uchar blue"])])
        + b"0 0 0 0 0 1 255 0 0\n1 1 1 1 0 0 0 255 0\n")

    m = "mesh_ply"
    tri = ["list uchar int vertex_indices"]
    put(m, "ascii_labels.ply",
        ply_header("ascii", [("vertex", 4, xyz),
                             ("face", 2, tri + ["uchar label"])]) +
        b"0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 1\n3 0 2 3 2\n")
    put(m, "ascii_quad_crlf.ply",
        (ply_header("ascii", [("vertex", 4, xyz), ("face", 1, ["list uchar uint vertex_index"])])
         + b"0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n").replace(b"\n", b"\r\n"))
    body = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 1)
    body += struct.pack("<B3iI", 3, 0, 1, 2, 3) + struct.pack("<B4iI", 4, 0, 1, 2, 3, 1)
    put(m, "binary_le_labels.ply",
        ply_header("binary_little_endian",
                   [("vertex", 4, xyz), ("face", 2, tri + ["uint label"])]) + body)
    body = struct.pack(">9d", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    body += struct.pack(">H3hh", 3, 0, 1, 2, 4)
    put(m, "binary_be_short.ply",
        ply_header("binary_big_endian",
                   [("vertex", 3, ["double x", "double y", "double z"]),
                    ("face", 1, ["list ushort short vertex_indices", "short label"])]) + body)
    put(m, "extra_elements.ply",
        ply_header("ascii", [("camera", 1, ["float view_px"]), ("vertex", 3, xyz + ["float s"]),
                             ("face", 1, tri + ["list uchar float texcoord"]),
                             ("edge", 1, ["int vertex1", "int vertex2"])]) +
        b"0.5\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2 2 0.5 0.5\n0 1\n")


def vrml():
    t = "mesh_vrml"
    put(t, "plant_yup.wrl", (FIXTURES / "plant_yup.wrl").read_bytes())
    put(t, "primitives.wrl", """#VRML V2.0 utf8
DEF Plant Transform {
  translation 0 0.1 0 rotation 1 0 0 0.5 scale 1 2 1
  center 0 0.05 0 scaleOrientation 0 0 1 0.3
  children [
    DEF Pot Shape { geometry Box { size 0.2 0.1 0.2 } }
    Transform { translation 0 0.3 0 children Shape { geometry Cylinder { radius 0.01 height 0.5 top FALSE } } }
    Shape { geometry Cone { bottomRadius 0.05 height 0.1 side TRUE bottom FALSE } }
    DEF Fruit Shape { geometry Sphere { radius 0.02 } }
  ]
}
Transform { translation 0.1 0 0 scale -1 1 1 children [ USE Fruit ] }
""")
    put(t, "groups.wrl", """#VRML V2.0 utf8
PROTO Leaf [ field SFFloat size 1 ] { Shape { geometry Box { size IS size } } }
EXTERNPROTO Stem [ ] "stem.wrl"
Group { children [
  Switch { whichChoice 1 choice [ Shape { geometry Box { } }
    Shape { geometry IndexedFaceSet { ccw FALSE
      coord DEF C Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] }
      coordIndex [ 0, 1, 2, 3, -1, 0 2 1 ] } } ] }
  LOD { level [ Shape { geometry IndexedFaceSet { coord USE C coordIndex [ 0 1 2 ] } } ] }
  Collision { children [ Billboard { children [ Anchor { children [ Leaf { } ] } ] } ] }
  Inline { url "other.wrl" }
  Script { field SFFloat x 0x1F eventIn SFBool go }
] }
ROUTE A.b TO C.d
""")


def assimp():
    # The first byte picks the format: 0 .obj, 1 .stl, 2 .dae (fuzz_mesh_assimp.cpp);
    # 0x10 forces Y up.
    t = "mesh_assimp"
    for name, kind in [("two_groups.obj", 0), ("two_objects.obj", 0), ("tetra_ascii.stl", 1),
                       ("plant_cm_yup.dae", 2), ("plant_cm_zup.dae", 2)]:
        put(t, name, bytes([kind]) + (FIXTURES / name).read_bytes())
    put(t, "quads.obj", bytes([0x10]) + b"o leaf\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        b"vn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\ng stem\nf -4 -3 -2\n")
    tris = struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0"
    tris += struct.pack("<12f", 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 0) + b"\0\0"
    put(t, "binary.stl", bytes([1]) + b"solid binary".ljust(80, b" ") +
        struct.pack("<I", 2) + tris)
    put(t, "x_up.dae", bytes([2]) + b"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="0.001"/><up_axis>X_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
<technique_common><accessor source="#pa" count="3" stride="3">
<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
</accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<polylist count="1"><input semantic="VERTEX" source="#v" offset="0"/>
<vcount>3</vcount><p>0 1 2</p></polylist>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node name="leaf">
<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
<instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
""")


def collada():
    t = "collada_text"
    for name in ["plant_cm_yup.dae", "plant_cm_zup.dae"]:
        put(t, name, (FIXTURES / name).read_bytes())
    # Node graphs: shared instances (a DAG), a cycle through library_nodes, self-instancing,
    # nesting, and instances that double at each level.
    head = ('<?xml version="1.0"?>\n<COLLADA xmlns="http://www.collada.org/2005/11/'
            'COLLADASchema" version="1.4.1">\n')
    put(t, "shared.dae", head + '<library_nodes><node id="leaf"/></library_nodes>\n'
        '<library_visual_scenes><visual_scene id="s"><node id="a">'
        '<instance_node url="#leaf"/><instance_node url="#leaf"/></node>'
        '<node id="b"><node id="c"><instance_node url="#a"/></node></node>'
        '</visual_scene></library_visual_scenes></COLLADA>\n')
    put(t, "cycle.dae", head + '<library_nodes><node id="x"><instance_node url="#y"/></node>'
        '<node id="y"><node><instance_node url="#x"/></node></node></library_nodes>\n'
        '<library_visual_scenes><visual_scene id="s"><node><instance_node url="#x"/>'
        '</node></visual_scene></library_visual_scenes></COLLADA>\n')
    put(t, "self.dae", head + '<library_visual_scenes><visual_scene id="s">'
        '<node id="n"><instance_node url="#n"/></node></visual_scene>'
        '</library_visual_scenes></COLLADA>\n')
    doubling = "".join('<node id="d%d"><instance_node url="#d%d"/><instance_node url="#d%d"/>'
                       '</node>' % (i, i + 1, i + 1) for i in range(8)) + '<node id="d8"/>'
    put(t, "doubling.dae", head + "<library_nodes>" + doubling + "</library_nodes>\n"
        "</COLLADA>\n")


def roi():
    t = "roi_yaml"
    put(t, "rois.yaml", (FIXTURES / "rois.yaml").read_bytes())
    put(t, "flow.yaml", "boxes: [{name: 'a b', center: [1, 0, 1.15], size: [+0.05, 5e-2, .7]},"
        " {center: [0, 0, 0], size: [0, 0, 0]}]\n")
    put(t, "quoted.yaml", "# comment\nboxes:\n  - name: \"null\"\n    center: [-1.5e0, 0x10, 2]\n"
        "    size: [1, 2, 3]\n")


def anatomy():
    t = "anatomy_json"
    leaflet = {"base": [1.0, 0.01, 0.9], "tip": [1.0, 0.08, 0.92], "length_m": 0.07,
               "width_m": 0.03, "terminal": False}
    plant = {
        "format": "plantnbv-anatomy", "version": 1, "name": "tomato_seed3",
        "base_position": [1.0, 0.0, 0.8], "yaw_rad": 0.5235987755982988,
        "stem": {"axis": [[1.0, 0.0, 0.8], [1.0, 0.0, 1.0], [1.0, 0.0, 1.3]],
                 "radius_m": [0.006, 0.005, 0.0], "height_m": 0.5, "top_height_m": 0.55},
        "leaves": [{"node": {"leaf_index": 0, "position": [1.0, 0.0, 0.9],
                             "stem_point": [1.0, 0.0, 0.9],
                             "petiole_direction": [0.0, 1.0, 0.0]},
                    "axis": [[1.0, 0.0, 0.9], [1.0, 0.1, 0.95]], "length_m": 0.12,
                    "full_leaflet_count": 3,
                    "leaflets": [leaflet, dict(leaflet, terminal=True)]}],
        "trusses": [{"leaf_below": 0, "attachment": [1.0, 0.0, 0.95],
                     "peduncle": [[1.0, 0.0, 0.95], [1.0, -0.03, 0.93]],
                     "fruits": [{"center": [1.0, -0.04, 0.9], "radius_m": 0.02}]}]}
    put(t, "plant.json", json.dumps(plant, indent=1))
    put(t, "no_leaves.json", json.dumps(dict(plant, leaves=[], trusses=[])))


def depth_png(width, height, units):
    """A 16-bit grey PNG (the depth images of a frames folder), big-endian pixels."""
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff))
    rows = b"".join(b"\0" + struct.pack(">%dH" % width, *units[y * width:(y + 1) * width])
                    for y in range(height))
    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def frames():
    # camera.yaml, groundtruth.txt, depth.txt and depth/000000.png, separated by NUL
    # bytes (fuzz_frames_folder.cpp).
    t = "frames_folder"
    ros_yaml = """image_width: 640
image_height: 480
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [525., 0., 319.5, 0., 525., 239.5,
         0., 0., 1.]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [0., 0., 0., 0., 0.]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1., 0., 0., 0., 1., 0., 0., 0., 1.]
projection_matrix:
  rows: 3
  cols: 4
  data: [525., 0., 319.5, 0., 0., 525., 239.5, 0., 0., 0., 1., 0.]
depth_scale: 5000
"""
    # In the form of TUM RGB-D fr1/xyz: poses at 100 Hz, depth at 30 Hz.
    tum_poses = """# ground truth trajectory
# file: 'rgbd_dataset_freiburg1_xyz.bag'
# timestamp tx ty tz qx qy qz qw
1305031102.1558 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248
1305031102.1658 1.3402 0.6264 1.6578 0.6578 0.6121 -0.2950 -0.3246
1305031102.1758 1.3397 0.6263 1.6579 0.6583 0.6116 -0.2950 -0.3245
1305031102.1858 1.3393 0.6262 1.6581 0.6587 0.6111 -0.2951 -0.3244
1305031102.1958 1.3388 0.6261 1.6583 0.6591 0.6106 -0.2952 -0.3242
"""
    tum_depth = """# depth maps
# file: 'rgbd_dataset_freiburg1_xyz.bag'
# timestamp filename
1305031102.160407 depth/1305031102.160407.png
1305031102.194330 depth/1305031102.194330.png
1305031102.226738 depth/1305031102.226738.png
"""
    put(t, "ros_tum_fr1.bin", "\0".join([ros_yaml, tum_poses, tum_depth]))
    # As FramesFolderWriter writes a folder (writeCameraInfo's camera.yaml), with its
    # first PNG: 8 x 6 pixels, 0 = no return.
    written_yaml = """# ROS camera_info (as camera_calibration writes it) + depth_scale (plantnbv)
image_width: 8
image_height: 6
camera_name: depth
camera_matrix:
  rows: 3
  cols: 3
  data: [3.3333333333333335, 0, 3.5, 0, 4.25, 2.5, 0, 0, 1]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [0, 0, 0, 0, 0]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [3.3333333333333335, 0, 3.5, 0, 0, 4.25, 2.5, 0, 0, 0, 1, 0]
depth_scale: 1000
"""
    written_poses = ("# T_W_O: the depth camera's optical frame (z forward, x right, y down) "
                     "in the world (z up)\n# timestamp tx ty tz qx qy qz qw\n"
                     "0.000000 0.59999999999999998 0.29999999999999999 1.3 "
                     "-0.5 0.5 -0.5 0.5\n"
                     "1.000000 0.5 -0.10000000000000001 1.2 0.27059805007309851 "
                     "0.65328148243818829 -0.65328148243818818 -0.27059805007309845\n")
    written_depth = ("# depth images (16-bit PNG, depth_scale units per metre in "
                     "camera.yaml)\n# timestamp filename\n"
                     "0.000000 depth/000000.png\n1.000000 depth/000000.png\n")
    units = [0 if i % 7 == 0 else 400 + 13 * i for i in range(48)]
    put(t, "written_8x6.bin", b"\0".join([written_yaml.encode(), written_poses.encode(),
                                          written_depth.encode(), depth_png(8, 6, units)]))
    # CRLF, blank lines, poses out of order, a frame without a pose, a quaternion to
    # normalize, a subnormal, poses.txt-style numbers.
    put(t, "unsorted_crlf.bin", "\0".join([
        "image_width: 4\r\nimage_height: 2\r\ncamera_matrix: {rows: 3, cols: 3, "
        "data: [2, 0, 1.5, 0, 2, 0.5, 0, 0, 1]}\r\ndistortion_model: plumb_bob\r\n"
        "distortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, 0, 0]}\r\n",
        "\r\n# t x y z qx qy qz qw\r\n2.01 1 2 3 0 0 0 1.0005\r\n"
        "0.995 -1e-3 5e-324 0x1p-3 0 0.6 0 0.8\r\n1.5 0 0 0 1 0 0 0\r\n",
        "1.0 depth/000000.png\r\n\r\n2.0\tdepth/000000.png\r\n3.0 depth/x.png\r\n",
        ""]).encode() + depth_png(4, 2, [1, 2, 65535, 0, 5000, 6000, 7000, 8000]))


def detections():
    # Detection files for an 8 x 6 image (fuzz_detections_json.cpp); beside the input,
    # "mask.png" is an 8 x 6 mask, "small.png" a 4 x 3 one, "text.png" not a PNG.
    t = "detections_json"
    put(t, "boxes.json", json.dumps({"detections": [
        {"class": "leaf_node", "score": 0.9, "box": [1.5, 2, 3.5, 3]},
        {"class": "fruit", "score": 1, "box": [0, 0, 8, 6]},
        {"class": "main_stem", "score": 0.0, "box": [3, 3, 3, 3]}]}, indent=1))
    put(t, "masks.json", '{"detections": [\n'
        '  {"class": "fruit", "score": 0.75, "box": [4, 2, 8, 6], "mask": "mask.png"},\n'
        '  {"class": "leaf_node", "score": 0.5, "box": [0, 0, 1, 1], "mask": "./mask.png"}\n'
        ']}\n')
    put(t, "empty.json", '{"detections": []}\n')
    put(t, "bad_mask_size.json", '{"detections": [{"class": "a", "score": 0.5, '
        '"box": [0, 0, 1, 1], "mask": "small.png"}]}')
    put(t, "bad_mask_png.json", '{"detections": [{"class": "a", "score": 0.5, '
        '"box": [0, 0, 1, 1], "mask": "text.png"}]}')
    put(t, "bad_mask_path.json", '{"detections": [{"class": "a", "score": 0.5, '
        '"box": [0, 0, 1, 1], "mask": "../mask.png"}]}')
    put(t, "bad_values.json", '{"detections": [{"class": "", "score": 1.5, '
        '"box": [3, 0, 2, 9], "colour": "red"}]}')
    put(t, "repeated_key.json", '{"detections": [{"class": "a", "class": "b", '
        '"score": 0.5, "box": [0, 0, 1, 1]}], "x": [[{"k": 1, "k": 2}]]}')
    put(t, "not_json.json", '{"detections": [{"class": "a", "score": 1e999, "box": [0, 0')


def campaign():
    t = "campaign_yaml"
    for name in ["quick.yaml", "paper.yaml", "roi_error.yaml", "roi_detections.yaml",
                 "roi_prior.yaml", "third_party.yaml"]:
        put(t, name, (ROOT / "data" / "campaigns" / name).read_bytes())
    put(t, "models.yaml", """name: models
seed: 7
plants:
  - {model: plant.ply, labels: "stem=Stem.*,leaflet=Leaf.*", rois: rois.yaml, name: m1}
  - {seed: 2, stage: 0.5, simplified: true}
yaws_deg: [0, -45.5]
views: 3
candidates: 9
resolution: 0.005
repetitions: 2
levels: [whole_plant, model_rois]
trial:
  camera: l515-640
  noise: true
  initial_view: {position: [0.6, 0.3, 1.3], orientation: [0, 0, 0, 1]}
  sector: {radius: 0.4, height: 0.7, bottom: 0.0, angle_deg: 90, rows: 3, cols: 3}
  map: {prob_hit: 0.7, prob_miss: 0.4, clamp_min: 0.12, clamp_max: 0.97,
        occupancy_threshold: 0.5, max_range: 0.75}
  gain: {raycast_range: 0.75, rays_x: 32, rays_y: 24, visibility_weighted: false}
  scene: {floor: true, support: false}
  stop_gain_bits: 0.5
studies:
  - name: s
    planners:
      - {type: nbv, attention: rois.yaml, name: mine}
      - {type: predefined, patterns: [2]}
    candidates: [9, 18]
    resolutions: [0.004]
""")


def yaml():
    t = "yaml_document"
    # Anchors shared without cycles, merge-like reuse, both styles, quoting, a comment.
    put(t, "anchors.yaml", "base: &b {x: 1, 'y': [2, 3]}\nother: *b\n"
        "list: [*b, *b, {z: &z [4]}, *z]\n# note\n")
    put(t, "block.yaml", "a:\n  - b:\n      - c: 1\n        d: \"two\"\n  - [e, {f: ~}]\n"
        "g: |\n  text\n")
    # Shapes the checks refuse: a cycle, deep nesting, a repeated key, aliases that
    # multiply (small enough to stay under the limit here; the fuzzer grows them).
    put(t, "cycle.yaml", "a: &x [1, {b: *x}]\n")
    put(t, "deep.yaml", "[" * 40 + "1" + "]" * 40 + "\n")
    put(t, "repeated.yaml", "k: 1\nm: {k: 2}\nk: 3\n")
    laughs = "a0: &a0 [x, x, x]\n" + "".join(
        "a%d: &a%d [*a%d, *a%d, *a%d]\n" % (i, i, i - 1, i - 1, i - 1) for i in range(1, 6))
    put(t, "laughs.yaml", laughs)


if __name__ == "__main__":
    if OUT.exists():
        shutil.rmtree(OUT)
    for make in [pcd, ply, vrml, assimp, collada, roi, frames, anatomy, detections,
                 campaign, yaml]:
        make()
    for d in sorted(OUT.iterdir()):
        print("%-14s %d files" % (d.name, len(list(d.iterdir()))))
