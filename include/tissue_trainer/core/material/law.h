#pragma once
// What a material law is, and the evaluation of one law at one point with the two options
// every law can use: inversion handling and PSD projection of its tangent.
//
// A law L is a small value type (no virtual function), used as a template argument by the
// element models (model/hyperelastic.h) so that the per-element loop calls it inline:
//   L::kName                        the registry name
//   L::kIsotropic                   psi(Q F R) = psi(F) for rotations Q, R (the projection then
//                                   uses the block form; see psd_projection.h)
//   L::kZeroRestStress              P(I) = 0 for every parameter set
//   L::Constants                    per material, read once (its registration file reads them)
//   L::Parameters                   per element: the constants plus what the element adds (its
//                                   fibre frame for an anisotropic law)
//   L::parameters(Constants, frame) the element's parameters; frame columns are the fibre,
//                                   sheet and sheet-normal axes
//   L::energy(p, F)                 energy density psi(F), J/m^3
//   L::stress(p, F)                 first Piola-Kirchhoff stress P = d psi / dF, Pa
//   L::stressDifferential(p, F, dF) dP = (d P / dF) : dF
// The tangent as a 9 x 9 matrix acts on vec(F), the columns of F stacked (Eigen's storage
// order): vec(dP) = A vec(dF), entry (i + 3 j, k + 3 l) = d P_ij / d F_kl.
#include <Eigen/Core>
#include <type_traits>
#include <utility>

namespace tt {

using Matrix9d = Eigen::Matrix<double, 9, 9>;

enum class PsdMethod { kEigen, kDiagonalBlocks };

struct LawOptions {
  // Inversion handling (Irving, Teran and Fedkiw, "Invertible finite elements for robust
  // simulation of large deformation", 2004, Sec. 4): the law is evaluated at
  // F^ = U diag(max(sigma_i, threshold)) V^T from the rotation-only SVD of F, so inverted and
  // flattened elements get a finite stress that pushes them back. 0 turns it off.
  double inversionThreshold = 0.0;
  // The tangent made positive semi-definite where a solver asks for it: the stiffness matrix
  // and the stiffness-vector product.
  bool psdProjection = false;
  // How (psd_projection.h): kEigen sets the negative eigenvalues of the 9 x 9 tangent to zero;
  // kDiagonalBlocks is Teran et al.'s projection as the muscle paper's Sec. 5.6 applies it
  // (the isotropic part clamped block by block in the singular-value frame, the fibre term
  // with its tension derivative clamped at zero), for laws with a diagonalBlocksTangent
  // (teran_muscle) and isotropic laws (whose projection already is the block form).
  PsdMethod psdMethod = PsdMethod::kEigen;
};

// Whether law L has the block-wise projected tangent of PsdMethod::kDiagonalBlocks.
template <class Law, class = void>
struct HasDiagonalBlocksTangent : std::false_type {};
template <class Law>
struct HasDiagonalBlocksTangent<
    Law, std::void_t<decltype(Law::diagonalBlocksTangent(
             std::declval<const typename Law::Parameters&>(),
             std::declval<const Eigen::Matrix3d&>(), std::declval<const Eigen::Matrix3d&>(),
             std::declval<const Eigen::Matrix3d&>(), std::declval<const Eigen::Vector3d&>()))>>
    : std::true_type {};
template <class Law>
constexpr bool supportsPsdMethod(PsdMethod method) {
  return method == PsdMethod::kEigen || Law::kIsotropic || HasDiagonalBlocksTangent<Law>::value;
}

// Whether law L has its own static tangent(p, F) (the same matrix, computed more cheaply).
template <class Law, class = void>
struct HasOwnTangent : std::false_type {};
template <class Law>
struct HasOwnTangent<Law, std::void_t<decltype(Law::tangent(
                              std::declval<const typename Law::Parameters&>(),
                              std::declval<const Eigen::Matrix3d&>()))>> : std::true_type {};

// The 9 x 9 tangent of law L at F from nine differentials (one per unit dF), or the law's own.
template <class Law>
Matrix9d lawTangent(const typename Law::Parameters& p, const Eigen::Matrix3d& F) {
  if constexpr (HasOwnTangent<Law>::value) return Law::tangent(p, F);
  Matrix9d A;
  for (int c = 0; c < 9; ++c) {
    Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
    dF(c % 3, c / 3) = 1.0;
    const Eigen::Matrix3d dP = Law::stressDifferential(p, F, dF);
    A.col(c) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
  }
  return A;
}

}  // namespace tt
