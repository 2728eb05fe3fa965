// The Newton keys (registry/newton_keys.h): max_newton_iterations, newton_tolerance and
// newton_abs_tolerance reach each integrator's settings; each deprecated name is read with the
// same meaning and one note of its file and line; old and new name together, or a malformed
// value, is one error line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const std::string kNewtonKeysFile = "newton_keys.yaml";

YamlEntry newtonKeysEntry(const std::string& type, const std::string& keys) {
  return testutil::integratorEntry(type, keys, kNewtonKeysFile);
}

// The Newton settings an integrator was made with (-1 where it has no such setting).
struct NewtonSettingsMade {
  int maxIterations = -1;
  double tolerance = -1;
  double absTolerance = -1;
};

NewtonSettingsMade newtonSettingsOf(const std::string& type, const std::string& keys,
                                    Notes& notes) {
  const auto integrator = registry().makeIntegrator(newtonKeysEntry(type, keys), notes);
  NewtonSettingsMade made;
  if (const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(integrator.get())) {
    made.maxIterations = be->params.newtonIterations;
    made.tolerance = be->params.newtonTolerance;
  } else if (const auto* qs = dynamic_cast<const QuasistaticIntegrator*>(integrator.get())) {
    made.maxIterations = qs->params().maxNewtonIterations;
    made.tolerance = qs->params().relativeTolerance;
    made.absTolerance = qs->params().absoluteTolerance;
  } else if (const auto* radau = dynamic_cast<const RadauIIA*>(integrator.get())) {
    made.maxIterations = radau->options().maxNewtonIterations;
  } else {
    ADD_FAILURE() << type;
  }
  return made;
}

std::string newtonKeysErrorOf(const std::string& type, const std::string& keys) {
  return testutil::integratorErrorOf(type, keys, kNewtonKeysFile);
}

TEST(NewtonKeys, EachIntegratorReadsTheSameNames) {
  Notes notes;
  const NewtonSettingsMade be =
      newtonSettingsOf("backward_euler", "max_newton_iterations: 4\nnewton_tolerance: 2.5e-7\n",
                       notes);
  EXPECT_EQ(be.maxIterations, 4);
  EXPECT_EQ(be.tolerance, 2.5e-7);

  const NewtonSettingsMade qs = newtonSettingsOf(
      "quasistatic",
      "max_newton_iterations: 9\nnewton_tolerance: 3e-8\nnewton_abs_tolerance: 4e-7\n", notes);
  EXPECT_EQ(qs.maxIterations, 9);
  EXPECT_EQ(qs.tolerance, 3e-8);
  EXPECT_EQ(qs.absTolerance, 4e-7);

  const NewtonSettingsMade radau =
      newtonSettingsOf("radau_iia", "max_newton_iterations: 5\n", notes);
  EXPECT_EQ(radau.maxIterations, 5);
  EXPECT_TRUE(notes.empty());

  // Absent keys keep the integrators' defaults.
  const NewtonSettingsMade beDefault = newtonSettingsOf("backward_euler", "", notes);
  EXPECT_EQ(beDefault.maxIterations, BackwardEulerParams().newtonIterations);
  EXPECT_EQ(beDefault.tolerance, BackwardEulerParams().newtonTolerance);
  const NewtonSettingsMade qsDefault = newtonSettingsOf("quasistatic", "", notes);
  EXPECT_EQ(qsDefault.maxIterations, EquilibriumParams().maxNewtonIterations);
  EXPECT_EQ(qsDefault.tolerance, EquilibriumParams().relativeTolerance);
  EXPECT_EQ(qsDefault.absTolerance, EquilibriumParams().absoluteTolerance);
  EXPECT_EQ(newtonSettingsOf("radau_iia", "", notes).maxIterations,
            RadauOptions().maxNewtonIterations);
  EXPECT_TRUE(notes.empty());
}

// An integrator's deprecated name of a Newton key and the key's name now.
struct RenamedNewtonKey {
  const char* type;
  const char* oldName;
  const char* name;
  const char* value;
};

const RenamedNewtonKey kRenamedNewtonKeys[] = {
    {"backward_euler", "newton_iterations", "max_newton_iterations", "3"},
    {"quasistatic", "rel_tolerance", "newton_tolerance", "2e-7"},
    {"quasistatic", "abs_tolerance", "newton_abs_tolerance", "5e-6"},
};

TEST(NewtonKeys, EachDeprecatedNameIsReadAsItsNewNameWithANoteOfItsLine) {
  for (const RenamedNewtonKey& k : kRenamedNewtonKeys) {
    Notes notes;
    const std::string value = std::string(": ") + k.value + "\n";
    const NewtonSettingsMade old = newtonSettingsOf(k.type, k.oldName + value, notes);
    ASSERT_EQ(notes.size(), 1u) << k.oldName;
    EXPECT_EQ(notes[0], kNewtonKeysFile + ":2: integrator." + k.oldName +
                            " is deprecated: write " + k.name + " (the same meaning)");
    Notes none;
    const NewtonSettingsMade renamed = newtonSettingsOf(k.type, k.name + value, none);
    EXPECT_TRUE(none.empty()) << k.name;
    EXPECT_EQ(old.maxIterations, renamed.maxIterations) << k.oldName;
    EXPECT_EQ(old.tolerance, renamed.tolerance) << k.oldName;
    EXPECT_EQ(old.absTolerance, renamed.absTolerance) << k.oldName;
    const NewtonSettingsMade defaults = newtonSettingsOf(k.type, "", none);
    EXPECT_FALSE(old.maxIterations == defaults.maxIterations &&
                 old.tolerance == defaults.tolerance &&
                 old.absTolerance == defaults.absTolerance)
        << k.oldName << " was not read";
  }
}

TEST(NewtonKeys, TheDeprecatedNameInASceneIsNotedWithTheScenesLine) {
  const std::string path = testutil::writeScene("deprecated_newton_iterations.yaml",
                                                R"(name: block
mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}
materials:
  - {young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa}
force_models:
  - {type: hyperelastic, law: neo_hookean}
integrator:
  type: backward_euler
  newton_iterations: 3
stability_guard: {enabled: false}
)");
  const Scene scene = loadScene(path);
  int noted = 0;
  for (const std::string& note : scene.notes)
    noted += note == path + ":9: integrator.newton_iterations is deprecated: write "
                            "max_newton_iterations (the same meaning)";
  EXPECT_EQ(noted, 1);
  const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(scene.integrator.get());
  ASSERT_NE(be, nullptr);
  EXPECT_EQ(be->params.newtonIterations, 3);
}

TEST(NewtonKeys, TheOldAndTheNewNameTogetherIsOneErrorNamingBoth) {
  for (const RenamedNewtonKey& k : kRenamedNewtonKeys) {
    const std::string message =
        newtonKeysErrorOf(k.type, std::string(k.name) + ": " + k.value + "\n" + k.oldName +
                                      ": " + k.value + "\n");
    EXPECT_EQ(message, kNewtonKeysFile + ":3: integrator." + k.oldName +
                           ": is the deprecated name of " + k.name + "; give " + k.name +
                           " only");
  }
}

TEST(NewtonKeys, AMalformedValueIsOneErrorNamingFileLineAndKey) {
  struct Taker {
    const char* type;
    const char* key;
  };
  const Taker takers[] = {
      {"backward_euler", "max_newton_iterations"}, {"backward_euler", "newton_tolerance"},
      {"quasistatic", "max_newton_iterations"},    {"quasistatic", "newton_tolerance"},
      {"quasistatic", "newton_abs_tolerance"},     {"radau_iia", "max_newton_iterations"},
      {"backward_euler", "newton_iterations"},     {"quasistatic", "rel_tolerance"},
      {"quasistatic", "abs_tolerance"},
  };
  for (const Taker& t : takers)
    for (const char* value : {"0", "-2", "many", "[1, 2]"}) {
      const std::string message =
          newtonKeysErrorOf(t.type, std::string(t.key) + ": " + value + "\n");
      EXPECT_EQ(message.find(kNewtonKeysFile + ":2: integrator." + t.key + ": expected "), 0u)
          << t.type << ", " << t.key << ": " << value << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  // An iteration count is a whole number.
  EXPECT_NE(newtonKeysErrorOf("backward_euler", "max_newton_iterations: 2.5\n")
                .find("integrator.max_newton_iterations: expected an integer, got '2.5'"),
            std::string::npos);
}

TEST(NewtonKeys, AnIntegratorRefusesTheOldNamesItNeverTook) {
  const std::pair<const char*, const char*> refused[] = {
      {"backward_euler", "rel_tolerance"},  {"backward_euler", "abs_tolerance"},
      {"backward_euler", "newton_abs_tolerance"}, {"quasistatic", "newton_iterations"},
      {"radau_iia", "newton_iterations"},   {"radau_iia", "newton_tolerance"},
  };
  for (const auto& [type, key] : refused)
    EXPECT_NE(newtonKeysErrorOf(type, std::string(key) + ": 1\n")
                  .find("unknown key '" + std::string(key) + "'"),
              std::string::npos)
        << type << ", " << key;
}

}  // namespace
}  // namespace tt
