// tissue_cli: the command-line face of the core. Its output is a contract other checks rely
// on (docs/cli.md). Exit codes: 0 ok, 2 bad input or usage, 3 the simulation
// failed (non-finite state or no convergence), 4 a landmark fit stopped without converging,
// 5 `run` was interrupted (SIGINT, SIGTERM).
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/specimen_loading.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/mesh_order.h"
#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace {

constexpr int kOk = 0, kBadInput = 2, kRunFailed = 3, kFitNotConverged = 4, kInterrupted = 5;

// Set by SIGINT or SIGTERM during `run`: the run ends after the frame in progress. The
// handler then steps aside, so a second signal ends the process at once (a frame that hangs).
volatile std::sig_atomic_t interruptSignal = 0;

extern "C" void requestInterrupt(int signal) {
  interruptSignal = signal;
  std::signal(signal, SIG_DFL);
}

void catchInterrupts() {
  std::signal(SIGINT, requestInterrupt);
  std::signal(SIGTERM, requestInterrupt);
}

const char* const kUsage =
    "usage:\n"
    "  tissue_cli info MESH | SCENE.yaml   (a scene adds shortest_edge, wave_speed, critical_step)\n"
    "  tissue_cli convert IN OUT            (OUT: .vtu, .msh (Gmsh v2), .vtk, .node/.ele (TetGen))\n"
    "  tissue_cli run SCENE.yaml [--duration T] [--out DIR] [--threads N]\n"
    "                                       (N: threads of the element loops, default: the cores;\n"
    "                                        SIGINT/SIGTERM end it after the frame, exit code 5)\n"
    "  tissue_cli forces --mesh MESH --deformed POSITIONS --model NAME --lambda L --mu M\n"
    "                    [--lambda-l LL --mu-l ML --fiber X Y Z] [--stiffness-times DIR]\n"
    "  tissue_cli forces --mesh MESH --deformed POSITIONS --model teran_muscle --mooney-rivlin A B\n"
    "                    --bulk K --peak-stress SIGMA_MAX --activation ALPHA --fiber X Y Z\n"
    "                    --fiber-stretch deviatoric|nondeviatoric [--inversion-threshold EPS]\n"
    "                    [--psd [--psd-method eigen|diagonal_blocks]] [--stiffness-times DIR]\n"
    "  tissue_cli forces --scene SCENE.yaml --deformed POSITIONS [--stiffness-times DIR]\n"
    "  tissue_cli stretch SCENE.yaml --axis x|y|z --max-strain S --steps N [--out FILE.csv]\n"
    "  tissue_cli shear SCENE.yaml --plane-normal x|y|z --direction x|y|z --max-shear G\n"
    "                   --steps N [--out FILE.csv]\n"
    "                                       (quasi-static stretch and simple shear of the scene's\n"
    "                                        specimen; CSV strain,stretch,force_N,stress_Pa or\n"
    "                                        shear,work_J,energy_J)\n"
    "  tissue_cli fit SCENE.yaml --targets FILE [--out DIR] [--max-iterations N] [--tolerance R]\n"
    "                 [--step-tolerance S] [--levenberg-marquardt LAMBDA] [--cranium]\n"
    "                 [--jaw | --jaw-box XMIN YMIN ZMIN XMAX YMAX ZMAX] [--orthogonality-weight W]\n"
    "                                       (landmark fit of the activations, jaw and cranium;\n"
    "                                        exit 4 when it stops without converging)\n"
    "  tissue_cli models                    (every registered force model, law and integrator)\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Options of the form --name value [value ...]; positional arguments kept in order.
struct Arguments {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> options;

  Arguments(int argc, char** argv, int first, const std::map<std::string, int>& arity) {
    for (int i = first; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg.rfind("--", 0) != 0) {
        positional.push_back(arg);
        continue;
      }
      const auto known = arity.find(arg.substr(2));
      if (known == arity.end()) throw UsageError("unknown option " + arg);
      if (options.count(known->first)) throw UsageError(arg + " given more than once");
      std::vector<std::string>& values = options[known->first];
      for (int k = 0; k < known->second; ++k) {
        if (++i >= argc) throw UsageError(arg + " expects " + std::to_string(known->second) + " value(s)");
        values.push_back(argv[i]);
      }
    }
  }
  bool has(const std::string& name) const { return options.count(name) > 0; }
  const std::string& text(const std::string& name) const {
    const auto it = options.find(name);
    if (it == options.end()) throw UsageError("missing --" + name);
    return it->second.front();
  }
  double number(const std::string& name, size_t index = 0) const {
    const auto it = options.find(name);
    if (it == options.end()) throw UsageError("missing --" + name);
    return parseNumber("--" + name, it->second.at(index));
  }
  static double parseNumber(const std::string& what, const std::string& text) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(value))
      throw UsageError(what + " expects a finite number, got '" + text + "'");
    return value;
  }
};

bool isScene(const std::string& path) {
  const auto endsWith = [&](const char* suffix) {
    const size_t n = std::strlen(suffix);
    return path.size() >= n && path.compare(path.size() - n, n, suffix) == 0;
  };
  return endsWith(".yaml") || endsWith(".yml");
}

// Speed of the longitudinal (P) wave, sqrt((lambda + 2 mu) / rho), with the larger of the
// transverse and the fibre pair (m/s); 0 for a material without Lame constants (its law reads
// others, e.g. hunter).
double pWaveSpeed(const tt::Material& m) {
  if (!m.elastic) return 0.0;
  const tt::ElasticConstants& k = *m.elastic;
  return std::sqrt(std::max(k.lambda + 2.0 * k.mu, k.lambdaL + 2.0 * k.muL) / m.density);
}

// The scene's placed mesh, then the critical step of "Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.5.6: h_c = L / c (Eq. 2.150), L the shortest element edge and c
// the fastest P-wave speed of the scene's materials.
int infoOfScene(const std::string& path) {
  const tt::Scene scene = tt::loadScene(path);
  const tt::System& s = scene.system;
  std::cout << "scene " << scene.name << " (" << path << ")\n";
  for (const auto& note : scene.notes) std::cout << "note " << note << "\n";
  std::cout << tt::formatQuality(tt::meshQuality(s.mesh));
  const double edge = tt::shortestEdge(s.mesh);
  int fastest = 0;
  for (int m = 1; m < static_cast<int>(s.materials.size()); ++m)
    if (pWaveSpeed(s.materials[m]) > pWaveSpeed(s.materials[fastest])) fastest = m;
  const double c = s.materials.empty() ? 0.0 : pWaveSpeed(s.materials[fastest]);
  std::printf("shortest_edge %.6g m\n", edge);
  std::printf("wave_speed %.6g m/s (P-wave sqrt((lambda + 2 mu) / rho), the fastest material: "
              "%d)\n", c, fastest);
  std::printf("critical_step %.6g s (h_c = L / c, Eq. 2.150)\n", edge / c);
  return kOk;
}

int info(const Arguments& args) {
  if (args.positional.size() != 1) throw UsageError("info expects one MESH or SCENE.yaml");
  if (isScene(args.positional[0])) return infoOfScene(args.positional[0]);
  tt::ReadNotes notes;
  tt::Mesh mesh = tt::readMesh(args.positional[0], &notes);
  std::cout << "mesh " << args.positional[0] << "\n";
  for (const auto& line : notes.lines) std::cout << "note " << line << "\n";
  std::cout << tt::formatQuality(tt::meshQuality(mesh));
  return kOk;
}

int convert(const Arguments& args) {
  if (args.positional.size() != 2) throw UsageError("convert expects IN and OUT");
  const std::string& out = args.positional[1];
  const tt::Mesh mesh = tt::readMesh(args.positional[0]);
  try {
    tt::writeMesh(out, mesh);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("convert: ") + e.what());
  }
  std::cout << "wrote " << out << " (" << mesh.numNodes() << " nodes, " << mesh.numTets()
            << " tets)\n";
  return kOk;
}

int threadCount(const Arguments& args) {
  const double n = args.number("threads");
  if (n < 1 || n > tt::kMaxThreads || n != std::floor(n))
    throw UsageError("--threads expects a whole number in [1, " + std::to_string(tt::kMaxThreads) +
                     "], got '" + args.text("threads") + "'");
  return static_cast<int>(n);
}

int run(const Arguments& args) {
  if (args.positional.size() != 1) throw UsageError("run expects one SCENE.yaml");
  tt::Scene scene = tt::loadScene(args.positional[0]);
  tt::RunOptions options;
  if (args.has("duration")) {
    options.duration = args.number("duration");
    if (options.duration <= 0.0) throw UsageError("--duration expects a positive time");
  }
  if (args.has("out")) options.outDir = args.text("out");
  tt::setThreadCount(args.has("threads") ? threadCount(args) : tt::hardwareThreads());
  for (const auto& note : scene.notes) std::cout << "note " << note << "\n";
  const tt::System& s = scene.system;
  std::cout << "scene " << scene.name << ": " << s.numNodes() << " nodes, " << s.mesh.numTets()
            << " tets, " << s.constrainedDofs.size() << " constrained DOFs, models:";
  for (const auto& m : s.models) std::cout << " " << m->name();
  std::cout << ", integrator: " << scene.integrator->name();
  if (const auto* guard = dynamic_cast<const tt::StabilityGuard*>(scene.integrator.get()))
    std::printf(", stability guard: max_halvings=%d energy_growth=%g min_volume_ratio=%g",
                guard->params().maxHalvings, guard->params().energyGrowth,
                guard->params().minVolumeRatio);
  std::cout << "\n";
  const double duration = options.duration >= 0 ? options.duration : scene.duration;
  const int total = static_cast<int>(std::ceil(duration / scene.frameTime - 1e-9));
  const int every = std::max(1, total / 10);
  options.onFrame = [&](const tt::FrameLog& f) {
    if (f.frame % every == 0 || f.frame == total || !f.step.ok)
      std::printf("frame %d/%d t=%.4f s  kinetic=%.4g J  elastic=%.4g J  volume=%.5f  "
                  "max_disp=%.4g m  step=%.3g ms\n",
                  f.frame, total, f.time, f.kineticEnergy, f.elasticEnergy, f.volumeRatio,
                  f.maxDisplacement, 1e3 * f.step.wallSeconds);
    if (f.step.ok && !f.guard.reason.empty())
      std::printf("frame %d: guard recovered with %d halvings from: %s\n", f.frame,
                  f.guard.halvings, f.guard.reason.c_str());
  };
  options.stopRequested = [] { return interruptSignal != 0; };
  const tt::RunSummary summary = tt::runScene(scene, options);
  if (summary.stop == tt::StopReason::kKineticEnergy)
    std::printf("stopped at t=%.6g s: kinetic energy %.6g J below stop_kinetic_energy %.6g J\n",
                summary.simulatedTime, summary.last.kineticEnergy, scene.kineticEnergyStop->below);
  if (summary.stop == tt::StopReason::kInterrupt)
    std::printf("stopped at t=%.6g s: interrupted by %s\n", summary.simulatedTime,
                interruptSignal == SIGTERM ? "SIGTERM" : "SIGINT");
  std::printf("summary frames=%d simulated=%.4f s wall=%.3f s real_time_factor=%.3g "
              "step_median=%.3g ms step_max=%.3g ms stop=%s\n",
              summary.frames, summary.simulatedTime, summary.wallSeconds,
              summary.simulatedTime / std::max(summary.wallSeconds, 1e-12),
              1e3 * summary.stepWallMedian, 1e3 * summary.stepWallMax,
              tt::stopReasonName(summary.stop));
  if (summary.guard.frames > 0)
    std::printf("guard frames=%ld recoveries=%ld halvings=%ld failures=%ld\n",
                summary.guard.frames, summary.guard.recoveries, summary.guard.halvings,
                summary.guard.failures);
  if (!summary.files.empty())
    std::cout << "files " << summary.files.size() << " in " << options.outDir << "\n";
  if (!summary.ok) {
    std::cerr << args.positional[0] << ": simulation failed at " << summary.failure << "\n";
    return kRunFailed;
  }
  return summary.stop == tt::StopReason::kInterrupt ? kInterrupted : kOk;
}

// One `x y z` line per node (blank lines and lines starting with # skipped); `what` names
// the content in errors ("positions", "direction").
Eigen::VectorXd readNodeVectors(const std::string& path, int numNodes, const char* what) {
  std::ifstream in(path);
  if (!in) throw tt::InputError(path, 0, std::string("cannot open the ") + what + " file");
  Eigen::VectorXd x(3 * numNodes);
  std::string line;
  int node = 0;
  long lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::istringstream fields(line);
    std::string first;
    if (!(fields >> first) || first[0] == '#') continue;
    if (node >= numNodes)
      throw tt::InputError(path, lineNumber, "expected " + std::to_string(numNodes) +
                                                 " lines (one per mesh node), found more");
    std::string tokens[3] = {first, "", ""};
    fields >> tokens[1] >> tokens[2];
    std::string extra;
    if (tokens[2].empty() || (fields >> extra))
      throw tt::InputError(path, lineNumber, "expected 3 numbers 'x y z'");
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const double v = std::strtod(tokens[k].c_str(), &end);
      if (*end != '\0' || !std::isfinite(v))
        throw tt::InputError(path, lineNumber, "expected a finite number, got '" + tokens[k] + "'");
      x[3 * node + k] = v;
    }
    ++node;
  }
  if (node != numNodes)
    throw tt::InputError(path, lineNumber, "expected " + std::to_string(numNodes) +
                                               " lines (one per mesh node), found " + std::to_string(node));
  return x;
}

// The output contract of `forces`: energy, one force line per node and, when d is given, the
// line `stiffness_times` and one line of H d per node, H = d2E/dx2 = -df/dx. Each model gives
// its stiffness-times-vector product where it has one, else its assembled stiffness times d.
int printForces(const std::vector<const tt::ForceModel*>& models, const tt::SparsePattern& pattern,
                const Eigen::VectorXd& x, const Eigen::VectorXd* d,
                const tt::FileNumbering& numbering) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd f = zero;
  double energy = 0.0;
  for (const tt::ForceModel* m : models) energy += m->addForce(x, zero, f);
  Eigen::VectorXd Hd = zero;
  if (d) {
    for (const tt::ForceModel* m : models) {
      if (m->hasStiffnessProduct()) {
        m->addStiffnessTimes(x, *d, -1.0, Hd);
      } else if (m->hasStiffness()) {
        tt::SparseMatrix K = pattern.zeroMatrix();
        m->addStiffness(x, -1.0, pattern, K);
        Hd += K * *d;
      } else {
        throw UsageError(std::string("--stiffness-times: force model ") + m->name() +
                         " provides no stiffness");
      }
    }
  }
  std::printf("energy %.17g\n", energy);
  const auto printRows = [&numbering](const Eigen::VectorXd& v) {
    const Eigen::VectorXd rows = tt::nodeValuesToFile(numbering, v);
    for (Eigen::Index i = 0; i < rows.size() / 3; ++i)
      std::printf("%.17g %.17g %.17g\n", rows[3 * i], rows[3 * i + 1], rows[3 * i + 2]);
  };
  printRows(f);
  if (d) {
    std::printf("stiffness_times\n");
    printRows(Hd);
  }
  return kOk;
}

// printForces at the --deformed positions, with the --stiffness-times direction when given;
// both files and the printed rows in the mesh file's node order (a scene's mesh.numbering).
int printForcesAt(const Arguments& args, const std::vector<const tt::ForceModel*>& models,
                  const tt::SparsePattern& pattern, int numNodes,
                  const tt::FileNumbering& numbering = {}) {
  const Eigen::VectorXd x =
      tt::nodeValuesFromFile(numbering, readNodeVectors(args.text("deformed"), numNodes, "positions"));
  if (!args.has("stiffness-times")) return printForces(models, pattern, x, nullptr, numbering);
  const Eigen::VectorXd d = tt::nodeValuesFromFile(
      numbering, readNodeVectors(args.text("stiffness-times"), numNodes, "direction"));
  return printForces(models, pattern, x, &d, numbering);
}

// The scene's elastic force models (its `force_models`; body loads such as gravity are left
// out) on its placed mesh.
int forcesOfScene(const Arguments& args) {
  for (const char* flag : {"mesh", "model", "lambda", "mu", "lambda-l", "mu-l", "fiber"})
    if (args.has(flag))
      throw UsageError(std::string("--") + flag + " belongs to the --mesh form, not to --scene");
  const tt::Scene scene = tt::loadScene(args.text("scene"));
  const tt::System& s = scene.system;
  std::vector<const tt::ForceModel*> models;
  for (const auto& m : s.models)
    if (!m->isBodyLoad()) models.push_back(m.get());
  return printForcesAt(args, models, s.pattern, s.numNodes(), s.mesh.numbering);
}

// The flags of the muscle law; the other flag-form models take none of them.
const char* const kMuscleFlags[] = {"mooney-rivlin", "bulk", "peak-stress", "activation",
                                    "fiber-stretch", "inversion-threshold", "psd",
                                    "psd-method"};

double nonNegativeFlag(const Arguments& args, const std::string& name, size_t index = 0) {
  const double v = args.number(name, index);
  if (!(v >= 0.0)) throw UsageError("--" + name + " expects a value >= 0, got '" +
                                    args.options.at(name).at(index) + "'");
  return v;
}

// `forces --model teran_muscle`: the law's constants and options from the flags (Pa), one
// fibre direction for every tet.
int forcesOfMuscle(const Arguments& args, tt::Mesh& mesh) {
  for (const char* flag : {"lambda", "mu", "lambda-l", "mu-l"})
    if (args.has(flag))
      throw UsageError(std::string("--") + flag + " does not apply to --model teran_muscle");
  if (!args.has("fiber")) throw UsageError("missing --fiber (teran_muscle needs a fibre direction)");
  tt::TeranMuscleLaw::Constants k;
  k.A = nonNegativeFlag(args, "mooney-rivlin", 0);
  k.B = nonNegativeFlag(args, "mooney-rivlin", 1);
  k.K = nonNegativeFlag(args, "bulk");
  k.sigmaMax = nonNegativeFlag(args, "peak-stress");
  k.activation = args.number("activation");
  if (!(k.activation >= 0.0 && k.activation <= 1.0))
    throw UsageError("--activation expects a value in [0, 1], got '" + args.text("activation") + "'");
  const std::string& stretch = args.text("fiber-stretch");
  if (stretch != "deviatoric" && stretch != "nondeviatoric")
    throw UsageError("--fiber-stretch expects deviatoric or nondeviatoric, got '" + stretch + "'");
  k.deviatoricStretch = stretch == "deviatoric";
  tt::LawOptions options;
  options.inversionThreshold = 0.25;  // PhysBAM's default
  if (args.has("inversion-threshold")) {
    options.inversionThreshold = args.number("inversion-threshold");
    if (!(options.inversionThreshold >= 0.0 && options.inversionThreshold < 1.0))
      throw UsageError("--inversion-threshold expects a value in [0, 1) (0 turns it off), got '" +
                       args.text("inversion-threshold") + "'");
  }
  options.psdProjection = args.has("psd");
  if (args.has("psd-method")) {
    const std::string& method = args.text("psd-method");
    if (!options.psdProjection) throw UsageError("--psd-method applies with --psd only");
    if (method != "eigen" && method != "diagonal_blocks")
      throw UsageError("--psd-method expects eigen or diagonal_blocks, got '" + method + "'");
    if (method == "diagonal_blocks") options.psdMethod = tt::PsdMethod::kDiagonalBlocks;
  }
  std::unique_ptr<tt::ForceModel> model;
  try {
    model = std::make_unique<tt::HyperelasticModel<tt::TeranMuscleLaw>>(
        mesh, std::vector<tt::TeranMuscleLaw::Constants>{k}, options);
  } catch (const std::invalid_argument& e) {  // an element inverted or flat at rest
    throw UsageError(e.what());
  }
  return printForcesAt(args, {model.get()}, tt::meshPattern(mesh), mesh.numNodes());
}

int forces(const Arguments& args) {
  if (!args.positional.empty()) throw UsageError("forces takes only options");
  if (args.has("scene")) {
    for (const char* flag : kMuscleFlags)
      if (args.has(flag))
        throw UsageError(std::string("--") + flag + " belongs to the --mesh form, not to --scene");
    return forcesOfScene(args);
  }
  const bool muscle = args.text("model") == tt::TeranMuscleLaw::kName;
  if (!muscle)
    for (const char* flag : kMuscleFlags)
      if (args.has(flag))
        throw UsageError(std::string("--") + flag + " applies to --model teran_muscle only");
  tt::Mesh mesh = tt::readMesh(args.text("mesh"));
  if (muscle) {
    if (args.has("fiber")) {
      Eigen::Vector3d a0(args.number("fiber", 0), args.number("fiber", 1), args.number("fiber", 2));
      if (a0.norm() == 0.0) throw UsageError("--fiber expects a non-zero direction");
      for (Eigen::Matrix3d& frame : mesh.fibreFrame) frame.col(0) = a0.normalized();
      for (Eigen::Matrix3d& frame : mesh.hexFibreFrame) frame.col(0) = a0.normalized();
    }
    mesh.material.assign(mesh.numTets(), 0);
    mesh.hexMaterial.assign(mesh.numHexes(), 0);
    return forcesOfMuscle(args, mesh);
  }
  tt::ElasticConstants k;
  k.lambda = args.number("lambda");
  k.mu = args.number("mu");
  k.lambdaL = args.has("lambda-l") ? args.number("lambda-l") : k.lambda;
  k.muL = args.has("mu-l") ? args.number("mu-l") : k.mu;
  tt::Material material = tt::Material::withConstants(k, 1000.0);
  if (k.lambdaL == k.lambda && k.muL == k.mu)  // isotropic: the tissue presets scale to E and nu
    material.moduli = tt::IsotropicModuli::fromLame(k.lambda, k.mu);
  if (args.has("fiber")) {
    Eigen::Vector3d a0(args.number("fiber", 0), args.number("fiber", 1), args.number("fiber", 2));
    if (a0.norm() == 0.0) throw UsageError("--fiber expects a non-zero direction");
    a0.normalize();
    for (Eigen::Matrix3d& frame : mesh.fibreFrame) frame.col(0) = a0;
  }
  mesh.material.assign(mesh.numTets(), 0);
  std::vector<std::unique_ptr<tt::ForceModel>> models;
  try {
    models = tt::makePresetModels(args.text("model"), mesh, {material});
  } catch (const tt::UnknownNameError&) {
    std::string known;
    for (const std::string& n : tt::registry().presetNames()) known += (known.empty() ? "" : ", ") + n;
    throw UsageError("--model expects one of: " + known + "; got '" + args.text("model") + "'");
  }
  std::vector<const tt::ForceModel*> used;
  for (const auto& m : models) used.push_back(m.get());
  return printForcesAt(args, used, tt::meshPattern(mesh), mesh.numNodes());
}

// --- stretch and shear: quasi-static material tests of the scene's specimen -----------------

int axisFlag(const Arguments& args, const std::string& name) {
  const std::string& value = args.text(name);
  if (value == "x") return 0;
  if (value == "y") return 1;
  if (value == "z") return 2;
  throw UsageError("--" + name + " expects x, y or z, got '" + value + "'");
}

int stepsFlag(const Arguments& args) {
  const double n = args.number("steps");
  if (!(n >= 1.0) || n != std::floor(n) || n > 1e6)
    throw UsageError("--steps expects a whole number >= 1, got '" + args.text("steps") + "'");
  return static_cast<int>(n);
}

// The scene's specimen for a material test: its force models without the body loads (gravity)
// and without the external force, time curves (active tension, cavity pressure) held at their
// value at t = 0 (no step updates are made), and, when its integrator is quasistatic, that
// integrator's solver settings.
struct Specimen {
  tt::Scene scene;
  tt::EquilibriumParams params;
};

Specimen loadSpecimen(const Arguments& args, const char* command) {
  if (args.positional.size() != 1) throw UsageError(std::string(command) + " expects one SCENE.yaml");
  Specimen specimen{tt::loadScene(args.positional[0]), {}};
  tt::System& s = specimen.scene.system;
  s.models.erase(std::remove_if(s.models.begin(), s.models.end(),
                                [](const auto& m) { return m->isBodyLoad(); }),
                 s.models.end());
  s.externalForce.setZero();
  if (const auto* q = dynamic_cast<const tt::QuasistaticIntegrator*>(
          &tt::unguarded(*specimen.scene.integrator)))
    specimen.params = q->params();
  if (!s.hasStiffness())
    throw UsageError("every force model of " + args.positional[0] + " must provide its stiffness");
  return specimen;
}

// The CSV goes to --out or to stdout.
struct CsvOutput {
  std::ofstream file;
  std::FILE* out = stdout;
  explicit CsvOutput(const Arguments& args) {
    if (!args.has("out")) return;
    file.open(args.text("out"));
    if (!file) throw UsageError("cannot write --out " + args.text("out"));
  }
  void line(const char* text) {
    if (file.is_open()) file << text << "\n";
    else std::fprintf(out, "%s\n", text);
  }
};

int finishSpecimen(const Arguments& args, const tt::SpecimenRun& run) {
  if (run.ok) return kOk;
  std::cerr << args.positional[0] << ": " << run.failure << "\n";
  return kRunFailed;
}

int stretch(const Arguments& args) {
  const int axis = axisFlag(args, "axis");
  const double maxStrain = args.number("max-strain");
  if (!(maxStrain > -1.0))
    throw UsageError("--max-strain expects a strain above -1, got '" + args.text("max-strain") + "'");
  const int steps = stepsFlag(args);
  Specimen specimen = loadSpecimen(args, "stretch");
  CsvOutput csv(args);
  csv.line("strain,stretch,force_N,stress_Pa");
  char text[160];
  tt::SpecimenRun run;
  try {
    run = tt::stretchSpecimen(specimen.scene.system, axis, maxStrain, steps, specimen.params,
                              [&](const tt::StretchRow& r) {
                                std::snprintf(text, sizeof text, "%.12g,%.12g,%.12g,%.12g",
                                              r.strain, r.stretch, r.force, r.stress);
                                csv.line(text);
                              });
  } catch (const std::invalid_argument& e) {
    throw UsageError(args.positional[0] + ": " + e.what());
  }
  return finishSpecimen(args, run);
}

int shear(const Arguments& args) {
  const int normal = axisFlag(args, "plane-normal");
  const int direction = axisFlag(args, "direction");
  if (direction == normal)
    throw UsageError("--direction must differ from --plane-normal (both '" +
                     args.text("direction") + "')");
  const double maxShear = args.number("max-shear");
  const int steps = stepsFlag(args);
  Specimen specimen = loadSpecimen(args, "shear");
  CsvOutput csv(args);
  csv.line("shear,work_J,energy_J");
  char text[160];
  tt::SpecimenRun run;
  try {
    run = tt::shearSpecimen(specimen.scene.system, normal, direction, maxShear, steps,
                            specimen.params, [&](const tt::ShearRow& r) {
                              std::snprintf(text, sizeof text, "%.12g,%.12g,%.12g", r.shear,
                                            r.work, r.energy);
                              csv.line(text);
                            });
  } catch (const std::invalid_argument& e) {
    throw UsageError(args.positional[0] + ": " + e.what());
  }
  return finishSpecimen(args, run);
}

void printKeys(const std::vector<tt::KeyDoc>& keys) {
  for (const tt::KeyDoc& k : keys) std::printf("  key %s: %s\n", k.key.c_str(), k.description.c_str());
}

// Every entry of the registry with its keys: what a scene may name.
int models(const Arguments& args) {
  if (!args.positional.empty()) throw UsageError("models takes no arguments");
  const tt::Registry& r = tt::registry();
  for (const tt::ForceModelEntry& m : r.forceModels()) {
    std::printf("force_model %s: %s\n", m.name.c_str(), m.description.c_str());
    printKeys(m.keys);
    for (const tt::ModelPreset& p : m.presets)
      std::printf("  preset %s%s%s: %s\n", p.name.c_str(), p.options.empty() ? "" : " ",
                  p.options.c_str(), p.description.c_str());
  }
  for (const tt::TissuePreset& t : r.tissuePresets())
    std::printf("tissue_preset %s: %s\n", t.name.c_str(), t.description.c_str());
  for (const tt::LawEntry& l : r.laws()) {
    std::printf("law %s: %s\n", l.name.c_str(), l.description.c_str());
    printKeys(l.materialKeys);
  }
  for (const tt::IntegratorEntry& i : r.integrators()) {
    std::printf("integrator %s: %s\n", i.name.c_str(), i.description.c_str());
    printKeys(i.keys);
  }
  return kOk;
}

void printAffine(const char* what, const Eigen::Matrix3d& M, const Eigen::Vector3d& t) {
  std::printf("%s", what);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) std::printf(" %.10g", M(i, j));
  for (int i = 0; i < 3; ++i) std::printf(" %.10g", t[i]);
  std::printf("\n");
}

// Landmark fitting (docs/cli.md, "fit"): activations [+ jaw, cranium] whose equilibrium puts
// the targets file's landmarks at their targets.
int fit(const Arguments& args) {
  if (args.positional.size() != 1) throw UsageError("fit expects one SCENE.yaml");
  tt::Scene scene = tt::loadScene(args.positional[0]);
  tt::System& s = scene.system;
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(args.text("targets"), s.mesh);
  tt::FitParams params;
  params.equilibrium.preconditioner = tt::EquilibriumParams::Preconditioning::kCholesky;
  params.equilibrium.absoluteTolerance = 1e-11;
  params.equilibrium.relativeTolerance = 1e-12;
  if (args.has("max-iterations")) {
    const double n = args.number("max-iterations");
    if (!(n >= 1 && n <= 1e6) || n != std::floor(n))
      throw UsageError("--max-iterations expects a whole number in [1, 1000000]");
    params.maxIterations = static_cast<int>(n);
  }
  const auto positive = [&](const char* name, double& into) {
    if (!args.has(name)) return;
    into = args.number(name);
    if (!(into > 0.0)) throw UsageError(std::string("--") + name + " expects a positive number");
  };
  positive("tolerance", params.residualTolerance);
  positive("step-tolerance", params.stepTolerance);
  positive("levenberg-marquardt", params.levenbergMarquardt);
  positive("orthogonality-weight", params.orthogonalityWeight);
  params.fitCranium = args.has("cranium");
  if (args.has("jaw") && args.has("jaw-box")) throw UsageError("give --jaw or --jaw-box, not both");
  if (args.has("jaw")) {
    if (scene.jawNodes.empty())
      throw UsageError("--jaw: the scene has no jaw nodes (a boundary.fixed entry with jaw: true)");
    params.jawNodes = scene.jawNodes;
    params.fitJaw = true;
  }
  if (args.has("jaw-box")) {
    Eigen::Vector3d lo, hi;
    for (int d = 0; d < 3; ++d) lo[d] = args.number("jaw-box", d), hi[d] = args.number("jaw-box", 3 + d);
    for (int n = 0; n < s.numNodes(); ++n) {
      const Eigen::Vector3d p = s.mesh.rest.col(n);
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all())
        params.jawNodes.push_back(n);
    }
    if (params.jawNodes.empty()) throw UsageError("--jaw-box holds no node");
    params.fitJaw = true;
  }
  tt::LandmarkFit fitter(s, landmarks, params);
  std::printf("fit %s: %zu landmarks, %d parameters\n", scene.name.c_str(), landmarks.size(),
              fitter.parameterCount());
  const tt::FitResult result = fitter.run([](int k, const tt::FitIteration& it) {
    std::printf("iteration %d residual %.6e step %.6e\n", k, it.residual, it.step);
  });
  for (int i = 0; i < fitter.activationCount(); ++i)
    std::printf("activation %s %.10g\n", fitter.parameterName(i).c_str(), fitter.parameters()[i]);
  if (params.fitJaw) printAffine("jaw", fitter.jawMatrix(), fitter.jawTranslation());
  if (params.fitCranium) printAffine("cranium", fitter.craniumMatrix(), fitter.craniumTranslation());
  std::printf("residual %.6e\n", result.residual);
  if (args.has("out")) {
    const std::string dir = args.text("out");
    std::filesystem::create_directories(dir);
    const Eigen::VectorXd x = fitter.fittedPositions();
    tt::VtuFields fields;
    fields.positions = &x;
    tt::writeVtu(dir + "/fit.vtu", s.mesh, fields);
  }
  if (!result.converged()) {
    std::printf("not converged (%s): %s\n", tt::stopName(result.stop), result.reason.c_str());
    return kFitNotConverged;
  }
  std::printf("converged (%s): %s\n", tt::stopName(result.stop), result.reason.c_str());
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    std::cout << kUsage;
    return argc < 2 ? kBadInput : kOk;
  }
  const std::string command = argv[1];
  try {
    if (command == "info") return info(Arguments(argc, argv, 2, {}));
    if (command == "convert") return convert(Arguments(argc, argv, 2, {}));
    if (command == "run") {
      catchInterrupts();
      return run(Arguments(argc, argv, 2, {{"duration", 1}, {"out", 1}, {"threads", 1}}));
    }
    if (command == "forces")
      return forces(Arguments(argc, argv, 2,
                              {{"mesh", 1}, {"deformed", 1}, {"model", 1}, {"lambda", 1},
                               {"mu", 1}, {"lambda-l", 1}, {"mu-l", 1}, {"fiber", 3},
                               {"scene", 1}, {"stiffness-times", 1}, {"mooney-rivlin", 2},
                               {"bulk", 1}, {"peak-stress", 1}, {"activation", 1},
                               {"fiber-stretch", 1}, {"inversion-threshold", 1}, {"psd", 0},
                               {"psd-method", 1}}));
    if (command == "fit")
      return fit(Arguments(argc, argv, 2,
                           {{"targets", 1}, {"out", 1}, {"max-iterations", 1}, {"tolerance", 1},
                            {"step-tolerance", 1}, {"levenberg-marquardt", 1}, {"cranium", 0},
                            {"jaw", 0}, {"jaw-box", 6}, {"orthogonality-weight", 1}}));
    if (command == "models") return models(Arguments(argc, argv, 2, {}));
    if (command == "stretch")
      return stretch(Arguments(argc, argv, 2,
                               {{"axis", 1}, {"max-strain", 1}, {"steps", 1}, {"out", 1}}));
    if (command == "shear")
      return shear(Arguments(argc, argv, 2,
                             {{"plane-normal", 1}, {"direction", 1}, {"max-shear", 1},
                              {"steps", 1}, {"out", 1}}));
    throw UsageError("unknown command '" + command + "'");
  } catch (const tt::InputError& e) {
    std::cerr << e.what() << "\n";
    return kBadInput;
  } catch (const UsageError& e) {
    std::cerr << "tissue_cli: " << e.what() << " (tissue_cli --help for usage)\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "tissue_cli: " << e.what() << "\n";
    return kBadInput;
  }
}
