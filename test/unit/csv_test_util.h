#pragma once
// Reading the benchmarks' CSV files in tests (plain comma-separated fields, no quoting).
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace tt {
namespace test {

inline std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

inline std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(splitCsv(line));
  return rows;
}

// The rows after the header, each as a map from the header's names to the row's fields.
inline std::vector<std::map<std::string, std::string>> namedRows(
    const std::filesystem::path& path) {
  const auto table = readCsv(path);
  std::vector<std::map<std::string, std::string>> rows;
  for (size_t i = 1; i < table.size(); ++i) {
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < table[0].size() && c < table[i].size(); ++c)
      row[table[0][c]] = table[i][c];
    rows.push_back(row);
  }
  return rows;
}

// The field `key` of a named row as a number (std::out_of_range when the column is missing).
inline double number(const std::map<std::string, std::string>& row, const std::string& key) {
  return std::stod(row.at(key));
}

}  // namespace test
}  // namespace tt
