"""Writes summary.md from the four tables in this folder: our time over each peer's, same run."""
import csv
import os

os.chdir(os.path.dirname(os.path.abspath(__file__)))


def load(f, keys):
    return {tuple(r[k] for k in keys): float(r['value']) for r in csv.DictReader(open(f))}


out = ["# Split headers, performance A/B (generated from the CSVs in this folder)", "",
       "Same-run ratios before and after the split of kd_tree.hpp, octree.hpp, ellipsoid.hpp and kdop.hpp",
       "(one run each, same machine, back to back; figures swing about ±5-15% between runs here).", "",
       "## kNN, uniform 1e6, 3D double: kd_tree time / peer time", "", "| peer | operation | before | after |",
       "|---|---|---|---|"]
K = ('structure', 'operation', 'params', 'metric')
a, b = load('knn_before.csv', K), load('knn_after.csv', K)
for k in sorted(a):
    if k[3] == 'time_ratio' and k[1] in ('knn', 'radius', 'build'):
        out.append(f"| {k[0]} | {k[1]} {k[2]} | {a[k]:.3f} | {b[k]:.3f} |")
out += ["", "## Rays, sphere 1e6 triangles: bvh (aabb) time / peer time", "", "| peer | rays | before | after |",
        "|---|---|---|---|"]
K = ('structure', 'bv', 'operation', 'params', 'metric')
a, b = load('raycast_before.csv', K), load('raycast_after.csv', K)
for peer in ('embree', 'cgal_aabb_tree'):
    for rays in ('rays=incoherent', 'rays=coherent;camera=128x128'):
        ours = ('bvh', 'aabb', 'ray', rays, 'time_per_op')
        theirs = (peer, '', 'ray', rays, 'time_per_op')
        out.append(f"| {peer} | {rays} | {a[ours] / a[theirs]:.3f} | {b[ours] / b[theirs]:.3f} |")
open('summary.md', 'w').write("\n".join(out) + "\n")
