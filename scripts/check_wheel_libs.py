"""Checks that an installed meshsmith wheel needs no shared library outside itself and the base system.

    python scripts/check_wheel_libs.py        (run with the interpreter of the venv that holds the wheel)

Two checks, each failing with exit status 1 and the offending libraries listed:
  1. `ldd` of meshsmith/_core*.so: every library it resolves (the whole tree) lies in the wheel's
     meshsmith.libs/ or is one of the base system's libraries of the manylinux policy (glibc's and
     GCC's runtime: BASE_SYSTEM below); nothing is "not found".
  2. At run time, after a CHOLMOD solve and a TBB-parallel decimation: every shared object mapped
     while they ran lies in the venv or is a BASE_SYSTEM library (catches what a library dlopens,
     which ldd cannot see, e.g. TBB looking for libtbbmalloc).
Prints the ldd summary: how many libraries come from the wheel and which from the base system.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

# glibc's and GCC's runtime libraries of auditwheel's manylinux policy (lib_whitelist), plus the
# dynamic loader and the vDSO. The policy's X11/GL/glib/expat/zlib entries are left out on purpose:
# meshsmith needs none of them, so one appearing is a change worth failing on.
BASE_SYSTEM = {"libc.so.6", "libm.so.6", "libmvec.so.1", "libdl.so.2", "librt.so.1", "libpthread.so.0",
               "libutil.so.1", "libnsl.so.1", "libanl.so.1", "libresolv.so.2", "libgcc_s.so.1",
               "libstdc++.so.6", "libatomic.so.1", "ld-linux-x86-64.so.2", "linux-vdso.so.1"}


def is_base_system(filename: str) -> bool:
    """Whether a library file (libstdc++.so.6 or the file it names, libstdc++.so.6.0.30) is BASE_SYSTEM's."""
    return any(filename == soname or filename.startswith(soname + ".") for soname in BASE_SYSTEM)


def mapped_libraries() -> set[Path]:
    """The shared objects mapped into this process."""
    paths = set()
    with open("/proc/self/maps") as maps:
        for line in maps:
            fields = line.split(maxsplit=5)
            if len(fields) == 6 and ".so" in fields[5]:
                paths.add(Path(fields[5].strip()))
    return paths


def main() -> int:
    import numpy as np  # noqa: F401  (mapped before the snapshot: not meshsmith's)
    import meshsmith
    from meshsmith import datasets, decimation, geometry

    package = Path(meshsmith.__file__).resolve().parent
    wheel_libs = package.parent / "meshsmith.libs"
    venv = Path(sys.prefix).resolve()
    failures = []
    if venv not in package.parents:
        failures.append(f"meshsmith imported from {package}, not from the venv {venv}")
    if not wheel_libs.is_dir():
        failures.append(f"{wheel_libs} is missing: not a repaired wheel")

    (extension,) = package.glob("_core*.so")
    ldd = subprocess.run(["ldd", str(extension)], capture_output=True, text=True, check=True).stdout
    from_wheel, from_system = [], []
    for line in ldd.splitlines():
        match = re.match(r"\s*(\S+)(?: => (.*?))?(?: \(0x[0-9a-f]+\))?$", line)
        if match is None:
            failures.append(f"unreadable ldd line: {line!r}")
            continue
        name, target = match.group(1), match.group(2) or match.group(1)
        if target == "not found":
            failures.append(f"{name}: not found")
        elif is_base_system(Path(name).name):
            from_system.append(f"{Path(name).name} ({target})" if "/" in target else Path(name).name)
        elif wheel_libs in Path(target).resolve().parents:
            from_wheel.append(name)
        else:
            failures.append(f"{name} => {target}: neither in {wheel_libs} nor a base-system library")
    print(f"check_wheel_libs: ldd {extension.name}: {len(from_wheel)} libraries from {wheel_libs.name}/ "
          f"({', '.join(sorted(from_wheel))}); {len(from_system)} from the base system ({', '.join(from_system)})")

    V, F = datasets.icosphere(6)
    before = mapped_libraries()
    values, _ = geometry.laplacian_eigenpairs(*datasets.icosphere(4), 4)  # CHOLMOD (SuiteSparse, OpenBLAS) through Spectra
    decimation.decimate(V, F, target_faces=2000)  # TBB's parallel rounds
    assert abs(values[1] - 2.0) < 1e-2, values  # the unit sphere's first nonzero eigenvalue, l(l+1) at l=1
    for path in sorted(mapped_libraries() - before):
        if venv not in path.resolve().parents and not is_base_system(path.name):
            failures.append(f"mapped at run time from outside the venv: {path}")

    for failure in failures:
        print(f"check_wheel_libs: FAIL {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
