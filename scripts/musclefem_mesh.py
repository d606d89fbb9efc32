#!/usr/bin/env python3
"""A closed muscle surface (STL or OBJ) to a tet4 or tet10 volume mesh through Gmsh.

Writes a Gmsh .msh 4.1 ASCII file in metres that `musclefem fibers` and scenes read, with
the physical groups `muscle` (the tetrahedra), `origin` and `insertion` (boundary faces
chosen by planes, boxes or points) and `outer` (every boundary face). `musclefem mesh`
runs this script; it also runs alone (Python >= 3.9 with the `gmsh` package from PyPI:
scripts/setup-gmsh.sh installs it into target/python-venv):

    python scripts/musclefem_mesh.py muscle.stl --units mm --size 4 --element tet10 \\
        --origin-plane 0,0,5,0,0,-1 --insertion-plane 0,0,45,0,0,1 --out muscle.msh

Every length on the command line (size, plane points, boxes, points, radii) is in the
surface's units (`--units m` or `mm`); the mesh file is in metres. The surface must be
closed, edge-manifold, consistently oriented and one piece; an inside-out surface is
turned. The volume is meshed either on a new surface mesh of the target size (default:
Gmsh classifies the triangles into patches at sharp edges of more than `--feature-angle`
degrees, reparametrises them and remeshes them) or on the surface's own triangles
(`--keep-surface`). The groups are made after volume meshing from the tetrahedra's
boundary faces (faces of one element only), each face taken by its corners' centroid:

- plane `px,py,pz,nx,ny,nz`: faces whose centroid c lies on the side the normal points
  to, (c - p) . n >= 0;
- box `x0,y0,z0,x1,y1,z1`: faces whose centroid lies in the box;
- points `x,y,z;x,y,z;...` (or a file of one `x,y,z` per line) with a radius: faces whose
  centroid lies within the radius of one of the points.

Selections of one group add up (repeat the option). An empty group, or a face in both
groups, is an error. Errors go to stderr as one `error: ...` line with exit status 1.
"""

import argparse
import math
import os
import struct
import sys
from collections import defaultdict

# Gmsh's node order: tet10 mid-edge nodes on edges (0,1), (1,2), (2,0), (3,0), (3,2), (3,1).
TET10_EDGE_NODE = {(0, 1): 4, (1, 2): 5, (0, 2): 6, (0, 3): 7, (2, 3): 8, (1, 3): 9}
# The faces of a positively oriented tetrahedron, corners ordered so that the right-hand
# normal points out of it.
TET_FACES = ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))
UNITS = {"m": 1.0, "mm": 1e-3}
GMSH_TYPE = {"tet4": (4, 2), "tet10": (11, 9)}  # (volume, surface) element types


class MeshingError(Exception):
    """A problem with the input or the meshing, reported as `error: ...`."""


def main(argv=None):
    args = parse_arguments(argv)
    try:
        run(args)
    except MeshingError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="musclefem_mesh.py",
        description="A closed surface (STL/OBJ) to a tet4/tet10 Gmsh .msh 4.1 mesh in metres "
        "with the groups muscle, origin, insertion and outer.",
    )
    parser.add_argument("surface", help="closed surface: .stl (ASCII or binary) or .obj")
    parser.add_argument("--out", required=True, help="the .msh file to write")
    parser.add_argument("--units", choices=sorted(UNITS), default="m",
                        help="units of the surface and of every length given here (default m)")
    parser.add_argument("--size", type=float, required=True,
                        help="target element edge length, in --units")
    parser.add_argument("--element", choices=sorted(GMSH_TYPE), default="tet10")
    parser.add_argument("--keep-surface", action="store_true",
                        help="mesh the volume on the surface's own triangles instead of "
                        "remeshing the surface at --size")
    parser.add_argument("--feature-angle", type=float, default=40.0,
                        help="edges sharper than this [degrees] stay edges when remeshing")
    for group in ("origin", "insertion"):
        parser.add_argument(f"--{group}-plane", action="append", default=[],
                            metavar="PX,PY,PZ,NX,NY,NZ")
        parser.add_argument(f"--{group}-box", action="append", default=[],
                            metavar="X0,Y0,Z0,X1,Y1,Z1")
        parser.add_argument(f"--{group}-points", action="append", default=[],
                            metavar="X,Y,Z;X,Y,Z|FILE")
        parser.add_argument(f"--{group}-radius", type=float, metavar="R",
                            help=f"radius around the --{group}-points")
    parser.add_argument("--verbose", action="store_true", help="show Gmsh's messages")
    return parser.parse_args(argv)


def run(args):
    scale = UNITS[args.units]
    if not (args.size > 0 and math.isfinite(args.size)):
        raise MeshingError(f"--size must be a positive length, got {args.size}")
    selections = {g: parse_selections(args, g, scale) for g in ("origin", "insertion")}
    points, triangles = read_surface(args.surface)
    points = [(x * scale, y * scale, z * scale) for x, y, z in points]
    triangles = check_closed_surface(points, triangles, args.surface)
    enclosed = signed_volume(points, triangles)
    if enclosed < 0:
        triangles = [(a, c, b) for a, b, c in triangles]
        enclosed = -enclosed
    nodes, tets = mesh_volume(points, triangles, args.size * scale, args)
    faces = boundary_faces(nodes, tets)
    groups = {}
    for group, chosen in selections.items():
        groups[group] = [i for i, face in enumerate(faces)
                         if any(select(centroid(nodes, face), s) for s in chosen)]
        if not groups[group]:
            lo, hi = bounding_box(points)
            raise MeshingError(
                f"{group}: no boundary face selected by {describe(chosen)}; the surface spans "
                + ", ".join(f"{a} {lo[k] / scale:.6g} .. {hi[k] / scale:.6g}"
                            for k, a in enumerate("xyz"))
                + f" [{args.units}]")
    both = set(groups["origin"]) & set(groups["insertion"])
    if both:
        raise MeshingError(f"{len(both)} boundary faces are selected as both origin and "
                           "insertion: make the selections apart")
    write_msh(args.out, nodes, tets, faces, groups, args.element)
    volume = sum(tet_volume(nodes, t) for t in tets)
    print(f"{args.surface}: {len(triangles)} triangles enclosing {enclosed:.6e} m^3 -> "
          f"{len(tets)} {args.element} and {len(nodes)} nodes, volume {volume:.6e} m^3; "
          f"{len(faces)} boundary faces, {len(groups['origin'])} origin, "
          f"{len(groups['insertion'])} insertion; wrote {args.out}")


# --- selections -------------------------------------------------------------------------

def numbers(text, count, option):
    try:
        values = [float(v) for v in text.replace(" ", "").split(",")]
    except ValueError:
        raise MeshingError(f"{option}: expected {count} numbers separated by commas, "
                           f"got '{text}'") from None
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise MeshingError(f"{option}: expected {count} finite numbers, got '{text}'")
    return values


def parse_selections(args, group, scale):
    chosen = []
    for text in getattr(args, f"{group}_plane"):
        v = numbers(text, 6, f"--{group}-plane")
        n = v[3:]
        length = math.sqrt(sum(c * c for c in n))
        if length == 0:
            raise MeshingError(f"--{group}-plane: the normal of '{text}' is zero")
        chosen.append(("plane", [c * scale for c in v[:3]], [c / length for c in n], text))
    for text in getattr(args, f"{group}_box"):
        v = numbers(text, 6, f"--{group}-box")
        lo, hi = v[:3], v[3:]
        if any(h < l for l, h in zip(lo, hi)):
            raise MeshingError(f"--{group}-box: '{text}' needs x0 <= x1, y0 <= y1, z0 <= z1")
        chosen.append(("box", [c * scale for c in lo], [c * scale for c in hi], text))
    radius = getattr(args, f"{group}_radius")
    for text in getattr(args, f"{group}_points"):
        if radius is None or not radius > 0:
            raise MeshingError(f"--{group}-points needs a positive --{group}-radius")
        if os.path.isfile(text):
            with open(text, encoding="utf-8") as f:
                rows = [line for line in f.read().splitlines()
                        if line.strip() and not line.lstrip().startswith("#")]
            # A header line (x,y,z) is skipped.
            if rows and not any(ch.isdigit() for ch in rows[0]):
                rows = rows[1:]
        else:
            rows = [r for r in text.split(";") if r.strip()]
        if not rows:
            raise MeshingError(f"--{group}-points: no point in '{text}'")
        pts = [[c * scale for c in numbers(r, 3, f"--{group}-points")] for r in rows]
        chosen.append(("points", pts, radius * scale, text))
    if not chosen:
        raise MeshingError(f"no {group} given: use --{group}-plane, --{group}-box or "
                           f"--{group}-points")
    return chosen


def select(c, selection):
    kind = selection[0]
    if kind == "plane":
        _, p, n, _ = selection
        return sum((c[k] - p[k]) * n[k] for k in range(3)) >= 0.0
    if kind == "box":
        _, lo, hi, _ = selection
        return all(lo[k] <= c[k] <= hi[k] for k in range(3))
    _, pts, radius, _ = selection
    return any(sum((c[k] - q[k]) ** 2 for k in range(3)) <= radius * radius for q in pts)


def describe(chosen):
    return " or ".join(f"{s[0]} '{s[-1]}'" for s in chosen)


# --- reading and checking the surface ----------------------------------------------------

def read_surface(path):
    """Points (deduplicated by exact coordinates) and triangles of an STL or OBJ file."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as error:
        raise MeshingError(f"{path}: {error.strerror}") from None
    extension = os.path.splitext(path)[1].lower()
    if extension == ".stl":
        corners = read_stl(data, path)
        index = {}
        points, triangles = [], []
        for tri in corners:
            ids = []
            for p in tri:
                if p not in index:
                    index[p] = len(points)
                    points.append(p)
                ids.append(index[p])
            triangles.append(tuple(ids))
        return points, triangles
    if extension == ".obj":
        return read_obj(data, path)
    raise MeshingError(f"{path}: not an .stl or .obj file")


def read_stl(data, path):
    count = struct.unpack_from("<I", data, 80)[0] if len(data) >= 84 else -1
    if count >= 0 and len(data) == 84 + 50 * count:
        return [tuple(struct.unpack_from("<3f", data, 84 + 50 * i + 12 * (k + 1))
                      for k in range(3)) for i in range(count)]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise MeshingError(f"{path}: neither a binary STL (its size does not match its "
                           "triangle count) nor ASCII text") from None
    triangles, current = [], []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if words and words[0] == "vertex":
            try:
                current.append(tuple(float(w) for w in words[1:4]))
            except ValueError:
                raise MeshingError(f"{path}:{number}: bad vertex '{line.strip()}'") from None
        elif words and words[0] == "endloop":
            if len(current) != 3:
                raise MeshingError(f"{path}:{number}: a facet with {len(current)} vertices")
            triangles.append(tuple(current))
            current = []
    if not triangles:
        raise MeshingError(f"{path}: no facet found")
    return triangles


def read_obj(data, path):
    points, triangles = [], []
    for number, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
        words = line.split()
        if not words:
            continue
        try:
            if words[0] == "v":
                points.append(tuple(float(w) for w in words[1:4]))
            elif words[0] == "f":
                ids = []
                for w in words[1:]:
                    i = int(w.split("/")[0])
                    ids.append(i - 1 if i > 0 else len(points) + i)
                if len(ids) < 3 or not all(0 <= i < len(points) for i in ids):
                    raise ValueError
                # A polygon as a fan of triangles.
                triangles.extend((ids[0], ids[k], ids[k + 1]) for k in range(1, len(ids) - 1))
        except (ValueError, IndexError):
            raise MeshingError(f"{path}:{number}: cannot read '{line.strip()}'") from None
    if not triangles:
        raise MeshingError(f"{path}: no face found")
    return points, triangles


def check_closed_surface(points, triangles, path):
    """Refuses an open, non-manifold, inconsistently oriented or multi-piece surface."""
    kept = [t for t in triangles if len(set(t)) == 3 and triangle_area(points, t) > 0]
    if len(kept) < len(triangles):
        raise MeshingError(f"{path}: {len(triangles) - len(kept)} degenerate triangles "
                           "(repeated or collinear corners): repair the surface first")
    directed = defaultdict(int)
    for a, b, c in triangles:
        for e in ((a, b), (b, c), (c, a)):
            directed[e] += 1
    undirected = defaultdict(int)
    for (a, b), n in directed.items():
        undirected[min(a, b), max(a, b)] += n
    open_edges = sum(1 for n in undirected.values() if n == 1)
    non_manifold = sum(1 for n in undirected.values() if n > 2)
    if open_edges or non_manifold:
        raise MeshingError(
            f"{path}: the surface is not closed: {open_edges} edges border one triangle "
            f"(holes) and {non_manifold} more than two (non-manifold); close and repair it "
            "(e.g. MeshLab, Blender's 3D print toolbox) first")
    flipped = sum(1 for e, n in directed.items() if n > 1)
    if flipped:
        raise MeshingError(f"{path}: {flipped} edges are run the same way by both of "
                           "their triangles: the triangles are not consistently oriented")
    # One piece: connected through shared edges.
    parent = list(range(len(points)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b, c in triangles:
        parent[root(b)] = root(a)
        parent[root(c)] = root(a)
    pieces = len({root(t[0]) for t in triangles})
    if pieces > 1:
        raise MeshingError(f"{path}: {pieces} separate closed surfaces: give one muscle")
    return triangles


def triangle_area(points, t):
    a, b, c = (points[i] for i in t)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return 0.5 * math.sqrt(sum(x * x for x in n))


def signed_volume(points, triangles):
    """Volume enclosed by a closed surface [m^3], sum of a . (b x c) / 6 (Gauss)."""
    total = 0.0
    for i, j, k in triangles:
        a, b, c = points[i], points[j], points[k]
        total += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                  + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return total / 6.0


def bounding_box(points):
    return ([min(p[k] for p in points) for k in range(3)],
            [max(p[k] for p in points) for k in range(3)])


# --- meshing ------------------------------------------------------------------------------

def mesh_volume(points, triangles, size, args):
    """Tetrahedra of the enclosed volume: node positions [m] (0-based) and the elements'
    nodes in Gmsh's order."""
    try:
        import gmsh
    except ImportError:
        raise MeshingError(f"the Python package gmsh is not installed in {sys.executable} "
                           "(scripts/setup-gmsh.sh installs it into target/python-venv)") from None
    gmsh.initialize(["musclefem_mesh"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 1 if args.verbose else 0)
        # One thread and a fixed seed: the same surface gives the same mesh, byte for byte.
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.add("muscle")
        surface = gmsh.model.addDiscreteEntity(2)
        flat = [c for p in points for c in p]
        gmsh.model.mesh.addNodes(2, surface, list(range(1, len(points) + 1)), flat)
        gmsh.model.mesh.addElementsByType(surface, 2, [],
                                          [i + 1 for t in triangles for i in t])
        if args.keep_surface:
            surfaces = [surface]
        else:
            gmsh.model.mesh.classifySurfaces(math.radians(args.feature_angle), True, True,
                                             math.pi)
            gmsh.model.mesh.createGeometry()
            surfaces = [tag for _, tag in gmsh.model.getEntities(2)]
        loop = gmsh.model.geo.addSurfaceLoop(surfaces)
        gmsh.model.geo.addVolume([loop])
        gmsh.model.geo.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        if not args.keep_surface:
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * size)
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.model.mesh.generate(3)
        if args.element == "tet10":
            # Mid-edge nodes on the straight edges: every tet10 is as valid as its tet4.
            # Optionally (scripts/visible_human_knee.py) the boundary's mid-edge nodes on
            # the surface instead, which keeps the volume the chords cut off.
            gmsh.option.setNumber("Mesh.SecondOrderLinear", 0 if getattr(args, "curved", False) else 1)
            gmsh.model.mesh.setOrder(2)
        volume_type = GMSH_TYPE[args.element][0]
        _, element_nodes = gmsh.model.mesh.getElementsByType(volume_type)
        tags, coords, _ = gmsh.model.mesh.getNodes()
    except Exception as error:  # Gmsh raises plain Exceptions with its last message.
        hint = "" if args.keep_surface else (" (try another --feature-angle, e.g. 60, another "
                                                "--size, or --keep-surface)")
        raise MeshingError(f"Gmsh could not mesh {args.surface}: {error}{hint}") from None
    finally:
        gmsh.finalize()
    per = 10 if args.element == "tet10" else 4
    element_nodes = [int(n) for n in element_nodes]
    if not element_nodes:
        raise MeshingError(f"Gmsh made no tetrahedra from {args.surface} (is it "
                           "self-intersecting?)")
    position = {int(t): (float(coords[3 * i]), float(coords[3 * i + 1]),
                         float(coords[3 * i + 2])) for i, t in enumerate(tags)}
    # Renumber the nodes the tetrahedra use, 0-based, in the order they first appear.
    index, nodes = {}, []
    tets = []
    for e in range(len(element_nodes) // per):
        tet = []
        for tag in element_nodes[per * e:per * (e + 1)]:
            if tag not in index:
                index[tag] = len(nodes)
                nodes.append(position[tag])
            tet.append(index[tag])
        if tet_volume(nodes, tet) <= 0:
            raise MeshingError(f"Gmsh made an inverted tetrahedron from {args.surface}")
        tets.append(tet)
    return nodes, tets


def tet_volume(nodes, tet):
    a, b, c, d = (nodes[i] for i in tet[:4])
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    w = [d[k] - a[k] for k in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0


def boundary_faces(nodes, tets):
    """Faces of one tetrahedron only, outward, as node lists in Gmsh's triangle order
    (3 corners, then for tet10 the mid-edge nodes of (0,1), (1,2), (2,0))."""
    count = defaultdict(int)
    for tet in tets:
        for face in TET_FACES:
            count[frozenset(tet[i] for i in face)] += 1
    faces = []
    for tet in tets:
        for face in TET_FACES:
            if count[frozenset(tet[i] for i in face)] == 1:
                corners = [tet[i] for i in face]
                if len(tet) == 10:
                    corners += [tet[TET10_EDGE_NODE[tuple(sorted((face[k], face[(k + 1) % 3])))]]
                                for k in range(3)]
                faces.append(corners)
    return faces


def centroid(nodes, face):
    return [sum(nodes[i][k] for i in face[:3]) / 3.0 for k in range(3)]


# --- writing ------------------------------------------------------------------------------

def write_msh(path, nodes, tets, faces, groups, element):
    """Gmsh 4.1 ASCII: volume entity 1 (group muscle), surface entities 1 (origin),
    2 (insertion) and 3 (the rest); physical groups 1 muscle (3-D), 2 origin, 3 insertion,
    4 outer (2-D, entities 1-3). Written to PATH.tmp and renamed: complete or not at all."""
    volume_type, surface_type = GMSH_TYPE[element]
    chosen = set(groups["origin"]) | set(groups["insertion"])
    entity_faces = {1: groups["origin"], 2: groups["insertion"],
                    3: [i for i in range(len(faces)) if i not in chosen]}
    lo, hi = bounding_box(nodes)
    box = " ".join(f"{v:.17g}" for v in lo + hi)
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", "4",
             '3 1 "muscle"', '2 2 "origin"', '2 3 "insertion"', '2 4 "outer"',
             "$EndPhysicalNames", "$Entities"]
    surfaces = [tag for tag, members in entity_faces.items() if members]
    lines.append(f"0 0 {len(surfaces)} 1")
    for tag in surfaces:
        physicals = "2 2 4" if tag == 1 else ("2 3 4" if tag == 2 else "1 4")
        lines.append(f"{tag} {box} {physicals} 0")
    lines.append(f"1 {box} 1 1 {len(surfaces)} " + " ".join(f"-{s}" for s in surfaces))
    lines += ["$EndEntities", "$Nodes", f"1 {len(nodes)} 1 {len(nodes)}",
              f"3 1 0 {len(nodes)}"]
    lines += [str(i + 1) for i in range(len(nodes))]
    lines += [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in nodes]
    lines.append("$EndNodes")
    element_count = len(tets) + len(faces)
    lines += ["$Elements", f"{1 + len(surfaces)} {element_count} 1 {element_count}",
              f"3 1 {volume_type} {len(tets)}"]
    lines += [f"{e + 1} " + " ".join(str(n + 1) for n in tet) for e, tet in enumerate(tets)]
    tag = len(tets)
    for entity in surfaces:
        lines.append(f"2 {entity} {surface_type} {len(entity_faces[entity])}")
        for i in entity_faces[entity]:
            tag += 1
            lines.append(f"{tag} " + " ".join(str(n + 1) for n in faces[i]))
    lines.append("$EndElements")
    temporary = path + ".tmp"
    try:
        with open(temporary, "w", encoding="ascii") as f:
            f.write("\n".join(lines) + "\n")
        os.replace(temporary, path)
    except OSError as error:
        raise MeshingError(f"{path}: {error.strerror}") from None


if __name__ == "__main__":
    sys.exit(main())
