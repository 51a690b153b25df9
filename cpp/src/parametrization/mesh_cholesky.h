#pragma once
// The parametrization chapter's names for the core's CHOLMOD set-up (../core/mesh_cholesky.h,
// shared with the deformation chapter).
#include "../core/mesh_cholesky.h"

namespace meshsmith::parametrization::detail {
using meshsmith::detail::CholeskyKind;
using meshsmith::detail::configure_cholesky;
using meshsmith::detail::configure_vertex_supernodes;
using meshsmith::detail::MeshCholesky;
using meshsmith::detail::SingleThreadedBlas;
using meshsmith::detail::SingleThreadedOpenMp;
}  // namespace meshsmith::parametrization::detail
