"""An independent check of 5-axis G-code (issue 13): written apart from the
core and sharing nothing with it. A helper, not a test file.

The program is read as LinuxCNC's interpreter runs it (``rs274 -g``: the
STRAIGHT_TRAVERSE / STRAIGHT_FEED canonical calls with x y z a b c); the
tool is a flat end of radius R and length L, or a bull nose of corner
radius rc, the tip (x, y, z) the centre of its bottom face, its axis
relative to the part (sin A sin C, -sin A cos C, cos A) as the op
documents. Each feed move (and, apart, each rapid) is swept as the machine
with TCP moves: tip and A, C interpolated linearly, at steps of at most
`step` mm of tip travel and `angle_step` degrees. Each tool instance is an oriented cylinder (the disc
of the bottom and the shank above it); a bull nose's is the cylinder from
rc up and, below, its corner: the solid torus (tube radius rc, its circle of
centres of radius R - rc at rc above the tip) and the disc that fills it
(a cylinder of radius R - rc, 2 rc high, from the tip), each line met
exactly (the torus by the real roots of its quartic).

The design surface is sampled from OpenCASCADE directly (the Part face's own
surface and normal, inside its wires). At a sample S with normal N (away
from the material):
  * left   = the distance along +N from S to the first tool instance the
             line meets (0 if S is inside one): the material left above S;
  * overcut = how far along -N below S a tool instance reaches.
"""

import math
import re

import numpy as np

CALL = re.compile(r"(STRAIGHT_TRAVERSE|STRAIGHT_FEED)\(([^)]*)\)")


def motions(canon):
    """[(kind, x, y, z, a, c)] from rs274's canonical calls."""
    out = []
    for line in canon:
        m = CALL.search(line)
        if m:
            v = [float(t) for t in m.group(2).split(",")]
            out.append(
                ("G0" if m.group(1) == "STRAIGHT_TRAVERSE" else "G1", v[0], v[1], v[2], v[3], v[5])
            )
    return out


def axis_of(a_deg, c_deg):
    a, c = np.radians(a_deg), np.radians(c_deg)
    return np.stack([np.sin(a) * np.sin(c), -np.sin(a) * np.cos(c), np.cos(a)], axis=-1)


def tool_instances(moves, step=0.02, angle_step=0.25, kind_swept="G1"):
    """(tips (M,3), axes (M,3)) of the tool along the moves of one kind: the
    feed moves (G1, what cuts) or the rapids (G0, which must cut nothing)."""
    tips, angles = [], []
    prev = None
    for kind, x, y, z, a, c in moves:
        cur = np.array([x, y, z, a, c])
        if kind == kind_swept and prev is not None:
            dist = np.linalg.norm(cur[:3] - prev[:3])
            turn = max(abs(cur[3] - prev[3]), abs(cur[4] - prev[4]))
            n = max(1, int(math.ceil(max(dist / step, turn / angle_step))))
            f = np.linspace(0.0, 1.0, n + 1)[:, None]
            pts = prev[None, :] * (1 - f) + cur[None, :] * f
            tips.append(pts[:, :3])
            angles.append(pts[:, 3:])
        prev = cur
    if not tips:
        return np.zeros((0, 3)), np.zeros((0, 3))
    tips = np.concatenate(tips)
    ang = np.concatenate(angles)
    return tips, axis_of(ang[:, 0], ang[:, 1])


def sample_face(face, spacing, margin):
    """(points (K,3), normals (K,3)) of the face about `spacing` apart, inside
    its wires and at least `margin` from its edges (in space)."""
    u0, u1, v0, v1 = face.ParameterRange
    # The parameter steps from the surface's speed at the middle.
    um, vm = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
    d = face.Surface.getD1(um, vm) if hasattr(face.Surface, "getD1") else None
    if d is not None:
        su, sv = d[1].Length, d[2].Length
    else:
        p = face.Surface.value(um, vm)
        su = (face.Surface.value(um + 1e-4 * (u1 - u0), vm) - p).Length / (1e-4 * (u1 - u0))
        sv = (face.Surface.value(um, vm + 1e-4 * (v1 - v0)) - p).Length / (1e-4 * (v1 - v0))
    nu = max(2, int((u1 - u0) * su / spacing))
    nv = max(2, int((v1 - v0) * sv / spacing))
    edge_pts = []
    for e in face.Edges:
        edge_pts.extend((p.x, p.y, p.z) for p in e.discretize(Distance=0.1 * max(margin, 0.5)))
    edge_pts = np.array(edge_pts)
    pts, nrm = [], []
    for i in range(nu):
        u = u0 + (u1 - u0) * (i + 0.5) / nu
        for j in range(nv):
            v = v0 + (v1 - v0) * (j + 0.5) / nv
            if not face.isPartOfDomain(u, v):
                continue
            p = face.valueAt(u, v)
            q = np.array([p.x, p.y, p.z])
            if margin > 0 and np.min(np.linalg.norm(edge_pts - q, axis=1)) < margin:
                continue
            n = face.normalAt(u, v)
            pts.append(q)
            nrm.append([n.x, n.y, n.z])
    return np.array(pts), np.array(nrm)


def line_cylinder(s, n, tips, axes, radius, length):
    """The interval [t0, t1] of the lines s + t n inside each cylinder
    (tip, axis, radius, length); t0 = +inf where the line misses."""
    w = s[None, :] - tips  # (M,3)
    wa = np.einsum("ij,ij->i", w, axes)
    na = axes @ n  # (M,)
    # Slab 0 <= wa + t na <= length.
    with np.errstate(divide="ignore", invalid="ignore"):
        ta = np.where(np.abs(na) > 1e-12, (0.0 - wa) / na, -np.inf)
        tb = np.where(np.abs(na) > 1e-12, (length - wa) / na, np.inf)
    lo = np.minimum(ta, tb)
    hi = np.maximum(ta, tb)
    inside_slab = (wa >= 0) & (wa <= length)
    lo = np.where(np.abs(na) > 1e-12, lo, np.where(inside_slab, -np.inf, np.inf))
    hi = np.where(np.abs(na) > 1e-12, hi, np.where(inside_slab, np.inf, -np.inf))
    # Radial: |w_perp + t n_perp|^2 <= r^2.
    wp = w - wa[:, None] * axes
    np_ = n[None, :] - na[:, None] * axes
    qa = np.einsum("ij,ij->i", np_, np_)
    qb = 2 * np.einsum("ij,ij->i", wp, np_)
    qc = np.einsum("ij,ij->i", wp, wp) - radius * radius
    disc = qb * qb - 4 * qa * qc
    ok = disc >= 0
    sq = np.sqrt(np.where(ok, disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        r0 = np.where(qa > 1e-15, (-qb - sq) / (2 * qa), np.where(qc <= 0, -np.inf, np.inf))
        r1 = np.where(qa > 1e-15, (-qb + sq) / (2 * qa), np.where(qc <= 0, np.inf, -np.inf))
    r0 = np.where(ok | (qa <= 1e-15), r0, np.inf)
    r1 = np.where(ok | (qa <= 1e-15), r1, -np.inf)
    t0 = np.maximum(lo, r0)
    t1 = np.minimum(hi, r1)
    miss = t0 > t1
    return np.where(miss, np.inf, t0), np.where(miss, -np.inf, t1)


def line_torus(s, n, centres, axes, major, minor):
    """The interval [t0, t1] from the first to the last point where the lines
    s + t n meet each solid torus (centre, axis, major and minor radius);
    t0 = +inf where the line misses. With w = s + t n - centre, h = w.axis:
    (|w|^2 + major^2 - minor^2)^2 = 4 major^2 (|w|^2 - h^2), a quartic in t
    with leading coefficient 1 (n a unit vector), solved as the eigenvalues
    of its companion matrices."""
    w0 = s[None, :] - centres
    b = w0 @ n
    h0 = np.einsum("ij,ij->i", w0, axes)
    na = axes @ n
    ww = np.einsum("ij,ij->i", w0, w0)
    c = ww + major * major - minor * minor
    m4 = 4 * major * major
    coeffs = np.stack(
        [
            4 * b,
            4 * b * b + 2 * c - m4 * (1 - na * na),
            4 * b * c - 2 * m4 * (b - h0 * na),
            c * c - m4 * (ww - h0 * h0),
        ],
        axis=1,
    )
    comp = np.zeros((len(centres), 4, 4))
    comp[:, 0, :] = -coeffs
    comp[:, 1, 0] = comp[:, 2, 1] = comp[:, 3, 2] = 1.0
    roots = np.linalg.eigvals(comp)
    real = np.abs(roots.imag) <= 1e-6 * max(1.0, major + minor)
    re = roots.real
    t0 = np.min(np.where(real, re, np.inf), axis=1)
    t1 = np.max(np.where(real, re, -np.inf), axis=1)
    return t0, t1


def tool_intervals(s, n, tips, axes, radius, length, corner):
    """[t0, t1] of the lines s + t n in each tool instance, two per instance
    for a bull nose (corner > 0: its corner and the cylinder above), one for
    a flat end (t0 = +inf where a part is missed)."""
    if corner <= 0:
        return line_cylinder(s, n, tips, axes, radius, length)
    core = radius - corner
    u0, u1 = line_cylinder(s, n, tips + corner * axes, axes, radius, length - corner)
    d0, d1 = line_cylinder(s, n, tips, axes, core, 2 * corner)
    # The torus only where the line meets the corner's bounding cylinder
    # (radius R, 2 rc high from the tip): the quartic costs most.
    b0, b1 = line_cylinder(s, n, tips, axes, radius, 2 * corner)
    k0, k1 = np.full(len(tips), np.inf), np.full(len(tips), -np.inf)
    hit = b0 <= b1
    if np.any(hit):
        k0[hit], k1[hit] = line_torus(s, n, tips[hit] + corner * axes[hit], axes[hit], core, corner)
    # The corner (the torus and its filling disc) is convex: one interval.
    c0, c1 = np.minimum(d0, k0), np.maximum(d1, k1)
    return np.concatenate([u0, c0]), np.concatenate([u1, c1])


def measure(points, normals, tips, axes, radius, length, reach=None, corner=0.0):
    """Per sample: (left, overcut) as the module docstring says; left is
    +inf where no tool instance's tip passes within `reach` (default R +
    1.5 mm: the cutting end, whose bottom cuts at most a strip's half-width
    (under 1.5 mm here) from the contact, and the first few mm of its side;
    the shank higher up is not swept here). `corner`: the bull nose's
    corner radius (0: a flat end)."""
    if not 0 <= corner < radius:
        raise ValueError("corner must be in [0, radius) (got %g)" % corner)
    reach = radius + 1.5 if reach is None else reach
    cell = reach
    left = np.full(len(points), np.inf)
    over = np.zeros(len(points))
    if len(tips) == 0:
        return left, over
    # Samples grouped by cell; per cell, the instances near it once.
    skeys = np.floor(points / cell).astype(np.int64)
    order = np.lexsort(skeys.T)
    sk = skeys[order]
    start = 0
    for i in range(1, len(order) + 1):
        if i < len(order) and np.all(sk[i] == sk[start]):
            continue
        group = order[start:i]
        start = i
        centre = (skeys[group[0]] + 0.5) * cell  # (group holds indices of points)
        near_cell = np.linalg.norm(tips - centre, axis=1) <= reach + cell * math.sqrt(3) / 2
        cand = np.nonzero(near_cell)[0]
        if len(cand) == 0:
            continue
        ct, ca = tips[cand], axes[cand]
        for k in group:
            s, n = points[k], normals[k]
            near = np.linalg.norm(ct - s, axis=1) <= reach
            if not np.any(near):
                continue
            t0, t1 = tool_intervals(s, n, ct[near], ca[near], radius, length, corner)
            hit = t1 >= 0
            if np.any(hit):
                left[k] = max(0.0, float(np.min(t0[hit])))
            if np.any(t0 < 0):
                over[k] = float(np.max(-t0[t0 < 0]))
    return left, over
