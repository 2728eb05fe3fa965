#include "tissue_trainer/core/operator/task_script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/registry/yaml_file.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {
namespace {

// Largest jaw opening a task may ask for (rad); the URDF limit is the node's business.
constexpr double kMaxJaw = M_PI;

bool knownPhase(const std::string& phase) {
  const auto& all = taskPhases();
  return std::find(all.begin(), all.end(), phase) != all.end();
}

std::string phaseList() {
  std::string out;
  for (const auto& p : taskPhases()) out += (out.empty() ? "" : ", ") + p;
  return out;
}

std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// Minimum-jerk blend s(u) = 10u^3 - 15u^4 + 6u^5 and its derivative ds/du.
double blend(double u) { return u * u * u * (10.0 + u * (-15.0 + 6.0 * u)); }
double blendRate(double u) { return 30.0 * u * u * (1.0 - u) * (1.0 - u); }

}  // namespace

const std::vector<std::string>& taskPhases() {
  static const std::vector<std::string> phases = {"start",   "approach", "palpate", "grasp",
                                                  "retract", "release",  "withdraw", "hold"};
  return phases;
}

TaskScript::TaskScript(std::vector<Keyframe> keyframes, std::string name)
    : keyframes_(std::move(keyframes)), name_(std::move(name)) {
  if (keyframes_.empty()) throw std::invalid_argument("task: expected at least one keyframe");
  for (size_t i = 0; i < keyframes_.size(); ++i) {
    const Keyframe& k = keyframes_[i];
    const std::string where = "task keyframe " + std::to_string(i) + ": ";
    if (!std::isfinite(k.time) || (i == 0 && k.time != 0.0))
      throw std::invalid_argument(where + "the first keyframe must be at t = 0");
    if (i > 0 && !(k.time > keyframes_[i - 1].time))
      throw std::invalid_argument(where + "expected a time after the previous keyframe's");
    if (!knownPhase(k.phase)) throw std::invalid_argument(where + "unknown phase '" + k.phase + "'");
    if (!k.tip.allFinite()) throw std::invalid_argument(where + "non-finite tip");
    if (!(k.jaw >= 0.0 && k.jaw <= kMaxJaw))
      throw std::invalid_argument(where + "expected a jaw opening in [0, pi]");
  }
}

TaskScript TaskScript::load(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "task file");
  const YamlEntry top(root, "", &path);
  top.expectMap({"name", "description", "scene", "frame", "keyframes"});
  const std::string name = top.has("name") ? top["name"].text()
                                           : std::filesystem::path(path).stem().string();
  if (top.has("description")) top["description"].text();
  if (top.has("scene")) top["scene"].text();
  if (top.has("frame") && top["frame"].text() != "world")
    top["frame"].fail("expected 'world' (keyframe tips are world positions)");
  const YamlEntry list = top["keyframes"];
  if (list.size() == 0) list.fail("expected at least one keyframe");
  std::vector<Keyframe> keyframes;
  for (size_t i = 0; i < list.size(); ++i) {
    const YamlEntry e = list[static_cast<int>(i)];
    e.expectMap({"t", "phase", "tip", "jaw", "note"});
    Keyframe k;
    const YamlEntry t = e["t"];
    k.time = t.number();
    if (i == 0 && k.time != 0.0) t.fail("expected 0 (the task starts at its first keyframe)");
    if (i > 0 && !(k.time > keyframes.back().time))
      t.fail("expected a time after the previous keyframe's (" + shortNumber(keyframes.back().time) + " s)");
    const YamlEntry phase = e["phase"];
    k.phase = phase.text();
    if (!knownPhase(k.phase)) phase.fail("expected one of: " + phaseList() + "; got '" + k.phase + "'");
    k.tip = e["tip"].vector3();
    if (e.has("jaw")) {
      k.jaw = e["jaw"].number();
      if (k.jaw < 0.0 || k.jaw > kMaxJaw) e["jaw"].fail("expected an opening angle in [0, 3.14159] rad");
    } else {
      k.jaw = keyframes.empty() ? 0.0 : keyframes.back().jaw;  // unchanged from the previous
    }
    if (e.has("note")) e["note"].text();
    keyframes.push_back(k);
  }
  return TaskScript(std::move(keyframes), name);
}

const Keyframe* TaskScript::find(const std::string& phase) const {
  for (const Keyframe& k : keyframes_)
    if (k.phase == phase) return &k;
  return nullptr;
}

TaskSample TaskScript::sample(double t) const {
  TaskSample s;
  s.tipVelocity.setZero();
  if (!(t > 0.0) || keyframes_.size() == 1) {  // before the start (or NaN): the first keyframe
    const Keyframe& k = keyframes_.front();
    s.tip = k.tip;
    s.jaw = k.jaw;
    s.phase = &k.phase;
    s.finished = keyframes_.size() == 1 && t >= 0.0;
    return s;
  }
  if (t >= duration()) {
    const Keyframe& k = keyframes_.back();
    s.tip = k.tip;
    s.jaw = k.jaw;
    s.phase = &k.phase;
    s.finished = true;
    return s;
  }
  // The segment [a, b] holding t.
  const auto next = std::upper_bound(keyframes_.begin(), keyframes_.end(), t,
                                     [](double v, const Keyframe& k) { return v < k.time; });
  const Keyframe& b = *next;
  const Keyframe& a = *(next - 1);
  const double span = b.time - a.time;
  const double u = (t - a.time) / span;
  const double w = blend(u);
  s.tip = a.tip + w * (b.tip - a.tip);
  s.tipVelocity = blendRate(u) / span * (b.tip - a.tip);
  s.jaw = a.jaw + w * (b.jaw - a.jaw);
  s.phase = &b.phase;
  return s;
}

}  // namespace tt
