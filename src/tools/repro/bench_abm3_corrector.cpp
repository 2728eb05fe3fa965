// The corrector of the Adams-Bashforth-Moulton method of "Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.5.4, as printed (Eqs. 2.140-2.141) and as the integrator uses it
// (integrate/abm3.h), on two scalar problems with known solutions:
//   u'' = -u, u(0) = 1, u'(0) = 0 (u = cos t), position error at t = 6.4;
//   y'  = -y, y(0) = 1 (y = e^-t), error at t = 1;
// for h = 0.1, 0.05, ..., 0.00625, starting from the exact values at t = h and 2h or from two
// forward-Euler steps (the chapter's start). Prints the errors and the observed orders
// log2(e(h) / e(h/2)).
//
//   bench_abm3_corrector [--quick]   (--quick: the same; it takes milliseconds)
//
// With a = M^-1 F and the Adams-Bashforth predictor of Eqs. 2.138-2.139 (the same in both), the
// printed corrector is
//   v+ = v_i + h (5/12 v~ + 8/12 a_i - 1/12 a_i-1),
//   u+ = u_i + h (5/12 u~ + 8/12 v_i - 1/12 v_i-1)
// (the predicted velocity where an acceleration belongs, the predicted position where a
// velocity belongs); the Adams-Moulton corrector is
//   v+ = v_i + h (5/12 a(u~, v~) + 8/12 a_i - 1/12 a_i-1),
//   u+ = u_i + h (5/12 v~ + 8/12 v_i - 1/12 v_i-1).
// For y' = f(y) the printed form reads y+ = y_i + h (5/12 y~ + 8/12 f_i - 1/12 f_i-1).
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "common/command_line.h"

namespace {

enum class Corrector { kPrinted, kAdamsMoulton };
enum class Start { kExact, kEuler };

// y' = f(y) for y in R^n.
using Vec = std::vector<double>;
using Rhs = std::function<Vec(const Vec&)>;

Vec axpy(const Vec& y, double h, const std::array<double, 3>& c, const std::array<Vec, 3>& f) {
  Vec out = y;
  for (size_t k = 0; k < y.size(); ++k)
    out[k] += h * (c[0] * f[0][k] + c[1] * f[1][k] + c[2] * f[2][k]) / 12.0;
  return out;
}

// Integrates to `end` with n = end / h steps; `printedTerm` gives, for a predicted state,
// what the printed corrector puts where f(y~) belongs.
Vec integrate(const Rhs& f, const Rhs& printedTerm, const std::function<Vec(double)>& exact,
              double end, double h, Corrector corrector, Start start) {
  const int n = static_cast<int>(std::lround(end / h));
  Vec y = exact(0.0);
  std::array<Vec, 3> history;  // f_i, f_i-1, f_i-2
  history[0] = f(y);
  for (int i = 0; i < 2; ++i) {  // the two starting steps
    if (start == Start::kExact) {
      y = exact((i + 1) * h);
    } else {
      for (size_t k = 0; k < y.size(); ++k) y[k] += h * history[0][k];
    }
    history[2] = history[1];
    history[1] = history[0];
    history[0] = f(y);
  }
  for (int i = 2; i < n; ++i) {
    const Vec predicted = axpy(y, h, {23.0, -16.0, 5.0}, history);
    const Vec term = corrector == Corrector::kPrinted ? printedTerm(predicted) : f(predicted);
    y = axpy(y, h, {5.0, 8.0, -1.0}, {term, history[0], history[1]});
    history[2] = history[1];
    history[1] = history[0];
    history[0] = f(y);
  }
  return y;
}

void table(const char* title, const Rhs& f, const Rhs& printedTerm,
           const std::function<Vec(double)>& exact, double end) {
  std::printf("%s\n", title);
  std::printf("%-40s %-52s %s\n", "corrector, start", "error at h = 0.1 0.05 0.025 0.0125 0.00625",
              "observed orders");
  for (Corrector corrector : {Corrector::kPrinted, Corrector::kAdamsMoulton})
    for (Start start : {Start::kExact, Start::kEuler}) {
      std::vector<double> errors;
      for (double h = 0.1; h > 0.006; h /= 2.0) {
        const Vec y = integrate(f, printedTerm, exact, end, h, corrector, start);
        errors.push_back(std::abs(y[0] - exact(end)[0]));
      }
      const std::string label =
          std::string(corrector == Corrector::kPrinted ? "printed 2.140-2.141" : "Adams-Moulton") +
          (start == Start::kExact ? ", exact start" : ", forward Euler start");
      std::printf("%-40s", label.c_str());
      for (double e : errors) std::printf(" %9.3g", e);
      std::printf("   ");
      for (size_t k = 1; k < errors.size(); ++k)
        std::printf(" %5.2f", std::log2(errors[k - 1] / errors[k]));
      std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
  tt::tools::CommandLine options(argc, argv, "bench_abm3_corrector [--quick]");
  options.flag("--quick");
  options.finish();
  // y = (u, v), f = (v, -u): the printed corrector puts u~ where v(y~) belongs (the position
  // equation) and v~ where a(y~) = -u~ belongs (the velocity equation), i.e. y~ itself.
  const Rhs oscillator = [](const Vec& y) { return Vec{y[1], -y[0]}; };
  const Rhs oscillatorPrinted = [](const Vec& y) { return Vec{y[0], y[1]}; };
  const auto cosine = [](double t) { return Vec{std::cos(t), -std::sin(t)}; };
  table("u'' = -u, u(0) = 1, u'(0) = 0: |u - cos t| at t = 6.4", oscillator, oscillatorPrinted,
        cosine, 6.4);
  const Rhs decay = [](const Vec& y) { return Vec{-y[0]}; };
  const Rhs decayPrinted = [](const Vec& y) { return y; };
  const auto exponential = [](double t) { return Vec{std::exp(-t)}; };
  std::printf("\n");
  table("y' = -y, y(0) = 1: |y - e^-t| at t = 1", decay, decayPrinted, exponential, 1.0);
  return 0;
}
