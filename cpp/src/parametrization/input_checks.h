#pragma once
// The chapter's input checks live in the installed header (the quadrangulation chapter runs them too).
#include <meshsmith/parametrization/mesh_checks.h>
