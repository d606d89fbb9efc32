#!/bin/sh
# Installs what the `mpi` cargo feature of musclefem needs on Debian/Ubuntu: OpenMPI
# (library, headers, mpirun) and libclang (the MPI bindings are generated with bindgen).
# Then: cargo build --release -p musclefem --features mpi
set -eu
packages="libopenmpi-dev openmpi-bin libclang-dev"
if dpkg -s $packages >/dev/null 2>&1; then
    echo "already installed: $packages"
    exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
$sudo apt-get update
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends $packages
