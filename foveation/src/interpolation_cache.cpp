#include "foveation/interpolation_cache.hpp"

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <deque>
#include <vector>

#include <xxhash.h>

#include "cache_file.hpp"

namespace foveart::foveation {

namespace {

constexpr char kMagic[8] = {'F', 'V', 'I', 'N', 'T', 'B', 'L', '1'};

std::string hexf(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

template <typename T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Fields of a mapped file in order; each get fails (false) past its end.
struct Reader {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;

  template <typename T>
  bool get(T& v) {
    if (sizeof v > size - at) return false;
    std::memcpy(&v, data + at, sizeof v);
    at += sizeof v;
    return true;
  }
  template <typename T>
  bool get_vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    if (!get(n) || n > (size - at) / sizeof(T)) return false;
    v.resize(std::size_t(n));
    if (n > 0) std::memcpy(v.data(), data + at, std::size_t(n) * sizeof(T));
    at += std::size_t(n) * sizeof(T);
    return true;
  }
};

// The payload as pieces, in file order: scalars and array lengths in small
// buffers of its own, the arrays straight from the table's memory (a k = 20
// RBF table is ~465 MB: no copy of it is made to write it).
class PayloadPieces {
 public:
  explicit PayloadPieces(const InterpolationTable& t) {
    scalar(std::int32_t(t.width_px));
    scalar(std::int32_t(t.height_px));
    scalar(t.stats);
    scalar(t.build_ms);
    array(t.weights_f32);
    array(t.weights_f16);
    array(t.weight_sum);
    const auto& l = t.layout;
    scalar(std::int32_t(l.width_px));
    scalar(std::int32_t(l.height_px));
    scalar(std::int32_t(l.k));
    array(l.tile_level);
    array(l.tile_first_block);
    array(l.block_palette);
    array(l.palette);
    array(l.slot);
  }
  const std::vector<detail::ByteSpan>& pieces() const { return pieces_; }
  std::size_t size() const {
    std::size_t n = 0;
    for (const auto& p : pieces_) n += p.size;
    return n;
  }

 private:
  template <typename T>
  void scalar(const T& v) {
    std::string& s = small_.emplace_back();  // a deque: earlier buffers stay where they are
    put(s, v);
    pieces_.push_back({s.data(), s.size()});
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    scalar(std::uint64_t(v.size()));
    if (!v.empty()) pieces_.push_back(detail::bytes_of(v.data(), v.size()));
  }
  std::deque<std::string> small_;
  std::vector<detail::ByteSpan> pieces_;
};

}  // namespace

std::string interpolation_cache_params(const PointSetKey& key, const PointSet& points, const InterpOptions& o,
                                       WeightPrecision precision) {
  const auto& d = key.display;
  const std::uint64_t points_hash =
      XXH3_64bits(points.position_px.data(), points.position_px.size() * sizeof(points.position_px[0]));
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016" PRIx64, points_hash);
  return "interp-v" + std::to_string(kInterpCacheFormatVersion) + ";pointset-v" + std::to_string(kCacheFormatVersion) +
         ";display=" + d.name + ";pattern=" + std::string(fovea_pattern_name(d.fovea_pattern)) + ";w=" + std::to_string(d.width_px) + ";h=" + std::to_string(d.height_px) +
         ";D=" + hexf(d.view_distance_px) + ";scale=" + hexf(d.scale) + ";ct0=" + hexf(d.csf.ct0) +
         ";alpha=" + hexf(d.csf.alpha) + ";e2=" + hexf(d.csf.e2_deg) + ";seed=" + std::to_string(key.seed) +
         ";points=" + std::to_string(points.size()) + ";canvas=" + std::to_string(points.canvas_width_px) + "x" +
         std::to_string(points.canvas_height_px) + ";points_xxh3=" + hash + ";method=" + std::string(method_name(o.method)) +
         ";k=" + std::to_string(o.k) + ";shape=" + hexf(effective_shape(o)) +
         ";constant=" + (o.constant_term ? "1" : "0") + ";rcond_min=" + hexf(o.rcond_min) +
         ";residual_max=" + hexf(o.residual_max) + ";precision=" + (precision == WeightPrecision::f16 ? "f16" : "f32");
}

std::filesystem::path interpolation_cache_path(const std::filesystem::path& dir, const std::string& params,
                                               const InterpOptions& o) {
  char name[96];
  std::snprintf(name, sizeof name, "interp_%s_k%d_%016" PRIx64 ".bin", std::string(method_name(o.method)).c_str(), o.k,
                XXH3_64bits(params.data(), params.size()));
  return dir / name;
}

std::string save_interpolation_table(const std::filesystem::path& file, const std::string& params,
                                     const InterpolationTable& t) {
  const PayloadPieces payload(t);
  std::string header(kMagic, sizeof kMagic);
  put(header, kInterpCacheFormatVersion);
  put(header, std::uint32_t(params.size()));
  header += params;
  put(header, std::uint64_t(payload.size()));
  put(header, detail::xxh3_of(payload.pieces()));
  std::vector<detail::ByteSpan> pieces{{header.data(), header.size()}};
  pieces.insert(pieces.end(), payload.pieces().begin(), payload.pieces().end());
  return detail::write_file_atomically(file, pieces);
}

std::optional<InterpolationTable> load_interpolation_table(const std::filesystem::path& file, const std::string& params,
                                                           std::string* error) {
  auto fail = [&](const std::string& why) -> std::optional<InterpolationTable> {
    if (error) *error = file.string() + ": " + why;
    return std::nullopt;
  };
  std::string why;
  const auto mapped = detail::map_file(file, &why);
  if (!mapped) return fail(why);
  // Straight from the mapping into the table's arrays: one copy of the payload.
  Reader in{mapped->bytes, mapped->size};
  if (in.size < sizeof kMagic || std::memcmp(in.data, kMagic, sizeof kMagic) != 0) {
    return fail("not an interpolation table (bad magic)");
  }
  in.at = sizeof kMagic;
  std::uint32_t version = 0, params_len = 0;
  if (!in.get(version)) return fail("truncated header");
  if (version != kInterpCacheFormatVersion) {
    return fail("format version " + std::to_string(version) + ", expected " + std::to_string(kInterpCacheFormatVersion));
  }
  if (!in.get(params_len) || params_len > in.size - in.at) return fail("truncated header");
  const std::string stored(reinterpret_cast<const char*>(in.data + in.at), params_len);
  in.at += params_len;
  if (stored != params) return fail("built for other parameters: '" + stored + "', wanted '" + params + "'");
  std::uint64_t size = 0, checksum = 0;
  if (!in.get(size) || !in.get(checksum)) return fail("truncated header");
  if (in.size - in.at != size) {
    return fail("payload is " + std::to_string(in.size - in.at) + " bytes, header says " + std::to_string(size) +
                " (truncated or padded)");
  }
  if (XXH3_64bits(in.data + in.at, std::size_t(size)) != checksum) return fail("checksum mismatch (corrupt)");
  InterpolationTable t;
  std::int32_t w = 0, h = 0;
  if (!in.get(w) || !in.get(h) || !in.get(t.stats) || !in.get(t.build_ms) || !in.get_vec(t.weights_f32) ||
      !in.get_vec(t.weights_f16) || !in.get_vec(t.weight_sum)) {
    return fail("payload layout does not parse");
  }
  auto& l = t.layout;
  std::int32_t lw = 0, lh = 0, lk = 0;
  if (!in.get(lw) || !in.get(lh) || !in.get(lk) || !in.get_vec(l.tile_level) || !in.get_vec(l.tile_first_block) ||
      !in.get_vec(l.block_palette) || !in.get_vec(l.palette) || !in.get_vec(l.slot) || in.at != in.size) {
    return fail("gather layout does not parse");
  }
  l.width_px = lw, l.height_px = lh, l.k = lk;
  t.width_px = w;
  t.height_px = h;
  return t;
}

CachedTable load_or_build_interpolation_table(const std::optional<std::filesystem::path>& cache_dir,
                                              const PointSetKey& key, const PointSet& points,
                                              const NeighborTable& neighbors, const InterpOptions& options,
                                              Executor& executor, std::optional<WeightPrecision> precision,
                                              const ProgressFn& progress, const LogFn& log) {
  const auto start = std::chrono::steady_clock::now();
  const WeightPrecision prec = precision.value_or(kDefaultWeightPrecision);
  InterpOptions opts = options;
  opts.shape = effective_shape(options);
  const std::string params = interpolation_cache_params(key, points, opts, prec);
  CachedTable result;
  std::filesystem::path file;
  if (cache_dir) {
    file = interpolation_cache_path(*cache_dir, params, opts);
    std::string error;
    if (auto t = load_interpolation_table(file, params, &error)) {
      const std::size_t expect = t->pixel_count() * std::size_t(opts.k);
      const bool sizes_ok = t->width_px == neighbors.width_px() && t->height_px == neighbors.height_px() &&
                            (opts.method == InterpMethod::nearest ||
                             (prec == WeightPrecision::f16 ? t->weights_f16.size() : t->weights_f32.size()) == expect);
      // Every slot inside its palette, every palette entry a point: the gather never reads out of bounds.
      const std::string layout_error =
          !sizes_ok || opts.method == InterpMethod::nearest
              ? std::string()
              : gather_layout_error(t->layout, neighbors.width_px(), neighbors.height_px(), opts.k, points.size());
      if (sizes_ok && layout_error.empty()) {
        t->options = opts;
        t->precision = prec;
        result.table = std::move(*t);
        result.from_cache = true;
      } else if (log) {
        log(file.string() + ": " + (sizes_ok ? layout_error : "sizes do not match the neighbour table") + "; rebuilding");
      }
    } else if (log && std::filesystem::exists(file)) {  // a missing file is a first build, not a rejection
      log("interpolation cache rejected: " + error + "; rebuilding");
    }
  }
  if (!result.from_cache) {
    result.table = build_interpolation_table(points, neighbors, opts, executor, prec, progress);
    if (cache_dir) {
      if (auto err = save_interpolation_table(file, params, result.table); !err.empty() && log) log(err);
    }
  }
  result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace foveart::foveation
