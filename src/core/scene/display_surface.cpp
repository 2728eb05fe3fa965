#include "tissue_trainer/core/scene/display_surface.h"

namespace tt {

DisplaySurface::DisplaySurface(const Scene& scene) {
  if (scene.renderSurface) {
    embedded_ = true;
    embedding_ = &scene.renderSurface->embedding;
    triangles_ = scene.renderSurface->triangles;
    return;
  }
  const Mesh& mesh = scene.system.mesh;
  std::vector<int> vertexOf(mesh.numNodes(), -1);
  for (const Triangle& t : mesh.surface) {
    Triangle local;
    for (int k = 0; k < 3; ++k) {
      int& v = vertexOf[t[k]];
      if (v < 0) {
        v = static_cast<int>(nodes_.size());
        nodes_.push_back(t[k]);
      }
      local[k] = v;
    }
    triangles_.push_back(local);
  }
}

void DisplaySurface::positions(const Eigen::VectorXd& x, Eigen::Matrix3Xd& out) const {
  if (embedded_) {
    embedding_->apply(x, out);
    return;
  }
  out.resize(3, static_cast<Eigen::Index>(nodes_.size()));
  for (size_t k = 0; k < nodes_.size(); ++k) out.col(k) = x.segment<3>(3 * nodes_[k]);
}

}  // namespace tt
