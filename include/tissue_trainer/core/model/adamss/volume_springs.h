#pragma once
// Bourguignon's volume-preservation springs in the Adamss mass-spring system ("Adamss: Advanced
// Anisotropic Mass-Spring System", Sec. 2.4.2.3): springs between each node and its element's
// barycentre, xi_i = x_i - x_b,
//   hexes (Eq. 2.75): f_i = -(k_s (|xi_i| - |xi_i^0|) + k_d theta_i . xi_hat_i) xi_hat_i,
//                     theta_i = v_i - v_b;
//   tets (Eq. 2.76):  f_i = -k_s (sum_j |xi_j| - sum_j |xi_j^0|) xi_hat_i.
// The print defines xi_i = x_b - x_i, with which both push an expanded element further out;
// xi_i = x_i - x_b, used here, restores it. As printed (`form: printed`) the forces act on the
// nodes alone and do not sum to zero on an irregular element. `form: gradient` subtracts their
// mean, which makes them minus the gradient of k_s/2 sum_i (|xi_i| - |xi_i^0|)^2 (hexes) or
// k_s/2 (sum_j |xi_j| - sum_j |xi_j^0|)^2 (tets), and the damping minus the velocity gradient of
// k_d/2 sum_i (theta_i . xi_hat_i)^2: no net force or moment. No stiffness here (explicit
// integrators).
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {
namespace adamss {

struct VolumeSpringParameters {
  double stiffness = 0.0;  // k_s, N/m
  double damping = 0.0;    // k_d, N s/m (hexes)
  bool gradient = false;
};

class VolumeSpringModel final : public ForceModel {
 public:
  // Throws std::invalid_argument naming a tet or hex with a node at its barycentre.
  VolumeSpringModel(const Mesh& mesh, const VolumeSpringParameters& parameters);

  const char* name() const override { return "adamss_volume_springs"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  bool hasEnergy() const override { return parameters_.gradient; }

 private:
  std::vector<Tet> tets_;
  std::vector<Eigen::Vector4d> tetRest_;   // |xi_i^0|
  std::vector<Hex> hexes_;
  std::vector<Eigen::Matrix<double, 8, 1>> hexRest_;
  VolumeSpringParameters parameters_;
};

}  // namespace adamss
}  // namespace tt
