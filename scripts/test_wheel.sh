#!/usr/bin/env bash
# Tests the repaired wheel in dist/ (make wheel) as a user would get it: installs it with the test
# extra from the package index into a fresh virtualenv under /tmp, checks that its extension needs
# no library outside the wheel and the base system (scripts/check_wheel_libs.py), then runs the
# whole test suite against that install, from outside the source tree.
#   scripts/test_wheel.sh [PYTHON]      PYTHON creates the venv (default python3)
# The suite sees MESHSMITH_WHEEL_TEST=<wheel>: tests/conftest.py then refuses a meshsmith imported
# from anywhere but the venv, and tests/test_cpp_sdk.py skips (the C++ SDK is not in the wheel).
set -euo pipefail
PYTHON=${1:-python3}
REPO=$(cd "$(dirname "$0")/.." && pwd)

tag=$("$PYTHON" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')
shopt -s nullglob
wheels=("$REPO"/dist/meshsmith-*-"$tag"-"$tag"-manylinux_*.whl)
if ((${#wheels[@]} != 1)); then
  echo "test_wheel: expected one repaired $tag wheel in dist/, found ${#wheels[@]}: run make wheel" >&2
  exit 1
fi
WHEEL=${wheels[0]}
echo "test_wheel: ${WHEEL##*/}: $(du -h "$WHEEL" | cut -f1) ($(stat -c %s "$WHEEL") bytes)"

WORK=$(mktemp -d /tmp/meshsmith-wheel-test.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
VENV=$WORK/venv
start=$SECONDS
"$PYTHON" -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --disable-pip-version-check "$WHEEL[test]"
echo "test_wheel: fresh venv with the wheel and the test extra in $((SECONDS - start)) s"

# From $WORK, nothing of the source tree is importable: meshsmith must come from the venv.
cd "$WORK"
"$VENV/bin/python" "$REPO/scripts/check_wheel_libs.py"
"$VENV/bin/meshsmith" --help >/dev/null   # the console script the wheel declares
start=$SECONDS
MESHSMITH_WHEEL_TEST=$WHEEL "$VENV/bin/python" -m pytest -q -p no:cacheprovider \
  -c "$REPO/pyproject.toml" --rootdir "$REPO" "$REPO/tests"
echo "test_wheel: the suite ran against the installed wheel in $((SECONDS - start)) s"
