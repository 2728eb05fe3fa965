// bench_scene_parts [--quick] [SCENE.yaml] [--frames N=300] (--quick: 10 frames): what each
// part of a scene costs per frame, to measure what "the simulation builds only what the scene
// lists" saves. Copies of the scene (each loaded from the file, so all start from the same
// state) advance frame by frame in turn, the order of the copies reversed every other frame; each copy lacks one part or adds
// one per-frame task of the simulation node:
//   frame            the scene as listed: its integrator's advance (with the stability guard
//                    unless the scene turns it off)
//   gravity          without: the gravity model removed from System::models
//   damping          without: System::damping zeroed (rayleigh_mass, node_damping)
//   stability guard  without: tt::unguarded(integrator)
//   render surface   with: the frame plus the embedding applied to the deformed nodes
//                    (tt::DisplaySurface::positions, as the simulation node does each frame)
//   contact          with: the frame plus TissueContact::setTool + update() with the grasper
//                    at the trocar, jaws open, far from the tissue (no contact arises)
//   same frame twice a second copy of the listed frame: the noise floor of the comparison
// Time: CPU time of the process (one thread) per frame; median and p90 over the frames.
// A part the scene does not list is checked to be absent (removing it removes nothing).
// Prints the final-state differences of the copies whose physics is that of the listed frame
// (they must be bit-identical while the guard does not step in) and of those whose physics
// differs. Exit 2 on bad input, 3 when a frame of the listed scene fails.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

constexpr const char* kTool = "bench_scene_parts";
constexpr const char* kDefaultScene = "config/scenes/liver_palpation.yaml";
constexpr int kDefaultFrames = 300;

struct Options {
  std::string scene = kDefaultScene;
  int frames = kDefaultFrames;
};

Options parseOptions(int argc, char** argv) {
  tt::tools::CommandLine command(argc, argv,
                                 "bench_scene_parts [--quick] [SCENE.yaml] [--frames N]");
  Options o;
  const bool quick = command.flag("--quick");
  o.frames = command.positiveInteger("--frames", quick ? 10 : kDefaultFrames);
  const std::vector<std::string> scene = command.positional(1);
  if (!scene.empty()) o.scene = scene.front();
  command.finish();
  return o;
}

// --- the instrument ----------------------------------------------------------------------

// The collision shapes of config/instruments/grasper.urdf: the shaft (cylinder behind the
// tip) and the two jaws (boxes), in their link frames.
std::vector<tt::ToolShape> grasperShapes() {
  tt::ToolShape shaft;
  shaft.type = tt::ToolShape::Type::kCylinder;
  shaft.radius = 0.0025;
  shaft.length = 0.30;
  shaft.offset = Eigen::Translation3d(0.0, 0.0, -0.15);
  shaft.link = "shaft";
  std::vector<tt::ToolShape> shapes{shaft};
  for (const double side : {1.0, -1.0}) {
    tt::ToolShape jaw;
    jaw.type = tt::ToolShape::Type::kBox;
    jaw.size = Eigen::Vector3d(0.004, 0.0016, 0.018);
    jaw.offset = Eigen::Translation3d(0.0, side * 0.0008, 0.009);
    jaw.link = side > 0.0 ? "jaw_upper" : "jaw_lower";
    jaw.jaw = true;
    shapes.push_back(jaw);
  }
  return shapes;
}

// The grasper at zero joints: the tip at the trocar (-0.035, 0.075, 0.20), the shaft along
// world -z (the trocar frame is world turned by pi about y), the jaws open.
struct ToolPose {
  Eigen::Isometry3d tip = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> links;  // shaft, upper jaw, lower jaw
  double jawAngle = 0.5;                 // rad: open (the default grasp_jaw_angle is 0.1)
};

ToolPose grasperAtTrocar() {
  ToolPose pose;
  pose.tip = Eigen::Translation3d(-0.035, 0.075, 0.20) *
             Eigen::AngleAxisd(EIGEN_PI, Eigen::Vector3d::UnitY());
  const double half = 0.5 * pose.jawAngle;
  pose.links = {pose.tip, pose.tip * Eigen::AngleAxisd(half, -Eigen::Vector3d::UnitX()),
                pose.tip * Eigen::AngleAxisd(half, Eigen::Vector3d::UnitX())};
  return pose;
}

// Distance from the tip to the nearest node (m).
double clearance(const tt::System& system, const Eigen::Vector3d& tip) {
  double nearest = INFINITY;
  for (int a = 0; a < system.numNodes(); ++a)
    nearest = std::min(nearest, (system.state.x.segment<3>(3 * a) - tip).norm());
  return nearest;
}

// --- the copies ---------------------------------------------------------------------------

struct Copy {
  std::string label;
  tt::Scene scene;
  tt::Integrator* integrator = nullptr;
  std::unique_ptr<tt::TissueContact> contact;  // declared after scene: destroyed before it
  std::optional<tt::DisplaySurface> surface;
  Eigen::Matrix3Xd surfacePositions;
  ToolPose tool;
  std::vector<double> frameSeconds;
  long linearIterations = 0;
  int recovered = 0;     // frames the guard redid (halvings > 0)
  int contactFrames = 0; // frames in which the contact query found contact
  std::string failure;   // the first failed frame
};

using Copies = std::vector<std::unique_ptr<Copy>>;

std::unique_ptr<Copy> loadCopy(const std::string& label, const std::string& file) {
  auto copy = std::make_unique<Copy>();
  copy->label = label;
  copy->scene = tt::loadScene(file);
  copy->integrator = copy->scene.integrator.get();
  return copy;
}

bool isGravity(const tt::ForceModel& m) {
  return m.isBodyLoad() && std::string(m.name()) == "gravity";
}

bool hasModel(const tt::System& system, const std::string& name) {
  return std::any_of(system.models.begin(), system.models.end(),
                     [&](const auto& m) { return name == m->name(); });
}

// Returns how many models were removed.
int removeGravity(tt::System& system) {
  const size_t before = system.models.size();
  auto& models = system.models;
  models.erase(std::remove_if(models.begin(), models.end(),
                              [](const auto& m) { return isGravity(*m); }),
               models.end());
  return static_cast<int>(before - models.size());
}

void addContact(Copy& copy) {
  copy.contact = std::make_unique<tt::TissueContact>(copy.scene.system, *copy.scene.contact,
                                                     grasperShapes());
  copy.tool = grasperAtTrocar();
}

void addSurface(Copy& copy) {
  copy.surface.emplace(copy.scene);
  copy.surface->positions(copy.scene.system.state.x, copy.surfacePositions);
}

// One frame of a copy: its per-frame task (contact query, surface mapping) and the advance.
void frameOf(Copy& copy) {
  tt::System& system = copy.scene.system;
  if (copy.contact) {
    copy.contact->setTool(copy.tool.tip, copy.tool.links, copy.tool.jawAngle, system.state.t);
    if (copy.contact->update().inContact) ++copy.contactFrames;
  }
  const tt::StepReport report = copy.integrator->advance(system, copy.scene.frameTime);
  if (copy.surface) copy.surface->positions(system.state.x, copy.surfacePositions);
  copy.linearIterations += report.linearIterations;
  const tt::StabilityGuard* guard = tt::guardOf(*copy.integrator);
  if (guard && guard->lastFrame().halvings > 0) ++copy.recovered;
  if (!report.ok && copy.failure.empty()) copy.failure = report.failure;
}

void timedFrame(Copy& copy) {
  const double start = tt::bench::cpuSeconds();
  frameOf(copy);
  copy.frameSeconds.push_back(tt::bench::cpuSeconds() - start);
}

// All copies advance `frames` frames, one frame each in turn, the order reversed every other
// frame.
void runInterleaved(Copies& copies, int frames) {
  for (auto& c : copies) c->frameSeconds.reserve(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    if (f % 2 == 0)
      for (auto& c : copies) timedFrame(*c);
    else
      for (auto it = copies.rbegin(); it != copies.rend(); ++it) timedFrame(**it);
  }
}

// --- the report ---------------------------------------------------------------------------

double percentile90(std::vector<double> v) {
  const size_t k = static_cast<size_t>(std::ceil(0.9 * static_cast<double>(v.size()))) - 1;
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

struct Timing {
  double median = 0.0, p90 = 0.0;  // s
  double iterations = 0.0;         // linear iterations per frame
};

Timing timingOf(const Copy& c) {
  const double frames = static_cast<double>(c.frameSeconds.size());
  return {tt::bench::median(c.frameSeconds), percentile90(c.frameSeconds),
          static_cast<double>(c.linearIterations) / frames};
}


// --- what the table compares ----------------------------------------------------------------

// One line of the table: the copy with the part and the copy without it (both null when the
// scene does not list the part and there is nothing to time).
struct Part {
  const char* name = "";
  bool listed = false;
  Copy* with = nullptr;
  Copy* without = nullptr;
  bool samePhysics = true;  // the two must end in the same state
  std::string note;
};

struct Plan {
  Copies copies;  // copies[0] is the frame as listed
  std::vector<Part> parts;
  Copy& listed() { return *copies.front(); }
  const Copy& listed() const { return *copies.front(); }
};

Copy& addCopy(Plan& plan, const std::string& label, const std::string& file) {
  plan.copies.push_back(loadCopy(label, file));
  return *plan.copies.back();
}

void planGravity(Plan& plan, const std::string& file) {
  const tt::System& listed = plan.listed().scene.system;
  const bool isListed = std::any_of(listed.models.begin(), listed.models.end(),
                                    [](const auto& m) { return isGravity(*m); });
  Copy& without = addCopy(plan, "without gravity", file);
  const int removed = removeGravity(without.scene.system);
  std::string note = "without: the gravity model removed from System::models";
  if (!isListed)
    note = removed == 0 ? "not listed: no gravity model, removing it removed nothing"
                        : "not listed, yet a gravity model was there";
  plan.parts.push_back({"gravity", isListed, &plan.listed(), &without, !isListed, note});
}

void planDamping(Plan& plan, const std::string& file) {
  const bool isListed = (plan.listed().scene.system.damping.array() != 0.0).any();
  Copy& without = addCopy(plan, "without damping", file);
  without.scene.system.damping.setZero();
  const std::string note =
      isListed ? "without: System::damping zeroed (f = -c .* v is still computed)"
               : "not listed: System::damping is zero already (f = -c .* v is still computed)";
  plan.parts.push_back({"damping", isListed, &plan.listed(), &without, !isListed, note});
}

void planGuard(Plan& plan, const std::string& file) {
  tt::Integrator* listed = plan.listed().integrator;
  const bool isListed = &tt::unguarded(*listed) != listed;
  Copy& without = addCopy(plan, "without guard", file);
  without.integrator = &tt::unguarded(*without.scene.integrator);
  const std::string note = isListed ? "without: tt::unguarded(integrator)"
                                    : "not listed (enabled: false): unguarded() is the integrator itself";
  plan.parts.push_back({"stability guard", isListed, &plan.listed(), &without, true, note});
}

void planSurface(Plan& plan, const std::string& file) {
  if (!plan.listed().scene.renderSurface) {
    plan.parts.push_back({"render surface", false, nullptr, nullptr, true,
                          "not listed: Scene::renderSurface empty, no embedding built"});
    return;
  }
  Copy& with = addCopy(plan, "with render surface", file);
  addSurface(with);
  const std::string note = "with: the embedding applied to the deformed nodes, " +
                           std::to_string(with.surfacePositions.cols()) + " vertices";
  plan.parts.push_back({"render surface", true, &with, &plan.listed(), true, note});
}

void planContact(Plan& plan, const std::string& file) {
  const Copy& listed = plan.listed();
  if (!listed.scene.contact) {
    const bool present = hasModel(listed.scene.system, "contact");
    plan.parts.push_back({"contact", false, nullptr, nullptr, true,
                          present ? "not listed, yet a contact model was there"
                                  : "not listed: no contact settings, no contact model"});
    return;
  }
  Copy& with = addCopy(plan, "with contact", file);
  addContact(with);
  char note[160];
  std::snprintf(note, sizeof note,
                "with: TissueContact setTool + update(), grasper tip %.1f cm from the nearest node",
                100.0 * clearance(with.scene.system, with.tool.tip.translation()));
  plan.parts.push_back({"contact", true, &with, &plan.listed(), true, note});
}

void planNoise(Plan& plan, const std::string& file) {
  Copy& twice = addCopy(plan, "same frame twice", file);
  plan.parts.push_back({"same frame twice", true, &plan.listed(), &twice, true,
                        "a second copy of the listed frame: the noise of the comparison"});
}

Plan makePlan(const std::string& file) {
  Plan plan;
  plan.copies.push_back(loadCopy("frame", file));
  planGravity(plan, file);
  planDamping(plan, file);
  planGuard(plan, file);
  planSurface(plan, file);
  planContact(plan, file);
  planNoise(plan, file);
  return plan;
}

// --- the report -----------------------------------------------------------------------------

void printHeader(const Plan& plan, const Options& o) {
  const Copy& listed = plan.listed();
  const tt::System& s = listed.scene.system;
  std::printf("%s %s (%s): %d tets, %d nodes, %s, frame %g s, %d frames, %zu copies "
              "interleaved (order reversed every other frame)\n",
              kTool, listed.scene.name.c_str(), o.scene.c_str(), s.mesh.numTets(), s.numNodes(),
              listed.integrator->name(), listed.scene.frameTime, o.frames, plan.copies.size());
  std::printf("time per frame: CPU time of the process (1 thread), ms, median / p90; "
              "CG: linear iterations per frame\n");
  std::printf("  %-17s %-6s %-19s %-19s %-9s  %-8s  %-13s %s\n", "part", "listed",
              "with (med / p90)", "without (med / p90)", "diff", "% frame", "CG with / w/o",
              "what");
}

void printFrameRow(const Copy& listed) {
  const Timing t = timingOf(listed);
  std::printf("  %-17s %-6s %7.3f / %-9.3f %-19s %-9s  %-8s  %5.1f         %s\n",
              "frame (as listed)", "yes", 1e3 * t.median, 1e3 * t.p90, "-", "-", "-",
              t.iterations, "the integrator's advance");
}

void printPart(const Part& p, double listedMedian) {
  const char* listed = p.listed ? "yes" : "no";
  if (!p.with) {
    std::printf("  %-17s %-6s %-19s %-19s %-9s  %-8s  %-13s %s\n", p.name, listed, "-", "-",
                "-", "-", "-", p.note.c_str());
    return;
  }
  const Timing a = timingOf(*p.with), b = timingOf(*p.without);
  const double diff = a.median - b.median;
  std::printf("  %-17s %-6s %7.3f / %-9.3f %7.3f / %-9.3f %+9.3f  %+7.1f%%  %5.1f / %-5.1f %s\n",
              p.name, listed, 1e3 * a.median, 1e3 * a.p90, 1e3 * b.median, 1e3 * b.p90,
              1e3 * diff, 100.0 * diff / listedMedian, a.iterations, b.iterations,
              p.note.c_str());
}

void printFinalState(const Part& p) {
  if (!p.with) return;
  const tt::State& a = p.with->scene.system.state;
  const tt::State& b = p.without->scene.system.state;
  const double dx = (a.x - b.x).cwiseAbs().maxCoeff(), dv = (a.v - b.v).cwiseAbs().maxCoeff();
  const bool identical = a.x == b.x && a.v == b.v && a.t == b.t;
  const char* verdict = identical          ? "bit-identical"
                        : p.samePhysics    ? "DIFFER (expected bit-identical)"
                                           : "differ (the physics differs)";
  std::printf("  %-17s %-32s max |dx| %.3e m, max |dv| %.3e m/s\n", p.name, verdict, dx, dv);
}

// Notes on what could spoil the comparison; returns false when the listed frame failed.
bool printNotes(const Plan& plan) {
  for (const auto& c : plan.copies) {
    if (!c->failure.empty()) std::printf("note: %s: a frame failed: %s\n", c->label.c_str(), c->failure.c_str());
    if (c->recovered > 0)
      std::printf("note: %s: the guard redid %d frames (guard on/off need not agree)\n",
                  c->label.c_str(), c->recovered);
    if (c->contactFrames > 0)
      std::printf("note: %s: the instrument touched the tissue in %d frames\n", c->label.c_str(),
                  c->contactFrames);
  }
  return plan.copies.front()->failure.empty();
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  tt::setThreadCount(1);
  Plan plan;
  try {
    plan = makePlan(options.scene);
  } catch (const tt::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  runInterleaved(plan.copies, options.frames);

  printHeader(plan, options);
  printFrameRow(plan.listed());
  const double listedMedian = timingOf(plan.listed()).median;
  for (const Part& p : plan.parts) printPart(p, listedMedian);
  std::printf("final states after %d frames, with against without:\n", options.frames);
  for (const Part& p : plan.parts) printFinalState(p);
  return printNotes(plan) ? 0 : 3;
}
