#pragma once
// The trilinear hexahedron in VTK / Gmsh node order: nodes 0-3 the bottom face and 4-7 the
// top face, node 4 + k above node k, at reference coordinates xi in [-1, 1]^3
//   0 (-1,-1,-1)  1 (+1,-1,-1)  2 (+1,+1,-1)  3 (-1,+1,-1)
//   4 (-1,-1,+1)  5 (+1,-1,+1)  6 (+1,+1,+1)  7 (-1,+1,+1)
// with N_p(xi) = (1 + xi_p xi)(1 + eta_p eta)(1 + zeta_p zeta) / 8. Positively oriented when
// det J = det(dX/dxi) > 0 everywhere (the unit cube in this order is). Integration uses the
// 2x2x2 Gauss rule (points +-1/sqrt(3), weights 1), exact for the rest volume (hexVolume in
// mesh/quality.h is the same integral).
#include <Eigen/Core>
#include <array>

#include "tissue_trainer/core/element/element.h"
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct Hex8 {
  static constexpr int kNodes = 8;
  static constexpr int kPoints = 8;
  static constexpr int kFaces = 6;
  static constexpr int kFaceNodes = 4;
  using Nodes = Hex;
  using Gradients = NodeMatrix<kNodes>;

  struct Rest {
    double volume = 0.0;                   // sum of the weights (exact for a trilinear map)
    std::array<Gradients, kPoints> grad;   // grad_X N_p at Gauss point q
    std::array<double, kPoints> weight{};  // Gauss weight (1) * det J at point q
  };

  // Reference coordinates of node p (each component -1 or +1).
  static constexpr int corner[kNodes][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                            {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

  // Shape function values N_p(xi) and their reference gradients dN_p/dxi (column p).
  static Eigen::Matrix<double, kNodes, 1> shape(const Eigen::Vector3d& xi);
  static Gradients referenceGradients(const Eigen::Vector3d& xi);
  // Gauss point q of the 2x2x2 rule: the components of corner[q] divided by sqrt(3).
  static Eigen::Vector3d gaussPoint(int q);

  // grad_X N_p at xi for rest node positions Xe; *detJ (if given) receives det(dX/dxi).
  // A point where det J == 0 gives non-finite gradients: check *detJ.
  static Gradients gradientsAt(const NodeMatrix<kNodes>& Xe, const Eigen::Vector3d& xi,
                               double* detJ = nullptr);

  // Rest data of the hex `nodes` at rest positions X (3 x n). A weight <= 0 means the hex is
  // inverted or degenerate at that Gauss point.
  static Rest rest(const Eigen::Matrix3Xd& X, const Nodes& nodes);

  // Quad faces in local node numbers, counter-clockwise seen from outside a positively
  // oriented hex (bottom, top, y = -1, x = +1, y = +1, x = -1). A quad (a, b, c, d) is split
  // into the triangles (a, b, c) and (a, c, d) where triangles are needed.
  static constexpr int faces[kFaces][kFaceNodes] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                    {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

  // Splits into positively oriented tets (local node numbers), for inversion checks and tet
  // volumes. Six tets around the diagonal 0-6 (each face is cut along its diagonal through node 0
  // or node 6, so translated neighbours' splits conform); or five: the corners at
  // nodes 1, 3, 4, 6 and the central tet (0, 2, 5, 7).
  static constexpr int sixTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                        {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  static constexpr int fiveTets[5][4] = {{1, 2, 0, 5}, {3, 0, 2, 7}, {4, 5, 0, 7},
                                         {6, 7, 2, 5}, {0, 2, 7, 5}};
  // The global tet k of the six-tet split of hex `nodes`.
  static Tet sixTet(const Nodes& nodes, int k) {
    return {nodes[sixTets[k][0]], nodes[sixTets[k][1]], nodes[sixTets[k][2]],
            nodes[sixTets[k][3]]};
  }
};

}  // namespace tt
