#pragma once
// A scalar function of time, for loads that change during a run (active tension, pressure).
// A value type: copy it into the model that follows it and call value(t) at each step's start.
//
//   constant:          value(t) = c.
//   piecewise_linear:  keys (t_k, v_k) with strictly increasing t_k; linear between keys, v_0
//                      before the first key and the last value held after the last key.
//   twitch:            a periodic single twitch (period T, peak P, rise time t_r, decay time
//                      t_d, onset t_0 with t_r + t_d <= T). With s = (t - t_0) mod T in [0, T):
//                        value = P (1 - cos(pi s / t_r)) / 2              for 0 <= s < t_r,
//                        value = P (1 + cos(pi (s - t_r) / t_d)) / 2      for t_r <= s < t_r + t_d,
//                        value = 0                                        otherwise.
//                      Both halves have zero slope at their ends, so the curve is C1 (its
//                      second derivative jumps at 0, t_r and t_r + t_d): the tension rises
//                      smoothly from rest to P at s = t_r and relaxes to rest at s = t_r + t_d.
#include <string>
#include <vector>

namespace tt {

class YamlEntry;

class TimeCurve {
 public:
  enum class Kind { kConstant, kPiecewiseLinear, kTwitch };

  struct Twitch {
    double period = 1.0;
    double peak = 0.0;
    double riseTime = 0.1;
    double decayTime = 0.3;
    double onset = 0.0;  // in [0, period)
  };

  // The constant 0.
  TimeCurve() = default;

  // The factories throw std::invalid_argument for parameters outside the ranges above (not
  // finite, times not strictly increasing, sizes that differ, t_r + t_d > T, ...).
  static TimeCurve constant(double value);
  static TimeCurve piecewiseLinear(std::vector<double> times, std::vector<double> values);
  static TimeCurve twitch(const Twitch& shape);

  Kind kind() const { return kind_; }
  // The curve at time t (no allocation).
  double value(double t) const;

 private:
  double piecewiseLinearValue(double t) const;
  double twitchValue(double t) const;

  Kind kind_ = Kind::kConstant;
  double constant_ = 0.0;
  std::vector<double> times_, values_;
  Twitch twitch_;
};

// True for the curve types readTimeCurve knows (constant, piecewise_linear, twitch).
bool isTimeCurveType(const std::string& name);

// Reads a curve from a YAML map (one error line naming the file, line and key otherwise):
//   {type: constant, value: 2.5}
//   {type: piecewise_linear, times: [0, 0.1, 0.4], values: [0, 1, 0]}
//   {type: twitch, period: 1.0, peak: 20e3, rise_time: 0.1, decay_time: 0.3, onset: 0}
// (onset is optional, default 0). `scale` multiplies the values and the peak (a unit factor).
TimeCurve readTimeCurve(const YamlEntry& entry, double scale = 1.0);

}  // namespace tt
