#!/usr/bin/env bash
# Installs every Debian 12 package the project needs (idempotent; skips what is present).
# Run as root (or with sudo available). Used by scripts/main.sh, scripts/test.sh and CI.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git
  clang-15 llvm-15
  libeigen3-dev libboost-dev libcgal-dev libnanoflann-dev libembree-dev libfcl-dev
  libgtest-dev libbenchmark-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libtomlplusplus-dev librapidcheck-dev
  python3 python3-matplotlib python3-numpy
  latexmk texlive-latex-base texlive-latex-recommended texlive-fonts-recommended
  slurmctld slurmd slurm-client munge
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
