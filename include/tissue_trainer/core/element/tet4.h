#pragma once
// The linear tetrahedron: nodes 0..3, positively oriented when det[X1-X0, X2-X0, X3-X0] > 0.
// Shape functions are the barycentric coordinates, so their gradients and F are constant over
// the element: one quadrature point with weight V0.
#include <Eigen/Core>
#include <array>

#include "tissue_trainer/core/element/element.h"
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct Tet4 {
  static constexpr int kNodes = 4;
  static constexpr int kPoints = 1;
  static constexpr int kFaces = 4;
  static constexpr int kFaceNodes = 3;
  using Nodes = Tet;
  using Gradients = NodeMatrix<kNodes>;

  struct Rest {
    double volume = 0.0;                   // signed V0 = det(Dm) / 6
    std::array<Gradients, kPoints> grad;   // grad_X N_p; the columns sum to zero
    std::array<double, kPoints> weight{};  // {V0}
  };

  // Rest data of the tet `nodes` at rest positions X (3 x n). A degenerate tet (V0 == 0)
  // gives non-finite gradients: callers check the volume first.
  static Rest rest(const Eigen::Matrix3Xd& X, const Nodes& nodes);

  // Faces in local node numbers, outward for a positively oriented tet.
  static constexpr int faces[kFaces][kFaceNodes] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
};

}  // namespace tt
