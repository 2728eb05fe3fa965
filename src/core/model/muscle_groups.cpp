#include "tissue_trainer/core/model/muscle_groups.h"

#include <algorithm>
#include <stdexcept>

namespace tt {
namespace {

std::vector<TeranMuscleLaw::Constants> withActivation(std::vector<TeranMuscleLaw::Constants> k,
                                                      double alpha) {
  for (TeranMuscleLaw::Constants& c : k) c.activation = alpha;
  return k;
}

std::vector<TeranMuscleLaw::Constants> activeTerms(std::vector<TeranMuscleLaw::Constants> k) {
  for (TeranMuscleLaw::Constants& c : k) c = TeranMuscleLaw::activationTerm(c);
  return k;
}

void checkActivation(const std::string& group, double a) {
  if (!(a >= 0.0 && a <= 1.0))
    throw std::invalid_argument("muscle '" + group + "': activation " + std::to_string(a) +
                                " is outside [0, 1]");
}

// The groups checked: names non-empty and distinct, elements in the mesh and in one group only.
std::vector<MuscleGroup> checkedGroups(const Mesh& mesh, std::vector<MuscleGroup> groups) {
  const int count = mesh.numTets() + mesh.numHexes();
  std::vector<int> owner(count, -1);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const MuscleGroup& group = groups[g];
    if (group.name.empty()) throw std::invalid_argument("a muscle without a name");
    for (std::size_t h = 0; h < g; ++h)
      if (groups[h].name == group.name)
        throw std::invalid_argument("two muscles are called '" + group.name + "'");
    if (group.elements.empty())
      throw std::invalid_argument("muscle '" + group.name + "' has no element");
    checkActivation(group.name, group.activation);
    for (int e : group.elements) {
      if (e < 0 || e >= count)
        throw std::invalid_argument("muscle '" + group.name + "': element " + std::to_string(e) +
                                    " is not in the mesh");
      if (owner[e] >= 0)
        throw std::invalid_argument("element " + std::to_string(e) + " is in muscle '" +
                                    groups[owner[e]].name + "' and in muscle '" + group.name +
                                    "' (muscles may not overlap)");
      owner[e] = static_cast<int>(g);
    }
  }
  return groups;
}

// The mesh with the elements outside `group` moved to the material id `none` (a law with every
// constant 0). The element models keep the mesh's element numbering, which the system's
// sparse pattern uses to place their stiffness blocks.
Mesh groupMesh(const Mesh& mesh, const MuscleGroup& group, int none) {
  Mesh out = mesh;
  std::vector<char> inGroup(mesh.numTets() + mesh.numHexes(), 0);
  for (int e : group.elements) inGroup[e] = 1;
  for (int t = 0; t < mesh.numTets(); ++t)
    if (!inGroup[t]) out.material[t] = none;
  for (int h = 0; h < mesh.numHexes(); ++h)
    if (!inGroup[mesh.numTets() + h]) out.hexMaterial[h] = none;
  return out;
}

}  // namespace

MuscleGroupsModel::MuscleGroupsModel(const Mesh& mesh, const std::vector<Constants>& constants,
                                     std::vector<MuscleGroup> groups, const LawOptions& options)
    : groups_(checkedGroups(mesh, std::move(groups))),
      passive_(mesh, withActivation(constants, 0.0), options),
      total_(passive_) {
  std::vector<Constants> active = activeTerms(constants);
  Constants none = active.empty() ? Constants{} : active.front();
  none.A = none.B = none.K = none.sigmaMax = none.activation = 0.0;
  none.passiveFibre = false;
  active.push_back(none);
  const int noneId = static_cast<int>(active.size()) - 1;
  for (const MuscleGroup& group : groups_)
    active_.push_back(std::make_unique<Model>(groupMesh(mesh, group, noneId), active, options));
  for (int i = 0; i < activationCount(); ++i) applyActivation(i);
}

void MuscleGroupsModel::applyActivation(int i) {
  const double a = groups_[i].activation;
  total_.editParameters(groups_[i].elements,
                        [a](TeranMuscleLaw::Parameters& p) { p.k.activation = a; });
}

double MuscleGroupsModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                   Eigen::VectorXd& f) const {
  return total_.addForce(x, x, f);  // the element model reads no velocity
}

double MuscleGroupsModel::energy(const Eigen::VectorXd& x) const { return total_.energy(x); }

void MuscleGroupsModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                     const SparsePattern& pattern, SparseMatrix& K) const {
  if (!passive_.options().psdProjection) return total_.addStiffness(x, scale, pattern, K);
  addPassiveStiffness(x, scale, pattern, K);
  for (int i = 0; i < activationCount(); ++i)
    if (groups_[i].activation != 0.0)
      addActiveStiffness(i, x, scale * groups_[i].activation, pattern, K);
}

void MuscleGroupsModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                          double scale, Eigen::VectorXd& out) const {
  if (!passive_.options().psdProjection) return total_.addStiffnessTimes(x, d, scale, out);
  passive_.addStiffnessTimes(x, d, scale, out);
  for (int i = 0; i < activationCount(); ++i)
    if (groups_[i].activation != 0.0)
      active_[i]->addStiffnessTimes(x, d, scale * groups_[i].activation, out);
}

bool MuscleGroupsModel::needsStepUpdates() const {
  for (const MuscleGroup& g : groups_)
    if (g.followsCurve) return true;
  return false;
}

void MuscleGroupsModel::beginStep(double t, const Eigen::VectorXd&, const Eigen::VectorXd&) {
  for (int i = 0; i < activationCount(); ++i) {
    MuscleGroup& g = groups_[i];
    if (!g.followsCurve) continue;
    // The scene checks that the curve stays in [0, 1]; the clamp only removes round-off.
    g.activation = std::min(1.0, std::max(0.0, g.curve.value(t)));
    applyActivation(i);
  }
}

void MuscleGroupsModel::setActivation(int i, double a) {
  MuscleGroup& g = groups_.at(i);
  checkActivation(g.name, a);
  g.activation = a;
  g.followsCurve = false;
  applyActivation(i);
}

int MuscleGroupsModel::groupIndex(const std::string& name) const {
  for (int i = 0; i < activationCount(); ++i)
    if (groups_[i].name == name) return i;
  return -1;
}

double MuscleGroupsModel::addPassiveForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  return passive_.addForce(x, x, f);  // the element model reads no velocity
}

double MuscleGroupsModel::addActiveForce(int i, const Eigen::VectorXd& x,
                                         Eigen::VectorXd& f) const {
  return active_.at(i)->addForce(x, x, f);
}

void MuscleGroupsModel::addPassiveStiffness(const Eigen::VectorXd& x, double scale,
                                            const SparsePattern& pattern, SparseMatrix& K) const {
  passive_.addStiffness(x, scale, pattern, K);
}

void MuscleGroupsModel::addActiveStiffness(int i, const Eigen::VectorXd& x, double scale,
                                           const SparsePattern& pattern, SparseMatrix& K) const {
  active_.at(i)->addStiffness(x, scale, pattern, K);
}

}  // namespace tt
