#include "tissue_trainer/core/model/time_curve.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {
namespace {

constexpr double kPi = 3.14159265358979323846;

void require(bool condition, const char* what) {
  if (!condition) throw std::invalid_argument(std::string("time curve: ") + what);
}

std::string show(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::vector<double> numbers(const YamlEntry& list, double scale) {
  std::vector<double> out(list.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = scale * list[static_cast<int>(i)].number();
  return out;
}

TimeCurve readPiecewiseLinear(const YamlEntry& entry, double scale) {
  entry.expectMap({"type", "times", "values"});
  const YamlEntry timesEntry = entry["times"];
  const std::vector<double> times = numbers(timesEntry, 1.0);
  if (times.empty()) timesEntry.fail("expected a list of at least one time, got an empty list");
  for (size_t i = 1; i < times.size(); ++i)
    if (!(times[i] > times[i - 1]))
      timesEntry[static_cast<int>(i)].fail("expected strictly increasing times, got " +
                                           show(times[i]) + " after " + show(times[i - 1]));
  const YamlEntry valuesEntry = entry["values"];
  if (valuesEntry.size() != times.size())
    valuesEntry.fail("expected " + std::to_string(times.size()) + " values (one per time), got " +
                     std::to_string(valuesEntry.size()));
  return TimeCurve::piecewiseLinear(times, numbers(valuesEntry, scale));
}

TimeCurve readTwitch(const YamlEntry& entry, double scale) {
  entry.expectMap({"type", "period", "peak", "rise_time", "decay_time", "onset"});
  TimeCurve::Twitch shape;
  shape.period = entry["period"].positive();
  shape.peak = scale * entry["peak"].number();
  shape.riseTime = entry["rise_time"].positive();
  const YamlEntry decay = entry["decay_time"];
  shape.decayTime = decay.positive();
  if (shape.riseTime + shape.decayTime > shape.period)
    decay.fail("expected rise_time + decay_time <= period (" + show(shape.period) + "), got " +
               show(shape.riseTime) + " + " + show(shape.decayTime));
  if (entry.has("onset")) {
    const YamlEntry onset = entry["onset"];
    shape.onset = onset.number();
    if (shape.onset < 0.0 || shape.onset >= shape.period)
      onset.fail("expected an onset in [0, period = " + show(shape.period) + "), got " +
                 show(shape.onset));
  }
  return TimeCurve::twitch(shape);
}

}  // namespace

TimeCurve TimeCurve::constant(double value) {
  require(std::isfinite(value), "the constant is not finite");
  TimeCurve c;
  c.constant_ = value;
  return c;
}

TimeCurve TimeCurve::piecewiseLinear(std::vector<double> times, std::vector<double> values) {
  require(!times.empty(), "a piecewise linear curve needs at least one key");
  require(times.size() == values.size(), "times and values differ in number");
  for (size_t i = 0; i < times.size(); ++i)
    require(std::isfinite(times[i]) && std::isfinite(values[i]), "a key is not finite");
  for (size_t i = 1; i < times.size(); ++i)
    require(times[i] > times[i - 1], "the times are not strictly increasing");
  TimeCurve c;
  c.kind_ = Kind::kPiecewiseLinear;
  c.times_ = std::move(times);
  c.values_ = std::move(values);
  return c;
}

TimeCurve TimeCurve::twitch(const Twitch& shape) {
  require(std::isfinite(shape.peak), "the peak is not finite");
  require(shape.period > 0.0 && std::isfinite(shape.period), "the period must be positive");
  require(shape.riseTime > 0.0 && shape.decayTime > 0.0,
          "the rise and decay times must be positive");
  require(shape.riseTime + shape.decayTime <= shape.period,
          "rise time + decay time exceeds the period");
  require(shape.onset >= 0.0 && shape.onset < shape.period, "the onset is outside [0, period)");
  TimeCurve c;
  c.kind_ = Kind::kTwitch;
  c.twitch_ = shape;
  return c;
}

double TimeCurve::value(double t) const {
  switch (kind_) {
    case Kind::kPiecewiseLinear: return piecewiseLinearValue(t);
    case Kind::kTwitch: return twitchValue(t);
    default: return constant_;
  }
}

double TimeCurve::piecewiseLinearValue(double t) const {
  if (t <= times_.front()) return values_.front();
  if (t >= times_.back()) return values_.back();
  const size_t k = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) -
                                       times_.begin());  // times_[k-1] <= t < times_[k]
  const double w = (t - times_[k - 1]) / (times_[k] - times_[k - 1]);
  return (1.0 - w) * values_[k - 1] + w * values_[k];
}

double TimeCurve::twitchValue(double t) const {
  const Twitch& w = twitch_;
  double s = std::fmod(t - w.onset, w.period);
  if (s < 0.0) s += w.period;
  if (s < w.riseTime) return 0.5 * w.peak * (1.0 - std::cos(kPi * s / w.riseTime));
  if (s < w.riseTime + w.decayTime)
    return 0.5 * w.peak * (1.0 + std::cos(kPi * (s - w.riseTime) / w.decayTime));
  return 0.0;
}

bool isTimeCurveType(const std::string& name) {
  return name == "constant" || name == "piecewise_linear" || name == "twitch";
}

TimeCurve readTimeCurve(const YamlEntry& entry, double scale) {
  if (!entry.node().IsMap())
    entry.fail("expected a curve map {type: constant|piecewise_linear|twitch, ...}");
  const std::string type = entry["type"].choice({"constant", "piecewise_linear", "twitch"});
  if (type == "piecewise_linear") return readPiecewiseLinear(entry, scale);
  if (type == "twitch") return readTwitch(entry, scale);
  entry.expectMap({"type", "value"});
  return TimeCurve::constant(scale * entry["value"].number());
}

}  // namespace tt
