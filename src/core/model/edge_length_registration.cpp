// Registers edge_length (and its preset edge_length_literal) in the scene registry.
#include "tissue_trainer/core/material/elastic_constants_reader.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerEdgeLengthModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "edge_length";
  e.description =
      "transversely isotropic St Venant-Kirchhoff tetrahedron written with edge lengths";
  e.keys = {{"path",
             "fast (F, E, S; default) | literal (the packed edge-length sum of Eq 31 and energy) | "
             "eq30 (the unpacked two-sum force of Eq 30, same energy)"},
            {"psd_projection",
             "false (default) | true: the system matrix from a positive semi-definite stiffness "
             "(S's negative eigenvalues and a negative fibre coefficient clamped to zero); forces unchanged"}};
  e.presets = {{"edge_length", "", "the fast path"},
               {"edge_length_literal", "{path: literal}", "the literal edge-length path"}};
  e.make = [](const YamlEntry& spec, const ModelContext& c) -> std::unique_ptr<ForceModel> {
    EdgeLengthPath path = EdgeLengthPath::kFast;
    if (spec.has("path")) parseEdgeLengthPath(spec["path"].choice({"fast", "literal", "eq30"}), path);
    return std::make_unique<EdgeLengthModel>(c.mesh, withLameConstants(c, "edge_length"), path,
                                             spec.boolean("psd_projection", false));
  };
  registry.add(std::move(e));
}

}  // namespace tt
