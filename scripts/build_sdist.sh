#!/usr/bin/env bash
# Builds the source distribution dist/meshsmith-<version>.tar.gz and checks that it holds what a
# build needs; with --build, also builds a wheel from it (a cold build in a temporary directory).
#   scripts/build_sdist.sh [PYTHON] [--build]
# scikit-build-core packs every file that .gitignore and sdist.exclude (pyproject.toml) leave.
set -euo pipefail
PYTHON=${1:-python3}
BUILD=${2:-}
cd "$(dirname "$0")/.."

bash scripts/bootstrap.sh "$PYTHON" --no-install
rm -f dist/meshsmith-*.tar.gz
name=$("$PYTHON" -c 'from scikit_build_core.build import build_sdist; print(build_sdist("dist"))' | tail -n 1)
sdist=dist/$name
version=${name#meshsmith-}
version=${version%.tar.gz}

listing=$(tar tzf "$sdist")
missing=()
for required in CMakeLists.txt pyproject.toml README.md LICENSE cmake/Dependencies.cmake cmake/FindCHOLMOD.cmake \
                cmake/meshsmithConfig.cmake.in cpp/include/meshsmith/ cpp/src/ cpp/python/ python/meshsmith/__init__.py \
                tests/conftest.py; do
  grep -q "^meshsmith-$version/$required" <<<"$listing" || missing+=("$required")
done
if ((${#missing[@]})); then
  echo "build_sdist: $sdist lacks ${missing[*]}" >&2
  exit 1
fi
for unwanted in build/ .venv/ dist/ .ci/; do
  if grep -q "^meshsmith-$version/$unwanted" <<<"$listing"; then
    echo "build_sdist: $sdist holds $unwanted (add it to .gitignore or sdist.exclude)" >&2
    exit 1
  fi
done
echo "build_sdist: $sdist: $(wc -l <<<"$listing") entries, $(du -h "$sdist" | cut -f1)"

if [[ "$BUILD" == --build ]]; then
  work=$(mktemp -d /tmp/meshsmith-sdist.XXXXXX)
  trap 'rm -rf "$work"' EXIT
  start=$SECONDS
  "$PYTHON" -m pip wheel -q --disable-pip-version-check --no-build-isolation --no-deps -w "$work" "$sdist"
  wheel=("$work"/meshsmith-"$version"-*.whl)
  "$PYTHON" - "${wheel[0]}" <<'EOF'
import re, sys, zipfile
if not any(re.fullmatch(r"meshsmith/_core\..*\.so", name) for name in zipfile.ZipFile(sys.argv[1]).namelist()):
    sys.exit(f"build_sdist: {sys.argv[1]} has no meshsmith/_core extension")
EOF
  echo "build_sdist: built ${wheel[0]##*/} from $sdist in $((SECONDS - start)) s"
fi
