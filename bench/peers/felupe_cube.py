#!/usr/bin/env python3
"""Peer comparison (not run by CI): the bench's neo-Hookean cube in felupe and in musclefem.

The cube of `musclefem bench` (crates/studies/src/bench/cube.rs): 1 cm, neo-Hookean with
mu = 10 kPa and K = 2/D = 100 kPa (felupe's NeoHooke(mu, bulk) has the same energy,
W = mu/2 (J^-2/3 I1 - 3) + K/2 (J - 1)^2), face x = 0 clamped, face x = 1 cm clamped
laterally and pulled 5 mm along x in 10 equal quasi-static increments. Both codes use
trilinear hexahedra with 2x2x2 Gauss points (musclefem hex8-full, felupe
RegionHexahedron) on the same N x N x N grid, Newton with a direct sparse solver.

It prints, for each N, both end reaction forces (they must agree: same model) and the
solve wall times measured here, in one run on one machine, with their ratio.

Usage (felupe from PyPI in a throw-away virtual environment):
    python3 -m venv /tmp/felupe-venv && /tmp/felupe-venv/bin/pip install felupe
    cargo build --release -p musclefem
    /tmp/felupe-venv/bin/python bench/peers/felupe_cube.py [--musclefem target/release/musclefem]
"""

import argparse
import os
import platform
import re
import subprocess
import tempfile
import time

import felupe as fem
import numpy as np

EDGE = 0.01  # m
PULL = 0.005  # m
MU = 1e4  # Pa
BULK = 1e5  # Pa
INCREMENTS = 10


def felupe_cube(divisions):
    """End reaction force [N] and solve wall time [s] of the cube in felupe."""
    started = time.perf_counter()
    mesh = fem.Cube(a=(0, 0, 0), b=(EDGE, EDGE, EDGE), n=divisions + 1)
    region = fem.RegionHexahedron(mesh)
    field = fem.FieldContainer([fem.Field(region, dim=3)])
    boundaries = {
        "left": fem.Boundary(field[0], fx=0.0),
        "right": fem.Boundary(field[0], fx=EDGE, skip=(1, 0, 0)),
        "move": fem.Boundary(field[0], fx=EDGE, skip=(0, 1, 1)),
    }
    solid = fem.SolidBody(fem.NeoHooke(mu=MU, bulk=BULK), field)
    setup = time.perf_counter() - started
    move = np.linspace(0, PULL, INCREMENTS + 1)[1:]
    step = fem.Step(items=[solid], ramp={boundaries["move"]: move}, boundaries=boundaries)
    job = fem.Job(steps=[step])
    started = time.perf_counter()
    job.evaluate(verbose=0)
    solve = time.perf_counter() - started
    internal = solid.assemble.vector(field).toarray().reshape(-1, 3)
    on_right = np.isclose(mesh.points[:, 0], EDGE)
    return internal[on_right, 0].sum(), setup, solve


def musclefem_scene(divisions):
    return f"""schema_version = 1
description = "clamped neo-Hookean cube pulled to stretch 1.5 (peer comparison)"

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = {{ mu = {MU:e}, D = {2.0 / BULK:e} }}

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-full"
density = 1000.0
mesh = {{ generator = "box", size = [{EDGE}, {EDGE}, {EDGE}], divisions = [{divisions}, {divisions}, {divisions}] }}

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "cube"
nodes = "x1"
components = ["x"]
value = {PULL}
amplitude = "ramp"

[[displacements]]
part = "cube"
nodes = "x1"
components = ["y", "z"]

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x", "y", "z"]

[step]
solver = "implicit"
duration = 1.0
output_interval = 0.1
implicit = {{ increments = {INCREMENTS} }}

[output]
frames = false
"""


def musclefem_cube(program, divisions, threads):
    """End reaction force [N] and solve wall time [s] (from run.log) of `musclefem run`."""
    with tempfile.TemporaryDirectory() as directory:
        scene = os.path.join(directory, "cube.toml")
        with open(scene, "w") as f:
            f.write(musclefem_scene(divisions))
        out = os.path.join(directory, "out")
        command = [program, "run", scene, "--out", out, "--threads", str(threads)]
        printed = subprocess.run(command, check=True, capture_output=True, text=True).stdout
        with open(os.path.join(out, "run.log")) as f:
            log = f.read()
    solve = float(re.search(r"^solve_s = (\S+)", log, re.M).group(1))
    force = float(re.search(r"cube\.x1\.x (\S+) N", printed).group(1))
    return force, solve


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--musclefem", default="target/release/musclefem")
    parser.add_argument("--divisions", type=int, nargs="+", default=[8, 12, 16])
    args = parser.parse_args()
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    print(f"felupe {fem.__version__}, numpy {np.__version__}; {cpu}, {os.cpu_count()} threads")
    print("N  dofs    force_felupe_N force_musclefem_N  felupe_solve_s  musclefem_solve_s(1 thread, all)  ratio felupe/musclefem(1 thread, all)")
    for n in args.divisions:
        f_force, _, f_solve = felupe_cube(n)
        m_force_1, m_solve_1 = musclefem_cube(args.musclefem, n, 1)
        m_force, m_solve = musclefem_cube(args.musclefem, n, os.cpu_count() or 1)
        assert abs(m_force_1 - m_force) <= 1e-9 * abs(m_force)
        dofs = 3 * (n + 1) ** 3
        print(
            f"{n:<2} {dofs:<7} {f_force:<14.6f} {m_force:<17.6f} {f_solve:<15.3f} "
            f"{m_solve_1:.3f}, {m_solve:.3f}{'':17} {f_solve / m_solve_1:.2f}, {f_solve / m_solve:.2f}"
        )


if __name__ == "__main__":
    main()
