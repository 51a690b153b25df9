# Type stub of the compiled extension meshsmith._core (cpp/python/module.cpp).
#
# The exceptions are declared exactly; each chapter's submodule of bindings is typed as Any,
# because the typed contract of meshsmith is its Python API (the modules that wrap these
# bindings), not the bindings themselves. A submodule added later needs no change here
# (module-level __getattr__).
from typing import Any

class InputError(ValueError): ...
class SolverError(RuntimeError): ...
class Cancelled(Exception): ...

core: Any
io: Any
topology: Any
geometry: Any
render: Any
points: Any
tessellation: Any
decimation: Any
parametrization: Any
reconstruction: Any

def __getattr__(name: str) -> Any: ...
