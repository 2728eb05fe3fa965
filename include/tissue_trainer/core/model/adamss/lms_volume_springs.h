#pragma once
// The adaptive volume springs of the Adamss mass-spring system ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.4.2.3, Eqs. 2.79-2.81), on tetrahedra: Bourguignon's tet spring
// (Eq. 2.76, Eq. 2.80 with the adaptive stiffness)
//   f_i = -k_e (sum_j |xi_j| - sum_j |xi_j^0|) xi_hat_i,   xi_i = x_i - x_b,
// whose stiffness k_e, one per tet, is adapted at the start of every step by least mean
// squares on the tet's volume error Delta V = V - V^0 (Eq. 2.79).
//
// Eq. 2.81 prints k <- k + mu Delta V sum_j |xi_j|. The factor sum_j |xi_j| is always positive,
// so the update has the sign of Delta V: with mu > 0 a compressed tet (Delta V < 0) softens
// its spring and loses more volume, and with mu < 0 an expanded one does. The LMS rule for a
// stiffness that multiplies the strain s = sum_j |xi_j| - sum_j |xi_j^0| uses that strain as
// its input: k <- k + mu Delta V s, which stiffens the spring whenever the volume error and
// the strain agree in sign (compression and expansion alike). That is the default
// (`update: strain`); `update: printed` keeps Eq. 2.81. Both keep k >= 0.
//
// The forces are as in VolumeSpringModel: as printed on the nodes (`form: printed`) or less
// their mean (`form: gradient`, minus the gradient of k_e/2 s^2 at the step's k_e).
//
// The update at a step's start depends on the stiffness before it. The model keeps the
// stiffness it had before each of its last kHistory updates with the update's time, so a step
// attempted again from the same start (a rejected step, a frame redone after a rollback)
// starts from the same stiffness and gets the same update.
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/force_model.h"

namespace tt {
namespace adamss {

struct LmsVolumeSpringParameters {
  double stiffness = 0.0;  // initial k_e, N/m
  double rate = 0.0;       // mu, N/m^5 (>= 0)
  bool printedUpdate = false;
  bool gradient = false;
};

class LmsVolumeSpringModel final : public ForceModel {
 public:
  static constexpr int kHistory = 64;

  // Tets only; throws std::invalid_argument naming a tet with a node at its barycentre, or
  // when the mesh has hexahedra.
  LmsVolumeSpringModel(const Mesh& mesh, const LmsVolumeSpringParameters& parameters);

  const char* name() const override { return "adamss_lms_volume_springs"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  // The stiffness changes at every step's start with no work done, so even the gradient form's
  // energy is not conserved: the stability guard counts the springs' work as that of a load.
  bool hasEnergy() const override { return false; }

  bool needsStepUpdates() const override { return true; }
  void beginStep(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& v) override;

  // The current stiffness of tet e (N/m).
  double stiffness(int e) const { return stiffness_[e]; }

 private:
  struct Checkpoint {
    double t = 0.0;
    std::vector<double> stiffness;  // before the update at t
  };
  Checkpoint& checkpoint(int age) {  // 0: the oldest kept
    return history_[(oldest_ + age) % kHistory];
  }

  std::vector<Tet> tets_;
  std::vector<double> restLengthSum_;  // sum_j |xi_j^0|
  std::vector<double> restVolume_;     // V^0
  std::vector<double> stiffness_;      // k_e
  // A ring of kHistory checkpoints, sized at construction (beginStep allocates nothing).
  std::vector<Checkpoint> history_;
  int oldest_ = 0, kept_ = 0;
  LmsVolumeSpringParameters parameters_;
};

}  // namespace adamss
}  // namespace tt
