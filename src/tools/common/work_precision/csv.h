#pragma once
// The rows of work_precision.csv, shared by every benchmark that writes them
// (bench_work_precision, bench_bullet_peer): one run's error, time and work, and the writer.
#include <cstdio>
#include <string>

#include "common/work_precision/problem.h"

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
std::string csvText(std::string s);

// One row of kCsvHeader's columns, flushed.
void writeRunRow(FILE* csv, const std::string& problem, const std::string& model,
                 const std::string& integrator, const std::string& parameterName,
                 double parameter, const RunResult& r);

}  // namespace work_precision
}  // namespace tt
