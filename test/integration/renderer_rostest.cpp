// Rostest gtest node for the renderer: publishes the liver surface (liver.msh scaled 0.025)
// on /tissue/surface (triangles on the first message only) and an instrument pose on
// /instrument/measured_cp, and checks /camera/image_raw, the PNG frames and the laparoscope
// frame.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <mutex>

#include <geometry_msgs/PoseStamped.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/transform_listener.h>

#include "tissue_trainer/TissueSurface.h"
#include "tissue_trainer/core/mesh/mesh_io.h"

namespace {

namespace fs = std::filesystem;

// The largest PNG frame in dir written at or after `since` (0 bytes when there is none).
std::uintmax_t largestFrameSince(const fs::path& dir, fs::file_time_type since) {
  std::uintmax_t largest = 0;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && e.path().extension() == ".png" &&
        e.last_write_time(ec) >= since)
      largest = std::max(largest, e.file_size(ec));
  }
  return largest;
}

TEST(Renderer, PublishesTheLiverAndTheInstrument) {
  const fs::file_time_type started = fs::file_time_type::clock::now();
  ros::NodeHandle nh;
  std::mutex m;
  sensor_msgs::Image last;
  std::atomic<int> images{0};
  ros::Subscriber sub = nh.subscribe<sensor_msgs::Image>("camera/image_raw", 2,
      [&](const sensor_msgs::Image::ConstPtr& img) {
        std::lock_guard<std::mutex> l(m);
        last = *img;
        ++images;
      });
  ros::Publisher surfacePub = nh.advertise<tissue_trainer::TissueSurface>("tissue/surface", 2);
  ros::Publisher posePub = nh.advertise<geometry_msgs::PoseStamped>("instrument/measured_cp", 2);
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  while ((surfacePub.getNumSubscribers() == 0 || posePub.getNumSubscribers() == 0) &&
         ros::WallTime::now() < deadline)
    ros::WallDuration(0.05).sleep();
  ASSERT_GT(surfacePub.getNumSubscribers(), 0u);

  std::string source;
  ASSERT_TRUE(ros::param::get("~source_dir", source));
  const tt::Mesh mesh = tt::readMesh(source + "/config/meshes/liver.msh");
  tissue_trainer::TissueSurface s;
  s.header.frame_id = "world";
  for (int i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k) s.positions.push_back(static_cast<float>(0.025 * mesh.rest(k, i)));
  for (const tt::Triangle& t : mesh.surface)
    for (int k = 0; k < 3; ++k) s.triangles.push_back(static_cast<std::uint32_t>(t[k]));
  s.triangles_changed = true;
  geometry_msgs::PoseStamped pose;  // tip 2 cm in front of the liver, shaft along world -z
  pose.header.frame_id = "world";
  pose.pose.position.x = -0.035;
  pose.pose.position.y = 0.075;
  pose.pose.position.z = 0.09;
  pose.pose.orientation.y = 1.0;  // pi about y: tip +z -> world -z
  for (int i = 0; i < 40; ++i) {
    s.header.stamp = pose.header.stamp = ros::Time::now();
    s.sequence = i;
    surfacePub.publish(s);
    posePub.publish(pose);
    if (i == 0) {  // later messages carry positions only
      s.triangles.clear();
      s.triangles_changed = false;
    }
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(images, 10) << "no images on /camera/image_raw";
  sensor_msgs::Image img;
  {
    std::lock_guard<std::mutex> l(m);
    img = last;
  }
  EXPECT_EQ(img.encoding, "rgb8");
  EXPECT_EQ(img.width, 640u);
  EXPECT_EQ(img.height, 480u);
  EXPECT_EQ(img.header.frame_id, "laparoscope");
  ASSERT_EQ(img.data.size(), std::size_t(img.step) * img.height);
  int organ = 0, grey = 0;
  for (std::size_t i = 0; i + 2 < img.data.size(); i += 3) {
    const int r = img.data[i], g = img.data[i + 1], b = img.data[i + 2];
    if (r > g + 30 && r > 60) ++organ;
    if (std::abs(r - b) < 30 && r + g + b > 200) ++grey;
  }
  const int n = int(img.width * img.height);
  std::printf("[renderer] image %ux%u: liver %.1f%%, instrument %.1f%% of the pixels, %d images\n", img.width,
              img.height, 100.0 * organ / n, 100.0 * grey / n, int(images));
  EXPECT_GT(organ, n / 8);
  EXPECT_GT(grey, n / 200);
  const int corner = img.data[0] + img.data[1] + img.data[2];
  EXPECT_LT(corner, 80) << "background expected in the corner";

  std::string pngDir;
  ASSERT_TRUE(ros::param::get("/renderer/png_dir", pngDir));
  // Every 10th image is a PNG (png_every); how many images a loaded machine renders in the
  // 2 s varies, so any frame of this run counts.
  EXPECT_GT(largestFrameSince(pngDir, started), 1000u) << "no PNG frame of this run in " << pngDir;

  EXPECT_TRUE(tf.canTransform("world", "laparoscope", ros::Time(0), ros::Duration(2.0)));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "renderer_rostest");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  ros::shutdown();
  return result;
}
