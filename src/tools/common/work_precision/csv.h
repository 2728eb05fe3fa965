#pragma once
// The rows of work_precision.csv, shared by every benchmark that writes them
// (bench_work_precision, bench_bullet_peer): one run's error, time and work, and the writer.
#include <algorithm>
#include <cstdio>
#include <string>

#include "work_precision_problems.h"

namespace tt {
namespace work_precision {

const char* const kCsvHeader =
    "problem,model,integrator,parameter,error,cpu_seconds,wall_seconds,steps,rejected_steps,"
    "newton_iterations,linear_iterations,stable,parameter_name,discrete_error,tets,note";

struct RunResult {
  Errors errors;
  double cpu = 0.0, wall = 0.0;
  long steps = 0, rejected = 0, newton = 0, linear = 0;
  bool stable = true;
  int tets = 0;
};

// Free text made safe for one CSV field.
inline std::string csvText(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

inline void writeRunRow(FILE* csv, const std::string& problem, const std::string& model,
                        const std::string& integrator, const std::string& parameterName,
                        double parameter, const RunResult& r) {
  std::fprintf(csv, "%s,%s,%s,%.6g,%.6g,%.6g,%.6g,%ld,%ld,%ld,%ld,%d,%s,%.6g,%d,%s\n",
               problem.c_str(), model.c_str(), integrator.c_str(), parameter, r.errors.error,
               r.cpu, r.wall, r.steps, r.rejected, r.newton, r.linear, r.stable ? 1 : 0,
               parameterName.c_str(), r.errors.discrete, r.tets, csvText(r.errors.note).c_str());
  std::fflush(csv);
}

}  // namespace work_precision
}  // namespace tt
