"""Geometry for scripts/visible_human_knee.py, in plain Python (no NumPy, so that the
generated files do not depend on a numerical library's version): binary STL reading and
writing, vertex normals, the distance from a point to a triangle surface through a grid of
cells, least-squares sphere and circle fits, and the femoral shaft as a tapered cylinder.

Lengths are in the unit of the data (mm) unless a docstring says otherwise.
"""

import math
import struct
from collections import defaultdict


def read_binary_stl(path):
    """Points (deduplicated by exact coordinates) and triangles of a binary STL."""
    data = path.read_bytes()
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * count:
        raise ValueError(f"{path}: not a binary STL (size does not match {count} triangles)")
    index, points, triangles = {}, [], []
    for i in range(count):
        ids = []
        for k in range(3):
            p = struct.unpack_from("<3f", data, 84 + 50 * i + 12 * (k + 1))
            if p not in index:
                index[p] = len(points)
                points.append(p)
            ids.append(index[p])
        triangles.append(tuple(ids))
    return points, triangles


def write_binary_stl(path, points, triangles, title):
    """A binary STL with an 80-byte header from `title`, normals from the corners and
    single-precision coordinates: the same input gives the same bytes."""
    header = title.encode("ascii")[:80].ljust(80, b" ")
    chunks = [header, struct.pack("<I", len(triangles))]
    for tri in triangles:
        a, b, c = (points[i] for i in tri)
        n = normalize(cross(sub(b, a), sub(c, a)))
        chunks.append(struct.pack("<12fH", *n, *a, *b, *c, 0))
    path.write_bytes(b"".join(chunks))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    length = norm(a)
    return (0.0, 0.0, 0.0) if length == 0 else scale(a, 1.0 / length)


def signed_volume(points, triangles):
    """Volume enclosed by a closed outward surface (Gauss: Σ a · (b × c) / 6)."""
    return sum(dot(points[i], cross(points[j], points[k])) for i, j, k in triangles) / 6.0


def vertex_normals(points, triangles):
    """Area-weighted unit normals at the vertices of an outward surface."""
    sums = [(0.0, 0.0, 0.0)] * len(points)
    for tri in triangles:
        a, b, c = (points[i] for i in tri)
        n = cross(sub(b, a), sub(c, a))
        for i in tri:
            sums[i] = add(sums[i], n)
    return [normalize(n) for n in sums]


def solve(matrix, rhs):
    """Solution of a small dense linear system by Gaussian elimination with pivoting."""
    n = len(rhs)
    a = [list(row) + [r] for row, r in zip(matrix, rhs)]
    for col in range(n):
        pivot = max(range(col, n), key=lambda r: abs(a[r][col]))
        a[col], a[pivot] = a[pivot], a[col]
        for r in range(col + 1, n):
            f = a[r][col] / a[col][col]
            for c in range(col, n + 1):
                a[r][c] -= f * a[col][c]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (a[r][n] - sum(a[r][c] * x[c] for c in range(r + 1, n))) / a[r][r]
    return x


def least_squares(rows, values):
    """x minimising Σ (row · x − value)² through the normal equations."""
    n = len(rows[0])
    ata = [[sum(r[i] * r[j] for r in rows) for j in range(n)] for i in range(n)]
    atb = [sum(r[i] * v for r, v in zip(rows, values)) for i in range(n)]
    return solve(ata, atb)


def fit_sphere(points):
    """Centre and radius of the least-squares sphere |p|² = 2 c · p + d (Kåsa)."""
    rows = [(2 * p[0], 2 * p[1], 2 * p[2], 1.0) for p in points]
    cx, cy, cz, d = least_squares(rows, [dot(p, p) for p in points])
    return (cx, cy, cz), math.sqrt(d + cx * cx + cy * cy + cz * cz)


def fit_circle(points):
    """Centre (x, y) and radius of the least-squares circle through 2-D points (Kåsa)."""
    rows = [(2 * x, 2 * y, 1.0) for x, y in points]
    cx, cy, d = least_squares(rows, [x * x + y * y for x, y in points])
    return (cx, cy), math.sqrt(d + cx * cx + cy * cy)


def point_triangle_distance(p, a, b, c):
    """Distance from p to the triangle abc (Ericson, Real-Time Collision Detection 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return norm(ap)
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return norm(bp)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        v = d1 / (d1 - d3)
        return norm(sub(p, add(a, scale(ab, v))))
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return norm(cp)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        w = d2 / (d2 - d6)
        return norm(sub(p, add(a, scale(ac, w))))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return norm(sub(p, add(b, scale(sub(c, b), w))))
    denominator = 1.0 / (va + vb + vc)
    v, w = vb * denominator, vc * denominator
    return norm(sub(p, add(a, add(scale(ab, v), scale(ac, w)))))


class SurfaceDistance:
    """Answers "is p within `reach` of the surface?" for one triangle surface: the
    triangles are binned into cubic cells of side `reach` by their bounding boxes, and a
    query looks at the 27 cells around p."""

    def __init__(self, points, triangles, reach):
        self.points, self.triangles, self.reach = points, triangles, reach
        self.cells = defaultdict(list)
        for t, tri in enumerate(triangles):
            corners = [points[i] for i in tri]
            lo = [math.floor(min(q[k] for q in corners) / reach) for k in range(3)]
            hi = [math.floor(max(q[k] for q in corners) / reach) for k in range(3)]
            for i in range(lo[0], hi[0] + 1):
                for j in range(lo[1], hi[1] + 1):
                    for k in range(lo[2], hi[2] + 1):
                        self.cells[i, j, k].append(t)

    def within(self, p):
        """Whether p is within `reach` of a triangle."""
        ci, cj, ck = (math.floor(p[k] / self.reach) for k in range(3))
        seen = set()
        for i in (ci - 1, ci, ci + 1):
            for j in (cj - 1, cj, cj + 1):
                for k in (ck - 1, ck, ck + 1):
                    for t in self.cells.get((i, j, k), ()):
                        if t in seen:
                            continue
                        seen.add(t)
                        a, b, c = (self.points[v] for v in self.triangles[t])
                        if point_triangle_distance(p, a, b, c) <= self.reach:
                            return True
        return False


def femur_shaft_fit(vi_points, vi_triangles, heights, slab, shift):
    """The femoral shaft's section circles fitted to the inner surface of the vastus
    intermedius: at each height z (mm), the VI vertices within ±slab/2 whose outward normal
    points towards the current centre estimate (cosine > 0.5) are fitted by a circle, and
    the centre is moved there; five passes, starting from the slab's centroid moved by
    `shift` (x, y) (the VI wraps the femur anteriorly and laterally, so the femur lies
    medial of the centroid). Returns [(z, cx, cy, r, inner vertex count)]."""
    normals = vertex_normals(vi_points, vi_triangles)
    fits = []
    for z in heights:
        near = [(p, n) for p, n in zip(vi_points, normals) if abs(p[2] - z) <= slab / 2]
        centre = (sum(p[0] for p, _ in near) / len(near) + shift[0],
                  sum(p[1] for p, _ in near) / len(near) + shift[1])
        for _ in range(5):
            inner = []
            for p, n in near:
                to_centre = normalize((centre[0] - p[0], centre[1] - p[1], 0.0))
                if n[0] * to_centre[0] + n[1] * to_centre[1] > 0.5:
                    inner.append((p[0], p[1]))
            centre, radius = fit_circle(inner)
        fits.append((z, centre[0], centre[1], radius, len(inner)))
    return fits


def ring_basis(axis):
    """Two unit vectors normal to `axis` and to each other."""
    helper = (1.0, 0.0, 0.0) if abs(axis[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = normalize(cross(axis, helper))
    return u, cross(axis, u)


def largest_empty_circle(points, reach, floor=0.05):
    """The centre (within `reach` of the origin) of the largest circle free of the 2-D
    `points`, and its radius: a deterministic pattern search over the 8 neighbours of
    the current centre, the step halved from reach / 4 down to `floor`."""

    def clearance(c):
        return min(math.hypot(p[0] - c[0], p[1] - c[1]) for p in points)

    centre, best, step = (0.0, 0.0), clearance((0.0, 0.0)), reach / 4
    while step > floor:
        moved = False
        for du, dv in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)):
            c = (centre[0] + du * step, centre[1] + dv * step)
            if math.hypot(*c) <= reach and clearance(c) > best:
                centre, best, moved = c, clearance(c), True
        if not moved:
            step /= 2
    return centre, best


def tube(centres, radii, axis, sides):
    """A closed, outward triangle surface: a circle of `sides` vertices of radii[k]
    around each centres[k], in planes normal to `axis`, capped by fans around the end
    centres. Returns (points, triangles)."""
    rings = len(radii) - 1
    u, v = ring_basis(axis)
    points, triangles = [], []
    for centre, radius in zip(centres, radii):
        for s in range(sides):
            angle = 2 * math.pi * s / sides
            offset = add(scale(u, radius * math.cos(angle)), scale(v, radius * math.sin(angle)))
            points.append(add(centre, offset))
    for r in range(rings):
        for s in range(sides):
            a, b = r * sides + s, r * sides + (s + 1) % sides
            c, d = a + sides, b + sides
            triangles += [(a, b, d), (a, d, c)]
    low, high = len(points), len(points) + 1
    points += [centres[0], centres[-1]]
    top_ring = rings * sides
    for s in range(sides):
        triangles.append((low, (s + 1) % sides, s))
        triangles.append((high, top_ring + s, top_ring + (s + 1) % sides))
    if signed_volume(points, triangles) < 0:
        triangles = [(a, c, b) for a, b, c in triangles]
    return points, triangles


#: Keast's 5-point rule on the unit tetrahedron (exact for degree 3), barycentric
#: (L1, L2, L3) and weights summing to 1/6.
KEAST = [((0.25, 0.25, 0.25), -2.0 / 15.0)] + [
    (p, 3.0 / 40.0) for p in ((1 / 6, 1 / 6, 1 / 6), (0.5, 1 / 6, 1 / 6),
                              (1 / 6, 0.5, 1 / 6), (1 / 6, 1 / 6, 0.5))]
#: Gmsh's tet10 mid-edge nodes: node 4 + k sits on the edge TET10_EDGES[k].
TET10_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))
BARYCENTRIC_GRADIENT = ((-1.0, -1.0, -1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def tet10_jacobian(nodes, tet, l1, l2, l3):
    """det J of a Gmsh-ordered tet10 at the barycentric point (1 − l1 − l2 − l3, l1, l2, l3)."""
    lam = (1.0 - l1 - l2 - l3, l1, l2, l3)
    grads = [scale(BARYCENTRIC_GRADIENT[i], 4 * lam[i] - 1) for i in range(4)]
    for i, j in TET10_EDGES:
        grads.append(scale(add(scale(BARYCENTRIC_GRADIENT[i], lam[j]),
                               scale(BARYCENTRIC_GRADIENT[j], lam[i])), 4.0))
    jac = [[0.0] * 3 for _ in range(3)]
    for a, g in zip(tet, grads):
        x = nodes[a]
        for r in range(3):
            for c in range(3):
                jac[r][c] += x[r] * g[c]
    return dot(jac[0], cross(jac[1], jac[2]))


def tet10_volume(nodes, tet):
    """Volume of a (curved) tet10: ∫ det J over the reference tetrahedron (Keast)."""
    return sum(w * tet10_jacobian(nodes, tet, *p) for p, w in KEAST)


def tet10_quality(nodes, tet):
    """Smallest det J at the corners, mid-edges and Keast points over the straight
    tetrahedron's (6 × its volume): 1 for a straight tet10, ≤ 0 for an invalid one."""
    points = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0),
              (0.5, 0.0, 0.0), (0.5, 0.5, 0.0), (0.0, 0.5, 0.0), (0.0, 0.0, 0.5),
              (0.0, 0.5, 0.5), (0.5, 0.0, 0.5)] + [p for p, _ in KEAST]
    straight = 6.0 * dot(sub(nodes[tet[1]], nodes[tet[0]]),
                         cross(sub(nodes[tet[2]], nodes[tet[0]]), sub(nodes[tet[3]], nodes[tet[0]]))) / 6.0
    return min(tet10_jacobian(nodes, tet, *p) for p in points) / straight
