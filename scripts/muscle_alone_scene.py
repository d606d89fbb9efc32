#!/usr/bin/env python3
"""One muscle of a knee run, pulled alone and quasi-statically: a mesh-convergence check
that leaves out everything but the muscle itself (docs/knee-model.md, "One muscle alone
converges with the mesh").

Usage:

    musclefem knee --passive --duration 0.02 --out RUN   # writes RUN/passive/scene.toml
    python3 scripts/muscle_alone_scene.py RUN/passive OUT [--muscle vastus_lateralis]
        [--pull-mm 45] [--increments 20] [--inertia]
    musclefem run OUT/scene.toml --out OUT/out

The rectus femoris hangs between two strand fans, slack at rest, so it has no
quasi-static equilibrium at the start: run it with `--inertia` (as measured:
`--muscle rectus_femoris --pull-mm 30 --increments 40 --inertia`).

From the knee's scene (its `muscles.inp`, `fibers.csv`, `strands.csv` and the muscle's
material) it writes a scene with that muscle alone: its elements, renumbered; its fibers;
its strands; its origin node set held (the origin faces, or the rectus femoris's pin
with its origin strands); its insertion anchor (the strands'
common end, the node set `<muscle>_insertion`) moved distally (−y in the knee frame) by
the pull on a half-cosine ramp over 0.4 s and held to 0.5 s; no contact, no bonds, no
bones; the implicit solver, quasi-static (no inertia, so no mass scaling either), or
with `--inertia` Newmark with the physical mass and numerical dissipation 0.3. The
history's `reaction_insertion_*` is the pull; `von_mises_p95_<muscle>_pa` its vm95.
Run it on a coarse and a medium knee and compare at equal pulls.
"""

import argparse
import csv
import math
import re
from pathlib import Path

RAMP_S = 0.4
DURATION_S = 0.5


def read_nodes(lines):
    """The *NODE block: {label: the rest of its line (", x, y, z")}."""
    start = lines.index("*NODE") + 1
    nodes = {}
    for line in lines[start:]:
        if line.startswith("*"):
            break
        label, rest = line.split(",", 1)
        nodes[int(label)] = "," + rest
    return nodes


def numbers_after(text, header):
    """The integers of the data lines under `header`, up to the next keyword line."""
    match = re.search(re.escape(header) + r"\n(.*?)(?=\n\*|\Z)", text, re.S)
    if match is None:
        raise SystemExit(f"muscles.inp has no '{header}'")
    return [int(x) for x in re.findall(r"\d+", match.group(1))]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("knee_scene_dir", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--muscle", default="vastus_lateralis")
    parser.add_argument("--pull-mm", type=float, default=45.0)
    parser.add_argument("--increments", type=int, default=20)
    parser.add_argument("--inertia", action="store_true",
                        help="Newmark with the physical mass instead of quasi-static")
    args = parser.parse_args()
    source, out, muscle = args.knee_scene_dir, args.out, args.muscle
    out.mkdir(parents=True, exist_ok=True)

    inp = (source / "muscles.inp").read_text()
    nodes = read_nodes(inp.split("\n"))
    connectivity = numbers_after(inp, f"*ELEMENT, TYPE=C3D10, ELSET={muscle}")
    elements = [connectivity[k:k + 11] for k in range(0, len(connectivity), 11)]
    # The insertion set is the strands' anchor; the origin set the origin faces' nodes,
    # or a pin outside the muscle (the rectus femoris's, joined to it by strands).
    ends = {end: numbers_after(inp, f"*NSET, NSET={muscle}_{end}")
            for end in ("insertion", "origin")}
    element_nodes = {n for e in elements for n in e[1:]}
    kept = sorted(element_nodes | set(ends["insertion"]) | set(ends["origin"]))
    label = {old: new for new, old in enumerate(kept, start=1)}
    first = elements[0][0]

    lines = ["*HEADING", f"{muscle} alone, from {source}", "*NODE"]
    lines += [f"{label[old]}{nodes[old]}" for old in kept]
    lines.append(f"*ELEMENT, TYPE=C3D10, ELSET={muscle}")
    for element in elements:
        ids = [str(label[n]) for n in element[1:]]
        lines.append(f"{element[0] - first + 1}, " + ", ".join(ids[:7]) + ",")
        lines.append(", ".join(ids[7:]))
    for end, members in ends.items():
        ids = [str(label[n]) for n in members]
        lines.append(f"*NSET, NSET={muscle}_{end}")
        lines += [", ".join(ids[p:p + 16]) for p in range(0, len(ids), 16)]
    lines.append(f"*ELSET, ELSET={muscle}")
    ids = [str(k) for k in range(1, len(elements) + 1)]
    lines += [", ".join(ids[p:p + 16]) for p in range(0, len(ids), 16)]
    (out / "muscles.inp").write_text("\n".join(lines) + "\n")

    with open(source / "fibers.csv") as f:
        fibers = list(csv.DictReader(f))
    with open(out / "fibers.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(fibers[0]))
        writer.writeheader()
        for row in fibers:
            element = int(row["element"])
            if first <= element < first + len(elements):
                writer.writerow({**row, "element": element - first + 1})

    with open(source / "strands.csv") as f:
        strands = [row for row in csv.DictReader(f) if int(row["node_a"]) in element_nodes]
    with open(out / "strands.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["node_a", "node_b", "slack_length",
                                               "strain_stiffness", "toe_strain"])
        writer.writeheader()
        for row in strands:
            writer.writerow({**row, "node_a": label[int(row["node_a"])],
                             "node_b": label[int(row["node_b"])]})

    scene = (source / "scene.toml").read_text()
    tables = re.split(r"\n(?=\[)", scene)
    part = next(t for t in tables if t.startswith("[[parts]]") and f'name = "{muscle}"' in t)
    material_name = re.search(r'material = "(\w+)"', part).group(1)
    materials = [t for t in tables if t.startswith("[[materials]]")
                 and (f'name = "{material_name}"' in t or 'name = "tendon"' in t)]
    # The anchor is in no element: the part takes the file's whole node array.
    part = part.replace("shared_nodes = false", "shared_nodes = true")
    strands_table = next(t for t in tables if t.startswith("[[strands]]"))
    strands_table = re.sub(r'part = "\w+"', f'part = "{muscle}"', strands_table)
    knots = ", ".join(
        f"[{RAMP_S * k / 20:.4f}, {0.5 * (1 - math.cos(math.pi * k / 20)):.6f}]"
        for k in range(21))
    dynamics = "\ndynamic = true\nnumerical_dissipation = 0.3" if args.inertia else ""
    text = [
        "schema_version = 1",
        f'description = "{muscle} pulled {args.pull_mm:g} mm alone, '
        f'{"with inertia" if args.inertia else "quasi-static"}"',
        *materials, part, strands_table,
        f'[[amplitudes]]\nname = "ramp"\npoints = [{knots}]',
        f'[[rigid_ties]]\nname = "origin"\npart = "{muscle}"\nnodes = "{muscle}_origin"\n'
        "translation = [0.0, 0.0, 0.0]",
        f'[[rigid_ties]]\nname = "insertion"\npart = "{muscle}"\nnodes = "{muscle}_insertion"\n'
        f'translation = [0.0, {-args.pull_mm * 1e-3}, 0.0]\ntranslation_amplitude = "ramp"',
        f'[step]\nsolver = "implicit"\nduration = {DURATION_S}\noutput_interval = 0.025\n\n'
        f"[step.implicit]\nincrements = {args.increments}{dynamics}",
        "[output]\nvon_mises_percentile = 95\nframes = true\nframe_interval = 0.125",
    ]
    (out / "scene.toml").write_text("\n\n".join(t.strip() for t in text) + "\n")
    print(f"{out / 'scene.toml'}: {muscle}, {len(elements)} elements, {len(kept)} nodes, "
          f"{len(strands)} strands, pulled {args.pull_mm:g} mm")


if __name__ == "__main__":
    main()
