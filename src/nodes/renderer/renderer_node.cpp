// renderer: the deformed tissue surface and the instrument inside the abdominal cavity,
// rendered offscreen (OSMesa) from a fixed laparoscope camera whose light sits at its tip,
// published on /camera/image_raw (rgb8) and optionally written as PNG frames.
#include <ros/ros.h>

#include <sys/resource.h>
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <mutex>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "../common/param_reader.h"
#include "../common/tissue_colour.h"
#include "instrument_shapes.h"
#include "offscreen_renderer.h"
#include "png_writer.h"
#include "tissue_trainer/TissueSurface.h"

namespace {

using tt_nodes::ParamReader;
using tt_render::Rgb;

Eigen::Vector3d vec(const std::array<double, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); }

Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  const Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  t.linear() = q.norm() > 0.5 ? q.normalized().toRotationMatrix() : Eigen::Matrix3d::Identity();
  return t;
}

enum class InstrumentSource { kAuto, kTf, kPose, kNone };

struct RendererParams {
  int width = 640, height = 480;
  double rate = 30.0;
  tt_render::Camera camera;
  std::string pngDir;
  int pngEvery = 30;
  int nice = 10;
  InstrumentSource instrument = InstrumentSource::kAuto;
  double shaftLength = 0.3;
  tt_render::Lighting lighting;
  double tissueTexture = tt_render::wetTissue().texture;
  Eigen::Vector3d cavityCentre{-0.036, 0.06, 0.03};
  Eigen::Vector3d cavityRadii{0.2, 0.16, 0.25};  // zero: no cavity; the camera and trocar inside
};

RendererParams readParams(const ros::NodeHandle& pnh) {
  const ParamReader p(pnh);
  RendererParams r;
  r.width = static_cast<int>(p.number("width", 640, 16, 4096));
  r.height = static_cast<int>(p.number("height", 480, 16, 4096));
  r.rate = p.number("rate", 30.0, 0.1, 240.0);
  const tt_render::Camera d;
  r.camera.position = vec(p.vector3("camera_position", {d.position.x(), d.position.y(), d.position.z()}));
  r.camera.target = vec(p.vector3("camera_target", {d.target.x(), d.target.y(), d.target.z()}));
  r.camera.up = vec(p.vector3("camera_up", {d.up.x(), d.up.y(), d.up.z()}));
  r.camera.fovDeg = p.number("fov_deg", d.fovDeg, 1.0, 170.0);
  r.pngDir = p.text("png_dir", "");
  r.pngEvery = static_cast<int>(p.number("png_every", 30, 1, 1e9));
  r.nice = static_cast<int>(p.number("nice", 10, 0, 19));
  r.instrument = static_cast<InstrumentSource>(p.choice("instrument", {"auto", "tf", "pose", "none"}, 0));
  r.shaftLength = p.number("shaft_length", 0.3, 0.001, 2.0);
  r.lighting.intensity = p.number("light_intensity", r.lighting.intensity, 0.0, 100.0);
  r.lighting.range = p.number("light_range", r.lighting.range, 1e-4, 100.0);
  r.lighting.ambient = p.number("ambient", r.lighting.ambient, 0.0, 1.0);
  r.lighting.vignette = p.number("vignette", r.lighting.vignette, 0.0, 1.0);
  r.tissueTexture = p.number("tissue_texture", r.tissueTexture, 0.0, 1.0);
  const RendererParams d2;
  r.cavityCentre = vec(p.vector3("cavity_center", {d2.cavityCentre.x(), d2.cavityCentre.y(), d2.cavityCentre.z()}));
  r.cavityRadii = vec(p.vector3("cavity_radii", {d2.cavityRadii.x(), d2.cavityRadii.y(), d2.cavityRadii.z()}));
  const bool noCavity = r.cavityRadii.isZero(0.0);
  if (!noCavity && !(r.cavityRadii.minCoeff() > 0.0))
    throw tt_nodes::ParamError(p.qualified("cavity_radii") + ": expected three positive semi-axes (m), or all zero for no cavity");
  return r;
}

class RendererNode {
 public:
  RendererNode(ros::NodeHandle& nh, const RendererParams& params)
      : params_(params), renderer_(params.width, params.height), listener_(tfBuffer_) {
    try {
      renderer_.setCamera(params_.camera);
    } catch (const std::exception& e) {
      throw tt_nodes::ParamError("~camera_position/~camera_target/~camera_up/~fov_deg: " + std::string(e.what()));
    }
    std::string urdf;
    const bool haveUrdf = nh.getParam("/robot_description", urdf);
    if (params_.instrument == InstrumentSource::kTf ||
        (params_.instrument == InstrumentSource::kAuto && haveUrdf)) {
      if (!haveUrdf) throw tt_nodes::ParamError("/robot_description: expected a URDF (~instrument is tf)");
      shapes_ = tt_render::shapesFromUrdf(urdf);
      useTf_ = true;
      ROS_INFO("renderer: instrument from tf, %zu shapes from /robot_description", shapes_.size());
    } else if (params_.instrument != InstrumentSource::kNone) {
      shapes_ = tt_render::defaultInstrument("instrument_tip", params_.shaftLength);
      poseSub_ = nh.subscribe("instrument/measured_cp", 5, &RendererNode::onPose, this);
      jawSub_ = nh.subscribe("instrument/jaw/measured_js", 5, &RendererNode::onJaw, this);
      ROS_INFO("renderer: instrument from /instrument/measured_cp and /instrument/jaw/measured_js");
    }
    if (!params_.pngDir.empty() && ::mkdir(params_.pngDir.c_str(), 0755) != 0 && errno != EEXIST)
      throw tt_nodes::ParamError("~png_dir: cannot create " + params_.pngDir + ": " + std::strerror(errno));
    renderer_.setLighting(params_.lighting);
    ROS_INFO("renderer: %s, %s", renderer_.glRenderer().c_str(),
             renderer_.shaded() ? "per-pixel scope light" : "no GLSL: fixed-function headlight");
    surfaceSub_ = nh.subscribe("tissue/surface", 5, &RendererNode::onSurface, this);
    imagePub_ = nh.advertise<sensor_msgs::Image>("camera/image_raw", 2);
    publishCameraFrame();
    timer_ = nh.createWallTimer(ros::WallDuration(1.0 / params_.rate),
                                [this](const ros::WallTimerEvent&) { renderFrame(); });
  }

 private:
  void onSurface(const tissue_trainer::TissueSurface::ConstPtr& msg) {
    if (msg->triangles_changed || !msg->triangles.empty()) triangles_ = msg->triangles;
    positions_ = msg->positions;
    for (std::uint32_t i : triangles_)
      if (3 * std::size_t(i) + 2 >= positions_.size()) {
        ROS_WARN_THROTTLE(5.0, "renderer: /tissue/surface triangle index beyond the positions; frame skipped");
        positions_.clear();
        break;
      }
    if (!positions_.empty()) normals_ = tt_render::vertexNormals(positions_, triangles_);
  }

  void onJaw(const sensor_msgs::JointState::ConstPtr& msg) {
    if (!msg->position.empty() && std::isfinite(msg->position[0])) jawAngle_ = msg->position[0];
  }

  void onPose(const geometry_msgs::PoseStamped::ConstPtr& msg) {
    tipPose_ = toIsometry(msg->pose);
    havePose_ = tipPose_.matrix().allFinite();
  }

  // Static world -> laparoscope, optical convention (z along the view, x right, y down).
  void publishCameraFrame() {
    const tt_render::Camera& c = params_.camera;
    const Eigen::Vector3d z = (c.target - c.position).normalized();
    const Eigen::Vector3d x = z.cross(c.up).normalized();
    Eigen::Matrix3d R;
    R << x, z.cross(x), z;
    const Eigen::Quaterniond q(R);
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "world";
    t.child_frame_id = "laparoscope";
    t.transform.translation.x = c.position.x();
    t.transform.translation.y = c.position.y();
    t.transform.translation.z = c.position.z();
    t.transform.rotation.x = q.x();
    t.transform.rotation.y = q.y();
    t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    staticBroadcaster_.sendTransform(t);
  }

  std::vector<Eigen::Isometry3d> linkPoses(std::vector<tt_render::Shape>& drawn) {
    std::vector<Eigen::Isometry3d> poses;
    for (const tt_render::Shape& s : shapes_) {
      if (useTf_) {
        try {
          const geometry_msgs::TransformStamped t = tfBuffer_.lookupTransform("world", s.link, ros::Time(0));
          geometry_msgs::Pose p;
          p.position.x = t.transform.translation.x;
          p.position.y = t.transform.translation.y;
          p.position.z = t.transform.translation.z;
          p.orientation = t.transform.rotation;
          poses.push_back(toIsometry(p));
        } catch (const tf2::TransformException&) {
          continue;  // link not (yet) in tf: not drawn
        }
      } else {
        if (!havePose_) continue;
        poses.push_back(tt_render::defaultInstrumentLinkPose(s, tipPose_, jawAngle_));
      }
      drawn.push_back(s);
    }
    return poses;
  }

  void renderFrame() {
    const auto start = std::chrono::steady_clock::now();
    renderer_.beginFrame();
    if (!positions_.empty() && !triangles_.empty()) {
      tt_render::Material tissue = tt_render::wetTissue();
      tissue.texture = static_cast<float>(params_.tissueTexture);
      renderer_.setMaterial(tissue);
      const tt_nodes::TissueColour c = tt_nodes::kParenchyma;
      renderer_.drawMesh(positions_, normals_, triangles_, Rgb{c.r, c.g, c.b});
    }
    std::vector<tt_render::Shape> drawn;
    const std::vector<Eigen::Isometry3d> poses = linkPoses(drawn);
    renderer_.setMaterial(tt_render::steel());
    tt_render::drawShapes(renderer_, drawn, poses);
    if (!params_.cavityRadii.isZero(0.0)) {  // last: the depth test skips what is hidden
      renderer_.setMaterial(tt_render::cavityWall());
      renderer_.drawCavity(params_.cavityCentre, params_.cavityRadii, Rgb{0.78f, 0.42f, 0.38f});
    }

    sensor_msgs::Image img;
    img.header.stamp = ros::Time::now();
    img.header.frame_id = "laparoscope";
    img.width = params_.width;
    img.height = params_.height;
    img.encoding = "rgb8";
    img.step = 3 * params_.width;
    renderer_.readRgb(img.data);
    renderSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    imagePub_.publish(img);

    if (!params_.pngDir.empty() && frame_ % params_.pngEvery == 0) {
      char name[64];
      std::snprintf(name, sizeof name, "/frame_%06ld.png", frame_);
      try {
        tt_render::writePng(params_.pngDir + name, params_.width, params_.height, img.data);
      } catch (const std::exception& e) {
        ROS_WARN_THROTTLE(10.0, "renderer: %s", e.what());
      }
    }
    ++frame_;
    if (frame_ % 150 == 0) {
      ROS_INFO("renderer: %ld frames, %.1f ms per frame (render + read back)", frame_,
               1e3 * renderSeconds_ / 150.0);
      renderSeconds_ = 0.0;
    }
  }

  RendererParams params_;
  tt_render::OffscreenRenderer renderer_;
  tf2_ros::Buffer tfBuffer_;
  tf2_ros::TransformListener listener_;
  tf2_ros::StaticTransformBroadcaster staticBroadcaster_;
  ros::Subscriber surfaceSub_, poseSub_, jawSub_;
  ros::Publisher imagePub_;
  ros::WallTimer timer_;

  std::vector<float> positions_, normals_;
  std::vector<std::uint32_t> triangles_;
  std::vector<tt_render::Shape> shapes_;
  bool useTf_ = false;
  Eigen::Isometry3d tipPose_ = Eigen::Isometry3d::Identity();
  bool havePose_ = false;
  double jawAngle_ = 0.0;
  long frame_ = 0;
  double renderSeconds_ = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "renderer");
  ros::NodeHandle nh, pnh("~");
  try {
    const RendererParams params = readParams(pnh);
    // Below the haptic bridge and the simulation: on a busy machine the frame rate drops, not
    // the force loop. Before the GL context exists, so llvmpipe's threads inherit it.
    if (params.nice > 0 && setpriority(PRIO_PROCESS, 0, getpriority(PRIO_PROCESS, 0) + params.nice) != 0)
      ROS_WARN("renderer: cannot lower its priority (~nice %d): %s", params.nice, std::strerror(errno));
    RendererNode node(nh, params);
    ros::spin();  // one thread: the GL context stays on it
  } catch (const tt_nodes::ParamError& e) {
    ROS_FATAL("renderer: bad parameter %s", e.what());
    return 2;
  } catch (const std::exception& e) {
    ROS_FATAL("renderer: %s", e.what());
    return 1;
  }
  return 0;
}
