// The linear-solve keys (registry/linear_solve_keys.h): each reaches the settings, backward_euler
// and quasistatic read them with the same meaning, the deprecated refactor_above is noted with
// its file and line, and a bad value is one error naming file, line and key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/registry/linear_solve_keys.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const std::string kKeysFile = "linear_keys.yaml";

YamlEntry keysEntry(const std::string& type, const std::string& keys) {
  return testutil::integratorEntry(type, keys, kKeysFile);
}

LinearSolveSettings linearSettingsOf(const std::string& type, const std::string& keys,
                                     Notes& notes) {
  const auto integrator = registry().makeIntegrator(keysEntry(type, keys), notes);
  if (const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(integrator.get()))
    return be->params.linearSolve();
  const auto* qs = dynamic_cast<const QuasistaticIntegrator*>(integrator.get());
  EXPECT_NE(qs, nullptr) << type;
  return qs ? qs->params().linearSolve() : LinearSolveSettings{};
}

std::string errorOf(const std::string& type, const std::string& keys) {
  return testutil::integratorErrorOf(type, keys, kKeysFile);
}

TEST(LinearSolveKeys, EachKeyReachesTheSettings) {
  Notes notes;
  const LinearSolveSettings s = readLinearSolveSettings(
      keysEntry("backward_euler",
                "linear_solver: gmres\ngmres_restart: 12\nlinear_tolerance: 2.5e-7\n"
                "linear_max_iterations: 77\npreconditioner: amg\nrefactor_iterations: 3\n"
                "background_refactor: false\n"),
      LinearSolveSettings{}, notes);
  EXPECT_EQ(s.method, LinearMethod::kGmres);
  EXPECT_EQ(s.gmresRestart, 12);
  EXPECT_EQ(s.tolerance, 2.5e-7);
  EXPECT_EQ(s.maxIterations, 77);
  EXPECT_EQ(s.preconditioner, PreconditionerKind::kAmg);
  EXPECT_EQ(s.refactorIterations, 3);
  EXPECT_FALSE(s.backgroundRefactor);
  EXPECT_TRUE(notes.empty());

  LinearSolveSettings defaults;
  defaults.backgroundRefactor = false;
  defaults.refactorIterations = 9;
  const LinearSolveSettings other = readLinearSolveSettings(
      keysEntry("backward_euler", "linear_solver: bicgstab\npreconditioner: cholesky\n"
                                  "background_refactor: true\n"),
      defaults, notes);
  EXPECT_EQ(other.method, LinearMethod::kBiCgStab);
  EXPECT_EQ(other.preconditioner, PreconditionerKind::kCholesky);
  EXPECT_TRUE(other.backgroundRefactor);
  EXPECT_EQ(other.refactorIterations, 9) << "an absent key keeps the default";
  EXPECT_EQ(other.tolerance, defaults.tolerance);
}

TEST(LinearSolveKeys, BackwardEulerAndQuasistaticGiveTheSameKeysTheSameMeaning) {
  const std::vector<std::string> keySets = {
      "preconditioner: cholesky\nrefactor_iterations: 0\nlinear_tolerance: 1e-7\n"
      "linear_max_iterations: 123\n",
      "preconditioner: amg\nrefactor_iterations: 42\nlinear_solver: pcg\n"
      "background_refactor: false\n",
      "preconditioner: jacobi\nlinear_tolerance: 3e-5\n"};
  for (const std::string& keys : keySets) {
    Notes notes;
    const LinearSolveSettings be = linearSettingsOf("backward_euler", keys, notes);
    const LinearSolveSettings qs = linearSettingsOf("quasistatic", keys, notes);
    LinearSolveSettings read = readLinearSolveSettings(keysEntry("quasistatic", keys),
                                                       LinearSolveSettings{}, notes);
    for (const LinearSolveSettings* s : {&be, &qs}) {
      if (keys.find("preconditioner") != std::string::npos)
        EXPECT_EQ(s->preconditioner, read.preconditioner) << keys;
      if (keys.find("refactor_iterations") != std::string::npos)
        EXPECT_EQ(s->refactorIterations, read.refactorIterations) << keys;
      if (keys.find("linear_tolerance") != std::string::npos)
        EXPECT_EQ(s->tolerance, read.tolerance) << keys;
      if (keys.find("linear_max_iterations") != std::string::npos)
        EXPECT_EQ(s->maxIterations, read.maxIterations) << keys;
      if (keys.find("background_refactor") != std::string::npos)
        EXPECT_FALSE(s->backgroundRefactor) << keys;
      EXPECT_EQ(s->method, LinearMethod::kPcg) << keys;
    }
    EXPECT_TRUE(notes.empty()) << keys;
  }
}

TEST(LinearSolveKeys, RefactorAboveIsReadAsRefactorIterationsWithANoteOfItsLine) {
  for (const int value : {0, 7}) {
    Notes notes;
    const std::string number = std::to_string(value);
    const LinearSolveSettings old = linearSettingsOf(
        "quasistatic", "preconditioner: cholesky\nrefactor_above: " + number + "\n", notes);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0], kKeysFile + ":3: integrator.refactor_above is deprecated: write "
                                    "refactor_iterations (the same meaning)");
    Notes none;
    const LinearSolveSettings renamed = linearSettingsOf(
        "quasistatic", "preconditioner: cholesky\nrefactor_iterations: " + number + "\n", none);
    EXPECT_TRUE(none.empty());
    EXPECT_EQ(old.refactorIterations, value);
    EXPECT_EQ(old.refactorIterations, renamed.refactorIterations);
  }
  // Through the scene loader the note is the scene's, with the scene file's line.
  const std::string path = testutil::writeScene("deprecated_refactor_above.yaml",
                                                R"(name: block
mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
integrator:
  type: quasistatic
  preconditioner: cholesky
  refactor_above: 0
stability_guard: {enabled: false}
)");
  const Scene scene = loadScene(path);
  int noted = 0;
  for (const std::string& note : scene.notes)
    noted += note.find(path + ":10: integrator.refactor_above is deprecated") == 0;
  EXPECT_EQ(noted, 1);
  const auto* qs = dynamic_cast<const QuasistaticIntegrator*>(scene.integrator.get());
  ASSERT_NE(qs, nullptr);
  EXPECT_EQ(qs->params().refactorIterations, 0);
}

TEST(LinearSolveKeys, ABadValueIsOneErrorNamingFileLineAndKey) {
  struct Bad {
    const char* value;  // on line 2
    const char* key;
  };
  const Bad shared[] = {
      {"preconditioner: ilu", "integrator.preconditioner"},
      {"refactor_iterations: -1", "integrator.refactor_iterations"},
      {"refactor_iterations: 2.5", "integrator.refactor_iterations"},
      {"linear_tolerance: 0", "integrator.linear_tolerance"},
      {"linear_tolerance: tight", "integrator.linear_tolerance"},
      {"linear_max_iterations: 0", "integrator.linear_max_iterations"},
      {"background_refactor: maybe", "integrator.background_refactor"},
      {"linear_solver: cg", "integrator.linear_solver"},
      {"gmres_restart: 5", "integrator.gmres_restart"},
  };
  for (const char* type : {"backward_euler", "quasistatic"})
    for (const Bad& bad : shared) {
      const std::string message = errorOf(type, std::string(bad.value) + "\n");
      EXPECT_EQ(message.find(kKeysFile + ":2: " + bad.key + ": "), 0u)
          << type << ", " << bad.value << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  // What the Newton solver cannot use, refused with the reason.
  EXPECT_EQ(errorOf("quasistatic", "linear_solver: gmres\n")
                .find(kKeysFile + ":2: integrator.linear_solver: quasistatic takes pcg only"),
            0u);
  EXPECT_EQ(errorOf("quasistatic", "background_refactor: true\n")
                .find(kKeysFile + ":2: integrator.background_refactor: quasistatic takes false"),
            0u);
  EXPECT_EQ(errorOf("quasistatic", "refactor_above: 3\nrefactor_iterations: 3\n")
                .find(kKeysFile + ":2: integrator.refactor_above: is the deprecated name"),
            0u);
  EXPECT_EQ(errorOf("quasistatic", "refactor_above: -2\n")
                .find(kKeysFile + ":2: integrator.refactor_above: expected an integer >= 0"),
            0u);
  // refactor_above was quasistatic's: backward_euler never took it.
  EXPECT_NE(errorOf("backward_euler", "refactor_above: 3\n").find("unknown key 'refactor_above'"),
            std::string::npos);
}

}  // namespace
}  // namespace tt
