// Rostest of the simulation node on the liver palpation scene (test/integration/
// simulation.test): a real master, the node, the grasper URDF as /robot_description, and this
// test moving the instrument tip (tf world -> instrument_tip, jaw links fixed to it) into the
// liver's anterior face.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <visualization_msgs/Marker.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <functional>

#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/LoadScene.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/TissueSurface.h"

namespace {

bool finite(double v) { return std::isfinite(v); }

struct Probe {
  ros::NodeHandle nh;
  tf2_ros::TransformBroadcaster tf;
  tf2_ros::StaticTransformBroadcaster staticTf;
  ros::Publisher cp = nh.advertise<geometry_msgs::PoseStamped>("instrument/measured_cp", 10);
  ros::Publisher jaw = nh.advertise<sensor_msgs::JointState>("instrument/jaw/measured_js", 10);
  tissue_trainer::ContactModel contact;
  tissue_trainer::TissueStatus status;
  int contacts = 0, statuses = 0, surfaces = 0, surfacesWithTriangles = 0, markers = 0,
      diagnostics = 0, nonFinite = 0, unstable = 0;
  size_t lastTriangles = 0, lastVertices = 0;
  std::vector<float> lastPositions;
  double jawAngle = 0.0;  // published with every tip pose
  bool badSurface = false;
  std::vector<ros::Subscriber> subs;

  Probe() {
    subs.push_back(nh.subscribe<tissue_trainer::ContactModel>("tissue/contact", 100, [this](const auto& m) {
      contact = *m;
      ++contacts;
      bool ok = finite(m->tool_position.x) && finite(m->tool_position.y) && finite(m->tool_position.z) &&
                finite(m->force.x) && finite(m->force.y) && finite(m->force.z) && finite(m->simulation_time);
      for (double k : m->stiffness) ok = ok && finite(k);
      nonFinite += !ok;
    }));
    subs.push_back(nh.subscribe<tissue_trainer::TissueStatus>("tissue/status", 100, [this](const auto& m) {
      status = *m;
      ++statuses;
      unstable += !m->stable;
      nonFinite += !(finite(m->simulation_time) && finite(m->kinetic_energy) &&
                     finite(m->elastic_energy) && finite(m->max_strain) && finite(m->strained_volume));
    }));
    subs.push_back(nh.subscribe<tissue_trainer::TissueSurface>("tissue/surface", 100, [this](const auto& m) {
      ++surfaces;
      if (m->positions.size() % 3 != 0 || m->positions.empty()) badSurface = true;
      for (float p : m->positions) badSurface = badSurface || !std::isfinite(p);
      lastVertices = m->positions.size() / 3;
      lastPositions = m->positions;
      // A change always carries the triangles; they are also resent once a second unchanged.
      if (m->triangles_changed && m->triangles.empty()) badSurface = true;
      if (!m->triangles.empty()) {
        ++surfacesWithTriangles;
        lastTriangles = m->triangles.size() / 3;
        if (m->triangles.size() % 3 != 0) badSurface = true;
        for (uint32_t t : m->triangles) badSurface = badSurface || t >= lastVertices;
      }
    }));
    subs.push_back(nh.subscribe<visualization_msgs::Marker>("tissue/surface_marker", 10, [this](const auto& m) {
      if (m->type == visualization_msgs::Marker::TRIANGLE_LIST && !m->points.empty() &&
          m->points.size() % 3 == 0)
        ++markers;
    }));
    subs.push_back(nh.subscribe<diagnostic_msgs::DiagnosticArray>("diagnostics", 10, [this](const auto& m) {
      for (const auto& s : m->status) diagnostics += s.name == "simulation";
    }));
  }

  // The jaw links ride on the tip (closed jaws, as at zero jaw angle).
  void publishJawLinks() {
    std::vector<geometry_msgs::TransformStamped> links;
    for (const char* name : {"shaft", "jaw_left", "jaw_right"}) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = ros::Time::now();
      t.header.frame_id = "instrument_tip";
      t.child_frame_id = name;
      t.transform.rotation.w = 1.0;
      links.push_back(t);
    }
    staticTf.sendTransform(links);
  }

  // Tip on the trocar's axis at height z, the shaft along world -z (tip frame x rotated by pi).
  void publishTip(double z) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "world";
    t.child_frame_id = "instrument_tip";
    t.transform.translation.x = -0.035;
    t.transform.translation.y = 0.075;
    t.transform.translation.z = z;
    t.transform.rotation.x = 1.0;
    tf.sendTransform(t);
    geometry_msgs::PoseStamped p;
    p.header = t.header;
    p.pose.position.x = -0.035;
    p.pose.position.y = 0.075;
    p.pose.position.z = z;
    p.pose.orientation.x = 1.0;
    cp.publish(p);
    sensor_msgs::JointState j;
    j.header.stamp = t.header.stamp;
    j.name = {"jaw"};
    j.position = {jawAngle};
    jaw.publish(j);
  }

  // Runs for `seconds`, publishing the tip at 200 Hz at height z(t); stops early when `done`.
  bool run(double seconds, const std::function<double(double)>& z,
           const std::function<bool()>& done = nullptr) {
    const ros::WallTime start = ros::WallTime::now();
    ros::WallRate rate(200.0);
    while (ros::ok()) {
      const double t = (ros::WallTime::now() - start).toSec();
      if (t > seconds) return false;
      if (z) publishTip(z(t));
      ros::spinOnce();
      if (done && done()) return true;
      rate.sleep();
    }
    return false;
  }
};

double largestChange(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size() || a.empty()) return INFINITY;
  double largest = 0.0;
  for (size_t k = 0; k < a.size(); ++k) largest = std::max(largest, double(std::abs(a[k] - b[k])));
  return largest;
}

Eigen::Matrix3d stiffnessOf(const tissue_trainer::ContactModel& m) {
  Eigen::Matrix3d K;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K(i, j) = m.stiffness[3 * i + j];
  return K;
}

TEST(Simulation, PalpationLoadSceneAndReset) {
  Probe probe;
  // The node publishes before any instrument pose: no contact.
  ASSERT_TRUE(probe.run(20.0, nullptr, [&] { return probe.statuses > 20 && probe.contacts > 20; }))
      << "no status from the simulation node";
  EXPECT_FALSE(probe.contact.in_contact);

  probe.publishJawLinks();
  const double above = 0.10;
  probe.run(0.5, [&](double) { return above; });
  EXPECT_FALSE(probe.contact.in_contact);
  EXPECT_EQ(probe.contact.force.x, 0.0);
  EXPECT_EQ(probe.contact.force.z, 0.0);

  // Down at 2 cm/s until the jaws touch the anterior face.
  double zTouch = above;
  const bool touched = probe.run(4.0, [&](double t) { return zTouch = above - 0.02 * t; },
                                 [&] { return bool(probe.contact.in_contact); });
  ASSERT_TRUE(touched) << "no contact down to z = " << zTouch;
  EXPECT_GT(zTouch, 0.068);  // the jaws (16 mm ahead of the tip) reach the face first
  EXPECT_LT(zTouch, 0.095);

  // 1 cm deeper over 1 s, then hold and let the liver settle.
  const int statusesBefore = probe.statuses;
  const ros::WallTime holdStart = ros::WallTime::now();
  probe.run(1.0, [&](double t) { return zTouch - 0.01 * t; });
  probe.run(2.0, [&](double) { return zTouch - 0.01; });
  const double holdSeconds = (ros::WallTime::now() - holdStart).toSec();
  const double statusRate = (probe.statuses - statusesBefore) / holdSeconds;
  const tissue_trainer::ContactModel pressed = probe.contact;
  ASSERT_TRUE(pressed.in_contact);
  const Eigen::Vector3d f(pressed.force.x, pressed.force.y, pressed.force.z);
  const Eigen::Matrix3d K = stiffnessOf(pressed);
  ROS_INFO("1 cm indentation: f0 = (%.4f, %.4f, %.4f) N, |f0| = %.4f N, K diag (%.1f %.1f %.1f) N/m, "
           "status %.1f Hz, real-time factor %.3f, step %.2f ms",
           f.x(), f.y(), f.z(), f.norm(), K(0, 0), K(1, 1), K(2, 2), statusRate,
           probe.status.real_time_factor, 1e3 * probe.status.step_wall_time);
  EXPECT_GT(f.norm(), 0.05);
  EXPECT_LT(f.norm(), 5.0);
  EXPECT_GT(f.z(), 0.0);  // the liver pushes the tool back out (+z)
  EXPECT_LT((K - K.transpose()).norm(), 1e-6 * K.norm());
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (K + K.transpose())).eigenvalues();
  EXPECT_GT(eig.maxCoeff(), 0.0);
  EXPECT_GE(eig.minCoeff(), -1e-6 * K.norm());
  EXPECT_NEAR(pressed.tool_position.z, zTouch - 0.01, 1e-9);
  EXPECT_GT(statusRate, 50.0) << "the node does not keep its 100 Hz";
  EXPECT_GT(probe.status.real_time_factor, 0.5);
  EXPECT_TRUE(probe.status.stable) << probe.status.failure;
  EXPECT_NEAR(probe.status.contact_force, f.norm(), 0.5);
  EXPECT_GT(probe.status.max_strain, 0.0);
  EXPECT_DOUBLE_EQ(probe.status.damage_strain, 0.3);

  // Surface, marker and diagnostics.
  EXPECT_FALSE(probe.badSurface);
  EXPECT_GE(probe.surfacesWithTriangles, 1);  // sent to a new subscriber
  EXPECT_GT(probe.lastTriangles, 100u);
  EXPECT_GT(probe.surfaces, 100);
  EXPECT_GT(probe.markers, 0);
  EXPECT_GT(probe.diagnostics, 0);

  // A broken scene file is refused with the loader's line; the node keeps publishing.
  const std::string broken = "/tmp/tt_simulation_check_broken.yaml";
  std::ofstream(broken) << "mesh: {generator: box, nodes: [3, 3]}\nmaterials: [\n";
  tissue_trainer::LoadScene load;
  load.request.scene_file = broken;
  ASSERT_TRUE(ros::service::waitForService("simulation/load_scene", 5000));
  ASSERT_TRUE(ros::service::call("simulation/load_scene", load));
  EXPECT_FALSE(load.response.success);
  EXPECT_NE(load.response.message.find(broken), std::string::npos) << load.response.message;
  EXPECT_EQ(load.response.message.find('\n'), std::string::npos);
  const int afterLoad = probe.statuses;
  probe.run(0.5, [&](double) { return zTouch - 0.01; });
  EXPECT_GT(probe.statuses - afterLoad, 20);
  EXPECT_TRUE(probe.contact.in_contact);  // same scene, still pressed

  // Reset: back to the initial state, the settled one (simulation time restarts from the
  // scene's run.settle_time).
  constexpr double kSettleTime = 0.5;  // config/scenes/liver_palpation.yaml
  probe.run(0.5, [&](double) { return above; });
  const double timeBefore = probe.status.simulation_time;
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("simulation/reset", reset));
  EXPECT_TRUE(reset.response.success);
  probe.run(0.3, [&](double) { return above; });
  EXPECT_GE(probe.status.simulation_time, kSettleTime);
  EXPECT_LT(probe.status.simulation_time, kSettleTime + 0.5);
  EXPECT_LT(probe.status.simulation_time, timeBefore);
  EXPECT_FALSE(probe.contact.in_contact);

  // The muscle scene: load it, press the jaws 5 mm into its belly from above, close them and
  // pull up 1 cm: the grasped tissue pulls the tool back down (-z).
  std::string muscle;
  ASSERT_TRUE(ros::param::get("~muscle_scene", muscle));
  load.request.scene_file = muscle;
  ASSERT_TRUE(ros::service::call("simulation/load_scene", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  const int trianglesBefore = probe.surfacesWithTriangles;
  double zMuscle = above;
  probe.jawAngle = 0.6;
  ASSERT_TRUE(probe.run(4.0, [&](double t) { return zMuscle = above - 0.02 * t; },
                        [&] { return bool(probe.contact.in_contact); }))
      << "no contact with the muscle";
  EXPECT_GT(probe.surfacesWithTriangles, trianglesBefore);  // the new scene's triangles
  probe.run(0.5, [&](double t) { return zMuscle - 0.01 * t; });
  probe.jawAngle = 0.0;
  probe.run(0.3, [&](double) { return zMuscle - 0.005; });
  probe.run(1.0, [&](double t) { return zMuscle - 0.005 + 0.01 * t; });
  probe.run(0.5, [&](double) { return zMuscle + 0.005; });
  ROS_INFO("grasp, pulled 1 cm: f0 = (%.4f, %.4f, %.4f) N, in contact %d, K zz %.1f N/m, "
           "real-time factor %.3f, step %.2f ms, max strain %.3f",
           probe.contact.force.x, probe.contact.force.y, probe.contact.force.z,
           int(probe.contact.in_contact), probe.contact.stiffness[8],
           probe.status.real_time_factor, 1e3 * probe.status.step_wall_time, probe.status.max_strain);
  EXPECT_GT(probe.status.real_time_factor, 0.5);
  EXPECT_TRUE(probe.contact.in_contact);
  EXPECT_LT(probe.contact.force.z, -0.01);
  probe.jawAngle = 0.6;
  probe.run(1.0, [&](double) { return above; });
  EXPECT_FALSE(probe.contact.in_contact);  // released, the tool out of the tissue
  EXPECT_EQ(probe.nonFinite, 0);
  EXPECT_EQ(probe.unstable, 0);
}

// /tissue/activation: a muscle scene contracts when its muscle is activated by name; a name
// the scene does not have and a value outside [0, 1] change nothing, and the node steps on.
TEST(Simulation, MuscleActivationsByTopic) {
  Probe probe;
  ros::Publisher activation = probe.nh.advertise<sensor_msgs::JointState>("tissue/activation", 10);
  std::string scene;  // test/integration/muscle_block.yaml: two layers, both at rest
  ASSERT_TRUE(ros::param::get("~muscle_block_scene", scene));
  tissue_trainer::LoadScene load;
  load.request.scene_file = scene;
  ASSERT_TRUE(ros::service::waitForService("simulation/load_scene", 5000));
  ASSERT_TRUE(ros::service::call("simulation/load_scene", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  const auto send = [&](const std::vector<std::string>& names, const std::vector<double>& values) {
    sensor_msgs::JointState m;
    m.header.stamp = ros::Time::now();
    m.name = names;
    m.position = values;
    activation.publish(m);
  };
  probe.run(1.0, nullptr);
  ASSERT_FALSE(probe.lastPositions.empty());
  const std::vector<float> rest = probe.lastPositions;

  send({"biceps", "lower"}, {1.0, 1.5});  // no such muscle; out of range
  probe.run(0.5, nullptr);
  EXPECT_LT(largestChange(rest, probe.lastPositions), 1e-6);

  const int statusesBefore = probe.statuses;
  send({"lower"}, {0.8});
  probe.run(1.0, nullptr);
  const double contracted = largestChange(rest, probe.lastPositions);
  ROS_INFO("lower at 0.8: largest surface vertex motion %.3f mm", 1e3 * contracted);
  EXPECT_GT(contracted, 2e-4);
  EXPECT_GT(probe.statuses - statusesBefore, 20);

  send({"lower"}, {0.0});
  probe.run(1.0, nullptr);
  EXPECT_LT(largestChange(rest, probe.lastPositions), 1e-6);  // quasistatic: back at rest
  EXPECT_EQ(probe.nonFinite, 0);
  EXPECT_EQ(probe.unstable, 0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "simulation_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
