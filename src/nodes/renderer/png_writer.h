#pragma once
// RGB8 images to PNG files (libpng).
#include <cstdint>
#include <string>
#include <vector>

namespace tt_render {

// rgb: width * height * 3 bytes, top row first. Throws std::runtime_error on failure.
void writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace tt_render
