#!/usr/bin/python3
"""A picture of a dense map's mesh.ply as a camera of the run saw the room: the mesh's vertices (1 cm apart at the
default voxel) projected into a pinhole camera, nearest first, coloured by their vertex colour and shaded by their
normal. For looking at a map without a display, and for the pictures in docs/dense.md (python3-open3d, Pillow).

    scripts/mesh_picture.py RUN/mesh.ply --trajectory RUN/keyframes.txt --at 0.5 --out picture.png
        [--back 1.0] [--width 640 --height 480 --fx 400]

--at: which pose of the trajectory, as a share of its length (0 the first, 1 the last); --back: metres the
viewpoint is moved back along the camera's view, so that more of the room is in the picture.
"""

import argparse
import sys

import numpy as np
import open3d as o3d
from PIL import Image


def rotation_of(qx, qy, qz, qw):
    x, y, z, w = qx, qy, qz, qw
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("--trajectory", required=True, help="TUM trajectory (the run's keyframes.txt)")
    parser.add_argument("--at", type=float, default=0.0)
    parser.add_argument("--back", type=float, default=0.0)
    parser.add_argument("--out", required=True)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--fx", type=float, default=400.0)
    args = parser.parse_args()

    poses = [list(map(float, line.split())) for line in open(args.trajectory) if line.strip() and line[0] != "#"]
    if not poses:
        sys.exit(f"error: {args.trajectory}: no poses")
    _, tx, ty, tz, qx, qy, qz, qw = poses[min(len(poses) - 1, int(args.at * (len(poses) - 1)))]
    rotation = rotation_of(qx, qy, qz, qw)
    centre = np.array([tx, ty, tz]) - args.back * rotation[:, 2]

    mesh = o3d.io.read_triangle_mesh(args.mesh)
    if len(mesh.vertices) == 0:
        sys.exit(f"error: {args.mesh}: no vertices")
    mesh.compute_vertex_normals()
    points = (np.asarray(mesh.vertices) - centre) @ rotation  # camera coordinates
    normals = np.asarray(mesh.vertex_normals) @ rotation
    colours = np.asarray(mesh.vertex_colors) if mesh.has_vertex_colors() else np.full(points.shape, 0.7)
    ahead = points[:, 2] > 0.1
    points, normals, colours = points[ahead], normals[ahead], colours[ahead]
    u = np.round(args.fx * points[:, 0] / points[:, 2] + args.width / 2).astype(int)
    v = np.round(args.fx * points[:, 1] / points[:, 2] + args.height / 2).astype(int)
    inside = (u >= 0) & (u < args.width) & (v >= 0) & (v < args.height)
    u, v, points, normals, colours = u[inside], v[inside], points[inside], normals[inside], colours[inside]
    shade = 0.35 + 0.65 * np.abs((normals * points).sum(1) / np.linalg.norm(points, axis=1))
    # Each vertex covers 2 × 2 pixels, so that the surface closes at the mesh's spacing; nearer ones written last.
    offsets = [(0, 0), (1, 0), (0, 1), (1, 1)]
    uu = np.concatenate([np.clip(u + du, 0, args.width - 1) for du, _ in offsets])
    vv = np.concatenate([np.clip(v + dv, 0, args.height - 1) for _, dv in offsets])
    depth = np.tile(points[:, 2], len(offsets))
    shaded = np.tile(colours * shade[:, None], (len(offsets), 1))
    farthest_first = np.argsort(-depth)
    image = np.ones((args.height, args.width, 3))
    image[vv[farthest_first], uu[farthest_first]] = shaded[farthest_first]
    Image.fromarray((np.clip(image, 0, 1) * 255).astype(np.uint8)).save(args.out)


if __name__ == "__main__":
    main()
