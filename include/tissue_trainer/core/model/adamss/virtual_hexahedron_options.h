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

}  // namespace adamss
}  // namespace tt
