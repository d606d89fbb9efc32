"""The cube of `musclefem bench --problem scaling` (issue #36) in felupe, for comparison.

A cube [0, 10 mm]^3 of n^3 hex8, neo-Hookean W = mu/2 (I1_bar - 3) + K/2 (J - 1)^2 with
mu = 10 kPa and K = 2 mu (1 + nu) / (3 (1 - 2 nu)), symmetry planes x0, y0, z0, the face
x1 pulled along x to stretch 1.5 in 10 equal load steps, the lateral faces free. SI units
(m, Pa, N), as in musclefem. felupe's element for nearly incompressible solids on hex8 is
SolidBodyNearlyIncompressible: a constant pressure per cell, condensed (a u/p formulation
like musclefem's F-bar mean dilatation). Its linear solver is felupe's default
(scipy.sparse.linalg.spsolve).

    python scripts/felupe_cube.py DIVISIONS POISSON

Prints one JSON line: divisions, poisson, unknowns (free degrees of freedom), seconds
(wall time of mesh, model and solve; Python start-up and imports excluded),
newton_iterations (over all steps), force (reaction on x1 along x at the end [N]),
peak_memory_bytes (the process's peak resident memory) and felupe's version.
Needs felupe (scripts/setup-felupe installs it into .venv-felupe). `musclefem bench
--problem scaling` runs this file (built into the binary) and reads the line. Not the
clamped cube of bench/peers/felupe_cube.py (the work-precision cube, whose faces x0 and x1
are clamped).
"""

import json
import resource
import sys
import time

import felupe as fem

SIDE = 0.01  # edge of the cube [m]
SHEAR_MODULUS = 1e4  # mu [Pa]
STRETCH = 1.5  # of the face x1 at the end [1]
STEPS = 10  # equal load steps


def bulk_modulus(poisson):
    """K = 2 mu (1 + nu) / (3 (1 - 2 nu)) [Pa]."""
    return 2.0 * SHEAR_MODULUS * (1.0 + poisson) / (3.0 * (1.0 - 2.0 * poisson))


def main():
    divisions = int(sys.argv[1])
    poisson = float(sys.argv[2])
    started = time.perf_counter()
    mesh = fem.Cube(a=(0.0, 0.0, 0.0), b=(SIDE, SIDE, SIDE), n=divisions + 1)
    region = fem.RegionHexahedron(mesh)
    field = fem.FieldContainer([fem.Field(region, dim=3)])
    # Symmetry on x0, y0, z0; x1 moved along x only (its lateral motion free).
    boundaries = fem.dof.uniaxial(
        field, clamped=False, sym=True, return_loadcase=False
    )
    _, free = fem.dof.partition(field, boundaries)
    solid = fem.SolidBodyNearlyIncompressible(
        fem.NeoHooke(mu=SHEAR_MODULUS), field, bulk=bulk_modulus(poisson)
    )
    # STEPS equal increments of the pull (linsteps adds the start, 0, as a trivial step).
    pull = fem.math.linsteps([0.0, (STRETCH - 1.0) * SIDE], num=STEPS)
    step = fem.Step(
        items=[solid], ramp={boundaries["move"]: pull}, boundaries=boundaries
    )
    job = fem.CharacteristicCurve(steps=[step], boundary=boundaries["move"])
    job.evaluate(verbose=0)
    seconds = time.perf_counter() - started
    # One list of residual norms per substep, one norm per Newton iteration; the first
    # substep is the start (no pull).
    newton_iterations = sum(len(norms) for norms in job.fnorms[1:])
    force = float(job.y[-1][0])
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    print(
        json.dumps(
            {
                "divisions": divisions,
                "poisson": poisson,
                "unknowns": int(len(free)),
                "seconds": seconds,
                "newton_iterations": int(newton_iterations),
                "force": force,
                "peak_memory_bytes": int(peak_kib) * 1024,
                "felupe": fem.__version__,
            }
        )
    )


if __name__ == "__main__":
    main()
