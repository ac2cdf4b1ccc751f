// PNG encoding and decoding through stb (compiled static here, so no other object sees its symbols).
#include "io/png_file.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include "io/atomic_file.h"

namespace dentsim {

Result<std::vector<uint8_t>> encodePng(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
    return makeError("", "cannot encode PNG: image size and pixel count disagree");
  std::vector<uint8_t> bytes;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* p = static_cast<const uint8_t*>(data);
    out->insert(out->end(), p, p + size);
  };
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(), image.width * 3))
    return makeError("", "cannot encode PNG");
  return bytes;
}

Status writePng(const std::string& path, const RgbImage& image) {
  auto bytes = encodePng(image);
  if (!bytes) return makeError(path, bytes.message());
  return writeFileAtomic(path, *bytes);
}

Result<RgbImage> readPng(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* pixels = stbi_load(path.c_str(), &w, &h, &channels, 3);
  if (!pixels) return makeError(path, std::string("cannot read PNG: ") + stbi_failure_reason());
  RgbImage image;
  image.width = w;
  image.height = h;
  image.rgb.assign(pixels, pixels + size_t(w) * size_t(h) * 3);
  stbi_image_free(pixels);
  return image;
}

}  // namespace dentsim
