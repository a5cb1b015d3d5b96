#!/usr/bin/env bash
# Installs the Debian 12 packages the build needs, if any is missing (needs root or sudo).
set -euo pipefail
packages=(cmake g++ make pkg-config libsystemc-dev libeigen3-dev libpcl-dev catch2
          nlohmann-json3-dev libcli11-dev libnanoflann-dev libflann-dev liblz4-dev libzstd-dev
          libbenchmark-dev libssl-dev python3 python3-dev python3-numpy python3-matplotlib python3-pytest python3-flake8
          pybind11-dev dpkg-dev graphviz clang-format verilator yosys)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi
