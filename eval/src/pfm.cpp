// PFM (Debevec's portable float map): "PF\n<w> <h>\n-1.0\n" then float RGB rows, bottom row first.
#include <eval/pfm.hpp>

#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

namespace foveart::eval {

namespace {

[[nodiscard]] bool fail(std::string* error, std::string message) {
  *error = std::move(message);
  return false;
}

}  // namespace

bool write_pfm(const std::string& path, const foveation::ImageRgb& im, std::string* error) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return fail(error, "cannot write " + path);
  out << "PF\n" << im.width_px << " " << im.height_px << "\n-1.0\n";  // negative scale: little-endian
  for (int y = im.height_px - 1; y >= 0; --y)
    out.write(reinterpret_cast<const char*>(im.at(0, y)), std::streamsize(sizeof(float) * 3 * std::size_t(im.width_px)));
  if (!out) return fail(error, "cannot write " + path);
  return true;
}

bool read_pfm(const std::string& path, foveation::ImageRgb* out, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(error, path + ": cannot open");
  std::string magic;
  int w = 0, h = 0;
  double scale = 0.0;
  if (!(in >> magic >> w >> h >> scale) || magic != "PF") return fail(error, path + ": not a colour PFM (expected 'PF')");
  if (w <= 0 || h <= 0 || w > 65536 || h > 65536) return fail(error, path + ": bad size " + std::to_string(w) + "x" + std::to_string(h));
  if (!(scale < 0.0)) return fail(error, path + ": big-endian PFM is not supported");
  in.get();  // the one whitespace byte after the scale
  foveation::ImageRgb im(w, h);
  for (int y = h - 1; y >= 0; --y)
    if (!in.read(reinterpret_cast<char*>(im.at(0, y)), std::streamsize(sizeof(float) * 3 * std::size_t(w))))
      return fail(error, path + ": truncated (row " + std::to_string(h - 1 - y) + " of " + std::to_string(h) + ")");
  *out = std::move(im);
  return true;
}

}  // namespace foveart::eval
