#!/usr/bin/python3
"""Open3D point clouds through the accelerator model: read two scans with Open3D (any format it
reads: .pcd, .ply, .xyz ...; KITTI .bin through tigris.load_cloud), voxel-downsample them there, and run the first's points as queries
into a tree of the second's with tigris.run, checked against the golden model.

    sudo apt-get install python3-open3d       # Debian's Open3D; only this example needs it
    PYTHONPATH=PREFIX/lib/python3/dist-packages python3 open3d_run.py SOURCE TARGET [--voxel 0.2]
    python3 open3d_run.py --builtin            # the built-in pair, through Open3D's structures

Open3D holds points as float64; the model's arithmetic is float32, so the arrays are converted
once (np.asarray(...).astype(np.float32)) and the results index those points.
"""
import argparse

import numpy as np
import open3d as o3d

import tigris


def read(path):
    """Open3D's reader, or tigris's for KITTI .bin scans (which Open3D does not read)."""
    if path.endswith(".bin"):
        cloud = o3d.geometry.PointCloud()
        cloud.points = o3d.utility.Vector3dVector(tigris.load_cloud(path).astype(np.float64))
        return cloud
    return o3d.io.read_point_cloud(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*", metavar="FILE", help="SOURCE TARGET (Open3D reads them)")
    ap.add_argument("--builtin", action="store_true", help="the built-in synthetic pair instead")
    ap.add_argument("--voxel", type=float, default=0.2, help="voxel size in metres (0: none)")
    ap.add_argument("--k", type=int, default=8, help="neighbours per query")
    a = ap.parse_args()
    if a.builtin == bool(a.files) or (a.files and len(a.files) != 2):
        ap.error("give SOURCE TARGET, or --builtin")
    if a.builtin:
        target_pts, source_pts = tigris.synthetic_pair()
        source, target = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
        source.points = o3d.utility.Vector3dVector(source_pts.astype(np.float64))
        target.points = o3d.utility.Vector3dVector(target_pts.astype(np.float64))
    else:
        source, target = (read(f) for f in a.files)
        for f, c in zip(a.files, (source, target)):
            if not c.has_points():
                ap.error(f"Open3D read no points from {f}")
    if a.voxel > 0:
        source, target = source.voxel_down_sample(a.voxel), target.voxel_down_sample(a.voxel)
    queries = np.asarray(source.points).astype(np.float32)
    cloud = np.asarray(target.points).astype(np.float32)
    job = tigris.run(cloud, queries, mode="knn", k=a.k)
    print(f"{len(queries):,} queries into {len(cloud):,} points, kNN k={a.k}: {job.verdict}, "
          f"{job.cycles:,} cycles ({job.seconds * 1e3:.3f} ms), {job.stats['energy_pj']['total'] * 1e-6:.1f} uJ, "
          f"{job.bound} bound")
    # The neighbours as Open3D sees them: colour each target point by how often it was found.
    hits = np.bincount(job.indices.reshape(-1), minlength=len(cloud))
    colours = np.zeros((len(cloud), 3))
    colours[:, 0] = np.minimum(hits / max(1, hits.max()), 1.0)
    target.colors = o3d.utility.Vector3dVector(colours)
    print(f"{int((hits > 0).sum()):,} target points are someone's neighbour; the busiest one {int(hits.max())} times")


if __name__ == "__main__":
    main()
