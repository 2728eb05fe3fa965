#pragma once
// Instrument-tissue contact with Bullet collision detection (library tissue_trainer_contact).
//
// The tissue is the boundary surface of the tet mesh as a Bullet triangle mesh
// (btBvhTriangleMeshShape over the deformed node positions; its vertices are rewritten and
// its tree refitted at every update). The instrument is a set of ToolShapes posed each step.
// update() runs one Bullet contact query (btCollisionWorld::contactPairTest) per tool shape
// against the tissue and turns every contact point into a linearised penalty contact in the
// system's ContactForceModel (see contact_force_model.h), then reports the force on the tool
// f0 and the contact stiffness K = -df0/dx (tissue held fixed) at the tip position x0.
//
// Grasp: when the jaw angle drops below ContactSettings::graspJawAngle (an open -> closed
// transition), the free nodes within graspRadius of the jaw centre (the mean of the jaw shapes'
// centres, or the tip when no shape is a jaw) and the nodes of the triangles the jaw shapes
// touched in the previous query (nearest first, at most graspMaxNodes) are tied to the tip by
// springs of
// graspStiffness, their anchors moving rigidly with the tip, until the jaw opens again.
// Penalty contacts on triangles with a grasped node are skipped (the springs hold them).
// Contact points: a face contact (Bullet's normal along the triangle's) outranks the edge
// contacts of the same shape (the neighbours of that face); normals facing into the tissue
// are dropped; points reported by several triangles count once. Each point is one penalty of
// ContactSettings::stiffness, so the contact gets stiffer, and the load more concentrated, as
// the surface is refined.
//
// Or, with ContactSettings::stiffnessPerArea > 0, per unit area (Bullet is not queried): the
// surface triangles near a tool are sampled at the tool's scale (sub-triangles of about
// ContactSettings::sampleSpacing), and every sample inside a tool shape is pushed back along
// its triangle's normal by a penalty of stiffnessPerArea times its share of the rest surface
// area at the depth of the tool below it (exitDistance(), tool_shape.h): the force for an
// indentation is stiffnessPerArea times the volume of the tool below the surface whatever the
// resolution, and a tool smaller than the triangles still meets the surface between the nodes.
//
// Bullet works internally in centimetres (kBulletScale): its GJK/EPA tolerances suit objects
// of about 0.05 to 10 units, millimetre jaws in metres do not.
#include <Eigen/Geometry>
#include <memory>
#include <stdexcept>
#include <vector>

#include "tissue_trainer/core/contact/contact_force_model.h"
#include "tissue_trainer/core/contact/contact_settings.h"
#include "tissue_trainer/core/contact/tool_shape.h"
#include "tissue_trainer/core/system.h"

namespace tt {

constexpr double kBulletScale = 100.0;  // Bullet units per metre

// One contact point of the last query (world, m).
struct ContactPoint {
  int shape = 0;                 // index into the tool shapes
  int triangle = 0;              // index into the mesh surface
  Eigen::Vector3d tissuePoint = Eigen::Vector3d::Zero();
  Eigen::Vector3d toolPoint = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // tissue -> tool
  double depth = 0.0;            // penetration (m, > 0)
};

struct ContactResult {
  bool inContact = false;        // some penalty contact or grasp spring is active
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();  // tip position (m)
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();  // force of the tissue on the tool (N)
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();   // -df0/dx0 (N/m), symmetric PSD
  std::vector<ContactPoint> points;
  std::vector<int> graspedNodes;
  bool grasping = false;         // the jaw is closed on tissue
};

class TissueContact {
 public:
  // Adds a ContactForceModel to system.models (the System owns it; this object must not
  // outlive the System, and the System must not be rebuilt while it lives).
  TissueContact(System& system, const ContactSettings& settings, std::vector<ToolShape> shapes);
  ~TissueContact();
  TissueContact(const TissueContact&) = delete;
  TissueContact& operator=(const TissueContact&) = delete;

  // The tool for the next update(): tip pose and one link pose per shape (same order as the
  // shapes; a shape's world pose is linkPose * shape.offset), the jaw opening (rad) and the
  // time (s, for the tool velocity of the damping term). Throws std::invalid_argument naming
  // the bad value when any number is not finite; the previous tool is then kept.
  void setTool(const Eigen::Isometry3d& tip, const std::vector<Eigen::Isometry3d>& linkPoses,
               double jawAngle, double time);
  // No tool pose known: the next update() has no contact (and releases a grasp).
  void clearTool();

  // Contact query at the system's current state; sets the force model's contacts and returns
  // the tool force model. Every number of the result is finite.
  const ContactResult& update();
  const ContactResult& result() const { return result_; }

  // Contacts off: the force model is emptied (e.g. before a reset).
  void clear();

  const std::vector<ToolShape>& shapes() const { return shapes_; }
  const ContactSettings& settings() const { return settings_; }
  const ContactForceModel& model() const { return *model_; }

 private:
  struct Bullet;
  void prepareSurfaceSampling();
  void updateGrasp(bool jawClosed, const std::vector<ContactPoint>& previous);
  void addPointPenalties(const Eigen::VectorXd& x);
  void addSampledPenalties(const Eigen::VectorXd& x);
  void addSample(int triangle, const Eigen::Vector3d& weights, const Eigen::Vector3d (&corner)[3],
                 const Eigen::Vector3d& outward, double area, const std::vector<int>& shapes);
  bool grasped(int node) const;
  Eigen::Matrix3d feltStiffness(const Eigen::VectorXd& x);
  double tissuePointStiffness(const PenaltyContact& c) const;
  Eigen::Vector3d graspCentre() const;

  System& system_;
  ContactSettings settings_;
  std::vector<ToolShape> shapes_;
  ContactForceModel* model_ = nullptr;  // owned by system_.models
  std::unique_ptr<Bullet> bullet_;

  bool haveTool_ = false;
  Eigen::Isometry3d tip_ = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> shapePoses_;  // world pose of each shape
  double jawAngle_ = 1.0;
  bool jawClosed_ = false;
  double toolTime_ = 0.0;
  Eigen::Vector3d lastTip_ = Eigen::Vector3d::Zero();
  double lastTime_ = 0.0;
  bool haveLast_ = false;
  std::vector<Eigen::Vector3d> graspOffsets_;  // grasped nodes' positions in the tip frame
  std::vector<int> graspNodes_;
  ContactResult result_;
  SparseMatrix tissueStiffness_;  // -df/dx of the tissue's models (ContactSettings::tissueInSeries)
  // With ContactSettings::stiffnessPerArea: each surface triangle's rest area (m^2) and the
  // spacing of the samples on the triangles (m).
  std::vector<double> triangleArea_;
  double sampleSpacing_ = 0.0;
};

}  // namespace tt
