#!/usr/bin/env python3
"""Cross-sections of the Visible Human Female's quadriceps along each muscle's long axis.

Measures how strongly the real, segmented muscles taper from mid-belly to their ends: the
area of the section cut by planes normal to each muscle's principal axis, at 17 evenly
spaced stations from the distal (0 %) to the proximal (100 %) end. It answers whether a
model whose fibers run along the muscle (every section in series with the tendon) would
concentrate the pull in the ends on the real geometry too (docs/knee-model.md).

Usage: scripts/visible_human_sections.py [DATA_DIR]
DATA_DIR defaults to ../shared/data/visible_human_female_right (binary STL in mm,
Andreassen et al. 2022, CC BY 4.0). Needs Python 3 and NumPy only.

The area of one section of a closed, outward-oriented surface is found without chaining
its segments into loops: each triangle that the plane cuts contributes the segment
(p, q) oriented so that (q - p) · (n × n_triangle) > 0, and the enclosed area is
½ Σ (p × q) · n over all segments (Green's theorem; holes and several loops come out
right by themselves).
"""

import struct
import sys
from pathlib import Path

import numpy as np

MUSCLES = ["VastusIntermedius", "VastusLateralis", "VastusMedialis", "RectusFemoris"]
STATIONS = np.linspace(0.02, 0.98, 17)


def read_binary_stl(path):
    """Triangles of a binary STL as an (n, 3, 3) array [mm]."""
    data = path.read_bytes()
    (count,) = struct.unpack("<I", data[80:84])
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    return np.frombuffer(data[84 : 84 + 50 * count], dtype=record)["v"].astype(float)


def section_area(triangles, origin, normal):
    """Area [mm²] enclosed by the plane (origin, unit normal)'s cut of a closed surface."""
    side = (triangles - origin) @ normal  # (n, 3) signed distances of the corners
    cut = (side.min(1) < 0) & (side.max(1) > 0)
    tri, d = triangles[cut], side[cut]
    points = []
    for a, b in [(0, 1), (1, 2), (2, 0)]:
        crosses = (d[:, a] < 0) != (d[:, b] < 0)
        t = np.where(crosses, d[:, a] / np.where(crosses, d[:, a] - d[:, b], 1.0), np.nan)
        points.append(tri[:, a] + t[:, None] * (tri[:, b] - tri[:, a]))
    points = np.stack(points, 1)  # (m, 3 edges, 3): two finite rows per triangle
    finite = ~np.isnan(points[:, :, 0])
    p = np.array([row[f][0] for row, f in zip(points, finite)])
    q = np.array([row[f][1] for row, f in zip(points, finite)])
    face_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    forward = np.einsum("ij,ij->i", q - p, np.cross(normal, face_normal)) > 0
    p, q = np.where(forward[:, None], p, q), np.where(forward[:, None], q, p)
    return 0.5 * (np.cross(p, q) @ normal).sum()


def main():
    default = Path(__file__).resolve().parents[2] / "shared/data/visible_human_female_right"
    data = Path(sys.argv[1]) if len(sys.argv) > 1 else default
    print("muscle, length [mm], volume [cm3], largest section [cm2], "
          "sections distal -> proximal [cm2], end / largest (distal, proximal)")
    for muscle in MUSCLES:
        triangles = read_binary_stl(data / f"VHF_Right_Muscle_{muscle}_smooth.stl")
        corners = triangles.reshape(-1, 3)
        volume = np.einsum(
            "ij,ij->i", triangles[:, 0], np.cross(triangles[:, 1], triangles[:, 2])
        ).sum() / 6.0
        centre = corners.mean(0)
        axis = np.linalg.svd(corners - centre, full_matrices=False)[2][0]
        axis *= np.sign(axis[2])  # z is superior in the data's frame: proximal positive
        along = (corners - centre) @ axis
        low, high = along.min(), along.max()
        areas = np.array([
            section_area(triangles, centre + axis * (low + f * (high - low)), axis)
            for f in STATIONS
        ]) / 100.0
        print(f"{muscle}, {high - low:.0f}, {volume / 1e3:.0f}, {areas.max():.1f}, "
              + " ".join(f"{a:.1f}" for a in areas)
              + f", {areas[0] / areas.max():.2f} {areas[-1] / areas.max():.2f}")


if __name__ == "__main__":
    main()
