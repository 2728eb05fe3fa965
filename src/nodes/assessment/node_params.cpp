#include "node_params.h"

#include <stdexcept>

#include "../common/param_reader.h"

namespace tt {

AssessmentNodeParams readAssessmentNodeParams(const ros::NodeHandle& nh) {
  const tt_nodes::ParamReader p(nh);
  // The ranges of the metric settings are checked once, by the core (validate()).
  AssessmentNodeParams out;
  AssessmentSettings& s = out.settings;
  for (const AssessmentSettingKey& k : kAssessmentSettingKeys)
    s.*k.value = p.number(k.key, s.*k.value);
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw tt_nodes::ParamError(p.qualified("") + "/" + e.what());
  }
  out.summaryRate = p.number("summary_rate", out.summaryRate, 1e-3, 100.0);
  out.outputDir = p.text("output_dir", out.outputDir);
  if (out.outputDir.empty())
    throw tt_nodes::ParamError(p.qualified("output_dir") + ": expected a non-empty directory path");
  // The package's bands unless told otherwise; "none": no score.
#ifndef TT_DEFAULT_BANDS
#define TT_DEFAULT_BANDS ""
#endif
  const std::string bands = p.text("reference_bands", TT_DEFAULT_BANDS);
  out.scored = bands != "none";
  if (out.scored) {
    try {
      out.bands = loadReferenceBands(bands);
    } catch (const std::exception& e) {
      throw tt_nodes::ParamError(p.qualified("reference_bands") + ": " + e.what());
    }
  }
  return out;
}

}  // namespace tt
