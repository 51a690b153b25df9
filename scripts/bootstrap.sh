#!/usr/bin/env bash
# Installs what meshsmith needs on a Debian 12 machine with Python 3.11, then the package itself.
#   scripts/bootstrap.sh [PYTHON] [EXTRAS]     e.g. scripts/bootstrap.sh python3 test,viz
#   scripts/bootstrap.sh PYTHON --no-install   the Debian packages and build requirements only
# Debian -dev packages are installed through apt-get only when absent; the package is built by
# scikit-build-core into build/<wheel tag> (kept between runs, so rebuilds are incremental).
set -euo pipefail
PYTHON=${1:-python3}
EXTRAS=${2:-viz}
cd "$(dirname "$0")/.."

DEBIAN_PACKAGES=(g++ make libeigen3-dev libopenmesh-dev libcgal-dev libgmp-dev libmpfr-dev
                 libboost-dev libsuitesparse-dev libspectra-dev libtbb-dev libnanoflann-dev
                 libopenblas0-pthread)  # optimized BLAS: CHOLMOD's supernodal factorization needs it
# Open3D (a benchmark peer) needs libusb at run time.
if [[ ",$EXTRAS," == *",bench,"* ]]; then DEBIAN_PACKAGES+=(libusb-1.0-0); fi
missing=()
for package in "${DEBIAN_PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if ((${#missing[@]})); then
  echo "bootstrap: installing Debian packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Build requirements are installed into the running interpreter so the build can reuse its
# build directory without isolation (an isolated build starts cold every time).
"$PYTHON" -m pip install -q --disable-pip-version-check "scikit-build-core>=0.10" "pybind11>=2.12" cmake ninja
if [[ "$EXTRAS" != --no-install ]]; then
  "$PYTHON" -m pip install -q --disable-pip-version-check --no-build-isolation ".[${EXTRAS}]"
fi
