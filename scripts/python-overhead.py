#!/usr/bin/env python3
"""The time of a Python call against the command line's for the same work (docs/python.md,
"Overhead"): a material point (neo-Hookean, stretched to 1.5 in 100 steps of 0.01 s) and
a small scene (examples/neo_hookean_cube_stretch.toml: 64 hex8-fbar, 10 increments,
11 frames). Each case is run REPEAT times; prints min and median [ms] as a Markdown table.

    target/python-venv/bin/python scripts/python-overhead.py [REPEAT]

Needs the release build of the command (`cargo build --release -p musclefem`) and the
module (`scripts/setup-python.sh`). "warm" is a call in a running interpreter with
musclefem imported; "cold" a new Python process that imports musclefem and makes the
call, as the command is a new process each time.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import musclefem

ROOT = Path(__file__).resolve().parents[1]
CLI = ROOT / "target" / "release" / "musclefem"
SCENE = ROOT / "examples" / "neo_hookean_cube_stretch.toml"
REPEAT = int(sys.argv[1]) if len(sys.argv) > 1 else 20


def timed(call):
    """min and median of REPEAT runs of call() [ms], after one run to warm caches."""
    call()
    samples = []
    for _ in range(REPEAT):
        started = time.perf_counter()
        call()
        samples.append(1e3 * (time.perf_counter() - started))
    return min(samples), statistics.median(samples)


def process(*argv):
    return lambda: subprocess.run(argv, check=True, capture_output=True)


def main():
    if not CLI.exists():
        sys.exit(f"{CLI}: build it first (cargo build --release -p musclefem)")
    out = Path(tempfile.mkdtemp(prefix="musclefem-overhead-"))
    point = ("neo-hookean", {"mu": 1e4, "D": 2e-5}, [0.0, 1.0], [1.0, 1.5], 0.01)
    point_call = (
        "musclefem.MaterialPoint('neo-hookean', mu=1e4, D=2e-5)"
        ".uniaxial([0.0, 1.0], [1.0, 1.5], dt=0.01)"
    )
    cases = {
        "nothing": {
            "Python, cold: a new interpreter importing musclefem and NumPy": process(
                sys.executable, "-c", "import numpy, musclefem"
            ),
        },
        "material point": {
            "command line (`musclefem point`, CSV, no chart)": process(
                str(CLI), "point", "--material", "neo-hookean", "--param", "mu=1e4",
                "--param", "D=2e-5", "--stretch", "0:1,1:1.5", "--dt", "0.01",
                "--out", str(out / "point.csv"), "--no-plot", "--force",
            ),
            "Python, warm (`MaterialPoint(...).uniaxial(...)`)": lambda: musclefem.MaterialPoint(
                point[0], **point[1]
            ).uniaxial(point[2], point[3], dt=point[4]),
            "Python, cold (new interpreter, import, call)": process(
                sys.executable, "-c", f"import musclefem; {point_call}"
            ),
        },
        "scene (cube)": {
            "command line (`musclefem run`, run directory)": process(
                str(CLI), "run", str(SCENE), "--out", str(out / "cli"), "--force"
            ),
            "Python, warm, in memory (`Scene(path).run()`)": lambda: musclefem.Scene(
                str(SCENE)
            ).run(),
            "Python, warm, run directory (`run(out=..., force=True)`)": lambda: musclefem.Scene(
                str(SCENE)
            ).run(out=str(out / "py"), force=True),
            "Python, cold, run directory (new interpreter)": process(
                sys.executable, "-c",
                f"import musclefem; musclefem.Scene({str(SCENE)!r})"
                f".run(out={str(out / 'py-cold')!r}, force=True)",
            ),
        },
    }
    cores = os.cpu_count()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{REPEAT} runs each, {cores} cores, load average {load:.2f} at the start\n")
    print("| case | call | min [ms] | median [ms] |")
    print("|---|---|---:|---:|")
    for case, calls in cases.items():
        for name, call in calls.items():
            low, middle = timed(call)
            print(f"| {case} | {name} | {low:.1f} | {middle:.1f} |")


if __name__ == "__main__":
    main()
