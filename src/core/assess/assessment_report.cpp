#include "tissue_trainer/core/assess/assessment_report.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
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

std::string assessmentYaml(const AssessmentReport& r, const std::string& source) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::BeginMap;
  e << YAML::Key << "source" << YAML::Value << source;
  e << YAML::Key << "settings" << YAML::Value << YAML::BeginMap
    << YAML::Key << "force_threshold" << YAML::Value << r.settings.forceThreshold
    << YAML::Key << "movement_speed_start" << YAML::Value << r.settings.movementSpeedStart
    << YAML::Key << "movement_speed_stop" << YAML::Value << r.settings.movementSpeedStop
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
  e << YAML::EndSeq << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

std::string assessmentMarkdown(const AssessmentReport& r, const std::string& source) {
  std::ostringstream s;
  s << "# Training assessment\n\nSource: `" << source << "`. Samples accepted (rejected "
    << "non-finite / out of order): tip " << r.tip.accepted << " (" << r.tip.nonFinite << " / "
    << r.tip.outOfOrder << "), force " << r.force.accepted << " (" << r.force.nonFinite << " / "
    << r.force.outOfOrder << "), tissue status " << r.status.accepted << " ("
    << r.status.nonFinite << " / " << r.status.outOfOrder << ").\n\n"
    << restartLines(r) << "| metric | value | unit | definition |\n|---|---|---|---|\n";
  for (const Metric& m : r.metrics)
    s << "| " << m.key << " | " << (m.hasData ? number(m.value) : "no data") << " | " << m.unit
      << " | " << cell(m.definition) << " |\n";
  s << "\nSettings: force_threshold " << number(r.settings.forceThreshold)
    << " N, movement_speed_start " << number(r.settings.movementSpeedStart)
    << " m/s, movement_speed_stop " << number(r.settings.movementSpeedStop)
    << " m/s, resample_rate " << number(r.settings.resampleRate) << " Hz, smoothing_time "
    << number(r.settings.smoothingTime) << " s, max_gap " << number(r.settings.maxGap) << " s.\n";
  return s.str();
}

std::string assessmentSummary(const AssessmentReport& r) {
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
  return s.str();
}

std::string writeAssessment(const AssessmentReport& r, const std::string& dir,
                            const std::string& source) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create the directory (" + ec.message() + ")");
  auto write = [](const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error(path + ": cannot write the file");
  };
  // The Markdown first, the YAML last and atomically: once assessment.yaml is there, both are.
  write((std::filesystem::path(dir) / "assessment.md").string(), assessmentMarkdown(r, source));
  const std::string yaml = (std::filesystem::path(dir) / "assessment.yaml").string();
  write(yaml + ".tmp", assessmentYaml(r, source));
  std::filesystem::rename(yaml + ".tmp", yaml, ec);
  if (ec) throw std::runtime_error(yaml + ": cannot write the file (" + ec.message() + ")");
  return yaml;
}

}  // namespace tt
