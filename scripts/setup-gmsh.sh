#!/bin/sh
# Installs Gmsh's Python package (`gmsh` from the package index, a wheel that carries the
# Gmsh library) into the project's virtual environment target/python-venv, for
# `musclefem mesh` (scripts/musclefem_mesh.py) and its tests. The wheel's library links
# to X11 and OpenGL libraries even when it runs without a display; when `import gmsh`
# fails for want of them, they are installed from Debian's packages (through sudo when
# not root), as scripts/setup-python.sh does for python3-venv.
# Afterwards: target/python-venv/bin/python -c "import gmsh"
set -eu
cd "$(dirname "$0")/.."
venv=target/python-venv
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
apt_install() {
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "$@"
}
if [ ! -x "$venv/bin/python" ]; then
    if ! python3 -m venv "$venv" 2>/dev/null; then
        # Debian's python3 keeps venv in its own package.
        apt_install python3-venv
        python3 -m venv "$venv"
    fi
fi
"$venv/bin/pip" install --quiet "gmsh>=4.11,<5"
if ! "$venv/bin/python" -c "import gmsh" 2>/dev/null; then
    apt_install libglu1-mesa libxcursor1 libxft2 libxinerama1 libxrender1 libxfixes3 \
        libxext6 libx11-6 libfontconfig1 libgomp1 libgl1
    "$venv/bin/python" -c "import gmsh"
fi
