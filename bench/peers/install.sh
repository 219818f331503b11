#!/usr/bin/env bash
# Installs the Debian 12 packages the peer programs need (only those missing).
# Idempotent: a second run installs nothing.
set -euo pipefail

packages=(g++ cmake pkg-config
          libboost-dev          # Boost.Odeint (header-only)
          libsimbody-dev        # Simbody 3.7 (CMake config + pkg-config)
          libmujoco-dev         # MuJoCo 2.2.2 (CMake config)
          libqhull-dev          # /usr/include/libqhull_r, named by mujoco::mujoco but not a dependency
          python3-numpy python3-scipy)
bash "$(dirname "$0")/../../tools"/install_missing.sh peers "${packages[@]}"
