// fovea interpolate --interpolation nearest|msm|rbf|rbf-gauss [--k K] [--shape E0]
//                   [--no-constant] [--rbf-clamp off|taps|block]
//                   --samples FILE --queries FILE
// Interpolates each query from its k nearest samples ((distance, row) order)
// with the renderer's weight code and, for RBF, its de-ringing clamp
// (foveation/rbf_clamp.hpp); prints one value per line (%.17g).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include <nanoflann.hpp>

#include "foveation/gather.hpp"
#include "foveation/input_file.hpp"
#include "foveation/interpolation_weights.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/rbf_clamp.hpp"
#include "interp_commands.hpp"

namespace foveart::fovea {

namespace fv = foveart::foveation;

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Splits a line into exactly `fields` numbers; false and *error saying what is wrong.
[[nodiscard]] bool parse_line(std::string_view line, int fields, double* out, std::string* error) {
  int n = 0;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string_view field = trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start));
    if (n == fields) {
      *error = "expected " + std::to_string(fields) + " fields, found more";
      return false;
    }
    double v = 0.0;
    const auto* first = field.data();
    const auto* last = field.data() + field.size();
    if (!field.empty() && *first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range) {
      *error = "field " + std::to_string(n + 1) + " '" + std::string(field) + "' is out of the double range";
      return false;
    }
    if (field.empty() || ec != std::errc() || ptr != last) {
      *error = "field " + std::to_string(n + 1) + " '" + std::string(field) + "' is not a number";
      return false;
    }
    out[n++] = v;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (n != fields) {
    *error = "expected " + std::to_string(fields) + " fields, found " + std::to_string(n);
    return false;
  }
  return true;
}

struct Cloud {
  const std::vector<double>* xyv;  // x, y, value per sample
  std::size_t kdtree_get_point_count() const { return xyv->size() / 3; }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*xyv)[i * 3 + dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud, double>, Cloud, 2,
                                                 std::uint32_t>;

}  // namespace

std::string parse_csv_rows(std::istream& in, const std::string& name, int fields, std::vector<double>& values) {
  std::string line;
  int line_no = 0;
  bool first_content = true;
  double row[3] = {0, 0, 0};
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view l = trim(line);
    if (l.empty()) continue;
    std::string why;
    if (!parse_line(l, fields, row, &why)) {
      if (first_content) {  // a header line
        first_content = false;
        continue;
      }
      return name + ":" + std::to_string(line_no) + ": " + why;
    }
    first_content = false;
    for (int i = 0; i < fields; ++i) {
      if (!std::isfinite(row[i])) {
        return name + ":" + std::to_string(line_no) + ": field " + std::to_string(i + 1) + " is not finite";
      }
      values.push_back(row[i]);
    }
  }
  if (values.empty()) return name + ": no data rows";
  return {};
}

namespace {

// The options as the weight code takes them; nullopt and *error naming a bad one.
std::optional<fv::InterpOptions> interp_options(const InterpolateArgs& a, bool* clamp_rbf, std::string* error) {
  const auto method = fv::parse_method(a.interpolation);
  if (!method) {
    *error = "unknown --interpolation '" + a.interpolation + "' (nearest, msm, rbf, rbf-gauss)";
    return std::nullopt;
  }
  if (a.k < 1 || a.k > fv::kMaxNeighbors) {
    *error = "--k " + std::to_string(a.k) + " is outside 1.." + std::to_string(fv::kMaxNeighbors);
    return std::nullopt;
  }
  if (!(a.shape >= 0.0) || !std::isfinite(a.shape)) {
    *error = "--shape must be a finite number >= 0";
    return std::nullopt;
  }
  const auto rbf_clamp = fv::parse_rbf_clamp(a.rbf_clamp);
  if (!rbf_clamp) {
    *error = "unknown --rbf-clamp '" + a.rbf_clamp + "' (off, taps, block)";
    return std::nullopt;
  }
  // A scattered query has no gather block: block clamps to its own taps, the
  // range that the renderer's block range always contains.
  *clamp_rbf = *rbf_clamp != fv::RbfClamp::off &&
               (*method == fv::InterpMethod::rbf || *method == fv::InterpMethod::rbf_gauss);
  fv::InterpOptions o;
  o.method = *method;
  o.k = a.k;
  o.shape = a.shape;
  o.constant_term = !a.no_constant;
  return o;
}

// One CSV file of rows with `fields` numbers each into *values; false and *error naming the file.
[[nodiscard]] bool read_rows(const std::string& file, const char* what, int fields, std::vector<double>* values,
                             std::string* error) {
  if (const std::string problem = fv::input_file_problem(file); !problem.empty()) {
    *error = std::string(what) + " file '" + file + "': " + problem;
    return false;
  }
  std::ifstream f(file);
  if (!f) {
    *error = std::string("cannot open ") + what + " file '" + file + "'";
    return false;
  }
  *error = parse_csv_rows(f, file, fields, *values);
  return error->empty();
}

// The k nearest samples of a query in exact (distance in double, row) order: every sample within
// the k-th distance (plus a rounding margin) is a candidate, so ties are complete.
class NearestSamples {
 public:
  NearestSamples(const std::vector<double>& samples, int k)
      : samples_(samples), cloud_{&samples}, tree_(2, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16)),
        k_(std::size_t(k)), idx_(k_), dist_(k_) {
    tree_.buildIndex();
  }

  // The rows of the k nearest samples of (x, y), nearest first.
  const std::vector<std::uint32_t>& of(const double qp[2]) {
    const std::size_t found = tree_.knnSearch(qp, k_, idx_.data(), dist_.data());
    double dk = 0.0;
    for (std::size_t i = 0; i < found; ++i) dk = std::max(dk, distance(idx_[i], qp));
    const double radius = dk * (1.0 + 1e-9) + 1e-12 * (std::abs(qp[0]) + std::abs(qp[1]) + 1.0);
    hits_.clear();
    tree_.radiusSearch(qp, radius * radius * (1.0 + 1e-9), hits_, nanoflann::SearchParams(32, 0.0f, false));
    cand_.clear();
    for (const auto& h : hits_) cand_.push_back({squared(h.first, qp), h.first});
    for (std::size_t i = 0; i < found; ++i)  // never fewer than k candidates
      if (std::none_of(cand_.begin(), cand_.end(), [&](const Cand& c) { return c.i == idx_[i]; }))
        cand_.push_back({squared(idx_[i], qp), idx_[i]});
    std::partial_sort(cand_.begin(), cand_.begin() + std::ptrdiff_t(k_), cand_.end(),
                      [](const Cand& x, const Cand& y) { return x.d2 != y.d2 ? x.d2 < y.d2 : x.i < y.i; });
    rows_.resize(k_);
    for (std::size_t j = 0; j < k_; ++j) rows_[j] = cand_[j].i;
    return rows_;
  }

 private:
  struct Cand {
    double d2;
    std::uint32_t i;
  };
  double squared(std::uint32_t i, const double qp[2]) const {
    const double dx = samples_[i * 3] - qp[0], dy = samples_[i * 3 + 1] - qp[1];
    return dx * dx + dy * dy;
  }
  double distance(std::uint32_t i, const double qp[2]) const {
    return std::hypot(samples_[i * 3] - qp[0], samples_[i * 3 + 1] - qp[1]);
  }

  const std::vector<double>& samples_;
  Cloud cloud_;
  Tree tree_;
  std::size_t k_;
  std::vector<std::uint32_t> idx_;
  std::vector<double> dist_;
  std::vector<std::pair<std::uint32_t, double>> hits_;
  std::vector<Cand> cand_;
  std::vector<std::uint32_t> rows_;
};

}  // namespace

int run_interpolate(const InterpolateArgs& a, std::ostream& out, std::ostream& err) {
  auto fail = [&](const std::string& msg, int code) {
    err << "fovea interpolate: " << msg << "\n";
    return code;
  };
  std::string error;
  bool clamp_rbf = false;
  const std::optional<fv::InterpOptions> o = interp_options(a, &clamp_rbf, &error);
  if (!o) return fail(error, 2);
  std::vector<double> samples, queries;
  if (!read_rows(a.samples_file, "samples", 3, &samples, &error) ||
      !read_rows(a.queries_file, "queries", 2, &queries, &error))
    return fail(error, 1);
  const std::size_t n = samples.size() / 3;
  if (std::size_t(a.k) > n)
    return fail("--k " + std::to_string(a.k) + " is larger than the " + std::to_string(n) + " samples", 2);
  if (n >= (std::size_t(1) << 32) - 1) return fail("too many samples", 1);
  NearestSamples nearest(samples, a.k);
  std::vector<fv::Vec2d> nb(std::size_t(a.k));
  std::vector<double> w(std::size_t(a.k)), f(std::size_t(a.k));
  char buf[40];
  for (std::size_t q = 0; q < queries.size() / 2; ++q) {
    const double qp[2] = {queries[q * 2], queries[q * 2 + 1]};
    const std::vector<std::uint32_t>& ids = nearest.of(qp);
    for (std::size_t j = 0; j < ids.size(); ++j) {
      nb[j] = {samples[ids[j] * 3], samples[ids[j] * 3 + 1]};
      f[j] = samples[ids[j] * 3 + 2];
    }
    fv::interpolation_weights(*o, nb, ids, {qp[0], qp[1]}, w);
    double v = fv::apply_weights(w, f);
    if (clamp_rbf) v = fv::rbf_clamp_to_taps<double>(v, f);
    if (!std::isfinite(v))
      return fail("query " + std::to_string(q + 1) + " gave a non-finite value (please report)", 1);
    std::snprintf(buf, sizeof buf, "%.17g", v);
    out << buf << '\n';
  }
  out.flush();
  return 0;
}

void register_interpolate(CLI::App& app) {
  auto args = std::make_shared<InterpolateArgs>();
  auto* sub = app.add_subcommand("interpolate", "Interpolate scattered samples at query points (CSV in, values out)");
  sub->add_option("--interpolation", args->interpolation, "nearest, msm, rbf or rbf-gauss")->required();
  sub->add_option("--k", args->k, "neighbours per query, 1..20")->capture_default_str();
  sub->add_option("--shape", args->shape, "RBF shape eps0 = eps * h_local (0 = default 0.2)");
  sub->add_flag("--no-constant", args->no_constant, "RBF without the constant term (the thesis's plain form)");
  sub->add_option("--rbf-clamp", args->rbf_clamp,
                  "RBF de-ringing as in the renderer: off (the thesis's plain RBF), taps (within the range of "
                  "the query's k samples) or block (the renderer's default; a scattered query has no gather "
                  "block, so the same as taps, whose range the renderer's block range contains)")
      ->capture_default_str();
  sub->add_option("--samples", args->samples_file, "CSV rows x,y,value (header line allowed)")->required();
  sub->add_option("--queries", args->queries_file, "CSV rows x,y (header line allowed)")->required();
  sub->callback([args] {
    const int rc = run_interpolate(*args, std::cout, std::cerr);  // never throws: problems are its exit code
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace foveart::fovea
