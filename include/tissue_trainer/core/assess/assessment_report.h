#pragma once
// Writers of an assessment report: YAML (yaml-cpp emitter, full double precision, read back
// by tests and tools), a Markdown page for people (with the scores against the reference
// bands and the plots, when there are any), and CSV series for the plotting script
// (scripts/assessment_plots.py).
#include <string>
#include <vector>

#include "tissue_trainer/core/assess/session_assessor.h"
#include "tissue_trainer/core/assess/skill_score.h"

namespace tt {

// The plots the report embeds when they exist beside it (made by scripts/assessment_plots.py).
struct ReportFigure {
  const char* file;
  const char* caption;
};
const std::vector<ReportFigure>& reportFigures();

std::string assessmentYaml(const AssessmentReport& report, const std::string& source,
                           const SkillScore* score = nullptr);
// figures: the files of reportFigures() to embed (relative to the page).
std::string assessmentMarkdown(const AssessmentReport& report, const std::string& source,
                               const SkillScore* score = nullptr,
                               const std::vector<std::string>& figures = {});
// A few lines for a terminal.
std::string assessmentSummary(const AssessmentReport& report, const SkillScore* score = nullptr);

// Creates dir if needed and writes the series (path.csv, movements.csv, force.csv,
// strain.csv), dir/assessment.md (embedding the figures already in dir), then
// dir/assessment.yaml (through a rename, so a reader never sees a partial YAML); returns the
// YAML path. Throws std::runtime_error naming the file it could not write.
std::string writeAssessment(const AssessmentReport& report, const std::string& dir,
                            const std::string& source, const SkillScore* score = nullptr);
// Rewrites dir/assessment.md only (after the plots were made).
void writeAssessmentMarkdown(const AssessmentReport& report, const std::string& dir,
                             const std::string& source, const SkillScore* score = nullptr);

// Several sessions of one trainee, in the order given: a learning-curve table.
struct SessionResult {
  std::string label;   // e.g. the bag's file name
  std::string dir;     // its report folder, relative to the learning-curve page
  AssessmentReport report;
  SkillScore score;
};
std::string learningCurveMarkdown(const std::vector<SessionResult>& sessions, bool withPlot);
std::string learningCurveCsv(const std::vector<SessionResult>& sessions);

}  // namespace tt
