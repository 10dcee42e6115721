// The converged reference (reference.hpp): two independent halves, the
// residual from their difference, a checksummed cache file per key.
#include <eval/reference.hpp>

#include <engine/render.hpp>

#include <foveation/elapsed.hpp>

#include <foveation/srgb.hpp>

#include <xxhash.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <unistd.h>

namespace foveart::eval {
namespace {

constexpr char kMagic[8] = {'F', 'V', 'R', 'T', 'R', 'E', 'F', '1'};
constexpr std::uint32_t kVersion = 2;  // 2: the signed luma half difference
constexpr int kChunkSpp = 8;  // rays per pixel of one render; halves take alternate chunks

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t width_px;
  std::uint32_t height_px;
  std::uint32_t spp;
  std::uint64_t key;
};
static_assert(sizeof(Header) == 32);

template <class T>
void hash_vector(XXH3_state_t* s, const std::vector<T>& v) {
  const std::uint64_t n = v.size();
  XXH3_64bits_update(s, &n, sizeof n);
  if (!v.empty()) XXH3_64bits_update(s, v.data(), sizeof(T) * v.size());
}

template <class T>
void hash_value(XXH3_state_t* s, const T& v) {
  XXH3_64bits_update(s, &v, sizeof v);
}

using foveation::ms_since;

float encode(float linear) {
  return foveation::linear_to_srgb(std::clamp(std::isnan(linear) ? 0.0f : linear, 0.0f, 1.0f));
}

}  // namespace

std::array<double, metrics::kRingCount> Reference::residual_mse(const metrics::EccentricityMap& map) const {
  std::array<double, metrics::kRingCount> out{};
  if (half_difference2.size() != map.ring.size()) {
    out.fill(std::numeric_limits<double>::quiet_NaN());
    return out;
  }
  for (std::size_t i = 0; i < map.ring.size(); ++i) out[map.ring[i]] += double(half_difference2[i]);
  for (std::size_t r = 0; r < out.size(); ++r)
    out[r] = map.ring_pixels[r] ? out[r] / (4.0 * double(map.ring_pixels[r])) : std::numeric_limits<double>::quiet_NaN();
  return out;
}

std::uint64_t scene_content_hash(const engine::Scene& scene) {
  XXH3_state_t* s = XXH3_createState();
  XXH3_64bits_reset(s);
  hash_vector(s, scene.mesh.positions);
  hash_vector(s, scene.mesh.normals);
  hash_vector(s, scene.mesh.uv0);
  hash_vector(s, scene.mesh.uv1);
  hash_vector(s, scene.mesh.triangles);
  hash_vector(s, scene.mesh.triangle_material);
  for (const engine::Material& m : scene.materials) {
    hash_value(s, m.base_color);
    hash_value(s, m.base_color_texture);
    hash_value(s, m.base_color_texcoord);
    hash_value(s, m.metallic);
    hash_value(s, m.roughness);
    hash_value(s, m.emissive);
    hash_value(s, m.alpha_mode);
    hash_value(s, m.alpha_cutoff);
    hash_value(s, m.transmission);
    hash_value(s, m.ior);
    hash_value(s, m.double_sided);
  }
  for (const engine::Texture& t : scene.textures) {
    hash_value(s, t.width);
    hash_value(s, t.height);
    hash_vector(s, t.texels);
    hash_value(s, t.wrap_s);
    hash_value(s, t.wrap_t);
    hash_value(s, t.nearest);
  }
  for (const engine::Light& l : scene.lights) {
    hash_value(s, l.type);
    hash_value(s, l.position);
    hash_value(s, l.direction);
    hash_value(s, l.color);
    hash_value(s, l.intensity);
    hash_value(s, l.range);
    hash_value(s, l.inner_cone_rad);
    hash_value(s, l.outer_cone_rad);
  }
  hash_value(s, scene.sky_zenith);
  hash_value(s, scene.sky_horizon);
  hash_value(s, scene.ambient);
  const std::uint64_t h = XXH3_64bits_digest(s);
  XXH3_freeState(s);
  return h;
}

std::uint64_t rendered_scene_hash(const engine::Tracer& tracer) {
  const std::uint64_t content = scene_content_hash(tracer.scene());
  if (tracer.effects() == tracer.scene_effects()) return content;
  XXH3_state_t* s = XXH3_createState();
  XXH3_64bits_reset(s);
  hash_value(s, content);
  hash_value(s, tracer.effects().bits());
  const std::uint64_t h = XXH3_64bits_digest(s);
  XXH3_freeState(s);
  return h;
}

std::uint64_t reference_key(std::uint64_t scene_hash, const FoveartEyeView& view, int spp, std::uint64_t seed,
                            foveation::PixelFilter filter) {
  XXH3_state_t* s = XXH3_createState();
  XXH3_64bits_reset(s);
  hash_value(s, scene_hash);
  // The view field by field (no padding bytes): size, frustum, pose.
  hash_value(s, view.width_px);
  hash_value(s, view.height_px);
  hash_value(s, view.angle_left_rad);
  hash_value(s, view.angle_right_rad);
  hash_value(s, view.angle_up_rad);
  hash_value(s, view.angle_down_rad);
  for (float p : view.position_m) hash_value(s, p);
  for (float q : view.orientation_xyzw) hash_value(s, q);
  hash_value(s, spp);
  hash_value(s, seed);
  hash_value(s, filter);
  hash_value(s, kChunkSpp);
  const std::uint64_t h = XXH3_64bits_digest(s);
  XXH3_freeState(s);
  return h;
}

std::filesystem::path reference_cache_path(const std::string& cache_dir, std::uint64_t scene_hash,
                                           const FoveartEyeView& view, int spp, std::uint64_t seed,
                                           foveation::PixelFilter filter) {
  char name[64];
  std::snprintf(name, sizeof name, "reference_%016llx.bin",
                static_cast<unsigned long long>(reference_key(scene_hash, view, spp, seed, filter)));
  return std::filesystem::path(cache_dir) / name;
}

std::string write_reference(const std::filesystem::path& file, std::uint64_t key, const Reference& ref) {
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kVersion;
  h.width_px = std::uint32_t(ref.image.width_px);
  h.height_px = std::uint32_t(ref.image.height_px);
  h.spp = std::uint32_t(ref.spp);
  h.key = key;
  XXH3_state_t* s = XXH3_createState();
  XXH3_64bits_reset(s);
  XXH3_64bits_update(s, &h, sizeof h);
  XXH3_64bits_update(s, ref.image.rgb.data(), ref.image.rgb.size() * sizeof(float));
  XXH3_64bits_update(s, ref.half_difference2.data(), ref.half_difference2.size() * sizeof(float));
  XXH3_64bits_update(s, ref.half_difference_luma.data(), ref.half_difference_luma.size() * sizeof(float));
  const std::uint64_t sum = XXH3_64bits_digest(s);
  XXH3_freeState(s);
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  // Written beside the final name and renamed over it: readers never see a partial file.
  const std::filesystem::path tmp = file.string() + "." + std::to_string(::getpid()) + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(ref.image.rgb.data()), std::streamsize(ref.image.rgb.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(ref.half_difference2.data()),
              std::streamsize(ref.half_difference2.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(ref.half_difference_luma.data()),
              std::streamsize(ref.half_difference_luma.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    if (!out) {
      std::filesystem::remove(tmp, ec);
      return "reference cache " + file.string() + ": cannot write";
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return "reference cache " + file.string() + ": cannot rename into place";
  }
  return "";
}

std::optional<Reference> read_reference(const std::filesystem::path& file, std::uint64_t key, std::string* error) {
  const auto fail = [&](const std::string& what) -> std::optional<Reference> {
    *error = "reference cache " + file.string() + ": " + what;
    return std::nullopt;
  };
  std::ifstream in(file, std::ios::binary);
  if (!in) return fail("not found");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Header h{};
  if (bytes.size() < sizeof h + sizeof(std::uint64_t)) return fail("truncated (" + std::to_string(bytes.size()) + " bytes)");
  std::memcpy(&h, bytes.data(), sizeof h);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return fail("not a reference file (bad magic)");
  if (h.version != kVersion) return fail("version " + std::to_string(h.version) + ", expected " + std::to_string(kVersion));
  if (h.key != key) return fail("key mismatch (another scene, view, count or pixel filter)");
  const std::uint64_t pixels = std::uint64_t(h.width_px) * h.height_px;
  if (h.width_px == 0 || h.height_px == 0 || h.width_px > 65536 || h.height_px > 65536)
    return fail("bad size " + std::to_string(h.width_px) + "x" + std::to_string(h.height_px));
  const std::uint64_t payload = pixels * 5 * sizeof(float);  // image (3), half_difference2, half_difference_luma
  if (bytes.size() != sizeof h + payload + sizeof(std::uint64_t))
    return fail("size " + std::to_string(bytes.size()) + " bytes does not match the header");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + sizeof h + payload, sizeof stored);
  if (XXH3_64bits(bytes.data(), sizeof h + payload) != stored) return fail("checksum mismatch (corrupt)");
  Reference ref;
  ref.image = foveation::ImageRgb(int(h.width_px), int(h.height_px));
  ref.half_difference2.resize(pixels);
  ref.half_difference_luma.resize(pixels);
  std::memcpy(ref.image.rgb.data(), bytes.data() + sizeof h, pixels * 3 * sizeof(float));
  std::memcpy(ref.half_difference2.data(), bytes.data() + sizeof h + pixels * 3 * sizeof(float), pixels * sizeof(float));
  std::memcpy(ref.half_difference_luma.data(), bytes.data() + sizeof h + pixels * 4 * sizeof(float),
              pixels * sizeof(float));
  ref.spp = int(h.spp);
  ref.from_cache = true;
  ref.cache_file = file.string();
  return ref;
}

std::optional<Reference> converged_reference(FoveartTraceRaysFn fn, void* user_data, std::uint64_t scene_hash,
                                             const FoveartEyeView& view, glm::vec2 gaze_px,
                                             const ReferenceOptions& o, foveation::Executor& executor,
                                             const ReferenceLog& log, std::string* error) {
  if (o.spp != 0 && (o.spp < 2 || o.spp % 2 != 0 || (o.spp > 2 * kChunkSpp && o.spp % (2 * kChunkSpp) != 0))) {
    *error = "reference rays per pixel must be 2, 4, ..., 16 or a multiple of 16, got " + std::to_string(o.spp);
    return std::nullopt;
  }
  const metrics::EccentricityMap map = metrics::eccentricity_map(view, gaze_px);
  const int w = int(view.width_px), h = int(view.height_px);
  const std::size_t n = std::size_t(w) * std::size_t(h);
  // Running sums of the two halves (linear), chunk by chunk: chunk j (kChunkSpp
  // rays per pixel, seed from j) goes to half j % 2. A larger count reuses the
  // chunks of a smaller one, so the check's doubling costs no repeated work.
  std::vector<double> sum_a(n * 3, 0.0), sum_b(n * 3, 0.0);
  int chunks = 0;
  int sums_chunk_spp = 0;  // rays per pixel of each chunk in the sums
  double render_ms = 0.0;
  foveation::ImageRgb chunk;
  const auto render_to = [&](int spp) -> bool {
    const int chunk_spp = std::min(kChunkSpp, spp / 2);
    if (chunk_spp != sums_chunk_spp) {  // a count below two full chunks: start afresh
      std::fill(sum_a.begin(), sum_a.end(), 0.0);
      std::fill(sum_b.begin(), sum_b.end(), 0.0);
      chunks = 0;
      sums_chunk_spp = chunk_spp;
    }
    while (chunks * chunk_spp < spp) {
      engine::RenderSettings settings;
      settings.spp = chunk_spp;
      settings.seed = 0x5EF0000000ull + o.seed * 65536u + std::uint64_t(chunks);
      settings.pixel_filter = o.pixel_filter;
      const auto t0 = std::chrono::steady_clock::now();
      const engine::RenderResult rr = engine::render_full(fn, user_data, view, settings, &chunk, executor);
      render_ms += ms_since(t0);
      if (rr.status != FOVEART_RESULT_SUCCESS) {
        *error = "reference render: engine callback failed with status " + std::to_string(rr.status);
        return false;
      }
      std::vector<double>& sum = chunks % 2 == 0 ? sum_a : sum_b;
      for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += double(chunk.rgb[i]);
      ++chunks;
    }
    return true;
  };
  const auto finish = [&](int spp) {
    Reference ref;
    ref.spp = spp;
    ref.image = foveation::ImageRgb(w, h);
    ref.half_difference2.resize(n);
    ref.half_difference_luma.resize(n);
    const double per_half = double(chunks / 2);
    for (std::size_t i = 0; i < n; ++i) {
      double d2 = 0.0, d_rgb[3] = {};
      for (std::size_t c = 0; c < 3; ++c) {
        const double a = sum_a[i * 3 + c] / per_half, b = sum_b[i * 3 + c] / per_half;
        ref.image.rgb[i * 3 + c] = float(0.5 * (a + b));
        const double d = double(encode(float(a))) - double(encode(float(b)));
        d2 += d * d;
        d_rgb[c] = d;
      }
      ref.half_difference2[i] = float(d2 / 3.0);
      ref.half_difference_luma[i] = float(metrics::rec601_luma(d_rgb[0], d_rgb[1], d_rgb[2]));
    }
    return ref;
  };
  const auto residual_db = [&](const Reference& ref) {
    std::vector<double> db;
    for (double mse : ref.residual_mse(map)) db.push_back(metrics::psnr_of_mse(mse));
    return db;
  };
  const double needed_spp = double(o.baseline_spp) * std::pow(10.0, o.margin_db / 10.0);
  std::vector<int> tried;
  std::vector<double> first_db;  // the residual at min_spp
  int doublings = 0;
  int spp = o.spp != 0 ? o.spp : std::max(2, o.min_spp);
  for (;;) {
    tried.push_back(spp);
    std::optional<Reference> ref;
    std::filesystem::path file;
    const std::uint64_t key = reference_key(scene_hash, view, spp, o.seed, o.pixel_filter);
    if (!o.cache_dir.empty()) {
      file = reference_cache_path(o.cache_dir, scene_hash, view, spp, o.seed, o.pixel_filter);
      std::string why;
      ref = read_reference(file, key, &why);
      if (!ref && std::filesystem::exists(file) && log) log(why + "; rendering it again");
    }
    if (!ref) {
      if (!render_to(spp)) return std::nullopt;
      ref = finish(spp);
      if (!o.cache_dir.empty()) {
        if (std::string e = write_reference(file, key, *ref); !e.empty()) {
          *error = e;
          return std::nullopt;
        }
        ref->cache_file = file.string();
      }
    }
    const std::vector<double> db = residual_db(*ref);
    if (first_db.empty()) first_db = db;
    bool law_holds = doublings > 0;
    ref->db_per_doubling.clear();
    for (std::size_t r = 0; r < db.size() && doublings > 0; ++r) {
      const double drop = (db[r] - first_db[r]) / doublings;
      ref->db_per_doubling.push_back(drop);
      if (std::isfinite(drop) && drop < 2.0 && map.ring_pixels[r] > 0) law_holds = false;
    }
    const bool goal = double(spp) >= needed_spp && law_holds;
    if (o.spp != 0 || goal || spp * 2 > o.max_spp) {
      ref->render_ms = render_ms;
      ref->tried_spp = tried;
      ref->converged = o.spp != 0 || goal;
      return ref;
    }
    ++doublings;
    spp *= 2;
  }
}

}  // namespace foveart::eval
