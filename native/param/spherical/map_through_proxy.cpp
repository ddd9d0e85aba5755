#include "param/spherical/map_through_proxy.h"

#include "common/errors.h"
#include "mesh/closest_points.h"

namespace paramorph::spherical {

MatrixX3d map_through_proxy(const MatrixX3d& V, const MatrixX3d& proxy_V, const MatrixX3i& proxy_F,
                            const MatrixX3d& proxy_map) {
  PM_REQUIRE(proxy_map.rows() == proxy_V.rows(), InvalidInputError, "map_through_proxy: ", proxy_map.rows(),
             " map points for ", proxy_V.rows(), " proxy vertices");
  const ClosestPoints on = ClosestPointTree(proxy_V, proxy_F).query(V);
  MatrixX3d out(V.rows(), 3);
  for (Index v = 0; v < V.rows(); ++v) {
    const auto f = proxy_F.row(on.face[v]);
    out.row(v) = (on.bary(v, 0) * proxy_map.row(f[0]) + on.bary(v, 1) * proxy_map.row(f[1]) +
                  on.bary(v, 2) * proxy_map.row(f[2])).normalized();
  }
  return out;
}

}  // namespace paramorph::spherical
