#!/usr/bin/env python3
"""An independent producer of a frames folder, and a check of the map plantnbv makes of it.

Usage: independent_frames.py PLANTNBV WORK_DIR [--mutate KIND]

Shares no code with plantnbv: it reads the plant's PLY mesh, renders depth images with
its own z-buffer rasterizer (numpy), writes a frames folder the way a TUM / ROS tool
would (camera.yaml as camera_calibration writes it, depth_scale 5000, poses.txt with
offset stamps and a pose without a frame, 16-bit PNGs from its own encoder), runs
`plantnbv integrate`, reads the map's .ot file itself and measures how far each occupied
voxel centre is from the mesh (exact point-to-triangle distances). The claim checked:
a map made from frames written by another program lies on the plant's surface: more
than 1000 occupied voxels, >= 95 % of their centres within 1.5 voxels of the mesh and
>= 99 % within half a voxel's diagonal + 0.2 mm (each voxel holds a surface point).

--mutate writes a deliberately wrong folder (to see that the check would catch it):
  cx          camera.yaml's cx 1 px off the one rendered with
  half-pixel  rays through pixel corners instead of pixel centres
  range       depth written as the range along the ray instead of z
  body-frame  poses of the camera's body frame (x forward) instead of the optical frame
Exit status: 0 pass, 1 fail, 77 skipped (numpy missing).
"""

import math
import os
import shutil
import struct
import subprocess
import sys
import time
import zlib

try:
    import numpy as np
except ImportError:
    print("SKIP: numpy is not installed for " + sys.executable +
          " (Debian: apt-get install python3-numpy)")
    sys.exit(77)

WIDTH, HEIGHT = 160, 120
FX = FY = 114.25
CX, CY = 81.0, 58.5          # off centre: (W-1)/2 = 79.5, (H-1)/2 = 59.5
DEPTH_SCALE = 5000.0         # TUM's own sequences: 1/5000 m per unit
AXIS = np.array([1.0, 0.0])  # the stem axis (x, y); the plant's base is (1, 0, 0.8)
RADIUS = 0.4
# (azimuth of the camera around the axis in degrees, height in metres)
VIEWS = [(0.0, 1.0), (125.0, 1.15), (240.0, 1.3)]
RESOLUTION = 0.003           # plantnbv integrate's default voxel size
NEAR = 0.05                  # triangles with a vertex nearer than this are not drawn
CHUNK = 1 << 18              # candidate pixels per vectorized batch


# ---------------------------------------------------------------------------- mesh ---
PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
    "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def read_ply(path):
    """Vertices (n x 3 float64) and triangles (m x 3 int64) of an ascii or binary PLY."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError(path + ": not a PLY file")
    body = data.index(b"\n", end) + 1
    header = data[:body].decode("ascii").splitlines()
    fmt, elements = None, []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            if w[1] == "list":
                elements[-1][2].append((w[4], "list", PLY_TYPES[w[2]], PLY_TYPES[w[3]]))
            else:
                elements[-1][2].append((w[2], PLY_TYPES[w[1]], None, None))
    verts, faces = None, []
    if fmt == "ascii":
        tokens = data[body:].split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = []
                for pname, kind, ctype, itype in props:
                    if kind == "list":
                        n = int(tokens[pos]); pos += 1
                        row.append([int(t) for t in tokens[pos:pos + n]]); pos += n
                    else:
                        row.append(float(tokens[pos])); pos += 1
                rows.append(row)
            if name == "vertex":
                names = [p[0] for p in props]
                ix = [names.index(c) for c in "xyz"]
                verts = np.array([[r[i] for i in ix] for r in rows], dtype=np.float64)
            elif name == "face":
                li = [p[1] for p in props].index("list")
                faces = [r[li] for r in rows]
    else:
        end_char = "<" if fmt == "binary_little_endian" else ">"
        pos = body
        for name, count, props in elements:
            if all(p[1] != "list" for p in props):
                dt = np.dtype([(p[0], end_char + p[1]) for p in props])
                arr = np.frombuffer(data, dtype=dt, count=count, offset=pos)
                pos += dt.itemsize * count
                if name == "vertex":
                    verts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
                continue
            rows = []
            for _ in range(count):
                row = None
                for pname, kind, ctype, itype in props:
                    if kind == "list":
                        (n,) = struct.unpack_from(end_char + ctype, data, pos)
                        pos += struct.calcsize(ctype)
                        row = struct.unpack_from(end_char + itype * n, data, pos)
                        pos += struct.calcsize(itype) * n
                    else:
                        pos += struct.calcsize(kind)
                rows.append(row)
            if name == "face":
                faces = rows
    tris = []
    for f in faces:  # fan-triangulate polygons
        for k in range(1, len(f) - 1):
            tris.append((f[0], f[k], f[k + 1]))
    return verts, np.array(tris, dtype=np.int64).reshape(-1, 3)


# ----------------------------------------------------------------------- the camera ---
def optical_pose(azimuth_deg, height):
    """R_W_O (columns: the optical x right, y down, z forward in the world) and t_W_O."""
    a = math.radians(azimuth_deg)
    t = np.array([AXIS[0] + RADIUS * math.cos(a), AXIS[1] + RADIUS * math.sin(a), height])
    z = np.array([-math.cos(a), -math.sin(a), 0.0])   # horizontal, at the axis
    y = np.array([0.0, 0.0, -1.0])                     # image rows go down
    x = np.cross(y, z)
    return np.stack([x, y, z], axis=1), t


def quaternion(R):
    """(qx, qy, qz, qw) of a rotation matrix (Shepperd's method)."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = ((R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, s / 4)
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = (s / 4, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s, (R[2, 1] - R[1, 2]) / s)
    elif R[1, 1] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = ((R[0, 1] + R[1, 0]) / s, s / 4, (R[1, 2] + R[2, 1]) / s, (R[0, 2] - R[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = ((R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, s / 4, (R[1, 0] - R[0, 1]) / s)
    return q


def render_depth(verts_W, tris, R, t, pixel_offset=0.0, range_not_z=False):
    """z (metres) of the nearest triangle at each pixel centre, NaN where none.

    A z-buffer rasterizer: each triangle is projected, the pixel centres (integer
    coordinates) inside its projection are found by edge functions, and the depth at a
    centre is where the centre's ray ((u - cx) / fx, (v - cy) / fy, 1) meets the
    triangle's plane."""
    P = (verts_W - t) @ R                     # optical frame: R^T (p - t)
    T = P[tris]                               # m x 3 x 3
    keep = np.all(T[:, :, 2] > NEAR, axis=1)
    T = T[keep]
    u = FX * T[:, :, 0] / T[:, :, 2] + CX - pixel_offset
    v = FY * T[:, :, 1] / T[:, :, 2] + CY - pixel_offset
    u0 = np.maximum(np.ceil(u.min(axis=1)), 0).astype(np.int64)
    u1 = np.minimum(np.floor(u.max(axis=1)), WIDTH - 1).astype(np.int64)
    v0 = np.maximum(np.ceil(v.min(axis=1)), 0).astype(np.int64)
    v1 = np.minimum(np.floor(v.max(axis=1)), HEIGHT - 1).astype(np.int64)
    nu, nv = u1 - u0 + 1, v1 - v0 + 1
    live = (nu > 0) & (nv > 0)
    T, u, v, u0, v0, nu, nv = T[live], u[live], v[live], u0[live], v0[live], nu[live], nv[live]
    normal = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    offset = np.einsum("ij,ij->i", normal, T[:, 0])
    area = (u[:, 1] - u[:, 0]) * (v[:, 2] - v[:, 0]) - (u[:, 2] - u[:, 0]) * (v[:, 1] - v[:, 0])

    zbuf = np.full(WIDTH * HEIGHT, np.inf)
    counts = nu * nv
    ends = np.cumsum(counts)
    first = 0
    while first < len(counts):  # batches of whole triangles, about CHUNK pixels each
        last = int(np.searchsorted(ends, (ends[first - 1] if first else 0) + CHUNK, "right"))
        last = max(last, first + 1)
        sel = np.arange(first, last)
        c = counts[sel]
        tri = np.repeat(sel, c)
        local = np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c)
        pu = u0[tri] + local % nu[tri]
        pv = v0[tri] + local // nu[tri]
        su, sv = pu.astype(np.float64), pv.astype(np.float64)
        tu, tv = u[tri], v[tri]
        # Edge functions of the three edges, signed like the triangle's area.
        e0 = (tu[:, 1] - tu[:, 0]) * (sv - tv[:, 0]) - (tv[:, 1] - tv[:, 0]) * (su - tu[:, 0])
        e1 = (tu[:, 2] - tu[:, 1]) * (sv - tv[:, 1]) - (tv[:, 2] - tv[:, 1]) * (su - tu[:, 1])
        e2 = (tu[:, 0] - tu[:, 2]) * (sv - tv[:, 2]) - (tv[:, 0] - tv[:, 2]) * (su - tu[:, 2])
        a = area[tri]
        inside = ((a > 0) & (e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | \
                 ((a < 0) & (e0 <= 0) & (e1 <= 0) & (e2 <= 0))
        ray = np.stack([(su + pixel_offset - CX) / FX, (sv + pixel_offset - CY) / FY,
                        np.ones_like(su)], axis=1)
        denom = np.einsum("ij,ij->i", normal[tri], ray)
        ok = inside & (np.abs(denom) > 1e-15)
        z = np.where(ok, offset[tri] / np.where(ok, denom, 1.0), np.inf)
        ok &= z > NEAR
        np.minimum.at(zbuf, (pv * WIDTH + pu)[ok], z[ok])
        first = last
    zbuf[~np.isfinite(zbuf)] = np.nan
    depth = zbuf.reshape(HEIGHT, WIDTH)
    if range_not_z:
        uu, vv = np.meshgrid(np.arange(WIDTH), np.arange(HEIGHT))
        depth = depth * np.sqrt(((uu - CX) / FX) ** 2 + ((vv - CY) / FY) ** 2 + 1.0)
    return depth


# ------------------------------------------------------------------------- writing ---
def write_png16(path, image):
    """A 16-bit greyscale PNG (colour type 0, bit depth 16, big-endian samples)."""
    h, w = image.shape
    raw = b"".join(b"\x00" + image[r].astype(">u2").tobytes() for r in range(h))

    def chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload +
                struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def camera_yaml(cx):
    """camera.yaml as ROS camera_calibration writes it, plus depth_scale."""
    k = [FX, 0, cx, 0, FY, CY, 0, 0, 1]
    p = [FX, 0, cx, 0, 0, FY, CY, 0, 0, 0, 1, 0]
    f = lambda vals: ", ".join("%.6f" % x for x in vals)
    return ("image_width: %d\nimage_height: %d\ncamera_name: independent_depth\n"
            "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [%s]\n"
            "distortion_model: plumb_bob\n"
            "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [%s]\n"
            "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [%s]\n"
            "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [%s]\n"
            "depth_scale: %g\n" % (WIDTH, HEIGHT, f(k), f([0] * 5), f([1, 0, 0, 0, 1, 0, 0, 0, 1]),
                                   f(p), DEPTH_SCALE))


def write_frames(folder, verts, tris, mutate):
    os.makedirs(os.path.join(folder, "depth"))
    with open(os.path.join(folder, "camera.yaml"), "w") as f:
        f.write(camera_yaml(CX + 1.0 if mutate == "cx" else CX))
    base = 1305031102.160407
    depth_lines = ["# depth maps", "# file: 'independent_frames.py'", "# timestamp filename"]
    pose_lines = ["# ground truth trajectory", "# file: 'independent_frames.py'",
                  "# timestamp tx ty tz qx qy qz qw"]
    pose_dt = [0.0093, -0.0071, 0.0048]  # pose stamps off the frames' by up to 0.01 s
    returns = []
    for i, (azimuth, height) in enumerate(VIEWS):
        R, t = optical_pose(azimuth, height)
        depth = render_depth(verts, tris, R, t,
                             pixel_offset=0.5 if mutate == "half-pixel" else 0.0,
                             range_not_z=mutate == "range")
        units = np.where(np.isfinite(depth), np.round(np.nan_to_num(depth) * DEPTH_SCALE), 0)
        units = np.where(units > 65535, 0, units).astype(np.uint16)
        returns.append(int(np.count_nonzero(units)))
        stamp = "%.6f" % (base + 0.633 * i)
        name = "depth/%s.png" % stamp
        write_png16(os.path.join(folder, name), units)
        depth_lines.append("%s %s" % (stamp, name))
        if mutate == "body-frame":  # T_W_C: x forward, y left, z up
            R = np.stack([R[:, 2], -R[:, 0], -R[:, 1]], axis=1)
        q = quaternion(R)
        pose_lines.append("%.6f %s" % (base + 0.633 * i + pose_dt[i],
                                       " ".join("%.6f" % x for x in list(t) + list(q))))
        if i == 0:  # a pose with no frame (0.3 s from any), far off the plant
            pose_lines.append("%.6f 0.000000 0.000000 2.000000 0.000000 0.000000 0.000000 "
                              "1.000000" % (base + 0.3))
    with open(os.path.join(folder, "depth.txt"), "w") as f:
        f.write("\n".join(depth_lines) + "\n")
    with open(os.path.join(folder, "poses.txt"), "w") as f:
        f.write("\n".join(pose_lines) + "\n")
    return returns


# ------------------------------------------------------------------------- the map ---
def read_ot_occupied(path):
    """Centres of the occupied voxels (finest level) of an OctoMap .ot (full) file."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"# Octomap OcTree file"):
        raise ValueError(path + ": not an OctoMap .ot file")
    pos, res, tree_id = 0, None, None
    while True:
        nl = data.index(b"\n", pos)
        line = data[pos:nl].decode("ascii").strip()
        pos = nl + 1
        if line.startswith("id "):
            tree_id = line[3:]
        elif line.startswith("res "):
            res = float(line[4:])
        elif line == "data":
            break
    if tree_id != "OcTree" or res is None:
        raise ValueError(path + ": id %r, res %r" % (tree_id, res))
    occupied_blocks = []  # (lower key x, y, z, size in voxels)
    # Depth-first: each node is its float log-odds and a byte of existing children;
    # child i takes the upper half of x if i & 1, of y if i & 2, of z if i & 4.
    stack = [(0, 0, 0, 65536)]
    while stack:
        kx, ky, kz, size = stack.pop()
        (logodds,) = struct.unpack_from("<f", data, pos)
        children = data[pos + 4]
        pos += 5
        if children == 0:
            if logodds > 0.0:  # probability > 0.5
                occupied_blocks.append((kx, ky, kz, size))
            continue
        half = size // 2
        for i in reversed(range(8)):  # popped in order 0..7
            if children & (1 << i):
                stack.append((kx + (half if i & 1 else 0), ky + (half if i & 2 else 0),
                              kz + (half if i & 4 else 0), half))
    if pos != len(data):
        raise ValueError(path + ": %d bytes after the tree" % (len(data) - pos))
    keys = []
    for kx, ky, kz, size in occupied_blocks:
        r = np.arange(size)
        g = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)
        keys.append(g + (kx, ky, kz))
    keys = np.concatenate(keys) if keys else np.zeros((0, 3), dtype=np.int64)
    return (keys - 32768 + 0.5) * res


# ------------------------------------------------------------------------ distance ---
def point_triangle_distance(p, a, b, c):
    """Exact distance from points p to triangles (a, b, c), all n x 3."""
    n = np.cross(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    good = nn > 1e-30
    nn = np.where(good, nn, 1.0)
    # Barycentrics of p's projection on the plane.
    ap = p - a
    w_b = np.einsum("ij,ij->i", np.cross(ap, c - a), n) / nn
    w_c = np.einsum("ij,ij->i", np.cross(b - a, ap), n) / nn
    inside = good & (w_b >= 0) & (w_c >= 0) & (w_b + w_c <= 1)
    plane = np.abs(np.einsum("ij,ij->i", ap, n)) / np.sqrt(nn)

    def segment(p, s0, s1):
        d = s1 - s0
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-30)
        tt = np.clip(np.einsum("ij,ij->i", p - s0, d) / dd, 0.0, 1.0)
        return np.linalg.norm(p - (s0 + tt[:, None] * d), axis=1)

    edge = np.minimum(np.minimum(segment(p, a, b), segment(p, b, c)), segment(p, c, a))
    return np.where(inside, plane, edge)


def distances_to_mesh(points, verts, tris, reach):
    """Each point's distance to the mesh, exact up to `reach`; beyond it: inf."""
    cell = reach
    T = verts[tris]
    lo = np.floor((T.min(axis=1) - reach) / cell).astype(np.int64)
    hi = np.floor((T.max(axis=1) + reach) / cell).astype(np.int64)
    origin = lo.min(axis=0)
    dims = hi.max(axis=0) - origin + 1
    lo -= origin
    hi -= origin
    # (cell, triangle) pairs for every cell that a triangle's grown box touches.
    span = hi - lo + 1
    count = span.prod(axis=1)
    tri = np.repeat(np.arange(len(tris)), count)
    local = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    sx, sy = span[tri, 0], span[tri, 1]
    cx_ = lo[tri, 0] + local % sx
    cy_ = lo[tri, 1] + (local // sx) % sy
    cz_ = lo[tri, 2] + local // (sx * sy)
    cell_id = (cz_ * dims[1] + cy_) * dims[0] + cx_
    order = np.argsort(cell_id, kind="stable")
    cell_id, tri = cell_id[order], tri[order]

    q = np.floor(points / cell).astype(np.int64) - origin
    inside = np.all((q >= 0) & (q < dims), axis=1)
    qid = np.where(inside, (q[:, 2] * dims[1] + q[:, 1]) * dims[0] + q[:, 0], -1)
    start = np.searchsorted(cell_id, qid, "left")
    stop = np.searchsorted(cell_id, qid, "right")
    stop = np.where(inside, stop, start)
    best = np.full(len(points), np.inf)
    n = stop - start
    # In batches of points, so that the (point, triangle) pairs stay small.
    ends = np.cumsum(n)
    first = 0
    while first < len(points):
        last = int(np.searchsorted(ends, (ends[first - 1] if first else 0) + 2_000_000, "right"))
        last = max(last, first + 1)
        idx = np.arange(first, last)
        m = n[idx]
        pt = np.repeat(idx, m)
        pair = np.repeat(start[idx] - (np.cumsum(m) - m), m) + np.arange(m.sum())
        t_ = tri[pair]
        d = point_triangle_distance(points[pt], T[t_, 0], T[t_, 1], T[t_, 2])
        np.minimum.at(best, pt, d)
        first = last
    best[best > reach] = np.inf
    return best


# ---------------------------------------------------------------------------- main ---
def run(cmd, log):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + r.stdout)
    if r.returncode != 0:
        print(r.stdout)
        raise SystemExit("FAIL: %s exited %d" % (" ".join(cmd), r.returncode))
    return r.stdout


def main(argv):
    if len(argv) not in (3, 5) or (len(argv) == 5 and argv[3] != "--mutate"):
        print(__doc__)
        return 2
    plantnbv, work = argv[1], argv[2]
    mutate = argv[4] if len(argv) == 5 else "none"
    if mutate not in ("none", "cx", "half-pixel", "range", "body-frame"):
        print("unknown --mutate " + mutate)
        return 2
    clock = time.time()
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    plant_dir = os.path.join(work, "plant")
    run([plantnbv, "plant", "--seed", "2", "-o", plant_dir], os.path.join(work, "plant.log"))
    verts, tris = read_ply(os.path.join(plant_dir, "plant.ply"))
    print("mesh: %d vertices, %d triangles" % (len(verts), len(tris)))

    frames = os.path.join(work, "frames")
    returns = write_frames(frames, verts, tris, mutate)
    print("wrote %s: %d frames (%s returns), mutate %s; %.1f s"
          % (frames, len(returns), ", ".join(map(str, returns)), mutate, time.time() - clock))

    map_path = os.path.join(work, "map.ot")
    out = run([plantnbv, "integrate", frames, "-o", map_path], os.path.join(work, "integrate.log"))
    print(out.strip().splitlines()[-1])
    centres = read_ot_occupied(map_path)
    reported = int(out.split("': ")[-1].split(" occupied")[0])

    dist = distances_to_mesh(centres, verts, tris, reach=4 * RESOLUTION)
    n = len(centres)
    frac = lambda r: float(np.count_nonzero(dist < r)) / max(n, 1)
    half_diagonal = math.sqrt(3) / 2 * RESOLUTION
    finite = dist[np.isfinite(dist)]
    print("occupied voxels: %d (integrate says %d)" % (n, reported))
    print("fraction of occupied voxel centres within 1.5 voxels (%.1f mm) of the mesh: %.4f"
          % (1.5 * RESOLUTION * 1e3, frac(1.5 * RESOLUTION)))
    print("  within a voxel's half diagonal + 0.2 mm (%.2f mm): %.4f; within 1 voxel: %.4f; "
          "within 4 voxels: %.4f" % ((half_diagonal + 2e-4) * 1e3, frac(half_diagonal + 2e-4),
                                     frac(RESOLUTION), frac(4 * RESOLUTION)))
    print("  median distance %.2f mm, 99th percentile %.2f mm (of those within 4 voxels)"
          % (np.median(finite) * 1e3 if len(finite) else float("nan"),
             np.percentile(finite, 99) * 1e3 if len(finite) else float("nan")))
    print("total %.1f s" % (time.time() - clock))

    failures = []
    if n != reported:
        failures.append("the .ot holds %d occupied voxels, integrate reported %d" % (n, reported))
    if n <= 1000:
        failures.append("only %d occupied voxels (expected > 1000)" % n)
    if frac(1.5 * RESOLUTION) < 0.95:
        failures.append("%.4f of the occupied voxel centres are within 1.5 voxels of the "
                        "mesh (expected >= 0.95)" % frac(1.5 * RESOLUTION))
    # Every occupied voxel holds a return, a point on the surface (up to the PNG's
    # 0.2 mm units), so its centre is within half a voxel's diagonal of the surface:
    # this catches what 1.5 voxels lets through (cx 1 px off: 0.88; rays through pixel
    # corners: 0.91).
    if frac(half_diagonal + 2e-4) < 0.99:
        failures.append("%.4f of the occupied voxel centres are within %.2f mm (half a "
                        "voxel's diagonal + 0.2 mm) of the mesh (expected >= 0.99)"
                        % (frac(half_diagonal + 2e-4), (half_diagonal + 2e-4) * 1e3))
    for f in failures:
        print("FAIL: " + f)
    if not failures:
        print("PASS: the map of the independent frames lies on the plant's surface")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
