#include "tissue_trainer/core/model/adamss/axis_spring_elements.h"

#include <numeric>

namespace tt {
namespace adamss {

AxisSpringElements::AxisSpringElements(const Mesh& mesh) {
  const AxisMesh axes = buildAxes(mesh);
  tets_ = mesh.tets;
  hexes_ = mesh.hexes;
  for (std::size_t e = 0; e < tets_.size(); ++e)
    tetRest_.push_back(axisSpringRest<Tet4>(gatherNodes<4>(mesh.rest, tets_[e]), axes.tetRest[e],
                                            Tet4::rest(mesh.rest, tets_[e]).weight[0]));
  for (std::size_t e = 0; e < hexes_.size(); ++e) {
    const Hex8::Rest rest = Hex8::rest(mesh.rest, hexes_[e]);
    hexRest_.push_back(axisSpringRest<Hex8>(gatherNodes<8>(mesh.rest, hexes_[e]), axes.hexRest[e],
                                            std::accumulate(rest.weight.begin(),
                                                            rest.weight.end(), 0.0)));
  }
}

}  // namespace adamss
}  // namespace tt
