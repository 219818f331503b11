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
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  echo "peers: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
