#include "tissue_trainer/core/contact/tissue_contact.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace tt {
namespace {

btVector3 toBullet(const Eigen::Vector3d& p) {
  return btVector3(static_cast<btScalar>(p.x() * kBulletScale),
                   static_cast<btScalar>(p.y() * kBulletScale),
                   static_cast<btScalar>(p.z() * kBulletScale));
}

Eigen::Vector3d fromBullet(const btVector3& p) {
  return Eigen::Vector3d(p.x(), p.y(), p.z()) / kBulletScale;
}

btTransform toBullet(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d R = pose.rotation();
  const btMatrix3x3 basis(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0),
                          R(2, 1), R(2, 2));
  return btTransform(basis, toBullet(pose.translation()));
}

bool finitePose(const Eigen::Isometry3d& pose) { return pose.matrix().allFinite(); }

// Bullet's normal within about 1 degree of the triangle's: a face contact.
constexpr double kFaceCosine = 0.99985;

// The contact per unit area: the automatic sample spacing is at most 1 mm, and a triangle is
// cut into at most 64 x 64 sub-triangles (a 6 cm triangle at 1 mm).
constexpr double kMaxAutomaticSpacing = 1e-3;
constexpr int kMaxSubdivisions = 64;

// The world-axis box around a tool shape at its world pose.
Eigen::AlignedBox3d worldBox(const ToolShape& s, const Eigen::Isometry3d& pose) {
  Eigen::Vector3d half;
  switch (s.type) {
    case ToolShape::Type::kSphere: half.setConstant(s.radius); break;
    case ToolShape::Type::kCapsule: half = Eigen::Vector3d(s.radius, s.radius, 0.5 * s.length + s.radius); break;
    case ToolShape::Type::kCylinder: half = Eigen::Vector3d(s.radius, s.radius, 0.5 * s.length); break;
    case ToolShape::Type::kBox: half = 0.5 * s.size; break;
  }
  const Eigen::Vector3d reach = pose.linear().cwiseAbs() * half;
  return Eigen::AlignedBox3d(pose.translation() - reach, pose.translation() + reach);
}

// Margins in Bullet units (kBulletScale per metre): 0.05 mm on the tool, none on the tissue.
constexpr btScalar kToolMargin = 0.005f;

std::unique_ptr<btCollisionShape> makeShape(const ToolShape& s) {
  const double k = kBulletScale;
  std::unique_ptr<btCollisionShape> shape;
  switch (s.type) {
    case ToolShape::Type::kSphere:
      shape = std::make_unique<btSphereShape>(s.radius * k);
      break;
    case ToolShape::Type::kCapsule:
      shape = std::make_unique<btCapsuleShapeZ>(s.radius * k, s.length * k);
      break;
    case ToolShape::Type::kCylinder:
      shape = std::make_unique<btCylinderShapeZ>(
          btVector3(s.radius * k, s.radius * k, 0.5 * s.length * k));
      shape->setMargin(kToolMargin);
      break;
    case ToolShape::Type::kBox:
      shape = std::make_unique<btBoxShape>(toBullet(0.5 * s.size));
      shape->setMargin(kToolMargin);
      break;
  }
  return shape;
}

void checkShape(const ToolShape& s) {
  const bool ok = s.offset.matrix().allFinite() &&
                  (s.type == ToolShape::Type::kBox
                       ? (s.size.array() > 0.0).all() && s.size.allFinite()
                       : s.radius > 0.0 && std::isfinite(s.radius) &&
                             (s.type == ToolShape::Type::kSphere ||
                              (s.length > 0.0 && std::isfinite(s.length))));
  if (!ok)
    throw std::invalid_argument("tool shape of link '" + s.link +
                                "': expected positive finite dimensions and a finite offset");
}

// Barycentric weights of the point of triangle (a, b, c) closest to p's projection.
Eigen::Vector3d triangleWeights(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d e0 = b - a, e1 = c - a, d = p - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double d20 = d.dot(e0), d21 = d.dot(e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0.0)) return Eigen::Vector3d::Constant(1.0 / 3.0);
  const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
  Eigen::Vector3d weights(1.0 - v - w, v, w);
  weights = weights.cwiseMax(0.0);
  const double sum = weights.sum();
  return sum > 0.0 ? Eigen::Vector3d(weights / sum) : Eigen::Vector3d::Constant(1.0 / 3.0);
}

struct Collector : btCollisionWorld::ContactResultCallback {
  const btCollisionObject* tissue = nullptr;
  int shape = 0;
  std::vector<ContactPoint>* out = nullptr;

  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* w0, int,
                           int index0, const btCollisionObjectWrapper* w1, int,
                           int index1) override {
    const double depth = -cp.getDistance() / kBulletScale;
    if (!(depth > 0.0)) return 0;
    const bool tissueIsB = w1->getCollisionObject() == tissue;
    if (!tissueIsB && w0->getCollisionObject() != tissue) return 0;
    ContactPoint p;
    p.shape = shape;
    p.triangle = tissueIsB ? index1 : index0;
    p.tissuePoint = fromBullet(tissueIsB ? cp.getPositionWorldOnB() : cp.getPositionWorldOnA());
    p.toolPoint = fromBullet(tissueIsB ? cp.getPositionWorldOnA() : cp.getPositionWorldOnB());
    const btVector3 n = tissueIsB ? cp.m_normalWorldOnB : -cp.m_normalWorldOnB;
    p.normal = Eigen::Vector3d(n.x(), n.y(), n.z());
    p.depth = depth;
    out->push_back(p);
    return 0;
  }
};

}  // namespace

struct TissueContact::Bullet {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};
  std::vector<btScalar> vertices;
  std::vector<int> indices;
  std::unique_ptr<btTriangleIndexVertexArray> meshInterface;
  std::unique_ptr<btBvhTriangleMeshShape> meshShape;
  btCollisionObject tissue;
  std::vector<std::unique_ptr<btCollisionShape>> toolShapes;
  std::vector<std::unique_ptr<btCollisionObject>> toolObjects;

  // Writes the deformed positions (scaled, finite) and refits the tree.
  void setPositions(const Eigen::VectorXd& x) {
    btVector3 lo(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT), hi = -lo;
    for (Eigen::Index i = 0; i < x.size(); i += 3) {
      const btVector3 p = toBullet(Eigen::Vector3d(x.segment<3>(i)));
      vertices[i] = p.x(), vertices[i + 1] = p.y(), vertices[i + 2] = p.z();
      lo.setMin(p);
      hi.setMax(p);
    }
    refit(lo, hi);
  }

  // True when a tool shape's box (with its margin) meets the box of the nodes: only then can
  // Bullet find a contact, and only then are the tree refit and the pair tests worth running.
  bool anyShapeNear(const Eigen::VectorXd& x, const std::vector<Eigen::Isometry3d>& poses) const {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
    for (Eigen::Index i = 0; i < x.size(); i += 3) {
      lo = lo.cwiseMin(x.segment<3>(i));
      hi = hi.cwiseMax(x.segment<3>(i));
    }
    const btVector3 pad(kNearPad, kNearPad, kNearPad);
    const btVector3 tissueLo = toBullet(lo) - pad, tissueHi = toBullet(hi) + pad;
    for (size_t k = 0; k < toolShapes.size(); ++k) {
      btVector3 toolLo, toolHi;
      toolShapes[k]->getAabb(toBullet(poses[k]), toolLo, toolHi);
      if (TestAabbAgainstAabb2(toolLo, toolHi, tissueLo, tissueHi)) return true;
    }
    return false;
  }

  // Bullet's contact points of each tool shape (at `poses`) with the tissue surface.
  void findContacts(const std::vector<Eigen::Isometry3d>& poses, std::vector<ContactPoint>& found) {
    for (size_t k = 0; k < toolObjects.size(); ++k) {
      toolObjects[k]->setWorldTransform(toBullet(poses[k]));
      Collector collector;
      collector.tissue = &tissue;
      collector.shape = static_cast<int>(k);
      collector.out = &found;
      world.contactPairTest(toolObjects[k].get(), &tissue, collector);
    }
  }

 private:
  static constexpr btScalar kNearPad = 0.1f;  // 1 mm, in Bullet units

  void refit(const btVector3& lo, const btVector3& hi) {
    const btVector3 pad(1.0, 1.0, 1.0);  // 1 cm around the quantisation box
    if (meshShape) {
      meshShape->refitTree(lo - pad, hi + pad);
    } else {
      meshShape = std::make_unique<btBvhTriangleMeshShape>(meshInterface.get(), true, lo - pad,
                                                           hi + pad, true);
      meshShape->setMargin(0.0);
      tissue.setCollisionShape(meshShape.get());
    }
  }
};

TissueContact::TissueContact(System& system, const ContactSettings& settings,
                             std::vector<ToolShape> shapes)
    : system_(system), settings_(settings), shapes_(std::move(shapes)),
      bullet_(std::make_unique<Bullet>()) {
  if (system_.mesh.surface.empty()) throw std::invalid_argument("contact: the mesh has no surface");
  auto model = std::make_unique<ContactForceModel>();
  model_ = model.get();
  system_.models.push_back(std::move(model));

  Bullet& b = *bullet_;
  b.vertices.assign(3 * system_.numNodes(), 0.0);
  for (const Triangle& t : system_.mesh.surface) b.indices.insert(b.indices.end(), t.begin(), t.end());
  b.meshInterface = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(system_.mesh.surface.size()), b.indices.data(), 3 * sizeof(int),
      system_.numNodes(), b.vertices.data(), 3 * sizeof(btScalar));
  b.setPositions(system_.state.x.allFinite()
                     ? system_.state.x
                     : Eigen::Map<const Eigen::VectorXd>(system_.mesh.rest.data(), system_.numDofs()));
  for (const ToolShape& s : shapes_) {
    checkShape(s);
    b.toolShapes.push_back(makeShape(s));
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(b.toolShapes.back().get());
    b.toolObjects.push_back(std::move(object));
  }
  shapePoses_.assign(shapes_.size(), Eigen::Isometry3d::Identity());
  if (settings_.stiffnessPerArea > 0.0) prepareSurfaceSampling();
}

// With a contact per unit area: each surface triangle's rest area, and the spacing of the
// samples taken on the triangles near a tool (ContactSettings::sampleSpacing, or a quarter of
// the thinnest tool shape and at most 1 mm).
void TissueContact::prepareSurfaceSampling() {
  const Mesh& mesh = system_.mesh;
  triangleArea_.reserve(mesh.surface.size());
  for (const Triangle& tri : mesh.surface) {
    const Eigen::Vector3d a = mesh.rest.col(tri[0]), b = mesh.rest.col(tri[1]), c = mesh.rest.col(tri[2]);
    triangleArea_.push_back(0.5 * (b - a).cross(c - a).norm());
  }
  sampleSpacing_ = settings_.sampleSpacing;
  if (sampleSpacing_ > 0.0) return;
  sampleSpacing_ = kMaxAutomaticSpacing;
  for (const ToolShape& s : shapes_) {
    const double thinnest = s.type == ToolShape::Type::kBox ? s.size.minCoeff() : 2.0 * s.radius;
    sampleSpacing_ = std::min(sampleSpacing_, 0.25 * thinnest);
  }
}

TissueContact::~TissueContact() {
  auto& models = system_.models;
  models.erase(std::remove_if(models.begin(), models.end(),
                              [this](const auto& m) { return m.get() == model_; }),
               models.end());
}

void TissueContact::setTool(const Eigen::Isometry3d& tip,
                            const std::vector<Eigen::Isometry3d>& linkPoses, double jawAngle,
                            double time) {
  if (!finitePose(tip)) throw std::invalid_argument("tool: the tip pose is not finite");
  if (linkPoses.size() != shapes_.size())
    throw std::invalid_argument("tool: expected " + std::to_string(shapes_.size()) +
                                " link poses, got " + std::to_string(linkPoses.size()));
  for (size_t k = 0; k < linkPoses.size(); ++k)
    if (!finitePose(linkPoses[k]))
      throw std::invalid_argument("tool: the pose of link '" + shapes_[k].link + "' is not finite");
  if (!std::isfinite(jawAngle)) throw std::invalid_argument("tool: the jaw angle is not finite");
  if (!std::isfinite(time)) throw std::invalid_argument("tool: the time is not finite");
  tip_ = tip;
  for (size_t k = 0; k < linkPoses.size(); ++k) shapePoses_[k] = linkPoses[k] * shapes_[k].offset;
  jawAngle_ = jawAngle;
  toolTime_ = time;
  haveTool_ = true;
}

void TissueContact::clearTool() {
  haveTool_ = false;
  haveLast_ = false;
}

void TissueContact::clear() {
  model_->penalties.clear();
  model_->springs.clear();
  graspNodes_.clear();
  graspOffsets_.clear();
  jawClosed_ = false;
  haveLast_ = false;
  result_ = ContactResult{};
}

Eigen::Vector3d TissueContact::graspCentre() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (size_t k = 0; k < shapes_.size(); ++k)
    if (shapes_[k].jaw) sum += shapePoses_[k].translation(), ++count;
  return count ? Eigen::Vector3d(sum / count) : Eigen::Vector3d(tip_.translation());
}

void TissueContact::updateGrasp(bool jawClosed, const std::vector<ContactPoint>& previous) {
  if (!jawClosed) {
    graspNodes_.clear();
    graspOffsets_.clear();
  } else if (!jawClosed_) {
    // The jaw has just closed: take the free nodes within the grasp radius of the jaw centre
    // and those of the triangles the jaws touched in the last query, nearest first.
    const Eigen::Vector3d centre = graspCentre();
    const Eigen::VectorXd& x = system_.state.x;
    std::vector<char> touched(system_.numNodes(), 0);
    for (const ContactPoint& p : previous)
      if (shapes_[p.shape].jaw)
        for (int a : system_.mesh.surface[p.triangle]) touched[a] = 1;
    std::vector<std::pair<double, int>> near;
    for (int a = 0; a < system_.numNodes(); ++a) {
      if (system_.isConstrained[3 * a] || system_.isConstrained[3 * a + 1] ||
          system_.isConstrained[3 * a + 2])
        continue;
      const double d = (x.segment<3>(3 * a) - centre).norm();
      if (d <= settings_.graspRadius || touched[a]) near.emplace_back(d, a);
    }
    std::sort(near.begin(), near.end());
    if (static_cast<int>(near.size()) > settings_.graspMaxNodes) near.resize(settings_.graspMaxNodes);
    for (const auto& [d, a] : near) {
      graspNodes_.push_back(a);
      graspOffsets_.push_back(tip_.inverse() * Eigen::Vector3d(x.segment<3>(3 * a)));
    }
  }
  jawClosed_ = jawClosed;
  model_->springs.clear();
  for (size_t k = 0; k < graspNodes_.size(); ++k)
    model_->springs.push_back({graspNodes_[k], tip_ * graspOffsets_[k], settings_.graspStiffness});
}

const ContactResult& TissueContact::update() {
  model_->penalties.clear();
  model_->springs.clear();
  const std::vector<ContactPoint> previous = std::move(result_.points);
  result_ = ContactResult{};
  const Eigen::VectorXd& x = system_.state.x;
  if (!haveTool_ || !x.allFinite()) {
    graspNodes_.clear();
    graspOffsets_.clear();
    jawClosed_ = false;
    return result_;
  }
  result_.x0 = tip_.translation();
  if (haveLast_ && toolTime_ > lastTime_) {
    const Eigen::Vector3d v = (tip_.translation() - lastTip_) / (toolTime_ - lastTime_);
    model_->toolVelocity = v.allFinite() ? v : Eigen::Vector3d::Zero();
  } else {
    model_->toolVelocity.setZero();
  }
  lastTip_ = tip_.translation();
  lastTime_ = toolTime_;
  haveLast_ = true;

  updateGrasp(jawAngle_ < settings_.graspJawAngle, previous);
  if (settings_.stiffnessPerArea > 0.0) addSampledPenalties(x);
  else addPointPenalties(x);

  if (!model_->penalties.empty() || !model_->springs.empty()) {
    result_.f0 = model_->toolForce(x, system_.state.v);
    result_.K = settings_.tissueInSeries ? feltStiffness(x) : model_->toolStiffness(x);
  }
  result_.graspedNodes = graspNodes_;
  result_.grasping = !graspNodes_.empty();
  if (!result_.f0.allFinite() || !result_.K.allFinite()) {
    model_->penalties.clear();
    model_->springs.clear();
    result_.f0.setZero();
    result_.K.setZero();
    result_.points.clear();
  }
  result_.inContact = !model_->penalties.empty() || !model_->springs.empty();
  return result_;
}

// ContactSettings::tissueInSeries: each penalty k_c in series with the tissue's stiffness k_t
// at its contact point along the normal, k = k_c k_t / (k_c + k_t). The point's compliance
// along n is w^T C w with C the tissue's compliance (K^-1, K = -df/dx of the tissue models) on
// its triangle's nodes; k_t takes 1 / sum_i w_i^2 / (n^T K_ii n) for it: (K^-1)_ii >= 1 / K_ii
// for a positive definite K, and the cross terms of neighbouring nodes, left out, are
// positive where pushing one node moves its neighbours along, so k_t is at least the point's
// true stiffness and k lies between the felt stiffness of the settled tissue and k_c (a test
// checks both). A penalty on a constrained node, or where a node's block is not positive
// along n, keeps k_c.
Eigen::Matrix3d TissueContact::feltStiffness(const Eigen::VectorXd& x) {
  system_.assembleStiffness(x, tissueStiffness_, -1.0);
  model_->addStiffness(x, 1.0, system_.pattern, tissueStiffness_);  // the tissue's part alone
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  for (const PenaltyContact& c : model_->penalties) {
    if (!(ContactForceModel::depth(c, x) > 0.0)) continue;
    const double kt = tissuePointStiffness(c);
    const double k = kt > 0.0 ? c.stiffness * kt / (c.stiffness + kt) : c.stiffness;
    K += k * c.normal * c.normal.transpose();
  }
  for (const GraspSpring& s : model_->springs) K += s.stiffness * Eigen::Matrix3d::Identity();
  return K;
}

double TissueContact::tissuePointStiffness(const PenaltyContact& c) const {
  double compliance = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (c.weights[i] == 0.0) continue;
    const int node = c.nodes[i];
    for (int k = 0; k < 3; ++k)
      if (system_.isConstrained[3 * node + k]) return 0.0;
    Eigen::Matrix3d block;
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s)
        block(r, s) = tissueStiffness_.coeff(3 * node + r, 3 * node + s);
    const double along = c.normal.dot(block * c.normal);
    if (!(along > 0.0)) return 0.0;
    compliance += c.weights[i] * c.weights[i] / along;
  }
  return compliance > 0.0 ? 1.0 / compliance : 0.0;
}

bool TissueContact::grasped(int node) const {
  return std::find(graspNodes_.begin(), graspNodes_.end(), node) != graspNodes_.end();
}

// The contact per unit area, sampled on the tissue's surface: every surface triangle whose box
// meets a tool shape's box is cut into m x m congruent sub-triangles (m: its longest edge over
// the sample spacing, at most kMaxSubdivisions). A sub-triangle's centroid inside a tool shape
// gets a penalty of k_A times the sub-triangle's rest area along the triangle's outward normal,
// at the depth of the tool below it: how far the point would have to move into the tissue to
// leave the shape (the deepest shape where several hold it, so none counts twice). The force
// for an indentation is then k_A times the volume of the tool below the surface, pressing it
// ever deeper raises it (a nearest-face depth would turn sideways under a narrow tool), and
// the samples are as fine as the tool whatever the mesh, so a tool smaller than the triangles
// cannot slip between the nodes.
void TissueContact::addSampledPenalties(const Eigen::VectorXd& x) {
  std::vector<Eigen::AlignedBox3d> toolBoxes;
  Eigen::AlignedBox3d anyTool;
  for (size_t k = 0; k < shapes_.size(); ++k) {
    toolBoxes.push_back(worldBox(shapes_[k], shapePoses_[k]));
    anyTool.extend(toolBoxes.back());
  }
  const auto& surface = system_.mesh.surface;
  std::vector<int> near;  // the shapes whose boxes meet the triangle's
  for (size_t t = 0; t < surface.size(); ++t) {
    const Triangle& tri = surface[t];
    const Eigen::Vector3d corner[3] = {x.segment<3>(3 * tri[0]), x.segment<3>(3 * tri[1]),
                                       x.segment<3>(3 * tri[2])};
    Eigen::AlignedBox3d box(corner[0]);
    box.extend(corner[1]).extend(corner[2]);
    if (!box.intersects(anyTool)) continue;
    if (std::any_of(tri.begin(), tri.end(), [&](int a) { return grasped(a); })) continue;
    near.clear();
    for (size_t k = 0; k < shapes_.size(); ++k)
      if (box.intersects(toolBoxes[k])) near.push_back(static_cast<int>(k));
    const Eigen::Vector3d outward = (corner[1] - corner[0]).cross(corner[2] - corner[0]).normalized();
    if (near.empty() || !outward.allFinite()) continue;
    const double longest = std::max({(corner[1] - corner[0]).norm(), (corner[2] - corner[1]).norm(),
                                     (corner[0] - corner[2]).norm()});
    const int m = static_cast<int>(
        std::clamp(std::ceil(longest / sampleSpacing_), 1.0, static_cast<double>(kMaxSubdivisions)));
    const double subArea = triangleArea_[t] / (m * m);
    // Sub-triangle centroids in barycentric coordinates (i, j: the lattice corner, steps of 1/m):
    // the m(m+1)/2 upright ones at (i + 1/3, j + 1/3) / m, the m(m-1)/2 inverted at (i + 2/3, j + 2/3) / m.
    for (int i = 0; i < m; ++i)
      for (int j = 0; i + j < m; ++j)
        for (const double shift : {1.0 / 3.0, 2.0 / 3.0}) {
          if (shift > 0.5 && i + j > m - 2) continue;
          const double u = (i + shift) / m, v = (j + shift) / m;
          const Eigen::Vector3d weights(1.0 - u - v, u, v);
          addSample(static_cast<int>(t), weights, corner, outward, subArea, near);
        }
  }
}

void TissueContact::addSample(int triangle, const Eigen::Vector3d& weights,
                              const Eigen::Vector3d (&corner)[3], const Eigen::Vector3d& outward,
                              double area, const std::vector<int>& shapes) {
  const Eigen::Vector3d p = weights[0] * corner[0] + weights[1] * corner[1] + weights[2] * corner[2];
  ContactPoint deepest;
  for (const int k : shapes) {
    double depth = 0.0;
    if (!exitDistance(shapes_[k], shapePoses_[k], p, -outward, depth) || depth <= deepest.depth)
      continue;
    deepest.shape = k;
    deepest.depth = depth;
  }
  if (!(deepest.depth > 0.0)) return;
  deepest.triangle = triangle;
  deepest.normal = outward;  // from the tissue toward the tool
  deepest.tissuePoint = p;
  deepest.toolPoint = p - deepest.depth * outward;
  const Triangle& tri = system_.mesh.surface[triangle];
  PenaltyContact pc;
  pc.nodes = {tri[0], tri[1], tri[2]};
  pc.weights = weights;
  pc.normal = outward;
  pc.toolPoint = deepest.toolPoint;
  pc.stiffness = settings_.stiffnessPerArea * area;
  pc.damping = settings_.damping * area;
  if (!pc.toolPoint.allFinite()) return;
  model_->penalties.push_back(pc);
  result_.points.push_back(deepest);
}

void TissueContact::addPointPenalties(const Eigen::VectorXd& x) {
  Bullet& b = *bullet_;
  std::vector<ContactPoint> found;
  if (b.anyShapeNear(x, shapePoses_)) {
    b.setPositions(x);
    b.findContacts(shapePoses_, found);
  }

  // Classify: a face contact has Bullet's normal along the triangle's outward normal; an
  // edge or vertex contact does not. When a shape has a face contact, its edge contacts are
  // the coplanar (or nearly so) neighbours of that face seeing the same tool from their edges:
  // dropped, so that a flat surface gives one contact with the face normal. Points whose
  // normal faces into the tissue (a triangle touched from behind) are dropped too, and
  // several triangles around one vertex or edge reporting the same point count once.
  const auto& surface = system_.mesh.surface;
  struct Candidate {
    ContactPoint point;
    bool face = false;
  };
  std::vector<Candidate> candidates;
  std::vector<char> shapeHasFace(shapes_.size(), 0);
  for (ContactPoint& p : found) {
    if (p.triangle < 0 || p.triangle >= static_cast<int>(surface.size())) continue;
    const Triangle& t = surface[p.triangle];
    const Eigen::Vector3d a = x.segment<3>(3 * t[0]), bb = x.segment<3>(3 * t[1]),
                          c = x.segment<3>(3 * t[2]);
    const Eigen::Vector3d outward = (bb - a).cross(c - a).normalized();
    p.normal.normalize();
    const double cosine = p.normal.dot(outward);
    if (!(cosine > 0.0) || !p.normal.allFinite() || !outward.allFinite()) continue;
    Candidate candidate{p, cosine > kFaceCosine};
    if (candidate.face) {
      candidate.point.normal = outward;
      shapeHasFace[p.shape] = 1;
    }
    candidates.push_back(candidate);
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& c) {
    return a.point.depth > c.point.depth;
  });
  const double mergeDistance = 1e-4;  // m
  for (const Candidate& candidate : candidates) {
    const ContactPoint& q = candidate.point;
    if (!candidate.face && shapeHasFace[q.shape]) continue;
    const bool duplicate = std::any_of(result_.points.begin(), result_.points.end(), [&](const ContactPoint& r) {
      return r.shape == q.shape && (r.tissuePoint - q.tissuePoint).norm() < mergeDistance;
    });
    if (duplicate) continue;
    const Triangle& t = surface[q.triangle];
    if (std::any_of(t.begin(), t.end(), [&](int a) { return grasped(a); })) continue;
    const Eigen::Vector3d a = x.segment<3>(3 * t[0]), bb = x.segment<3>(3 * t[1]),
                          c = x.segment<3>(3 * t[2]);
    PenaltyContact pc;
    pc.nodes = {t[0], t[1], t[2]};
    pc.weights = triangleWeights(a, bb, c, q.tissuePoint);
    const Eigen::Vector3d onTissue = pc.weights[0] * a + pc.weights[1] * bb + pc.weights[2] * c;
    pc.normal = q.normal;
    pc.toolPoint = onTissue - q.depth * q.normal;
    pc.stiffness = settings_.stiffness;
    pc.damping = settings_.damping;
    if (!pc.weights.allFinite() || !pc.normal.allFinite() || !pc.toolPoint.allFinite()) continue;
    model_->penalties.push_back(pc);
    result_.points.push_back(q);
  }
}

}  // namespace tt
