#include "tissue_trainer/core/haptics/contact_model.h"

#include <cmath>

namespace tt {

bool ContactModel::isFinite() const {
  return std::isfinite(stamp) && std::isfinite(simTime) && x0.allFinite() && f0.allFinite() &&
         K.allFinite();
}

LinearForceField LinearForceField::blend(const LinearForceField& a, const LinearForceField& b,
                                         double w) {
  // (1-w)(fa - Ka (x - xa)) + w (fb - Kb (x - xb)), rewritten around xb.
  LinearForceField out;
  out.x0 = b.x0;
  out.f0 = (1.0 - w) * a.at(b.x0) + w * b.f0;
  out.K = (1.0 - w) * a.K + w * b.K;
  return out;
}

}  // namespace tt
