#!/bin/sh
# Builds the Python module `musclefem` (crates/python, pyo3 + maturin) into a virtual
# environment with what its tests and examples need: target/python-venv (maturin, pytest,
# NumPy, and for examples/python and Result.history_frame SciPy, matplotlib and pandas,
# from the package index).
# Afterwards: target/python-venv/bin/python -m pytest crates/python/tests
# Elsewhere, `pip install ./crates/python` builds and installs it into any Python >= 3.9.
set -eu
cd "$(dirname "$0")/.."
venv=target/python-venv
if ! python3 -m venv "$venv" 2>/dev/null; then
    # Debian's python3 keeps venv in its own package.
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        sudo="sudo"
    fi
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends python3-venv
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet "maturin>=1.9,<2" "pytest>=7" "numpy>=1.21" \
    "scipy>=1.7" "matplotlib>=3.5" "pandas>=1.3"
# In the workspace's target directory, so the release build of the tests is reused.
VIRTUAL_ENV="$PWD/$venv" PATH="$PWD/$venv/bin:$PATH" \
    "$venv/bin/maturin" develop --release --quiet -m crates/python/Cargo.toml
