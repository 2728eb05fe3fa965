#include "tissue_trainer/core/assess/assessment_report.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tt {
namespace {

void emitCounts(YAML::Emitter& e, const char* name, const StreamCounts& c) {
  e << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap
    << YAML::Key << "accepted" << YAML::Value << c.accepted
    << YAML::Key << "non_finite" << YAML::Value << c.nonFinite
    << YAML::Key << "out_of_order" << YAML::Value << c.outOfOrder << YAML::EndMap;
}

// A table cell: '|' would end it.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// "Simulation restarted at t = ..." for each restart, or nothing.
std::string restartLines(const AssessmentReport& r) {
  std::string s;
  for (const SimulationRestart& x : r.restarts)
    s += "Simulation restarted at t = " + number(x.time) + " s (no contact model for " +
         number(x.gap) + " s before it; the metrics skip that gap).\n\n";
  return s;
}

}  // namespace

const std::vector<ReportFigure>& reportFigures() {
  static const std::vector<ReportFigure> figures = {
      {"tip_path.png",
       "Tip path seen from the front (as the laparoscope) and from the side; movements in colour, pauses grey; "
       "the tissue at rest shaded when assess_bag was given the scene"},
      {"speed.png",
       "Smoothed tip speed; each movement shaded (hatched where the tool touched the tissue), with its log "
       "dimensionless jerk"},
      {"force.png", "Tool-tissue force with the excessive-force threshold"},
      {"strain.png", "Largest tissue strain over time"},
  };
  return figures;
}

const char* const kScoreRule =
    "metric score = 100 * clamp((novice - value) / (novice - expert), 0, 1): 100 at the expert "
    "value or better, 0 at the novice value or worse, linear between; overall = mean of the "
    "metric scores with data, each metric weighing the same";

std::string assessmentYaml(const AssessmentReport& r, const std::string& source, const SkillScore* score) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::BeginMap;
  e << YAML::Key << "source" << YAML::Value << source;
  e << YAML::Key << "settings" << YAML::Value << YAML::BeginMap
    << YAML::Key << "force_threshold" << YAML::Value << r.settings.forceThreshold
    << YAML::Key << "movement_speed_start" << YAML::Value << r.settings.movementSpeedStart
    << YAML::Key << "movement_speed_stop" << YAML::Value << r.settings.movementSpeedStop
    << YAML::Key << "movement_min_pause" << YAML::Value << r.settings.movementMinPause
    << YAML::Key << "resample_rate" << YAML::Value << r.settings.resampleRate
    << YAML::Key << "smoothing_time" << YAML::Value << r.settings.smoothingTime
    << YAML::Key << "max_gap" << YAML::Value << r.settings.maxGap << YAML::EndMap;
  e << YAML::Key << "samples" << YAML::Value << YAML::BeginMap;
  emitCounts(e, "tip", r.tip);
  emitCounts(e, "force", r.force);
  emitCounts(e, "status", r.status);
  e << YAML::EndMap;
  e << YAML::Key << "metrics" << YAML::Value << YAML::BeginMap;
  for (const Metric& m : r.metrics)
    e << YAML::Key << m.key << YAML::Value << m.value << YAML::Comment(m.unit);
  e << YAML::EndMap;
  e << YAML::Key << "no_data" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const Metric& m : r.metrics)
    if (!m.hasData) e << m.key;
  e << YAML::EndSeq;
  e << YAML::Key << "simulation_restarts" << YAML::Value << YAML::BeginSeq;
  for (const SimulationRestart& x : r.restarts)
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "time" << YAML::Value << x.time
      << YAML::Key << "gap" << YAML::Value << x.gap << YAML::EndMap;
  e << YAML::EndSeq;
  e << YAML::Key << "movements" << YAML::Value << YAML::BeginSeq;
  for (const Movement& m : r.movements) {
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "start" << YAML::Value << m.start
      << YAML::Key << "end" << YAML::Value << m.end << YAML::Key << "path_length" << YAML::Value
      << m.pathLength << YAML::Key << "chord" << YAML::Value << m.chord << YAML::Key << "peak_speed"
      << YAML::Value << m.peakSpeed;
    if (m.hasJerk)
      e << YAML::Key << "dimensionless_jerk" << YAML::Value << m.dimensionlessJerk << YAML::Key
        << "ldlj" << YAML::Value << m.logDimensionlessJerk;
    e << YAML::Key << "contact" << YAML::Value << m.inContact;
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
  if (score) {
    e << YAML::Key << "score" << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "rule" << YAML::Value << kScoreRule;
    e << YAML::Key << "bands_source" << YAML::Value << score->source;
    e << YAML::Key << "overall" << YAML::Value << score->overall;
    e << YAML::Key << "has_data" << YAML::Value << score->hasData;
    e << YAML::Key << "metrics" << YAML::Value << YAML::BeginMap;
    for (const MetricScore& m : score->metrics) {
      e << YAML::Key << m.key << YAML::Value << YAML::Flow << YAML::BeginMap;
      if (m.hasData) e << YAML::Key << "score" << YAML::Value << m.score;
      e << YAML::Key << "expert" << YAML::Value << m.expert << YAML::Key << "novice" << YAML::Value
        << m.novice << YAML::EndMap;
    }
    e << YAML::EndMap << YAML::EndMap;
  }
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

std::string assessmentMarkdown(const AssessmentReport& r, const std::string& source,
                               const SkillScore* score, const std::vector<std::string>& figures) {
  std::ostringstream s;
  s << "# Training assessment\n\nSource: `" << source << "`. Samples accepted (rejected "
    << "non-finite / out of order): tip " << r.tip.accepted << " (" << r.tip.nonFinite << " / "
    << r.tip.outOfOrder << "), force " << r.force.accepted << " (" << r.force.nonFinite << " / "
    << r.force.outOfOrder << "), tissue status " << r.status.accepted << " ("
    << r.status.nonFinite << " / " << r.status.outOfOrder << ").\n\n"
    << restartLines(r);
  if (score) {
    s << "## Score\n\n";
    if (score->hasData)
      s << "**Overall score: " << fixed(score->overall, 0) << " / 100**\n\n";
    else
      s << "**Overall score: no data**\n\n";
    s << "Rule: " << kScoreRule << ".\n\nReference bands: " << cell(score->source) << "\n\n"
      << "| metric | value | expert | novice | score |\n|---|---|---|---|---|\n";
    for (const MetricScore& m : score->metrics)
      s << "| " << m.key << " | " << (m.hasData ? number(m.value) : "no data") << " | "
        << number(m.expert) << " | " << number(m.novice) << " | "
        << (m.hasData ? fixed(m.score, 0) : "-") << " |\n";
    s << "\n";
  }
  if (!figures.empty()) {
    s << "## Plots\n\n";
    for (const ReportFigure& f : reportFigures())
      if (std::find(figures.begin(), figures.end(), f.file) != figures.end())
        s << "![" << f.caption << "](" << f.file << ")\n\n*" << f.caption << ".*\n\n";
  }
  s << "## Metrics\n\n| metric | value | unit | definition |\n|---|---|---|---|\n";
  for (const Metric& m : r.metrics)
    s << "| " << m.key << " | " << (m.hasData ? number(m.value) : "no data") << " | " << m.unit
      << " | " << cell(m.definition) << " |\n";
  if (!r.movements.empty()) {
    s << "\n## Movements\n\n| # | start (s) | duration (s) | path (mm) | peak speed (mm/s) | "
         "log dimensionless jerk | contact |\n|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < r.movements.size(); ++i) {
      const Movement& m = r.movements[i];
      s << "| " << i + 1 << " | " << fixed(m.start, 2) << " | " << fixed(m.duration(), 2) << " | "
        << fixed(1e3 * m.pathLength, 1) << " | " << fixed(1e3 * m.peakSpeed, 1) << " | "
        << (m.hasJerk ? fixed(m.logDimensionlessJerk, 2) : "no data") << " | "
        << (m.inContact ? "yes" : "no") << " |\n";
    }
  }
  s << "\nSettings: force_threshold " << number(r.settings.forceThreshold)
    << " N, movement_speed_start " << number(r.settings.movementSpeedStart)
    << " m/s, movement_speed_stop " << number(r.settings.movementSpeedStop)
    << " m/s, movement_min_pause " << number(r.settings.movementMinPause)
    << " s, resample_rate " << number(r.settings.resampleRate) << " Hz, smoothing_time "
    << number(r.settings.smoothingTime) << " s, max_gap " << number(r.settings.maxGap) << " s.\n";
  return s.str();
}

std::string assessmentSummary(const AssessmentReport& r, const SkillScore* score) {
  std::ostringstream s;
  s << "samples: tip " << r.tip.accepted << ", force " << r.force.accepted << ", status "
    << r.status.accepted << " (rejected " << r.tip.nonFinite + r.force.nonFinite + r.status.nonFinite
    << " non-finite, " << r.tip.outOfOrder + r.force.outOfOrder + r.status.outOfOrder
    << " out of order)\n" << restartLines(r);
  for (const Metric& m : r.metrics) {
    char line[96];
    std::snprintf(line, sizeof line, "  %-24s %14s %s\n", m.key.c_str(),
                  m.hasData ? number(m.value).c_str() : "no data",
                  m.hasData && m.unit != "1" ? m.unit.c_str() : "");
    s << line;
  }
  if (score && score->hasData) s << "  overall score " << fixed(score->overall, 0) << " / 100\n";
  return s.str();
}

namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path + ": cannot write the file");
}

std::string seriesCsv(const std::vector<TimedValue>& series, const char* header) {
  std::string out = std::string(header) + "\n";
  char line[64];
  for (const TimedValue& v : series) {
    std::snprintf(line, sizeof line, "%.6f,%.9g\n", v.t, v.value);
    out += line;
  }
  return out;
}

std::string pathCsv(const AssessmentReport& r) {
  std::string out = "t,x,y,z,speed,movement\n";
  char line[160];
  for (const PathSample& p : r.path) {
    std::snprintf(line, sizeof line, "%.6f,%.9g,%.9g,%.9g,%.9g,%d\n", p.t, p.position.x(),
                  p.position.y(), p.position.z(), p.speed, p.movement);
    out += line;
  }
  return out;
}

std::string movementsCsv(const AssessmentReport& r) {
  std::string out = "start,end,path_length,chord,peak_speed,ldlj,contact\n";
  char line[160];
  for (const Movement& m : r.movements) {
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.9g,%.9g,%.9g,%s,%d\n", m.start, m.end, m.pathLength,
                  m.chord, m.peakSpeed, m.hasJerk ? number(m.logDimensionlessJerk).c_str() : "",
                  m.inContact ? 1 : 0);
    out += line;
  }
  return out;
}

std::vector<std::string> figuresIn(const std::string& dir) {
  std::vector<std::string> found;
  for (const ReportFigure& f : reportFigures())
    if (std::filesystem::exists(std::filesystem::path(dir) / f.file)) found.push_back(f.file);
  return found;
}

}  // namespace

void writeAssessmentMarkdown(const AssessmentReport& r, const std::string& dir,
                             const std::string& source, const SkillScore* score) {
  writeText((std::filesystem::path(dir) / "assessment.md").string(),
            assessmentMarkdown(r, source, score, figuresIn(dir)));
}

std::string writeAssessment(const AssessmentReport& r, const std::string& dir,
                            const std::string& source, const SkillScore* score) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create the directory (" + ec.message() + ")");
  const std::filesystem::path d(dir);
  writeText((d / "path.csv").string(), pathCsv(r));
  writeText((d / "movements.csv").string(), movementsCsv(r));
  writeText((d / "force.csv").string(), seriesCsv(r.forceSeries, "t,force"));
  writeText((d / "strain.csv").string(), seriesCsv(r.strainSeries, "t,max_strain"));
  // The Markdown first, the YAML last and atomically: once assessment.yaml is there, all are.
  writeAssessmentMarkdown(r, dir, source, score);
  const std::string yaml = (d / "assessment.yaml").string();
  writeText(yaml + ".tmp", assessmentYaml(r, source, score));
  std::filesystem::rename(yaml + ".tmp", yaml, ec);
  if (ec) throw std::runtime_error(yaml + ": cannot write the file (" + ec.message() + ")");
  return yaml;
}

namespace {
const char* kCurveMetrics[] = {"motion_time", "path_length_smoothed", "ldlj_median", "idle_time",
                               "excessive_force_time", "peak_force"};
}  // namespace

std::string learningCurveMarkdown(const std::vector<SessionResult>& sessions, bool withPlot) {
  std::ostringstream s;
  s << "# Learning curve\n\n" << sessions.size() << " sessions in the order given.";
  if (!sessions.empty()) s << " Scores: " << kScoreRule << ".";
  s << "\n\n";
  if (withPlot) s << "![Overall score and key metrics per session](learning_curve.png)\n\n";
  s << "| # | session | score |";
  for (const char* k : kCurveMetrics) s << " " << k << " |";
  s << "\n|---|---|---|";
  for (std::size_t i = 0; i < std::size(kCurveMetrics); ++i) s << "---|";
  s << "\n";
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    const SessionResult& x = sessions[i];
    s << "| " << i + 1 << " | [" << cell(x.label) << "](" << x.dir << "/assessment.md) | "
      << (x.score.hasData ? fixed(x.score.overall, 0) : "no data") << " |";
    for (const char* k : kCurveMetrics) {
      const Metric* m = x.report.find(k);
      s << " " << (m && m->hasData ? number(m->value) : "no data") << " |";
    }
    s << "\n";
  }
  return s.str();
}

std::string learningCurveCsv(const std::vector<SessionResult>& sessions) {
  std::string out = "session,label,score";
  for (const char* k : kCurveMetrics) out += std::string(",") + k;
  out += "\n";
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    const SessionResult& x = sessions[i];
    std::string label = x.label;
    std::replace(label.begin(), label.end(), ',', ' ');
    out += std::to_string(i + 1) + "," + label + "," + (x.score.hasData ? number(x.score.overall) : "");
    for (const char* k : kCurveMetrics) {
      const Metric* m = x.report.find(k);
      out += "," + (m && m->hasData ? number(m->value) : std::string());
    }
    out += "\n";
  }
  return out;
}

}  // namespace tt
