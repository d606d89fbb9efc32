"""What the tests share: the repository's paths, closed forms and small meshes."""

import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[3]
CUBE = ROOT / "examples" / "neo_hookean_cube_stretch.toml"
# The command line, when built (`cargo build --release -p musclefem`): the tests that
# compare with it are skipped without it.
CLI = ROOT / "target" / "release" / "musclefem"


def neo_hookean_uniaxial(mu, d, stretch):
    """Engineering stress P11 [Pa] of W = mu/2 (I1bar - 3) + (J - 1)^2 / D in uniaxial
    stress at `stretch`: the lateral stretch t from sigma22 = 0 by bisection."""

    def sigma(t):
        j = stretch * t * t
        trace = (stretch**2 + 2 * t * t) / 3
        pressure = 2 * (j - 1) / d
        deviatoric = mu / j * j ** (-2 / 3)
        return deviatoric * (stretch**2 - trace) + pressure, deviatoric * (t * t - trace) + pressure

    lo, hi = 0.3, 1.5
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if sigma(lo)[1] * sigma(mid)[1] <= 0:
            hi = mid
        else:
            lo = mid
    t = 0.5 * (lo + hi)
    return stretch * t * t * sigma(t)[0] / stretch


def box_deck(path, nx=2, ny=2, nz=6, size=(0.01, 0.01, 0.03)):
    """An Abaqus deck of a box of hex8 (C3D8), node sets ORIGIN (z = 0) and INSERTION
    (z = L), element labels from 101."""
    def node(i, j, k):
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)

    lines = ["*NODE"]
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                x, y, z = (size[0] * i / nx, size[1] * j / ny, size[2] * k / nz)
                lines.append(f"{node(i, j, k)}, {x}, {y}, {z}")
    lines.append("*ELEMENT, TYPE=C3D8, ELSET=MUSCLE")
    label = 101
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                corners = [
                    node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                    node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                    node(i, j + 1, k + 1),
                ]
                lines.append(f"{label}, " + ", ".join(map(str, corners)))
                label += 1
    for name, k in [("ORIGIN", 0), ("INSERTION", nz)]:
        lines.append(f"*NSET, NSET={name}")
        lines.append(", ".join(str(node(i, j, k)) for j in range(ny + 1) for i in range(nx + 1)))
    path.write_text("\n".join(lines) + "\n")


def cube_dict(divisions=(4, 4, 4)):
    """examples/neo_hookean_cube_stretch.toml as a dict (Scene.from_dict)."""
    return {
        "schema_version": 1,
        "description": "neo-Hookean cube stretched to 1.5 (uniaxial stress)",
        "materials": [
            {"name": "rubber", "model": "neo-hookean", "parameters": {"mu": 1e4, "D": 2e-5}}
        ],
        "parts": [
            {
                "name": "cube",
                "material": "rubber",
                "element": "hex8-fbar",
                "density": 1000.0,
                "mesh": {"generator": "box", "size": [0.01] * 3, "divisions": list(divisions)},
            }
        ],
        "amplitudes": [{"name": "ramp", "points": [[0.0, 0.0], [1.0, 1.0]]}],
        "displacements": [
            {"part": "cube", "nodes": "x1", "components": ["x"], "value": 0.005, "amplitude": "ramp"},
            {"part": "cube", "nodes": "x0", "components": ["x"]},
            {"part": "cube", "nodes": "y0", "components": ["y"]},
            {"part": "cube", "nodes": "z0", "components": ["z"]},
        ],
        "step": {
            "solver": "implicit",
            "duration": 1.0,
            "output_interval": 0.1,
            "implicit": {"increments": 10},
        },
    }
