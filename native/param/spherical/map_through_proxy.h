// A sphere map of a fine mesh read off the sphere map of a coarse proxy of
// it (mesh/simplify): every vertex goes to its closest point on the proxy
// and takes the proxy map's value there (barycentric, renormalised). The
// morph computes its correspondence on proxies of a few thousand faces and
// carries it to the models this way (issue 16: 97k faces in a minute). The
// result may fold where the fine surface turns against the proxy's faces
// (thin tips, noise); param/spherical/untangle_sphere_map repairs that.
#pragma once

#include "mesh/types.h"

namespace paramorph::spherical {

/// V: #V by 3 fine vertices; proxy_V, proxy_F: the proxy mesh; proxy_map:
/// #proxy_V by 3 unit vectors. Returns #V by 3 unit vectors.
MatrixX3d map_through_proxy(const MatrixX3d& V, const MatrixX3d& proxy_V, const MatrixX3i& proxy_F,
                            const MatrixX3d& proxy_map);

}  // namespace paramorph::spherical
