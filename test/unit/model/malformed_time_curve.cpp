// Bad time curves: each gives one InputError line naming the file, the line and the key.
// (Built again under AddressSanitizer + UBSan by scripts/test.)
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/model/time_curve.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {
namespace {

struct BadCurve {
  const char* what;
  std::string text;  // a document whose key `curve` holds the curve
  long line;
  const char* phrase;
};

TEST(MalformedTimeCurve, EachErrorNamesFileLineAndKey) {
  const std::string file = "scene.yaml";
  const std::vector<BadCurve> cases = {
      {"not a map", "x: 1\ncurve: 3\n", 2, "curve: expected a curve map"},
      {"no type", "curve:\n  value: 3\n", 2, "curve: missing required key 'type'"},
      {"unknown type", "curve:\n  type: sawtooth\n", 2, "curve.type: expected one of: constant, piecewise_linear, twitch; got 'sawtooth'"},
      {"misspelt key", "curve:\n  type: constant\n  valu: 3\n", 3, "curve.valu: unknown key 'valu'"},
      {"constant without value", "curve:\n  type: constant\n", 2, "missing required key 'value'"},
      {"constant not a number", "curve:\n  type: constant\n  value: high\n", 3, "curve.value: expected a finite number, got 'high'"},
      {"no times", "curve:\n  type: piecewise_linear\n  values: [1]\n", 2, "missing required key 'times'"},
      {"times not a list", "curve:\n  type: piecewise_linear\n  times: 0\n  values: [1]\n", 3, "curve.times: expected a list"},
      {"empty times", "curve:\n  type: piecewise_linear\n  times: []\n  values: []\n", 3, "curve.times: expected a list of at least one time"},
      {"times decreasing", "curve:\n  type: piecewise_linear\n  times:\n    - 0\n    - 0.5\n    - 0.4\n  values: [0, 1, 2]\n", 6, "curve.times[2]: expected strictly increasing times, got 0.4 after 0.5"},
      {"times repeated", "curve:\n  type: piecewise_linear\n  times: [0, 1, 1]\n  values: [0, 1, 2]\n", 3, "curve.times[2]: expected strictly increasing times"},
      {"a time not a number", "curve:\n  type: piecewise_linear\n  times: [0, soon]\n  values: [0, 1]\n", 3, "curve.times[1]: expected a finite number, got 'soon'"},
      {"fewer values", "curve:\n  type: piecewise_linear\n  times: [0, 1, 2]\n  values:\n    [0, 1]\n", 5, "curve.values: expected 3 values (one per time), got 2"},
      {"a value not a number", "curve:\n  type: piecewise_linear\n  times: [0, 1]\n  values: [0, .nan]\n", 4, "curve.values[1]: expected a finite number"},
      {"twitch without peak", "curve:\n  type: twitch\n  period: 1\n  rise_time: 0.1\n  decay_time: 0.2\n", 2, "missing required key 'peak'"},
      {"twitch zero period", "curve:\n  type: twitch\n  period: 0\n  peak: 1\n  rise_time: 0.1\n  decay_time: 0.2\n", 3, "curve.period: expected a positive number, got '0'"},
      {"twitch negative rise", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise_time: -0.1\n  decay_time: 0.2\n", 5, "curve.rise_time: expected a positive number"},
      {"twitch longer than its period", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise_time: 0.4\n  decay_time: 0.7\n", 6, "curve.decay_time: expected rise_time + decay_time <= period (1), got 0.4 + 0.7"},
      {"twitch onset at the period", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise_time: 0.1\n  decay_time: 0.2\n  onset: 1\n", 7, "curve.onset: expected an onset in [0, period = 1), got 1"},
      {"twitch negative onset", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise_time: 0.1\n  decay_time: 0.2\n  onset: -0.1\n", 7, "curve.onset: expected an onset in [0, period"},
      {"twitch misspelt key", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise: 0.1\n  decay_time: 0.2\n", 5, "curve.rise: unknown key 'rise' (expected one of: type, period, peak, rise_time, decay_time, onset)"},
      {"twitch key of another type", "curve:\n  type: twitch\n  period: 1\n  peak: 1\n  rise_time: 0.1\n  decay_time: 0.2\n  values: [1]\n", 7, "curve.values: unknown key 'values'"},
  };
  for (const BadCurve& c : cases) {
    try {
      readTimeCurve(YamlEntry(YAML::Load(c.text)["curve"], "curve", &file));
      ADD_FAILURE() << c.what << ": no error";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.file(), file) << c.what;
      EXPECT_EQ(e.line(), c.line) << c.what << ": " << message;
      EXPECT_NE(message.find(c.phrase), std::string::npos) << c.what << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << c.what << ": one line";
    }
  }
}

}  // namespace
}  // namespace tt
