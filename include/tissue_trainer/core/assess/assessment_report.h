#pragma once
// Writers of an assessment report: YAML (yaml-cpp emitter, full double precision, read back
// by tests and tools) and a short Markdown page for people.
#include <string>

#include "tissue_trainer/core/assess/session_assessor.h"

namespace tt {

std::string assessmentYaml(const AssessmentReport& report, const std::string& source);
std::string assessmentMarkdown(const AssessmentReport& report, const std::string& source);
// A few lines for a terminal.
std::string assessmentSummary(const AssessmentReport& report);

// Creates dir if needed and writes dir/assessment.md, then dir/assessment.yaml (through a
// rename, so a reader never sees a partial YAML); returns the YAML path. Throws std::runtime_error naming the file it could not write.
std::string writeAssessment(const AssessmentReport& report, const std::string& dir,
                            const std::string& source);

}  // namespace tt
