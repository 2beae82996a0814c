#!/usr/bin/env python3
"""The union of an SWC scene's links built with manifold3d, at a certified tolerance.

The peer side of docs/report/union_mesh_peers.md: the same links `tubecast mesh` meshes
(each link the convex hull of its two end spheres: a round cone), the same two-sided
Hausdorff tolerance eps to the union's exact surface, and what it costs (wall time per
phase, peak resident memory, triangles, the binary PLY bytes tubecast's writer would use).

Construction: every node sphere is manifold's `Manifold.sphere(r, n)`; each link is
`batch_hull` of its two spheres; the solid is `batch_boolean(links, Add)`.

Certificate (one way of the two-sided bound tubecast certifies; see below for the other):
* manifold's sphere is inscribed: its vertices lie on the sphere up to rounding, measured
  here (`vertex_out`), so the hulls, and their union, lie inside the exact union up to that.
* if P_a, P_b contain the balls B(a, r_a - s_a), B(b, r_b - s_b) (s the sphere polyhedron's
  sagitta: r minus its least face-plane distance from the centre, measured from manifold's
  own triangles), their hull contains (1-t) P_a + t P_b, which contains
  B(c(t), r(t) - ((1-t) s_a + t s_b)): every generating ball of the round cone shrunk by at
  most max(s_a, s_b). The round cone shrunk by d (d <= both radii) is the round cone with both
  radii reduced by d. So a point of the union's surface is within max s of the solid's
  surface (union surface -> mesh <= max(max s, vertex_out)).
* the other way is NOT max s: a mesh point is at most s deep in every tube, but where two
  hulls' faces cross (a crease of the union, exterior opening beta) the mesh vertex there is
  up to s / sin(beta/2) from the union's surface (its distance to the exact crease), and
  sin(beta/2) -> 0 for tubes overlapping at a narrow angle. The `certified` printed here is
  the one-way bound max s; --check measures min over tubes of the SDF, which is the depth
  only away from creases. tubecast's own union (crates/render/src/mesh/union/) bounds the
  depth with witnesses outside the union (docs/design/union-mesh.md, "The bound").
The segment count n of each sphere is the least multiple of 4 (manifold rounds
`circularSegments` to one) whose measured sagitta r * c(n) is <= eps - vertex_out, chosen per
radius (a sphere of a thin branch needs fewer segments than the soma).

Pinned: manifold3d==3.5.4, numpy==2.4.6 (crates/lab/peers/requirements.txt), run in a venv:
    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install --only-binary=:all: \
        -r crates/lab/peers/requirements.txt
    /usr/bin/time -v /tmp/peers/bin/python crates/lab/peers/union_manifold.py SCENE.swc \
        --eps-rel 1e-2 [--out union.ply] [--threads 2]
Prints one JSON object. --eps-rel is relative to the mean node radius (as the report's).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import sys
import time


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scene", help="SWC file (id type x y z r parent)")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--eps", type=float, help="absolute tolerance (scene units)")
    g.add_argument("--eps-rel", type=float, help="tolerance relative to the mean node radius")
    p.add_argument("--out", help="write the union as binary PLY (f32 positions, as tubecast's)")
    p.add_argument("--threads", type=int, default=0, help="CPUs to pin the process to (0: all)")
    p.add_argument(
        "--check",
        action="store_true",
        help="check the bound at the vertices and triangle centroids against the exact union SDF "
        "(numpy, O(points x links): small scenes)",
    )
    return p.parse_args()


def read_swc(path):
    """Nodes (x, y, z, r) in file order and links (node, parent) as index pairs."""
    ids, nodes, parents = {}, [], []
    with open(path, "r", encoding="utf-8") as f:
        for line in f:
            s = line.split("#", 1)[0].split()
            if not s:
                continue
            if len(s) < 7:
                raise SystemExit(f"{path}: a row with {len(s)} columns (7 expected): {line!r}")
            i, x, y, z, r, parent = int(s[0]), *map(float, s[2:6]), int(s[6])
            if i in ids:
                raise SystemExit(f"{path}: repeated id {i}")
            if not (r > 0.0 and all(math.isfinite(v) for v in (x, y, z, r))):
                raise SystemExit(f"{path}: node {i} has radius {r} or a non-finite position")
            ids[i] = len(nodes)
            nodes.append((x, y, z, r))
            parents.append(parent)
    links = []
    for k, parent in enumerate(parents):
        if parent == -1:
            continue
        if parent not in ids:
            raise SystemExit(f"{path}: parent {parent} of row {k} is not in the file")
        links.append((ids[parent], k))
    return nodes, links


def union_sdf(np, P, nodes, links):
    """The exact signed distance of the union of round cones at points P (k x 3): min over
    links of the round cone's closed form (Quilez's sdRoundCone, exact inside and out; where
    one end sphere holds the other, that sphere's)."""
    N = np.asarray(nodes, dtype=np.float64)
    best = np.full(len(P), np.inf)
    for i, j in links:
        a, ra, b, rb = N[i, :3], N[i, 3], N[j, :3], N[j, 3]
        ba = b - a
        l2 = ba @ ba
        rr = ra - rb
        a2 = l2 - rr * rr
        if a2 <= 0.0:  # one sphere inside the other (or a zero-length link)
            c, r = (a, ra) if ra >= rb else (b, rb)
            d = np.linalg.norm(P - c, axis=1) - r
        else:
            pa = P - a
            y = pa @ ba
            z = y - l2
            q = pa * l2 - np.outer(y, ba)
            x2 = np.einsum("ij,ij->i", q, q)
            y2, z2 = y * y * l2, z * z * l2
            k = np.sign(rr) * rr * rr * x2
            d = (np.sqrt(x2 * a2 / l2) + y * rr) / l2 - ra
            d = np.where(np.sign(y) * a2 * y2 < k, np.sqrt(x2 + y2) / l2 - ra, d)
            d = np.where(np.sign(z) * a2 * z2 > k, np.sqrt(x2 + z2) / l2 - rb, d)
        best = np.minimum(best, d)
    return best


def main():
    a = parse_args()
    if a.threads > 0 and hasattr(os, "sched_setaffinity"):
        cpus = sorted(os.sched_getaffinity(0))[: a.threads]
        os.sched_setaffinity(0, set(cpus))  # before TBB's pool starts: it sizes to these
    import numpy as np
    from importlib.metadata import version
    from manifold3d import Error, Manifold, OpType

    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    t0 = time.perf_counter()
    nodes, links = read_swc(a.scene)
    radii = np.array([n[3] for n in nodes])
    r_mean = float(radii.mean())
    eps = a.eps if a.eps is not None else a.eps_rel * r_mean
    t_read = time.perf_counter() - t0

    # Sagitta and vertex radius error of the unit sphere per segment count, measured from
    # manifold's own triangles (the sphere scales exactly with r, up to rounding).
    cache = {}

    def unit_sagitta(n):
        if n not in cache:
            m = Manifold.sphere(1.0, n).to_mesh64()
            V = np.asarray(m.vert_properties)[:, :3].astype(np.float64)
            F = np.asarray(m.tri_verts).astype(np.int64)
            A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
            nrm = np.cross(B - A, C - A)
            nrm /= np.linalg.norm(nrm, axis=1)[:, None]
            face = np.abs(np.einsum("ij,ij->i", nrm, A))
            vr = np.linalg.norm(V, axis=1)
            cache[n] = (float(1.0 - face.min()), float(max(vr.max() - 1.0, 0.0)))
        return cache[n]

    t0 = time.perf_counter()
    seg = {}
    bound = 0.0
    for r in sorted(set(radii.tolist())):
        n = 4
        while True:
            s, out = unit_sagitta(n)
            if r * (s + out) <= eps:
                break
            n += 4
            if n > 1 << 16:
                raise SystemExit(f"radius {r}: no sphere within eps = {eps}")
        seg[r] = n
        bound = max(bound, r * (s + out))
    spheres = {}

    def sphere(i):
        if i not in spheres:
            x, y, z, r = nodes[i]
            spheres[i] = Manifold.sphere(r, seg[r]).translate((x, y, z))
        return spheres[i]

    pieces = [Manifold.batch_hull([sphere(i), sphere(j)]) for i, j in links]
    spheres.clear()
    t_hull = time.perf_counter() - t0

    t0 = time.perf_counter()
    solid = Manifold.batch_boolean(pieces, OpType.Add) if len(pieces) > 1 else pieces[0]
    pieces.clear()
    tri = solid.num_tri()  # forces the lazy boolean
    status = solid.status()
    t_bool = time.perf_counter() - t0

    t0 = time.perf_counter()
    mesh = solid.to_mesh64()  # f64 positions (the check reads them; the PLY stores f32)
    V = np.asarray(mesh.vert_properties)[:, :3]
    F = np.asarray(mesh.tri_verts)
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment manifold3d union\n"
        f"element vertex {len(V)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode()
    ply_bytes = len(header) + 12 * len(V) + 13 * len(F)
    if a.out:
        face = np.zeros(len(F), dtype=[("n", "u1"), ("v", "<i4", 3)])
        face["n"], face["v"] = 3, F
        with open(a.out, "wb") as f:
            f.write(header)
            f.write(np.ascontiguousarray(V, dtype="<f4").tobytes())
            f.write(face.tobytes())
    t_out = time.perf_counter() - t0

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    check = None
    if a.check:
        V64 = np.asarray(V, dtype=np.float64)
        pts = np.concatenate([V64, V64[F].mean(axis=1)])
        f = union_sdf(np, pts, nodes, links)
        # Inside the union by at most the bound, outside by at most rounding.
        check = dict(points=int(len(pts)), deepest=float(-f.min()), farthest_out=float(f.max()))
        if -f.min() > bound * (1 + 1e-9) + 1e-9 or f.max() > 1e-9 * (1 + abs(pts).max()):
            print(json.dumps(check), file=sys.stderr)
            sys.exit("the manifold mesh breaks the certified bound: see above")
    ns = sorted(set(seg.values()))
    print(
        json.dumps(
            dict(
                scene=a.scene,
                manifold3d=version("manifold3d"),
                links=len(links),
                nodes=len(nodes),
                mean_radius=r_mean,
                eps=eps,
                certified=bound,
                segments_min=ns[0],
                segments_max=ns[-1],
                status=str(status),
                genus=int(solid.genus()),
                vertices=int(len(V)),
                triangles=int(tri),
                ply_bytes=int(ply_bytes),
                seconds=dict(read=t_read, spheres_hulls=t_hull, boolean=t_bool, export=t_out),
                total_seconds=t_read + t_hull + t_bool + t_out,
                peak_rss_bytes=int(peak),
                rss_after_imports_bytes=int(rss0),
                cpus=len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
                manifold_tolerance=float(solid.get_tolerance()),
                check=check,
            )
        )
    )
    if status != Error.NoError:
        sys.exit(f"manifold3d reported {status}")


if __name__ == "__main__":
    main()
