"""Type hints (issue 13 part 5): every public function and method is annotated, the package ships
py.typed and its _core stub, and `mypy python/meshsmith` reports no error."""
import importlib
import inspect
import pkgutil
import typing
from pathlib import Path

import pytest

import meshsmith

SOURCE = Path(__file__).resolve().parents[1] / "python" / "meshsmith"
INSTALLED = Path(meshsmith.__file__).resolve().parent


def public_modules():
    for info in pkgutil.walk_packages(meshsmith.__path__, "meshsmith."):
        if info.name in ("meshsmith.__main__", "meshsmith._core"):  # __main__ runs the CLI on import
            continue
        yield importlib.import_module(info.name)


def public_names(module):
    """The module's __all__, or (cli and demo modules, which have none) the public names it defines."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    return [name for name, value in vars(module).items()
            if not name.startswith("_") and getattr(value, "__module__", None) == module.__name__]


def callables(module):
    """(qualified name, function) for every public function of the module and every public method
    (and __init__) a public class of it defines itself (inherited tuple/NamedTuple methods are not ours)."""
    for name in public_names(module):
        value = getattr(module, name)
        if inspect.isfunction(value):
            yield f"{module.__name__}.{name}", value
        elif inspect.isclass(value) and value.__module__ == module.__name__:
            for attribute, member in vars(value).items():
                if isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                elif isinstance(member, property):
                    member = member.fget
                if inspect.isfunction(member) and (not attribute.startswith("_") or attribute == "__init__") \
                        and member.__qualname__.startswith(value.__qualname__ + "."):
                    yield f"{module.__name__}.{name}.{attribute}", member


def missing_annotations(function):
    signature = inspect.signature(function)
    missing = [p.name for p in signature.parameters.values()
               if p.annotation is inspect.Parameter.empty and p.name not in ("self", "cls")]
    if signature.return_annotation is inspect.Signature.empty:
        missing.append("return")
    return missing


def test_every_public_function_and_method_is_annotated():
    found = {qualified: missing_annotations(function)
             for module in public_modules() for qualified, function in callables(module)}
    assert len(found) > 150  # the enumeration sees the whole API, not an empty list
    unannotated = {name: missing for name, missing in found.items() if missing}
    assert not unannotated, f"public callables without annotations: {unannotated}"


def test_the_enumeration_notices_a_missing_annotation():
    def annotated(V: int, *, k: int = 1) -> int:
        return V

    def partly(V, k: int = 1) -> int:
        return V

    def no_return(V: int):
        return V

    assert missing_annotations(annotated) == []
    assert missing_annotations(partly) == ["V"]
    assert missing_annotations(no_return) == ["return"]


def test_arrays_and_callbacks_use_the_shared_aliases():
    from meshsmith import geometry, points
    from meshsmith._typing import ProgressCallback
    hints = inspect.signature(geometry.laplacian_eigenpairs).parameters
    assert hints["V"].annotation == "ArrayLike" and hints["progress"].annotation == "ProgressCallback"
    assert inspect.signature(geometry.face_normals).return_annotation == "FloatArray"
    assert inspect.signature(points.knn).return_annotation == "Neighbours"
    # the callback alias is the documented protocol: (fraction, stage) -> bool | None, or no callback
    callback, none = typing.get_args(ProgressCallback)
    assert none is type(None)
    arguments, result = typing.get_args(callback)
    assert arguments == [float, str] and set(typing.get_args(result)) == {bool, type(None)}


@pytest.mark.parametrize("name", ["py.typed", "_core.pyi"])
def test_the_package_ships_its_type_information(name):
    assert (SOURCE / name).is_file()
    assert (INSTALLED / name).is_file(), f"{name} is missing from the installed package {INSTALLED}"


def test_mypy_reports_no_error():
    api = pytest.importorskip("mypy.api", reason="mypy is in the test extra")
    # The configuration ([tool.mypy] in pyproject.toml: check_untyped_defs, disallow_incomplete_defs)
    # is read from the repository root.
    stdout, stderr, status = api.run(["--config-file", str(SOURCE.parents[1] / "pyproject.toml"), str(SOURCE)])
    assert status == 0, stdout + stderr
    assert "Success: no issues found" in stdout
