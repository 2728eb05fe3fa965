#pragma once
// The colour of liver parenchyma in both views of the tissue: the renderer's laparoscope image
// (its light, highlight and texture on top) and the simulation's RViz marker, so that the two
// look like the same organ. Linear RGB in [0, 1].
namespace tt_nodes {

struct TissueColour {
  float r, g, b;
};
constexpr TissueColour kParenchyma{0.62f, 0.22f, 0.18f};

}  // namespace tt_nodes
