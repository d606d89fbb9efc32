#!/usr/bin/env python3
"""The Visible Human Female's knee (issue #35, first part): the segmented quadriceps
surfaces to tet10 volume meshes with named face groups, the femoral shaft built from the
vastus intermedius, and the bones and cartilage the knee's contact needs.

Usage (after scripts/setup-gmsh.sh):

    target/python-venv/bin/python scripts/visible_human_knee.py [--data DIR] [--out DIR]

DIR defaults to ../shared/data/visible_human_female_right (binary STL in mm, x to the
subject's right, y anterior, z superior; Andreassen et al. 2022, CC BY 4.0) and OUT to
crates/studies/data/visible_human. Writes into OUT:

- `<M>_<resolution>.msh` for M in VI, VL, VM, RF and the resolutions coarse and medium:
  Gmsh 4.1 ASCII, metres, tet10, groups `muscle` (the elements), `origin`, `insertion`,
  `aponeurosis`, `interface_<N>` for each other muscle N within reach, and `outer` (every
  boundary face); origin, insertion and aponeurosis are disjoint;
- `femur_shaft.stl` (see build_femur), `femur_cartilage_distal.stl`,
  `patella.stl`, `patella_cartilage.stl`, `tibia.stl` (binary STL in mm, the bones
  remeshed by Gmsh at BONE_SIZE);
- `landmarks.csv`: the knee's landmarks (flexion axis, trochlear groove, patella,
  patellar tendon, hip and ankle; scripts/visible_human_landmarks.py);
- `summary.csv` (one row per mesh: counts, volumes, group areas), `femur.csv` (the
  shaft's fitted sections) and `femur_rings.csv` (its rings' radii);
- `README.md` (sources, citations, the rules below and the summary) and a copy of
  `SOURCE_README.txt`.

The meshing is scripts/musclefem_mesh.py's (Gmsh remeshes each surface at the target
size, feature angle 60°, then meshes the volume; one thread, fixed random seed), so two
runs give the same bytes (`--check` regenerates into a temporary folder and compares).
Each muscle is meshed alone: the 0.05 mm gaps between neighbours are kept up to the
remeshing's chordal deviation (reported as the interface faces, not closed).

The face groups are chosen on the boundary faces of the volume mesh, from each face's
centroid c and outward unit normal n, with the femoral axis (unit a, proximal) and the
radial unit r = the part of c − (axis point) normal to a, normalised, and the height
fraction s = (c − lowest point) · a / the muscle's extent along a (0 distal, 1 proximal):

- insertion: s < END (the distal end, towards the quadriceps tendon and patella);
- origin (the flow's inlet): the proximal cap s > 1 − END and the faces of
  RULES[M]["origin"];
- aponeurosis (an outlet with the insertion): not insertion or origin, the faces of
  RULES[M]["aponeurosis"];
- interface_N: faces whose centroid or a corner lies within INTERFACE_REACH of muscle
  N's surface.
"""

import argparse
import filecmp
import math
import shutil
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

sys.path.insert(0, str(Path(__file__).resolve().parent))
import musclefem_mesh as mesher  # noqa: E402
import visible_human_geometry as geo  # noqa: E402
import visible_human_landmarks as landmarks  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_DATA = ROOT.parent / "shared/data/visible_human_female_right"
DEFAULT_OUT = ROOT / "crates/studies/data/visible_human"
MUSCLES = {"VI": "VastusIntermedius", "VL": "VastusLateralis", "VM": "VastusMedialis",
           "RF": "RectusFemoris"}
#: Target element edge lengths [mm].
RESOLUTIONS = {"coarse": 9.0, "medium": 6.0}
#: Bones and cartilage: the source file and the edge length [mm] they are remeshed at
#: (the tibia, whose proximal end alone is in the knee, coarser).
BONES = {"patella": ("Bone_Patella", 1.5), "patella_cartilage": ("Cartilage_Patella", 1.5),
         "tibia": ("Bone_Tibia", 3.0), "femur_cartilage_distal": ("Cartilage_FemurDistal", 2.0)}
FEATURE_ANGLE = 60.0  # degrees, as the RF needs (musclefem mesh --feature-angle)
END = 0.04  # height fraction of the distal and proximal end caps
FACING = 0.5  # cosine: a face "faces the femur" when n · r < −FACING
ANTERIOR = 0.3  # cosine with the anterior direction y⊥: "anterior" and "posterior" faces
#: The fiber flow's inlet (`origin`, besides the proximal cap s > 1 − END) and outlet
#: (`aponeurosis`, besides the insertion s < END) on each muscle's side faces: (side,
#: lowest s, highest s) or None, side one of "deep" (n · r < −FACING, facing the femur),
#: "superficial" (n · r > FACING), "anterior" (superficial and n · y⊥ > ANTERIOR) and
#: "posterior" (n · y⊥ < −ANTERIOR). Inlet and outlet are staggered along the muscle (the
#: inlet proximal, the outlet distal, on opposite faces) so that the flow crosses the belly
#: obliquely, as the fibers do: where they face each other across the belly the flow runs
#: straight across it (90° to the long axis). RULE_REASONS gives each rule's anatomy.
RULES = {
    "VI": {"origin": ("deep", 0.85, 1.0), "aponeurosis": ("anterior", END, 0.2)},
    "VL": {"origin": ("superficial", 0.8, 1.0), "aponeurosis": ("deep", END, 0.3)},
    "VM": {"origin": ("posterior", 0.6, 1.0), "aponeurosis": ("deep", END, 0.3)},
    "RF": {"origin": ("superficial", 0.8, 1.0), "aponeurosis": ("deep", END, 0.3)},
}
#: Why each muscle's inlet and outlet lie where RULES puts them (for the README).
RULE_REASONS = {
    "VI": "arises from the anterior and lateral femoral shaft (its deep face) and inserts "
          "on the aponeurosis on its anterior face that joins the quadriceps tendon; the "
          "origin is kept to the upper 15 % and the aponeurosis to the lower 16 % (the "
          "anatomical ones span the upper two thirds and most of the anterior face) because "
          "the VI is thin: where the two faces overlap in height the flow crosses the belly "
          "at right angles",
    "VL": "arises from the greater trochanter and intertrochanteric line through a "
          "proximal aponeurosis on its superficial (lateral) face; its fibers cross the "
          "belly distally and deep to the distal aponeurosis on its deep face, which joins "
          "the quadriceps tendon",
    "VM": "arises from the lower intertrochanteric line, the spiral line and the medial "
          "lip of the linea aspera, on its posterior (posteromedial) face; its fibers run "
          "anteriorly and distally to the aponeurosis on its deep face and the medial "
          "quadriceps tendon (the oblique distal part)",
    "RF": "arises from the anterior inferior iliac spine by a tendon that spreads as an "
          "aponeurosis over its anterior (superficial) proximal face; its fibers run "
          "distally and deep to the distal aponeurosis on its posterior (deep) face",
}
INTERFACE_REACH = 1.0  # mm
#: Smallest det J of a curved tet10 over its straight value (see straighten). At 0.1 a few
#: of the most curved elements (0.1–0.2 at rest) turned a corner inside out in the squat
#: (docs/knee-model.md, "Curved tet10 that invert"); 0.5 costs 0.7–1.8 % of the volume.
MIN_JACOBIAN = 0.5
#: The femoral shaft is fitted to the VI at these heights [mm] (where its inner surface
#: hugs the bone, see femur.csv) and spans SHAFT_BOTTOM..SHAFT_TOP.
SHAFT_FIT = [600.0 + 10.0 * k for k in range(17)]
SHAFT_BOTTOM, SHAFT_TOP = 515.0, 860.0
SHAFT_SHIFT = (-15.0, 0.0)
SHAFT_SIDES, SHAFT_RINGS = 48, 35
SHAFT_GAP = 0.5  # mm between the shaft and the nearest muscle vertex
SHAFT_MOVE = 6.0  # mm: how far a ring's centre may leave the fitted axis


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA)
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    parser.add_argument("--check", action="store_true",
                        help="regenerate into a temporary folder and compare with --out "
                        "byte for byte (exit status 1 on a difference)")
    args = parser.parse_args(argv)
    if args.check:
        with tempfile.TemporaryDirectory() as scratch:
            build(args.data, Path(scratch))
            names = sorted(p.name for p in Path(scratch).iterdir())
            committed = sorted(p.name for p in args.out.iterdir())
            _, mismatch, errors = filecmp.cmpfiles(scratch, args.out, names, shallow=False)
            if mismatch or errors or names != committed:
                print(f"differs from {args.out}: {mismatch + errors}; files "
                      f"{sorted(set(names) ^ set(committed))} only on one side")
                return 1
            print(f"{len(names)} files regenerated byte for byte")
            return 0
    build(args.data, args.out)
    return 0


def build(data, out):
    out.mkdir(parents=True, exist_ok=True)
    surfaces = {}
    for key, name in MUSCLES.items():
        points, triangles = geo.read_binary_stl(data / f"VHF_Right_Muscle_{name}_smooth.stl")
        triangles = mesher.check_closed_surface(points, triangles, name)
        if geo.signed_volume(points, triangles) < 0:
            triangles = [(a, c, b) for a, b, c in triangles]
        surfaces[key] = (points, triangles)
    femur = build_femur(data, out, surfaces)
    reach = {key: geo.SurfaceDistance(p, t, INTERFACE_REACH) for key, (p, t) in surfaces.items()}
    rows = []
    for resolution, size in RESOLUTIONS.items():
        for key in MUSCLES:
            rows.append(mesh_muscle(key, resolution, size, surfaces, femur, reach, out))
            print(", ".join(f"{k} {v}" for k, v in rows[-1].items()), flush=True)
    for name, (source, size) in BONES.items():
        remesh_bone(data / f"VHF_Right_{source}_smooth.stl", out / f"{name}.stl", name, size)
    marks = landmarks.knee_landmarks(data)
    landmarks.write_landmarks(out / "landmarks.csv", marks)
    write_summary(out / "summary.csv", rows)
    shutil.copyfile(data / "SOURCE_README.txt", out / "SOURCE_README.txt")
    write_readme(out / "README.md", rows, femur, marks)


# --- femur --------------------------------------------------------------------------------

def build_femur(data, out, surfaces):
    """Fits the shaft (see visible_human_geometry.femur_shaft_fit) and writes
    femur_shaft.stl, femur.csv (the section fits) and femur_rings.csv (the shaft's rings);
    returns the axis (point, unit direction) [mm] and the fits.

    The shaft's axis and fitted radius are straight lines in z through the section fits.
    A least-squares circle cuts into the irregular inner surface of the VI by up to 7 mm,
    and the contact needs the bone outside the muscles, so each ring (normal to the
    axis) is then placed in the largest circle free of the muscle vertices (VI, VL, VM,
    RF) within one ring spacing, its centre within SHAFT_MOVE of the axis, and its
    radius is the fitted one or, where smaller, that circle's less SHAFT_GAP."""
    fits = geo.femur_shaft_fit(*surfaces["VI"], SHAFT_FIT, 6.0, SHAFT_SHIFT)
    rows = [(1.0, z) for z, *_ in fits]
    x0, x1 = geo.least_squares(rows, [f[1] for f in fits])
    y0, y1 = geo.least_squares(rows, [f[2] for f in fits])
    r0, r1 = geo.least_squares(rows, [f[3] for f in fits])
    head, head_radius = geo.fit_sphere(geo.read_binary_stl(
        data / "VHF_Right_Cartilage_FemurHead_smooth.stl")[0])

    def at(z):
        return (x0 + x1 * z, y0 + y1 * z, z)

    bottom, top = at(SHAFT_BOTTOM), at(SHAFT_TOP)
    axis = geo.normalize(geo.sub(top, bottom))
    length = geo.norm(geo.sub(top, bottom))
    spacing = length / SHAFT_RINGS
    fitted = [r0 + r1 * (SHAFT_BOTTOM + (SHAFT_TOP - SHAFT_BOTTOM) * k / SHAFT_RINGS)
              for k in range(SHAFT_RINGS + 1)]
    u, v = geo.ring_basis(axis)
    near = [[] for _ in fitted]
    for points, _ in surfaces.values():
        for q in points:
            h = geo.dot(geo.sub(q, bottom), axis)
            offset = geo.sub(q, bottom)
            for k in range(max(0, math.floor(h / spacing)),
                           min(SHAFT_RINGS, math.ceil(h / spacing)) + 1):
                if abs(h - k * spacing) <= spacing:
                    near[k].append((geo.dot(offset, u), geo.dot(offset, v)))
    centres, radii = [], []
    for k, radius in enumerate(fitted):
        on_axis = geo.add(bottom, geo.scale(axis, k * spacing))
        if near[k]:
            (cu, cv), clearance = geo.largest_empty_circle(near[k], SHAFT_MOVE)
            radius = min(radius, clearance - SHAFT_GAP)
            on_axis = geo.add(on_axis, geo.add(geo.scale(u, cu), geo.scale(v, cv)))
        centres.append(on_axis)
        radii.append(radius)
    points, triangles = geo.tube(centres, radii, axis, SHAFT_SIDES)
    geo.write_binary_stl(out / "femur_shaft.stl", points, triangles,
                         "musclefem visible_human_knee.py: femoral shaft, mm")
    with open(out / "femur.csv", "w", encoding="ascii") as f:
        f.write("z_mm,centre_x_mm,centre_y_mm,radius_mm,inner_vertices\n")
        for z, cx, cy, r, n in fits:
            f.write(f"{z:.1f},{cx:.3f},{cy:.3f},{r:.3f},{n}\n")
    with open(out / "femur_rings.csv", "w", encoding="ascii") as f:
        f.write("centre_x_mm,centre_y_mm,centre_z_mm,fitted_radius_mm,radius_mm\n")
        for centre, fit, radius in zip(centres, fitted, radii):
            f.write(",".join(f"{c:.3f}" for c in centre) + f",{fit:.3f},{radius:.3f}\n")
    return SimpleNamespace(point=bottom, axis=axis, bottom=bottom, top=top,
                           radius=(r0 + r1 * SHAFT_BOTTOM, r0 + r1 * SHAFT_TOP),
                           rings=(min(radii), max(radii)),
                           head=head, head_radius=head_radius)


def remesh_bone(source, target, name, size):
    """A bone or cartilage surface remeshed by Gmsh at `size` (mm), binary STL. The sizes
    stay within 0.9–1 × `size` (a smaller lower bound lets Gmsh refine the patches of the
    reparametrised surface far below it)."""
    import gmsh

    points, triangles = geo.read_binary_stl(source)
    gmsh.initialize(["visible_human_knee"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.add(name)
        surface = gmsh.model.addDiscreteEntity(2)
        gmsh.model.mesh.addNodes(2, surface, list(range(1, len(points) + 1)),
                                 [c for p in points for c in p])
        gmsh.model.mesh.addElementsByType(surface, 2, [], [i + 1 for t in triangles for i in t])
        gmsh.model.mesh.classifySurfaces(math.radians(FEATURE_ANGLE), True, True, math.pi)
        gmsh.model.mesh.createGeometry()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.9 * size)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, element_nodes = gmsh.model.mesh.getElementsByType(2)
    finally:
        gmsh.finalize()
    index = {int(t): i for i, t in enumerate(tags)}
    new_points = [tuple(float(c) for c in coords[3 * i:3 * i + 3]) for i in range(len(tags))]
    new_triangles = [tuple(index[int(n)] for n in element_nodes[3 * e:3 * e + 3])
                     for e in range(len(element_nodes) // 3)]
    if geo.signed_volume(new_points, new_triangles) < 0:
        new_triangles = [(a, c, b) for a, b, c in new_triangles]
    geo.write_binary_stl(target, new_points, new_triangles,
                         f"musclefem visible_human_knee.py: {name}, mm")
    print(f"{name}: {len(triangles)} -> {len(new_triangles)} triangles", flush=True)


# --- muscles ------------------------------------------------------------------------------

def mesh_muscle(key, resolution, size, surfaces, femur, reach, out):
    points, triangles = surfaces[key]
    metres = [(x * 1e-3, y * 1e-3, z * 1e-3) for x, y, z in points]
    options = SimpleNamespace(keep_surface=False, feature_angle=FEATURE_ANGLE,
                              element="tet10", verbose=False, surface=f"{key} surface",
                              curved=True)
    nodes, tets = mesher.mesh_volume(metres, triangles, size * 1e-3, options)
    straightened = straighten(nodes, tets)
    faces = mesher.boundary_faces(nodes, tets)
    groups = name_groups(key, nodes, faces, femur, reach)
    path = out / f"{key}_{resolution}.msh"
    write_msh(path, nodes, tets, faces, groups)
    row = {"muscle": key, "resolution": resolution, "size_mm": f"{size:g}",
           "elements": len(tets), "nodes": len(nodes),
           "surface_volume_mm3": f"{geo.signed_volume(points, triangles):.1f}",
           "mesh_volume_mm3": f"{1e9 * sum(geo.tet10_volume(nodes, t) for t in tets):.1f}",
           "min_jacobian_ratio": f"{min(geo.tet10_quality(nodes, t) for t in tets):.3f}",
           "straightened_elements": straightened, "boundary_faces": len(faces)}
    for group, members in groups.items():
        area = sum(face_area(nodes, faces[i]) for i in members) * 1e6
        row[f"{group}_faces"] = len(members)
        row[f"{group}_area_mm2"] = f"{area:.0f}"
    return row


def straighten(nodes, tets):
    """Moves the mid-edge nodes of every element whose det J falls below MIN_JACOBIAN times
    its straight value halfway back to its straight edges, until none does; returns how
    many times an element was moved. Gmsh places the boundary's mid-edge nodes on the
    surface, which keeps its volume, but where an element is thin across a curved face
    that can fold it."""
    count = 0
    while True:
        bad = [t for t in tets if geo.tet10_quality(nodes, t) < MIN_JACOBIAN]
        if not bad:
            return count
        count += len(bad)
        moved = set()
        for tet in bad:
            for k, (i, j) in enumerate(geo.TET10_EDGES):
                if tet[4 + k] in moved:
                    continue
                moved.add(tet[4 + k])
                middle = geo.scale(geo.add(nodes[tet[i]], nodes[tet[j]]), 0.5)
                nodes[tet[4 + k]] = geo.scale(geo.add(nodes[tet[4 + k]], middle), 0.5)


def name_groups(key, nodes, faces, femur, reach):
    """The face groups of the module's rules: {name: [face index]} (see the docstring)."""
    a = femur.axis
    anterior = geo.normalize(geo.sub((0.0, 1.0, 0.0), geo.scale(a, a[1])))
    centres = [geo.scale(mesher.centroid(nodes, f), 1e3) for f in faces]
    normals = [geo.normalize(face_normal(nodes, f)) for f in faces]
    heights = [geo.dot(geo.sub(c, femur.point), a) for c in centres]
    low, high = min(heights), max(heights)
    groups = {"origin": [], "insertion": [], "aponeurosis": []}

    def on(rule, s, radial, n):
        if rule is None:
            return False
        side, lowest, highest = rule
        if not lowest <= s < highest:
            return False
        if side == "deep":
            return radial < -FACING
        if side == "superficial":
            return radial > FACING
        if side == "anterior":
            return radial > FACING and geo.dot(n, anterior) > ANTERIOR
        if side == "posterior":
            return geo.dot(n, anterior) < -ANTERIOR
        raise ValueError(side)

    for i, (c, n, h) in enumerate(zip(centres, normals, heights)):
        s = (h - low) / (high - low)
        offset = geo.sub(c, geo.add(femur.point, geo.scale(a, h)))
        radial = geo.dot(n, geo.normalize(offset))
        if s < END:
            groups["insertion"].append(i)
        elif s > 1 - END or on(RULES[key]["origin"], s, radial, n):
            groups["origin"].append(i)
        elif on(RULES[key]["aponeurosis"], s, radial, n):
            groups["aponeurosis"].append(i)
    for other in MUSCLES:
        if other != key:
            members = [i for i, (c, f) in enumerate(zip(centres, faces))
                       if any(reach[other].within(q) for q in
                              [c] + [geo.scale(nodes[k], 1e3) for k in f[:3]])]
            if members:
                groups[f"interface_{other}"] = members
    for group, members in groups.items():
        if not members:
            raise SystemExit(f"error: {key}: the group {group} is empty")
    return groups


def face_normal(nodes, face):
    a, b, c = (nodes[i] for i in face[:3])
    return geo.cross(geo.sub(b, a), geo.sub(c, a))


def face_area(nodes, face):
    return 0.5 * geo.norm(face_normal(nodes, face))


def write_msh(path, nodes, tets, faces, groups):
    """Gmsh 4.1 ASCII in metres: volume entity 1 (group `muscle`); one surface entity per
    distinct set of groups a boundary face belongs to, each carrying those groups and
    `outer`. Physical tags: 1 muscle, then the groups in order, then outer."""
    names = list(groups)
    tag_of = {name: k + 2 for k, name in enumerate(names)}
    outer = len(names) + 2
    membership = [[] for _ in faces]
    for name in names:
        for i in groups[name]:
            membership[i].append(tag_of[name])
    entities = {}
    for i, tags in enumerate(membership):
        entities.setdefault(tuple(tags), []).append(i)
    keys = sorted(entities, key=lambda t: (len(t), t))
    lo, hi = mesher.bounding_box(nodes)
    box = " ".join(f"{v:.9g}" for v in lo + hi)
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames",
             str(len(names) + 2), '3 1 "muscle"']
    lines += [f'2 {tag_of[n]} "{n}"' for n in names] + [f'2 {outer} "outer"',
                                                         "$EndPhysicalNames", "$Entities"]
    lines.append(f"0 0 {len(keys)} 1")
    for e, tags in enumerate(keys, 1):
        physicals = list(tags) + [outer]
        lines.append(f"{e} {box} {len(physicals)} " + " ".join(map(str, physicals)) + " 0")
    lines.append(f"1 {box} 1 1 {len(keys)} " + " ".join(f"-{e}" for e in range(1, len(keys) + 1)))
    lines += ["$EndEntities", "$Nodes", f"1 {len(nodes)} 1 {len(nodes)}",
              f"3 1 0 {len(nodes)}"]
    lines += [str(i + 1) for i in range(len(nodes))]
    lines += [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in nodes]
    lines.append("$EndNodes")
    count = len(tets) + len(faces)
    lines += ["$Elements", f"{1 + len(keys)} {count} 1 {count}", f"3 1 11 {len(tets)}"]
    lines += [f"{e + 1} " + " ".join(str(n + 1) for n in tet) for e, tet in enumerate(tets)]
    tag = len(tets)
    for e, key in enumerate(keys, 1):
        lines.append(f"2 {e} 9 {len(entities[key])}")
        for i in entities[key]:
            tag += 1
            lines.append(f"{tag} " + " ".join(str(n + 1) for n in faces[i]))
    lines.append("$EndElements")
    path.write_text("\n".join(lines) + "\n", encoding="ascii")


# --- records ------------------------------------------------------------------------------

def write_summary(path, rows):
    columns = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    with open(path, "w", encoding="ascii") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(str(row.get(c, "")) for c in columns) + "\n")


def write_readme(path, rows, femur, marks):
    from visible_human_readme import readme_text

    path.write_text(readme_text(rows, femur, marks, sys.modules[__name__]), encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
