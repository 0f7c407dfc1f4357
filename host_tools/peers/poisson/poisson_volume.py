#!/usr/bin/env python3
"""Screened Poisson peer of the accuracy report (docs/accuracy.md "Peers").

Measures the pit volume of a cloud written by
`pitvol measure FILE --export-levelled OUT.ply` (bottom plane at z = 0, the
pit opening towards +z, mm; the rim height in the comment pitvol_rim_mm):

 1. statistical outlier removal (20 neighbours, 3 sigma) and points above
    rim + 30 mm dropped (they cannot shape the surface below the lid);
 2. normals from 30 nearest neighbours, oriented into the void: each normal
    is flipped to face a target on the pit axis above its point,
    (cx, cy, z + max(0.2 r, 20 mm)), r the point's distance from the axis:
    walls face the axis (undercuts too, up to 79 deg from vertical), floor
    and ground face up;
 3. Open3D's screened Poisson reconstruction, depth 9 (as CloudCompare's
    and MeshLab's defaults use it);
 4. no density trimming: the volume only reads the surface in the columns
    inside the rim outline, where the samples are dense; trimming there
    opened the surface at the floor's edge (a cylinder read +0.9 %, the
    columns below read +0.02 % on the untrimmed mesh);
 5. vertical rays on a 0.5 mm grid over the rim outline (per 5 deg sector
    the third largest radius of the samples 1 to 10 mm below the rim, as
    the 2.5D grid peer draws it, plus 5 mm) list every crossing of the surface; along a ray, a crossing whose
    triangle faces up (into the void) starts void, one facing down ends it;
    the void below the rim plane, summed over the columns, is the volume.
    Undercuts (a ray crossing the wall twice) count correctly.

Prints one JSON object. Exit 0 measured, 3 unreadable input, 4 no volume.
"""
import json
import sys
import time

import numpy as np
import open3d as o3d


def read_rim(path):
    with open(path, "rb") as f:
        for raw in f:
            line = raw.decode("ascii", "replace").split()
            if line[:2] == ["comment", "pitvol_rim_mm"]:
                return float(line[2])
            if line[:1] == ["end_header"]:
                break
    return None


def column_void_mm(z, nz, rim):
    """Length of void below rim along one upward ray: crossings z (sorted)
    with the z-component nz of their triangles' void-facing normals."""
    length, start = 0.0, None
    for zi, ni in zip(z, nz):
        if zi > rim:
            break
        if ni > 0:
            start = zi
        elif start is not None:
            length += zi - start
            start = None
    if start is not None:
        length += rim - start
    return length


def main():
    if len(sys.argv) < 2:
        print("usage: poisson_volume.py LEVELLED.ply [--depth 9]", file=sys.stderr)
        return 2
    path = sys.argv[1]
    depth = 9
    if "--depth" in sys.argv:
        depth = int(sys.argv[sys.argv.index("--depth") + 1])
    t0 = time.monotonic()
    rim = read_rim(path)
    pcd = o3d.io.read_point_cloud(path)
    if rim is None or rim <= 0 or len(pcd.points) == 0:
        print(json.dumps({"status": "refused", "message": "not a levelled pitvol cloud with a rim",
                          "volume_cm3": None}))
        return 3
    o3d.utility.random.seed(1)
    pts = np.asarray(pcd.points)
    pcd = pcd.select_by_index(np.nonzero(pts[:, 2] <= rim + 30.0)[0])
    pcd, _ = pcd.remove_statistical_outlier(nb_neighbors=20, std_ratio=3.0)
    pts = np.asarray(pcd.points)

    low = pts[pts[:, 2] < 0.5 * rim]
    if len(low) < 100:
        print(json.dumps({"status": "refused", "message": "no points below half the depth",
                          "volume_cm3": None}))
        return 4
    cx, cy = np.median(low[:, 0]), np.median(low[:, 1])

    pcd.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(knn=30))
    n = np.asarray(pcd.normals)
    r = np.hypot(pts[:, 0] - cx, pts[:, 1] - cy)
    target = np.stack([np.full(len(pts), cx), np.full(len(pts), cy),
                       pts[:, 2] + np.maximum(0.2 * r, 20.0)], axis=1)
    flip = np.einsum("ij,ij->i", n, target - pts) < 0
    n[flip] *= -1
    pcd.normals = o3d.utility.Vector3dVector(n)

    t_poisson = time.monotonic()
    if "--load-mesh" in sys.argv:  # debugging the volume on a saved surface
        mesh = o3d.io.read_triangle_mesh(sys.argv[sys.argv.index("--load-mesh") + 1])
        dens = np.zeros(len(mesh.vertices))
    else:
        mesh, dens = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pcd, depth=depth)
    t_poisson = time.monotonic() - t_poisson
    if "--save-mesh" in sys.argv:
        o3d.io.write_triangle_mesh(sys.argv[sys.argv.index("--save-mesh") + 1], mesh)
        np.save(sys.argv[sys.argv.index("--save-mesh") + 1] + ".dens.npy", np.asarray(dens))
    mesh.compute_triangle_normals()
    tn = np.asarray(mesh.triangle_normals)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))

    # rim outline, as the 2.5D grid peer draws it (grid25.h): per sector the
    # third largest radius of the samples 1 to 10 mm below the rim (two
    # strays cannot widen it), here per 5 deg, plus a 5 mm margin of ground
    band = pts[(pts[:, 2] >= rim - 10.0) & (pts[:, 2] <= rim - 1.0)]
    sectors = 72

    def sector_of(x, y):
        return ((np.arctan2(y - cy, x - cx) + np.pi) / (2 * np.pi) * sectors).astype(int) % sectors

    bs = sector_of(band[:, 0], band[:, 1])
    br = np.hypot(band[:, 0] - cx, band[:, 1] - cy)
    outline = np.zeros(sectors)
    for k in range(sectors):
        rk = br[bs == k]
        if len(rk) >= 3:
            outline[k] = np.partition(rk, len(rk) - 3)[len(rk) - 3]
    if (outline == 0).sum() * 2 > sectors:
        print(json.dumps({"status": "refused", "volume_cm3": None,
                          "message": "the top of the wall is seen in fewer than half the directions"}))
        return 4
    outline[outline == 0] = outline[outline > 0].min()
    outline += 5.0

    h = 0.5
    g = np.arange(-outline.max(), outline.max(), h) + h / 2
    X, Y = np.meshgrid(cx + g, cy + g)
    X, Y = X.ravel(), Y.ravel()
    keep = np.hypot(X - cx, Y - cy) <= outline[sector_of(X, Y)]
    X, Y = X[keep], Y[keep]
    z_from = float(pts[:, 2].min()) - 50.0
    rays = np.zeros((len(X), 6), dtype=np.float32)
    rays[:, 0], rays[:, 1], rays[:, 2], rays[:, 5] = X, Y, z_from, 1.0
    hits = scene.list_intersections(o3d.core.Tensor(rays))
    splits = hits["ray_splits"].numpy()
    z_hit = z_from + hits["t_hit"].numpy().astype(np.float64)
    nz_hit = tn[hits["primitive_ids"].numpy(), 2]
    # Open3D orients the Poisson surface along the input normals (into the
    # void); check it on the lowest crossing of the central ray (the floor).
    centre = int(np.argmin(np.hypot(X - cx, Y - cy)))
    a, b = splits[centre], splits[centre + 1]
    if b > a and nz_hit[a + int(np.argmin(z_hit[a:b]))] < 0:
        nz_hit = -nz_hit
    vol_mm3 = 0.0
    for i in range(len(X)):
        a, b = splits[i], splits[i + 1]
        if b > a:
            o = np.argsort(z_hit[a:b])
            vol_mm3 += float(column_void_mm(z_hit[a:b][o], nz_hit[a:b][o], rim)) * h * h
    ms = (time.monotonic() - t0) * 1000.0
    print(json.dumps({"status": "ok", "volume_cm3": vol_mm3 / 1000.0, "rim_mm": rim,
                      "depth": depth, "points": int(len(pts)), "columns": int(len(X)),
                      "triangles": int(len(tn)), "poisson_ms": round(t_poisson * 1000.0, 1),
                      "ms": round(ms, 1)}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
