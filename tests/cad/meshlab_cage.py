"""MeshLab's side of the cage comparison (app/tests/cli_cage_meshlab.rs), through pymeshlab.

    python meshlab_cage.py decimate ORIGINAL OUT.obj FACES [OUT.obj FACES ...]
        MeshLab's quadric edge collapse alone, as a designer would run it for a light mesh:
        optimal placement, topology and boundary preserved, down to FACES triangles, from the
        original each time; writes each cage and prints a JSON list of {"faces": n, "seconds": the
        decimation's own time, loading and saving excluded}.
    python meshlab_cage.py measure ORIGINAL SURFACE [SURFACE ...]
        MeshLab's own measures of each SURFACE (a sampled limit surface) against ORIGINAL: the
        Hausdorff distance both ways (vertices, edges and faces sampled, 200,000 samples a side),
        the mean of the two one-sided mean distances, both over the original's bounding-box
        diagonal, and the relative volume change (null when the original is open). Prints a JSON
        list, one entry a surface.
"""
import json
import sys
import time

import pymeshlab

SAMPLES = 200_000


def load(*paths):
    ms = pymeshlab.MeshSet()
    for p in paths:
        ms.load_new_mesh(p)
    return ms


def decimate(original, *pairs):
    results = []
    for out, faces in zip(pairs[::2], pairs[1::2]):
        ms = load(original)
        started = time.perf_counter()
        ms.meshing_decimation_quadric_edge_collapse(
            targetfacenum=int(faces), optimalplacement=True, preservetopology=True, preserveboundary=True
        )
        seconds = time.perf_counter() - started
        ms.save_current_mesh(out, save_vertex_normal=False)
        results.append({"faces": ms.current_mesh().face_number(), "seconds": seconds})
    print(json.dumps(results))


def measure(original, *surfaces):
    results = []
    for surface in surfaces:
        ms = load(original, surface)
        diagonal = ms.mesh(0).bounding_box().diagonal()
        common = dict(samplevert=True, sampleedge=True, sampleface=True, samplenum=SAMPLES)
        forward = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, **common)
        backward = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, **common)
        ms.set_current_mesh(0)
        closed = ms.get_topological_measures()["boundary_edges"] == 0
        volumes = []
        for k in (0, 1):
            ms.set_current_mesh(k)
            volumes.append(ms.get_geometric_measures().get("mesh_volume"))
        change = abs(volumes[1] - volumes[0]) / abs(volumes[0]) if closed and volumes[0] else None
        results.append(
            {
                "hausdorff": max(forward["max"], backward["max"]) / diagonal,
                "mean": 0.5 * (forward["mean"] + backward["mean"]) / diagonal,
                "volume_change": change,
            }
        )
    print(json.dumps(results))


if __name__ == "__main__":
    command, *args = sys.argv[1:]
    {"decimate": decimate, "measure": measure}[command](*args)
