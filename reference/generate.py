#!/usr/bin/env python3
"""Independent ground truth for tubecast: mesh the test scenes with manifold3d, query libigl.

Writes one JSON fixture per scene into the output folder (default: reference/fixtures).

Three independent sources are stored side by side for every ray and every SDF sample:

* ``exact``: the sphere-sweep surface computed here in numpy, *not* from the Rust code:
  per-link exact signed distance (closed form in the plane through the axis) or, for the
  spline tube, ``min_u |x - p(u)| - r(u)`` by dense sampling + bisection on the sign of g';
  ray first boundaries by sphere tracing on that distance, then bisection on its sign.
* ``mesh``: libigl's answers on the manifold3d mesh (first ray hit, signed distance).
* bounds: the mesh's inscribed-sagitta ``h`` measured from the actual triangles.

The mesh is inscribed (every vertex lies on a sphere of the sweep), so mesh hits are never
nearer than the true surface and libigl's signed distance is never smaller than the true
one; see README.md for the bounds the Rust tests derive from ``h``.

Deterministic: every random draw comes from ``numpy.random.default_rng(scene seed)``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

# manifold3d runs its booleans on a TBB thread pool whose scheduling changes which
# near-degenerate triangles its simplification collapses (the triangle count varies by a
# few between runs; the geometry does not). Pin this process to one CPU before the pool
# starts so that regeneration reproduces the committed fixtures exactly.
if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})

import numpy as np  # noqa: E402
import igl  # noqa: E402
import manifold3d  # noqa: E402
from manifold3d import Manifold, OpType

FORMAT_VERSION = 1

# --------------------------------------------------------------------------------------
# Scenes. Nodes are (x, y, z, r); links are node index pairs. Keep these small: the
# regeneration in reference/check.sh must finish in minutes on two cores.
# --------------------------------------------------------------------------------------

SCENES = [
    dict(
        name="link_cone",
        kind="links",
        seed=11,
        n=256,
        nodes=[[0.0, 0.0, 0.0, 1.0], [3.0, 0.5, 0.2, 0.5]],
        links=[[0, 1]],
    ),
    dict(
        name="link_cylinder",
        kind="links",
        seed=12,
        n=256,
        nodes=[[-1.0, 0.3, 0.0, 0.7], [2.0, -0.4, 1.0, 0.7]],
        links=[[0, 1]],
    ),
    dict(
        name="link_steep",
        kind="links",
        seed=13,
        n=256,
        # |ra - rb| close to L: a nearly flat cone, the far sphere almost swallowed.
        nodes=[[0.0, 0.0, 0.0, 1.2], [0.0, 0.0, 1.0, 0.25]],
        links=[[0, 1]],
    ),
    dict(
        name="polyline",
        kind="links",
        seed=14,
        n=256,
        nodes=[
            [0.0, 0.0, 0.0, 0.6],
            [2.0, 0.5, 0.0, 0.45],
            [3.5, 2.0, 0.5, 0.5],
            [3.0, 3.8, 1.5, 0.3],
            [1.5, 4.5, 1.0, 0.35],
        ],
        links=[[0, 1], [1, 2], [2, 3], [3, 4]],
    ),
    dict(
        # A tree: a parent, a 3-way bifurcation with different radii, and a 2-way one.
        name="bifurcation",
        kind="links",
        seed=15,
        n=256,
        nodes=[
            [-3.0, 0.0, 0.0, 0.8],
            [0.0, 0.0, 0.0, 0.6],
            [2.5, 1.8, 0.0, 0.45],
            [2.2, -1.5, 1.2, 0.3],
            [1.0, -0.5, -2.8, 0.22],
            [4.5, 2.2, 0.8, 0.25],
            [3.8, 3.5, -0.9, 0.18],
        ],
        links=[[0, 1], [1, 2], [1, 3], [1, 4], [2, 5], [2, 6]],
    ),
    dict(
        # Same tree, coarse mesh: the Rust tests check that errors scale like 1/n^2.
        name="bifurcation_n64",
        kind="links",
        seed=15,
        n=64,
        same_rays_as="bifurcation",
    ),
    dict(
        name="spline_quadratic",
        kind="spline",
        seed=16,
        n=128,
        # Quadratic Bezier sphere sweep: centre p(u) and radius r(u) both quadratic Beziers.
        control_points=[[0.0, 0.0, 0.0], [2.0, 3.0, 0.5], [4.0, 0.0, 1.0]],
        control_radii=[0.5, 0.8, 0.3],
        samples=160,
    ),
]

N_RANDOM = 160
N_FAR = 40
N_INSIDE = 60
N_GRAZING = 80
N_SDF_POINTS = 60
SDF_OFFSETS = [0.0, 1e-3, -1e-3, 0.03, -0.03, 0.2, -0.2]  # in units of the local radius
FAR_DISTANCE = 1.0e4  # far-origin rays start this many scene radii away


# --------------------------------------------------------------------------------------
# Exact geometry (numpy, independent of the Rust crate)
# --------------------------------------------------------------------------------------


def norm(v):
    return np.linalg.norm(v, axis=-1)


def unit(v):
    return v / norm(v)[..., None]


def random_units(rng, k):
    v = rng.normal(size=(k, 3))
    return unit(v)


class LinkSet:
    """Union of round cones (convex hulls of two spheres)."""

    def __init__(self, nodes, links):
        self.nodes = np.asarray(nodes, dtype=np.float64)
        self.links = np.asarray(links, dtype=np.int64)
        self.a = self.nodes[self.links[:, 0], :3]
        self.ra = self.nodes[self.links[:, 0], 3]
        self.b = self.nodes[self.links[:, 1], :3]
        self.rb = self.nodes[self.links[:, 1], 3]
        v = self.b - self.a
        self.L = norm(v)
        self.axis = v / self.L[:, None]
        self.has_cone = np.abs(self.ra - self.rb) < self.L
        self.s = np.where(self.has_cone, (self.ra - self.rb) / self.L, 0.0)
        self.c = np.sqrt((1.0 - self.s) * (1.0 + self.s))
        self.r_min = float(min(self.ra.min(), self.rb.min()))

    def count(self):
        return len(self.links)

    def link_sdf(self, x, i):
        """Exact signed distance to link i, with the outward normal of the nearest surface
        point, the sweep parameter u of the touching generating sphere and its radius.
        In the plane through the axis (z along the axis from a, rho from the axis) the
        side is the line s*z + c*rho = ra; the normals through its two tangent points split
        the plane into the parts nearest sphere a, the side, and sphere b."""
        a, b, ra, rb = self.a[i], self.b[i], self.ra[i], self.rb[i]
        ax, s, c, L = self.axis[i], self.s[i], self.c[i], self.L[i]
        y = x - a
        z = y @ ax
        radial = y - z[:, None] * ax
        rho = norm(radial)
        da = norm(y) - ra
        db = norm(x - b) - rb
        na = unit_or(y, ax * -1.0)
        nb = unit_or(x - b, ax)
        if not self.has_cone[i]:
            big_a = ra >= rb
            d = da if big_a else db
            n = na if big_a else nb
            u = np.full(len(x), 0.0 if big_a else 1.0)
            r = np.full(len(x), ra if big_a else rb)
            return d, n, u, r
        k = c * z - s * rho
        dc = s * z + c * rho - ra
        rhat = unit_or(radial, any_perp(ax))
        nc = c * rhat + s * ax
        in_a = k < 0.0
        in_b = k > c * L
        d = np.where(in_a, da, np.where(in_b, db, dc))
        n = np.where(in_a[:, None], na, np.where(in_b[:, None], nb, nc))
        u = np.clip(k / (c * L), 0.0, 1.0)
        r = ra + (rb - ra) * u
        return d, n, u, r

    def sdf(self, x):
        """min over links of the per-link exact SDF (exact distance outside the union; inside
        it is minus the largest per-link depth, a lower bound on the true depth). Returns
        (d, normal, link id, u, generating radius, per-link distances)."""
        x = np.atleast_2d(x)
        per = []
        best = None
        for i in range(self.count()):
            d, n, u, r = self.link_sdf(x, i)
            per.append(d)
            if best is None:
                best = [d, n, np.zeros(len(x), dtype=np.int64), u, r]
            else:
                m = d < best[0]
                best[0] = np.where(m, d, best[0])
                best[1] = np.where(m[:, None], n, best[1])
                best[2] = np.where(m, i, best[2])
                best[3] = np.where(m, u, best[3])
                best[4] = np.where(m, r, best[4])
        return best[0], best[1], best[2], best[3], best[4], np.stack(per, axis=1)

    def bounding_sphere(self):
        pts = np.concatenate([self.a, self.b])
        rs = np.concatenate([self.ra, self.rb])
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        radius = float((norm(pts - centre) + rs).max())
        return centre, radius

    def surface_samples(self, rng, k):
        """Points on the boundary of the union: (point, outward normal, link, u, radius)."""
        out = []
        while len(out) < k:
            i = int(rng.integers(self.count()))
            ax, s, c = self.axis[i], self.s[i], self.c[i]
            if not self.has_cone[i]:
                big_a = self.ra[i] >= self.rb[i]
                centre, r, u = (self.a[i], self.ra[i], 0.0) if big_a else (self.b[i], self.rb[i], 1.0)
                w = random_units(rng, 1)[0]
            else:
                choice = rng.random()
                if choice < 0.6:
                    u = rng.random()
                    centre = self.a[i] + u * (self.b[i] - self.a[i])
                    r = self.ra[i] + u * (self.rb[i] - self.ra[i])
                    e1 = any_perp(ax)
                    e2 = np.cross(ax, e1)
                    phi = rng.random() * 2.0 * math.pi
                    w = s * ax + c * (math.cos(phi) * e1 + math.sin(phi) * e2)
                else:
                    w = random_units(rng, 1)[0]
                    if choice < 0.8:
                        if w @ ax > s:
                            continue
                        centre, r, u = self.a[i], self.ra[i], 0.0
                    else:
                        if w @ ax < s:
                            continue
                        centre, r, u = self.b[i], self.rb[i], 1.0
            y = centre + r * w
            _, _, _, _, _, per = self.sdf(y[None])
            others = np.delete(per[0], i)
            if others.size and others.min() < 1e-9:
                continue  # inside (or on) another link: not on the union's boundary
            out.append((y, w, i, u, r, centre))
        return out


class BezierSweep:
    """Sphere sweep S(p(u), r(u)), u in [0, 1], p and r quadratic Beziers."""

    GRID = 2049

    def __init__(self, points, radii):
        self.P = np.asarray(points, dtype=np.float64)
        self.R = np.asarray(radii, dtype=np.float64)
        self.ug = np.linspace(0.0, 1.0, self.GRID)
        self.pg = self.p(self.ug)
        self.rg = self.r(self.ug)
        self.r_min = float(self.rg.min())

    def p(self, u):
        u = np.asarray(u, dtype=np.float64)[..., None]
        w = 1.0 - u
        return w * w * self.P[0] + 2.0 * w * u * self.P[1] + u * u * self.P[2]

    def r(self, u):
        u = np.asarray(u, dtype=np.float64)
        w = 1.0 - u
        return w * w * self.R[0] + 2.0 * w * u * self.R[1] + u * u * self.R[2]

    def dp(self, u):
        u = np.asarray(u, dtype=np.float64)[..., None]
        return 2.0 * (1.0 - u) * (self.P[1] - self.P[0]) + 2.0 * u * (self.P[2] - self.P[1])

    def dr(self, u):
        u = np.asarray(u, dtype=np.float64)
        return 2.0 * (1.0 - u) * (self.R[1] - self.R[0]) + 2.0 * u * (self.R[2] - self.R[1])

    def count(self):
        return 1

    def _g(self, x, u):
        return norm(x - self.p(u)) - self.r(u)

    def _dg(self, x, u):
        """g'(u) = -(x - p(u))·p'(u)/|x - p(u)| - r'(u)."""
        v = x - self.p(u)
        dist = np.maximum(norm(v), np.finfo(np.float64).tiny)
        return -np.sum(v * self.dp(u), axis=-1) / dist - self.dr(u)

    def _refine(self, x, idx):
        """Minimiser of g(u) = |x - p(u)| - r(u) on the two grid cells around idx (g is
        unimodal there for the smooth sweeps used here), by bisection on the sign of g'.

        Golden-section search on values of g would resolve the argmin only to ~sqrt(eps)
        (g is flat to second order at its minimum), so u, and the normal and radius taken
        at it, would depend on the last bits of each evaluation: a machine whose numpy sums
        in another order lands elsewhere on that plateau, ~1e-8 away. Bisection on the sign
        of the derivative resolves u to a few ulps wherever |g''| is not tiny, which makes
        the fixtures reproducible to compare.py's 1e-9."""
        h = 1.0 / (self.GRID - 1)
        lo = np.clip(self.ug[idx] - h, 0.0, 1.0)
        hi = np.clip(self.ug[idx] + h, 0.0, 1.0)
        at_lo = self._dg(x, lo) >= 0.0  # g increasing from the left end: argmin at lo
        at_hi = self._dg(x, hi) <= 0.0  # g decreasing up to the right end: argmin at hi
        a, b = lo.copy(), hi.copy()
        for _ in range(200):
            m = 0.5 * (a + b)
            if not ((m > a) & (m < b)).any():
                break
            up = self._dg(x, m) >= 0.0
            b = np.where(up, m, b)
            a = np.where(up, a, m)
        return np.where(at_lo, lo, np.where(at_hi, hi, 0.5 * (a + b)))

    def sdf(self, x):
        x = np.atleast_2d(x)
        out_d = np.empty(len(x))
        out_u = np.empty(len(x))
        for s0 in range(0, len(x), 256):
            xs = x[s0 : s0 + 256]
            g = norm(xs[:, None, :] - self.pg[None, :, :]) - self.rg[None, :]
            i1 = np.argmin(g, axis=1)
            # second basin: best grid point at least 8 cells away from the first
            far = np.abs(np.arange(self.GRID)[None, :] - i1[:, None]) >= 8
            i2 = np.argmin(np.where(far, g, np.inf), axis=1)
            u1 = self._refine(xs, i1)
            u2 = self._refine(xs, i2)
            g1 = self._g(xs, u1)
            g2 = self._g(xs, u2)
            take2 = g2 < g1
            out_u[s0 : s0 + 256] = np.where(take2, u2, u1)
            out_d[s0 : s0 + 256] = np.where(take2, g2, g1)
        c = self.p(out_u)
        n = unit_or(x - c, np.array([0.0, 0.0, 1.0]))  # at a centre any direction will do
        r = self.r(out_u)
        return out_d, n, np.zeros(len(x), dtype=np.int64), out_u, r, out_d[:, None]

    def bounding_sphere(self):
        pts = self.pg
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        radius = float((norm(pts - centre) + self.rg).max())
        return centre, radius

    def surface_samples(self, rng, k):
        out = []
        while len(out) < k:
            u = rng.random()
            if rng.random() < 0.15:
                u = 0.0 if rng.random() < 0.5 else 1.0
            c, r = self.p(u), float(self.r(u))
            t = self.dp(u)
            tl = norm(t)
            that = t / tl
            cos_b = -float(self.dr(u)) / tl  # w . that on the characteristic circle
            if u in (0.0, 1.0):
                w = random_units(rng, 1)[0]
                sign = -1.0 if u == 0.0 else 1.0
                if sign * (w @ that) < sign * cos_b:
                    continue  # not on the exposed end cap
            else:
                e1 = any_perp(that)
                e2 = np.cross(that, e1)
                phi = rng.random() * 2.0 * math.pi
                sb = math.sqrt(max(0.0, 1.0 - cos_b * cos_b))
                w = cos_b * that + sb * (math.cos(phi) * e1 + math.sin(phi) * e2)
            y = c + r * w
            d = self.sdf(y[None])[0][0]
            if d < -1e-12:
                continue  # covered by another part of the sweep
            out.append((y, w, 0, u, r, c))
        return out


def any_perp(v):
    e = np.array([1.0, 0.0, 0.0]) if abs(v[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e = e - (e @ v) * v
    return e / np.linalg.norm(e)


def unit_or(v, fallback):
    n = norm(v)
    ok = n > 0.0
    safe = np.where(ok, n, 1.0)
    return np.where(ok[:, None], v / safe[:, None], fallback[None, :])


def first_boundary(geo, o, d, t_far):
    """First t >= 0 where the ray o + t d crosses the surface of the solid.

    Outside start: sphere tracing on the exact distance (it never overshoots), then
    bisection on the sign. Inside start: stepping by minus the (lower bound of the) depth,
    then bisection. Returns (t or nan, entering, clearance): clearance is a certified lower
    bound on the distance between a missing ray and the solid (half the smallest sphere
    tracing step, by the 1-Lipschitz property), nan for hits."""
    n = len(o)
    dl = norm(d)
    f0 = geo.sdf(o)[0]
    inside = f0 < 0.0
    t = np.zeros(n)
    f = f0.copy()
    active = np.ones(n, dtype=bool)
    clear = np.full(n, np.inf)
    scale = geo.bounding_sphere()[1]
    eta = 1e-9 * scale
    for _ in range(20000):
        if not active.any():
            break
        idx = np.nonzero(active)[0]
        step = np.abs(f[idx]) / dl[idx]
        t[idx] = t[idx] + step
        f[idx] = geo.sdf(o[idx] + t[idx, None] * d[idx])[0]
        out_side = ~inside[idx]
        clear[idx[out_side]] = np.minimum(clear[idx[out_side]], 0.5 * f[idx[out_side]])
        done = (np.abs(f[idx]) < eta) | ((~inside[idx]) & (f[idx] < 0.0)) | (inside[idx] & (f[idx] > 0.0))
        done |= t[idx] > t_far[idx]
        active[idx[done]] = False
    else:
        raise RuntimeError("sphere tracing did not converge")
    miss = (~inside) & (t > t_far)
    # Bracket the crossing: lo on the start side, hi past the surface.
    lo = t.copy()
    hi = t.copy()
    grow = eta / dl
    ok = ~miss
    for _ in range(80):
        fh = geo.sdf(o + hi[:, None] * d)[0]
        crossed = np.where(inside, fh > 0.0, fh <= 0.0)
        need = ok & ~crossed
        if not need.any():
            break
        lo = np.where(need, hi, lo)
        hi = np.where(need, hi + grow, hi)
        grow = grow * 2.0
    else:
        # A grazing ray that came within eta of the surface but never crossed.
        pass
    fh = geo.sdf(o + hi[:, None] * d)[0]
    crossed = np.where(inside, fh > 0.0, fh <= 0.0)
    grazing_miss = ok & ~crossed
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if not ((mid > lo) & (mid < hi) & ok).any():
            break
        fm = geo.sdf(o + mid[:, None] * d)[0]
        past = np.where(inside, fm > 0.0, fm <= 0.0)
        hi = np.where(ok & past, mid, hi)
        lo = np.where(ok & ~past, mid, lo)
    t_hit = np.where(miss | grazing_miss, np.nan, hi)
    clearance = np.where(miss, clear, np.where(grazing_miss, 0.0, np.nan))
    return t_hit, ~inside, clearance


def certified_deep_until(geo, o, d, t_end, h):
    """For rays starting inside: a T such that every point of o + t d, t in [0, T], lies at
    per-piece depth > h (hence inside the inscribed mesh). The per-piece depth D(t) (minus the
    min over pieces of their exact SDF) is |d|-Lipschitz in t, so D > h on
    [t, t + (D(t) - h)/|d|); stepping by that covers [0, T] without gaps. Steps shrink
    geometrically where D approaches h; stop when they are below 1e-13 of the scene."""
    dl = norm(d)
    t = np.zeros(len(o))
    active = np.ones(len(o), dtype=bool)
    tiny = 1e-13 * geo.bounding_sphere()[1]
    for _ in range(100000):
        if not active.any():
            break
        idx = np.nonzero(active)[0]
        depth = -geo.sdf(o[idx] + t[idx, None] * d[idx])[0]
        step = (depth - h) / dl[idx]
        stop = (step <= tiny / dl[idx]) | (t[idx] >= t_end[idx])
        t[idx] = np.where(stop, t[idx], np.minimum(t[idx] + step, t_end[idx]))
        active[idx[stop]] = False
    else:
        raise RuntimeError("certified_deep_until did not converge")
    return t


# --------------------------------------------------------------------------------------
# Mesh (manifold3d) and its queries (libigl)
# --------------------------------------------------------------------------------------


def sphere_sagitta(r, n):
    """Largest gap between the sphere of radius r and the triangles of Manifold.sphere(r, n):
    r - (distance from the centre to the face plane), maximised over faces. Every point of
    the ball lies within this of the polyhedron (radial projection onto the face it meets)."""
    mesh = Manifold.sphere(r, n).to_mesh64()
    V = np.asarray(mesh.vert_properties)[:, :3].astype(np.float64)
    F = np.asarray(mesh.tri_verts).astype(np.int64)
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    nrm = unit(np.cross(B - A, C - A))
    dist = np.abs(np.einsum("ij,ij->i", nrm, A))
    vr = norm(V)
    return float((r - dist).max()), float(np.abs(vr - r).max())


def build_mesh(scene, geo):
    n = scene["n"]
    if scene["kind"] == "links":
        spheres = [(geo.nodes[i, :3], geo.nodes[i, 3]) for i in range(len(geo.nodes))]
        pieces = []
        for ia, ib in geo.links:
            sa = Manifold.sphere(float(geo.nodes[ia, 3]), n).translate(tuple(geo.nodes[ia, :3]))
            sb = Manifold.sphere(float(geo.nodes[ib, 3]), n).translate(tuple(geo.nodes[ib, :3]))
            pieces.append(Manifold.batch_hull([sa, sb]))
        chord = 0.0
    else:
        k = scene["samples"]
        us = np.linspace(0.0, 1.0, k + 1)
        ps, rs = geo.p(us), geo.r(us)
        spheres = [(ps[j], rs[j]) for j in range(k + 1)]
        balls = [Manifold.sphere(float(rs[j]), n).translate(tuple(ps[j])) for j in range(k + 1)]
        pieces = [Manifold.batch_hull([balls[j], balls[j + 1]]) for j in range(k)]
        # Hull of consecutive samples = sweep of the linear interpolants; |p_lin - p| and
        # |r_lin - r| are at most |p''| du^2 / 8 and |r''| du^2 / 8, and a sphere sweep moves
        # by at most |dp| + |dr| when its spheres do.
        p2 = norm(2.0 * (geo.P[0] - 2.0 * geo.P[1] + geo.P[2]))
        r2 = abs(2.0 * (geo.R[0] - 2.0 * geo.R[1] + geo.R[2]))
        chord = float((p2 + r2) / (8.0 * k * k))
    solid = Manifold.batch_boolean(pieces, OpType.Add) if len(pieces) > 1 else pieces[0]
    if solid.status() != manifold3d.Error.NoError:
        raise RuntimeError(f"manifold3d failed on {scene['name']}: {solid.status()}")
    mesh = solid.to_mesh64()
    V = np.ascontiguousarray(np.asarray(mesh.vert_properties)[:, :3], dtype=np.float64)
    F = np.ascontiguousarray(np.asarray(mesh.tri_verts), dtype=np.int64)
    sag, coeff, vert_err = 0.0, 0.0, 0.0
    seen = {}
    for _, r in spheres:
        key = float(r)
        if key not in seen:
            seen[key] = sphere_sagitta(key, n)
        s, ve = seen[key]
        sag = max(sag, s)
        coeff = max(coeff, s * n * n / key)
        vert_err = max(vert_err, ve)
    info = dict(
        circular_segments=n,
        triangles=int(len(F)),
        vertices=int(len(V)),
        genus=int(solid.genus()),
        sagitta=sag,
        sagitta_coeff=coeff,
        vertex_radius_error=vert_err,
        manifold_tolerance=float(solid.get_tolerance()),
        chord_error=chord,
    )
    return V, F, info


def mesh_first_hits(V, F, tree, o, d, centre, radius):
    """libigl's first hit of each ray, with t recomputed in double.

    libigl's ray–triangle test works in single precision (t is off by ~1e-7 relative, 1e-3
    absolute for far origins), so it is used only to pick the triangle: the origin is first
    moved along the ray to just outside the scene's bounding sphere (exact up to one rounding
    of o + t0 d), and t is recomputed by a double-precision ray–plane intersection with the
    chosen triangle, whose barycentric coordinates are checked in double."""
    oc = o - centre
    dd = np.einsum("ij,ij->i", d, d)
    b = np.einsum("ij,ij->i", oc, d) / dd
    c = (np.einsum("ij,ij->i", oc, oc) - (1.5 * radius) ** 2) / dd
    disc = b * b - c
    t0 = np.where(c > 0.0, np.maximum(0.0, -b - np.sqrt(np.maximum(disc, 0.0))), 0.0)
    o2 = o + t0[:, None] * d
    I, _, _ = tree.intersect_ray_first(V, F, o2, d)
    t = np.full(len(o), np.nan)
    bary_min = np.full(len(o), np.nan)
    for j in range(len(o)):
        if I[j] < 0:
            continue
        A, B, C = V[F[I[j]]]
        nrm = np.cross(B - A, C - A)
        tt = ((A - o2[j]) @ nrm) / (d[j] @ nrm)
        x = o2[j] + tt * d[j]
        area = nrm @ nrm
        l0 = np.cross(B - x, C - x) @ nrm / area
        l1 = np.cross(C - x, A - x) @ nrm / area
        l2 = 1.0 - l0 - l1
        bary_min[j] = min(l0, l1, l2)
        t[j] = t0[j] + tt
    return t, I, bary_min


# --------------------------------------------------------------------------------------
# Fixture assembly
# --------------------------------------------------------------------------------------


def make_geometry(scene):
    if scene["kind"] == "links":
        return LinkSet(scene["nodes"], scene["links"])
    return BezierSweep(scene["control_points"], scene["control_radii"])


def make_rays(scene, geo, h):
    """Rays for a scene; h (for the grazing band) is that of the scene's ray_n resolution so
    that scenes sharing rays (same_rays_as) get identical rays."""
    rng = np.random.default_rng(scene["seed"])
    centre, radius = geo.bounding_sphere()
    rays = []

    def add(kind, o, d):
        for oj, dj in zip(o, d):
            rays.append((kind, oj, dj))

    # random: origins on a sphere of 2.5 scene radii, aimed at random points of the scene
    o = centre + 2.5 * radius * random_units(rng, N_RANDOM)
    target = centre + 0.7 * radius * random_units(rng, N_RANDOM) * rng.random((N_RANDOM, 1)) ** (1 / 3)
    scale = 0.5 + 1.5 * rng.random((N_RANDOM, 1))  # directions need not be unit
    add("random", o, (target - o) * scale / norm(target - o)[:, None])
    # far origin
    o = centre + FAR_DISTANCE * radius * random_units(rng, N_FAR)
    target = centre + 0.5 * radius * random_units(rng, N_FAR)
    add("far", o, unit(target - o))
    # inside: from a generating sphere's centre (depth r(u) >= r_min >> h)
    samp = geo.surface_samples(rng, N_INSIDE)
    o = np.array([s[5] for s in samp])
    add("inside", o, random_units(rng, N_INSIDE) * (0.5 + 1.5 * rng.random((N_INSIDE, 1))))
    # grazing: through a surface point y tangentially, tilted inward by cos(alpha) ~ the
    # band sqrt(2h/r), or tangent at a height of a few h above the surface
    samp = geo.surface_samples(rng, N_GRAZING)
    for j, (y, w, _, _, r, _) in enumerate(samp):
        tang = any_perp(w)
        phi = rng.random() * 2.0 * math.pi
        tang = math.cos(phi) * tang + math.sin(phi) * np.cross(w, tang)
        band = math.sqrt(2.0 * h / r)
        if j % 2 == 0:
            beta = band * 2.0 * rng.random()
            dj = unit(tang - beta * w)
            yj = y
        else:
            dj = tang
            yj = y + w * (3.0 * h * rng.random())
        add("grazing", [yj - 2.5 * radius * dj], [dj])
    return rays


def process(scene, geo, out_dir, log):
    t_start = time.time()
    V, F, info = build_mesh(scene, geo)
    h = info["sagitta"]
    tree = igl.AABB()
    tree.init(V, F)
    log(f"  mesh: {info['triangles']} triangles, h = {h:.3e}, {time.time() - t_start:.1f}s")
    centre, radius = geo.bounding_sphere()

    ray_n = scene.get("ray_n", scene["n"])
    r_max = float(geo.nodes[:, 3].max()) if scene["kind"] == "links" else float(geo.rg.max())
    band_h = sphere_sagitta(1.0, ray_n)[0] * r_max  # the sphere mesh scales with r
    rays = make_rays(scene, geo, band_h)
    o = np.array([r[1] for r in rays])
    d = np.array([r[2] for r in rays])
    kinds = [r[0] for r in rays]
    t_far = (norm(o - centre) + 2.0 * radius) / norm(d)
    t_ex, entering, clearance = first_boundary(geo, o, d, t_far)
    hit = ~np.isnan(t_ex)
    x_ex = o + np.where(hit, t_ex, 0.0)[:, None] * d
    f_ex, n_ex, id_ex, u_ex, r_ex, _ = geo.sdf(x_ex)
    # the generating sphere at the hit point: centre x - r n
    cos_a = np.abs(np.einsum("ij,ij->i", n_ex, d)) / norm(d)
    s_mesh_at_exact, _, _, _ = igl.signed_distance(x_ex, V, F)
    t_mesh, tri, bary = mesh_first_hits(V, F, tree, o, d, centre, radius)
    log(f"  rays: {len(o)} ({int(hit.sum())} hit), {time.time() - t_start:.1f}s")
    t_cert = np.full(len(o), np.nan)
    ins = hit & ~entering
    if ins.any():
        t_cert[ins] = certified_deep_until(geo, o[ins], d[ins], t_ex[ins], h + info["chord_error"])

    ray_out = []
    for j in range(len(o)):
        rec = dict(kind=kinds[j], o=o[j].tolist(), d=d[j].tolist())
        if hit[j]:
            rec["exact"] = dict(
                t=float(t_ex[j]),
                entering=bool(entering[j]),
                point=x_ex[j].tolist(),
                normal=n_ex[j].tolist(),
                piece=int(id_ex[j]),
                u=float(u_ex[j]),
                radius=float(r_ex[j]),
                cos_angle=float(cos_a[j]),
                sdf_residual=float(f_ex[j]),
                mesh_sdf=float(s_mesh_at_exact[j]),
            )
            if ins[j]:
                rec["exact"]["deep_until"] = float(t_cert[j])
        else:
            rec["exact"] = None
            rec["clearance"] = float(clearance[j])
        if np.isnan(t_mesh[j]):
            rec["mesh"] = None
        else:
            rec["mesh"] = dict(t=float(t_mesh[j]), triangle_bary_min=float(bary[j]))
        ray_out.append(rec)

    # SDF samples near and on the surface, with exactly known signed distance
    rng = np.random.default_rng(scene["seed"] + 1000)
    samp = geo.surface_samples(rng, N_SDF_POINTS)
    pts, exact = [], []
    for y, w, _, _, r, _ in samp:
        for off in SDF_OFFSETS:
            delta = off * r
            x = y + delta * w
            if delta > 0.0:
                # outside: the min over pieces is the exact distance; it equals delta unless
                # another piece is nearer
                val = float(geo.sdf(x[None])[0][0])
                if abs(val - delta) > 1e-9 * r:
                    continue
            pts.append(x)
            exact.append(delta)  # inside: B(x, |delta|) is in the generating ball, y on the boundary
    pts = np.array(pts)
    s_mesh, _, _, _ = igl.signed_distance(pts, V, F)
    sdf_out = [dict(x=pts[j].tolist(), exact=float(exact[j]), mesh=float(s_mesh[j])) for j in range(len(pts))]
    log(f"  sdf: {len(pts)} samples, {time.time() - t_start:.1f}s")

    fx = dict(
        format=FORMAT_VERSION,
        scene=scene["name"],
        generator=dict(
            manifold3d=manifold3d.__version__ if hasattr(manifold3d, "__version__") else "3.5.4",
            libigl=getattr(igl, "__version__", "2.6.3"),
            numpy=np.__version__,
            seed=scene["seed"],
        ),
        kind=scene["kind"],
        mesh=info,
        bounding_sphere=dict(centre=centre.tolist(), radius=radius),
        rays=ray_out,
        sdf=sdf_out,
    )
    if scene["kind"] == "links":
        fx["nodes"] = geo.nodes.tolist()
        fx["links"] = geo.links.tolist()
    else:
        fx["control_points"] = geo.P.tolist()
        fx["control_radii"] = geo.R.tolist()
        fx["samples"] = scene["samples"]
    path = os.path.join(out_dir, scene["name"] + ".json")
    with open(path, "w") as fh:
        json.dump(fx, fh, indent=0, separators=(",", ":"))
        fh.write("\n")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "fixtures"))
    ap.add_argument("--only", nargs="*", help="scene names (default: all)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    by_name = {s["name"]: s for s in SCENES}
    for scene in SCENES:
        if args.only and scene["name"] not in args.only:
            continue
        if "same_rays_as" in scene:
            base = dict(by_name[scene["same_rays_as"]])
            base["ray_n"] = base["n"]
            base.update({k: v for k, v in scene.items() if k != "same_rays_as"})
            scene = base
        print(f"{scene['name']}:", flush=True)
        path = process(scene, make_geometry(scene), args.out, lambda m: print(m, flush=True))
        print(f"  wrote {path}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
