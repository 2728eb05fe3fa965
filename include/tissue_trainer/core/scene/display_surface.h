#pragma once
// The surface a scene shows (renderer, RViz): its render surface when it lists one (vertices
// embedded in the tets), else the tet mesh's boundary triangles over only the nodes they use.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/scene/scene.h"

namespace tt {

class DisplaySurface {
 public:
  DisplaySurface() = default;
  explicit DisplaySurface(const Scene& scene);

  int numVertices() const { return embedded_ ? embedding_->numPoints() : static_cast<int>(nodes_.size()); }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  bool embedded() const { return embedded_; }
  // Deformed vertices (3 x numVertices) from node positions x (3n).
  void positions(const Eigen::VectorXd& x, Eigen::Matrix3Xd& out) const;

 private:
  bool embedded_ = false;
  const Embedding* embedding_ = nullptr;  // the scene's (the scene must outlive this)
  std::vector<int> nodes_;                // boundary: vertex k is mesh node nodes_[k]
  std::vector<Triangle> triangles_;
};

}  // namespace tt
