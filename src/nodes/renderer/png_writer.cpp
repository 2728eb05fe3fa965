#include "png_writer.h"

#include <png.h>

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace tt_render {

namespace {

void writePngFile(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!file) throw std::runtime_error("writePng: cannot open " + path + " for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("writePng: libpng initialisation failed");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("writePng: libpng failed writing " + path);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (int row = 0; row < height; ++row)
    png_write_row(png, const_cast<png_bytep>(&rgb[std::size_t(row) * width * 3]));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0) throw std::runtime_error("writePng: cannot write " + path);
}

}  // namespace

// Written beside the target and renamed over it, so that a reader (a viewer, a test) never
// sees a partly written frame.
void writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (rgb.size() != std::size_t(width) * height * 3)
    throw std::runtime_error("writePng: " + path + ": image size does not match the data");
  const std::string partial = path + ".partial";
  try {
    writePngFile(partial, width, height, rgb);
  } catch (...) {
    std::remove(partial.c_str());
    throw;
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0) {
    std::remove(partial.c_str());
    throw std::runtime_error("writePng: cannot rename " + partial + " to " + path);
  }
}

}  // namespace tt_render
