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
  if (spec.has("psd_method")) {
    const YamlEntry method = spec["psd_method"];
    if (!options.psdProjection)
      method.fail("applies with psd_projection: true only (it chooses how the tangent is "
                  "projected)");
    if (method.choice({"eigen", "diagonal_blocks"}) == "diagonal_blocks")
      options.psdMethod = PsdMethod::kDiagonalBlocks;
  }
  return options;
}

std::vector<KeyDoc> lawOptionKeys() {
  return {{"inversion_threshold",
           "eps >= 0: singular values of F clamped at eps, so inverted elements push back "
           "(0, the default, turns it off)"},
          {"psd_projection",
           "true: the stiffness and stiffness products use the law's tangent with negative "
           "eigenvalues removed (default false)"},
          {"psd_method",
           "with psd_projection: true, eigen (default: the 9 x 9 tangent's negative eigenvalues "
           "set to zero) or diagonal_blocks (the muscle paper's Sec. 5.6: the isotropic part "
           "clamped block by block in the singular-value frame, the fibre tension derivative "
           "clamped at zero; teran_muscle and isotropic laws)"}};
}

}  // namespace tt
