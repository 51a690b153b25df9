#pragma once
// The chapter's CHOLMOD set-up lives in the installed header (the quadrangulation chapter uses it too).
#include <meshsmith/parametrization/mesh_cholesky.h>
