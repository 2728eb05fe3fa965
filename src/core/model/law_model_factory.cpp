#include "tissue_trainer/core/model/law_model_factory.h"

namespace tt {

LawOptions readLawOptions(const YamlEntry& spec) {
  LawOptions options;
  if (spec.has("inversion_threshold")) {
    const YamlEntry eps = spec["inversion_threshold"];
    options.inversionThreshold = eps.number();
    if (!(options.inversionThreshold >= 0.0 && options.inversionThreshold < 1.0))
      eps.fail("expected a threshold in [0, 1) (a singular value of F; 0 turns it off)");
  }
  options.psdProjection = spec.boolean("psd_projection", false);
  return options;
}

std::vector<KeyDoc> lawOptionKeys() {
  return {{"inversion_threshold",
           "eps >= 0: singular values of F clamped at eps, so inverted elements push back "
           "(0, the default, turns it off)"},
          {"psd_projection",
           "true: the stiffness and stiffness products use the law's tangent with negative "
           "eigenvalues removed (default false)"}};
}

}  // namespace tt
