#!/bin/sh
# Installs gfortran from the distribution's packages (Debian/Ubuntu), which `musclefem
# vumat build` needs to compile a user's Abaqus VUMAT (docs/vumat.md) and which the VUMAT
# tests need (crates/vumat/tests, crates/cli/tests/vumat.rs). Uses sudo when not root.
set -eu
if command -v gfortran >/dev/null 2>&1; then
    echo "already installed: $(gfortran --version | head -n 1)"
    exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
$sudo apt-get update
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends gfortran
gfortran --version | head -n 1
