#pragma once
// The rate of a stamped message stream as the rate checks judge it: the median over
// consecutive windows, so that one stall of a shared test machine (seen: a 25 ms scheduling
// gap on a loaded two-core machine) does not stand for the loop's steady rate, beside the
// lowest window and the longest gap between two messages, which the checks bound separately.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace tt_test {

struct StreamRate {
  double median = 0.0;      // Hz, median of the windows
  double lowest = 0.0;      // Hz, the slowest window
  double largestGap = 0.0;  // s, between two consecutive stamps
  int windows = 0;
};

// `stamps` in non-decreasing order; windows of `windowLength` seconds from the first stamp,
// the last partial window left out (at least one window is always counted).
inline StreamRate streamRate(const std::vector<double>& stamps, double windowLength) {
  StreamRate r;
  if (stamps.size() < 2 || !(windowLength > 0.0)) return r;
  std::vector<double> rates;
  std::size_t begin = 0;
  for (double start = stamps.front();; start += windowLength) {
    const double end = start + windowLength;
    if (end > stamps.back() && !rates.empty()) break;
    std::size_t i = begin;
    while (i < stamps.size() && stamps[i] < end) ++i;
    const double length = std::min(end, stamps.back()) - start;
    rates.push_back(length > 0.0 ? static_cast<double>(i - begin) / length : 0.0);
    begin = i;
    if (end > stamps.back()) break;
  }
  for (std::size_t i = 1; i < stamps.size(); ++i)
    r.largestGap = std::max(r.largestGap, stamps[i] - stamps[i - 1]);
  r.windows = static_cast<int>(rates.size());
  r.lowest = *std::min_element(rates.begin(), rates.end());
  std::nth_element(rates.begin(), rates.begin() + rates.size() / 2, rates.end());
  r.median = rates[rates.size() / 2];
  return r;
}

}  // namespace tt_test
