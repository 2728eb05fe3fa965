// Registers stvk_displacement (and its preset stvk_displacement_paper_literal).
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerStvkDisplacementModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "stvk_displacement";
  e.description =
      "transversely isotropic St Venant-Kirchhoff tetrahedron in displacement form";
  e.keys = {{"alpha_sign", "correct (default) | paper_literal (the printed sign of the shape "
                           "vectors alpha)"}};
  e.presets = {{"stvk_displacement", "", "the corrected sign"},
               {"stvk_displacement_paper_literal", "{alpha_sign: paper_literal}",
                "the printed sign"}};
  e.make = [](const YamlEntry& spec, const ModelContext& c) -> std::unique_ptr<ForceModel> {
    AlphaSign sign = AlphaSign::kCorrect;
    if (spec.has("alpha_sign"))
      parseAlphaSign(spec["alpha_sign"].choice({"correct", "paper_literal"}), sign);
    return std::make_unique<StvkDisplacementModel>(
        c.mesh, withLameConstants(c, "stvk_displacement"), sign);
  };
  registry.add(std::move(e));
}

}  // namespace tt
