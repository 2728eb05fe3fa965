#pragma once
// The options of the virtual-hexahedron model (model/adamss/virtual_hexahedron.h) that the
// registry passes to a law's factory.

namespace tt {
namespace adamss {

// How the virtual hexahedron gets an element's deformation gradient ("Adamss: Advanced
// Anisotropic Mass-Spring System", Sec. 2.4.2.2).
enum class DeformationGradientSource {
  kShapeFunctions,     // the element's shape functions: exact on tets, at the centre on hexes
  kAxisApproximation,  // from the axes' stretches and angles (Eqs. 2.59-2.62): approximate
};

// How the forces at the intersection points reach the element's nodes ("Adamss: Advanced
// Anisotropic Mass-Spring System", Sec. 2.4.2.3, the paragraph after Eq. 2.100).
enum class PointForceDistribution {
  kAxes,      // Eq. 2.29 with C: each point's force to its face's nodes by the point's weights
  kVertices,  // Eq. 2.29 with an equal-share C: each point's force in equal parts to its face's
              // nodes, whatever the point's place on the face
};

}  // namespace adamss
}  // namespace tt
