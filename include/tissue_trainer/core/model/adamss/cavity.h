#pragma once
// A cavity of the Adamss mass-spring system ("Adamss: Advanced Anisotropic Mass-Spring
// System", Secs. 2.3 and 2.4.4.3): a closed surface of triangle and quad facets over mesh
// nodes, with a pressure on its faces and an optional penalty on its volume.
//
// The enclosed volume is computed by the divergence theorem, V = sum over triangles of
// (a - o) . ((b - o) x (c - o)) / 6 (o: the rest centroid of the cavity's nodes, which cancels
// on a closed surface but keeps the rounding small), instead of the Delaunay tetrahedralisation
// of Sec. 2.3: it is exact for the facets, differentiable and needs no new mesh per step. A
// quad counts as the mean of its two triangulations (abc + acd and abd + bcd), as Sec. 2.9.1
// (Fig. 2.32) averages them for areas and normals.
//
// Energy: E = -p V + k/2 (V - V_target)^2. Its force -dE/dx = (p - k (V - V_target)) dV/dx.
// For the pressure alone this is Eq. 2.119, f_i = -(1/n) P A_j n_j per face (n_j pointing into
// the cavity), exactly on a triangle; on a closed surface dV/dx_i summed over the faces at node
// i equals sum A_j n_j / 3 with outward n_j. For a planar parallelogram quad the averaged
// triangulations give the printed A n / 4. Stiffness df/dx = (p - k dV) d2V/dx2 - k dV/dx
// dV/dx^T: the last term couples every pair of the cavity's nodes (couplings()).
//
// The facets may be given in either orientation, but consistently; the model turns them so
// the rest volume is positive (normals out of the cavity), so p > 0 inflates it.
#include <array>
#include <vector>

#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/time_curve.h"

namespace tt {
namespace adamss {

struct CavityParameters {
  double pressure = 0.0;          // p, Pa (> 0 pushes the walls out of the cavity)
  double volumeStiffness = 0.0;   // k, J/m^6 (0: no volume penalty)
  double targetVolumeRatio = 1.0; // V_target / V_rest
  // When set, p follows this curve (Pa): beginStep sets p = curve(t) for the step from t, and
  // the energy, force and stiffness are those of that p.
  bool pressureFollowsCurve = false;
  TimeCurve pressureCurve;
};

// A facet: 3 node indices (triangle) or 4 (quad, nodes in order around it).
using CavityFacet = std::vector<int>;

// Throws std::invalid_argument with one line naming the problem (a facet of the wrong size, a
// node out of range or repeated in a facet, an edge not in exactly two facets, two facets
// running along an edge the same way, no enclosed volume) when the facets do not enclose a
// cavity.
void checkClosedSurface(const std::vector<CavityFacet>& facets, int numNodes);

// The signed volume the facets enclose at positions x (3 x n) by the divergence theorem,
// positive when the facets' normals (right-hand rule) point out of it; a quad counts as the
// mean of its two triangulations. The facets are not checked.
double enclosedVolume(const std::vector<CavityFacet>& facets, const Eigen::Ref<const Eigen::Matrix3Xd>& x);

class CavityModel final : public ForceModel {
 public:
  // rest: the 3 x n rest positions. Throws std::invalid_argument (checkClosedSurface).
  CavityModel(const Eigen::Matrix3Xd& rest, const std::vector<CavityFacet>& facets,
              const CavityParameters& parameters);

  const char* name() const override { return "adamss_cavity"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                  Eigen::VectorXd& f) const override;
  double energy(const Eigen::VectorXd& x) const override;
  // With a pressure curve, -p V jumps at every step's start with no work done, so the stability
  // guard counts this model's work as that of a load instead of as stored energy.
  bool hasEnergy() const override { return !parameters_.pressureFollowsCurve; }
  int observableCount() const override { return 1; }
  const char* observableName(int) const override { return "cavity_volume"; }
  double observable(int, const Eigen::VectorXd& x) const override { return volume(x); }
  bool toleratesInversion() const override { return true; }
  bool needsStepUpdates() const override { return parameters_.pressureFollowsCurve; }
  void beginStep(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& v) override;

  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override;
  bool hasStiffnessProduct() const override { return true; }
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out) const override;
  std::vector<std::array<int, 2>> couplings() const override;

  // The enclosed volume at x (m^3), positive for the rest shape.
  double volume(const Eigen::VectorXd& x) const;
  double restVolume() const { return restVolume_; }
  double targetVolume() const { return targetVolume_; }
  const CavityParameters& parameters() const { return parameters_; }
  // The pressure of the current step (Pa).
  double pressure() const { return pressure_; }
  // The cavity's nodes, sorted.
  const std::vector<int>& nodes() const { return nodes_; }

 private:
  struct Triangle {
    std::array<int, 3> node;  // mesh node indices, oriented out of the cavity
    std::array<int, 3> local; // the same as indices into nodes_
    double weight;            // 1 for a triangle facet, 1/2 for each of a quad's four
  };
  // dV/dx at the cavity's nodes (a column per node, in nodes_ order).
  Eigen::Matrix3Xd volumeGradient(const Eigen::VectorXd& x) const;
  // The multiplier of dV/dx in the force, p - k (V - V_target).
  double forceFactor(double volume) const;

  std::vector<Triangle> triangles_;
  std::vector<int> nodes_;
  Eigen::Vector3d origin_;
  double restVolume_ = 0.0;
  double targetVolume_ = 0.0;
  double pressure_ = 0.0;
  CavityParameters parameters_;
};

}  // namespace adamss
}  // namespace tt
