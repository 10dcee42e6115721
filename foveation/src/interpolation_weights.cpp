#include "foveation/interpolation_weights.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "rbf_system.hpp"

namespace foveart::foveation {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

std::string_view method_name(InterpMethod method) {
  switch (method) {
    case InterpMethod::nearest:
      return "nearest";
    case InterpMethod::msm: return "msm";
    case InterpMethod::rbf:
      return "rbf";
    case InterpMethod::rbf_gauss: return "rbf-gauss";
  }
  return "?";
}

std::optional<InterpMethod> parse_method(std::string_view name) {
  for (auto m : {InterpMethod::nearest, InterpMethod::msm, InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    if (method_name(m) == name) return m;
  }
  return std::nullopt;
}

double default_shape(InterpMethod method) {
  // Near-flat shapes converge fastest on smooth data (docs/interpolation.md sweep)
  // while staying well conditioned up to k = 20.
  (void)method;
  return 0.2;
}

double apply_weights(std::span<const double> weights, std::span<const double> values) {
  double s = 0.0;
  for (std::size_t i = 0; i < weights.size() && i < values.size(); ++i) s += weights[i] * values[i];
  return s;
}

namespace {

double distance(Vec2d a, Vec2d b) { return std::hypot(a.x - b.x, a.y - b.y); }

// Index of the first neighbour at distance 0, or -1.
int exact_hit(std::span<const Vec2d> nb, Vec2d q) {
  for (std::size_t i = 0; i < nb.size(); ++i) {
    if (nb[i].x == q.x && nb[i].y == q.y) return int(i);
  }
  return -1;
}

void one_hot(std::span<double> out, int i) {
  std::fill(out.begin(), out.end(), 0.0);
  out[std::size_t(i)] = 1.0;
}

}  // namespace

WeightStatus msm_weights(std::span<const Vec2d> nb, Vec2d q, std::span<double> out) {
  if (int hit = exact_hit(nb, q); hit >= 0) {
    one_hot(out, hit);
    return WeightStatus::exact;
  }
  std::array<double, kMaxNeighbors> h{};
  double h_min = kInf;
  double radius = 0.0;
  for (std::size_t i = 0; i < nb.size(); ++i) {
    h[i] = distance(nb[i], q);
    h_min = std::min(h_min, h[i]);
    radius = std::max(radius, h[i]);
  }
  if (h_min <= 0.0) {  // hypot underflow of a sub-denormal offset: on the point
    for (std::size_t i = 0; i < nb.size(); ++i) {
      if (h[i] <= 0.0) {
        one_hot(out, int(i));
        return WeightStatus::exact;
      }
    }
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < nb.size(); ++i) {
    out[i] = msm_weight(h[i], h_min, radius);  // Renka 1988 / thesis eq. 6, squared
    sum += out[i];
  }
  if (!(sum > 0.0)) {  // every neighbour at distance R: the symmetric mean
    std::fill(out.begin(), out.end(), 1.0 / double(nb.size()));
    return WeightStatus::equidistant;
  }
  for (auto& w : out) w /= sum;
  return WeightStatus::ok;
}

WeightInfo interpolation_weights(const InterpOptions& o, std::span<const Vec2d> nb,
                                 std::span<const std::uint32_t> ids, Vec2d q, std::span<double> out) {
  return detail::weights_cached(o, nb, ids, q, out, nullptr);
}

namespace detail {

WeightInfo weights_cached(const InterpOptions& o, std::span<const Vec2d> nb,
                          std::span<const std::uint32_t> ids, Vec2d q, std::span<double> out,
                          RbfCache* cache) {
  const std::size_t n = nb.size();
  if (n < 1 || n > std::size_t(kMaxNeighbors) || out.size() != n || (!ids.empty() && ids.size() != n)) {
    throw std::invalid_argument("interpolation_weights: need 1.." + std::to_string(kMaxNeighbors) +
                                " neighbours and as many weights (got " + std::to_string(n) + ")");
  }
  if (!std::isfinite(q.x) || !std::isfinite(q.y)) {
    throw std::invalid_argument("interpolation_weights: query is not finite");
  }
  for (const auto& p : nb) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::invalid_argument("interpolation_weights: neighbour position is not finite");
    }
  }
  WeightInfo info;
  if (o.method == InterpMethod::nearest) {
    // First minimal squared distance in list order: ties go to the lowest index.
    int best = 0;
    double best_d2 = kInf;
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = nb[i].x - q.x, dy = nb[i].y - q.y;
      const double d2 = dx * dx + dy * dy;
      if (d2 < best_d2) best_d2 = d2, best = int(i);
    }
    one_hot(out, best);
    info.status = best_d2 == 0.0 ? WeightStatus::exact : WeightStatus::ok;
    return info;
  }
  if (o.method == InterpMethod::msm) {
    info.status = msm_weights(nb, q, out);
    return info;
  }
  // RBF: on a point the interpolant is that point's value (cardinal property).
  if (int hit = exact_hit(nb, q); hit >= 0) {
    one_hot(out, hit);
    info.status = WeightStatus::exact;
    return info;
  }
  // Canonical order: ascending id (list position without ids).
  std::array<int, kMaxNeighbors> perm{};
  std::iota(perm.begin(), perm.begin() + long(n), 0);
  if (!ids.empty()) {
    std::stable_sort(perm.begin(), perm.begin() + long(n), [&](int a, int b) { return ids[std::size_t(a)] < ids[std::size_t(b)]; });
  }
  RbfCache local;
  RbfCache& c = cache ? *cache : local;
  bool hit = !ids.empty() && c.n == int(n);
  for (std::size_t i = 0; hit && i < n; ++i) hit = c.ids[i] == ids[std::size_t(perm[i])];
  if (hit) {
    ++c.hits;
  } else {
    std::array<Vec2d, kMaxNeighbors> pts{};
    for (std::size_t i = 0; i < n; ++i) pts[i] = nb[std::size_t(perm[i])];
    c.system.factor(o, std::span<const Vec2d>(pts.data(), n));
    c.n = ids.empty() ? -1 : int(n);
    for (std::size_t i = 0; i < n && !ids.empty(); ++i) c.ids[i] = ids[std::size_t(perm[i])];
    ++c.misses;
  }
  const RbfSystem& sys = c.system;
  info.rcond = sys.rcond();
  info.merged = sys.merged();
  info.collinear = sys.collinear();
  std::array<double, kMaxNeighbors> w{};
  if (sys.usable()) {
    info.residual = sys.solve(q, std::span<double>(w.data(), n));
    if (info.residual <= o.residual_max) {
      for (std::size_t i = 0; i < n; ++i) out[std::size_t(perm[i])] = w[i];
      return info;
    }
  }
  msm_weights(nb, q, out);
  info.status = WeightStatus::fallback_msm;
  return info;
}

}  // namespace detail

// ---- RbfSystem ----------------------------------------------------------------

namespace detail {

double RbfSystem::kernel(double r2) const {
  const double e2r2 = eps_ * eps_ * r2;
  // Thesis eq. 10 as sqrt(1 + (eps r)^2) (= sqrt(r^2 + c^2) / c, c = 1/eps) and eq. 9.
  return gaussian_ ? std::exp(-e2r2) : std::sqrt(1.0 + e2r2);
}

void RbfSystem::factor(const InterpOptions& o, std::span<const Vec2d> pts) {
  gaussian_ = o.method == InterpMethod::rbf_gauss;
  constant_ = o.constant_term;
  eps_ = effective_shape(o);
  n_ = int(pts.size());
  usable_ = false;
  collinear_ = false;
  rcond_ = 0.0;
  // Centre on the centroid, scale by the local spacing (rms radius of a uniform
  // disc of n points is R / sqrt(2); spacing ~ R sqrt(pi / n)).
  Vec2d c{};
  for (const auto& p : pts) c.x += p.x, c.y += p.y;
  c.x /= double(n_), c.y /= double(n_);
  double ms = 0.0;
  for (const auto& p : pts) ms += (p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y);
  const double rms = std::sqrt(ms / double(n_));
  const double h_local = rms * std::sqrt(2.0 * std::numbers::pi / double(n_));
  centre_ = c;
  inv_h_ = h_local > 0.0 && std::isfinite(h_local) ? 1.0 / h_local : 1.0;
  m_ = 0;
  for (int i = 0; i < n_; ++i) {
    const Vec2d u{(pts[std::size_t(i)].x - c.x) * inv_h_, (pts[std::size_t(i)].y - c.y) * inv_h_};
    bool duplicate = false;
    for (int j = 0; j < m_ && !duplicate; ++j) {
      const double dx = u.x - u_[std::size_t(j)].x, dy = u.y - u_[std::size_t(j)].y;
      duplicate = dx * dx + dy * dy < kDuplicateTolerance * kDuplicateTolerance;
    }
    if (duplicate) continue;
    active_[std::size_t(m_)] = i;
    u_[std::size_t(m_)] = u;
    ++m_;
  }
  if (m_ >= 3) {  // smallest / largest eigenvalue of the 2x2 covariance
    double sxx = 0, syy = 0, sxy = 0;
    for (int i = 0; i < m_; ++i) {
      const auto& u = u_[std::size_t(i)];
      sxx += u.x * u.x, syy += u.y * u.y, sxy += u.x * u.y;
    }
    const double half_tr = 0.5 * (sxx + syy);
    const double disc = std::sqrt(std::max(0.0, half_tr * half_tr - (sxx * syy - sxy * sxy)));
    collinear_ = (half_tr - disc) <= 1e-12 * (half_tr + disc);
  }
  const int size = m_ + (constant_ ? 1 : 0);
  system_.resize(size, size);
  for (int i = 0; i < m_; ++i) {
    for (int j = i; j < m_; ++j) {
      const auto& a = u_[std::size_t(i)];
      const auto& b = u_[std::size_t(j)];
      const double dx = a.x - b.x, dy = a.y - b.y;
      const double v = kernel(dx * dx + dy * dy);
      system_(i, j) = v;
      system_(j, i) = v;
    }
  }
  if (constant_) {
    for (int i = 0; i < m_; ++i) system_(i, m_) = system_(m_, i) = 1.0;
    system_(m_, m_) = 0.0;
  }
  if (gaussian_) {
    llt_.compute(system_.topLeftCorner(m_, m_));
    if (llt_.info() != Eigen::Success) return;
    rcond_ = llt_.rcond();
    if (constant_) {
      z_ = llt_.solve(SysVector::Ones(m_));
      one_z_ = z_.sum();
      if (!(one_z_ > 0.0) || !std::isfinite(one_z_)) return;
    }
  } else {
    lu_.compute(system_);
    rcond_ = lu_.rcond();
  }
  usable_ = std::isfinite(rcond_) && rcond_ >= o.rcond_min;
}

double RbfSystem::solve(Vec2d q, std::span<double> out) const {
  const Vec2d uq{(q.x - centre_.x) * inv_h_, (q.y - centre_.y) * inv_h_};
  const int size = m_ + (constant_ ? 1 : 0);
  SysVector b(size);
  for (int i = 0; i < m_; ++i) {
    const auto& u = u_[std::size_t(i)];
    const double dx = uq.x - u.x, dy = uq.y - u.y;
    b(i) = kernel(dx * dx + dy * dy);
  }
  if (constant_) b(m_) = 1.0;
  SysVector x(size);
  if (gaussian_) {
    SysVector y = llt_.solve(b.head(m_));
    x.head(m_) = y;
    if (constant_) {
      const double mu = (y.sum() - 1.0) / one_z_;
      x.head(m_) = y - mu * z_;
      x(m_) = mu;
    }
  } else {
    x = lu_.solve(b);
  }
  const double residual = (system_ * x - b).norm() / b.norm();
  std::fill(out.begin(), out.end(), 0.0);
  for (int i = 0; i < m_; ++i) {
    const double w = x(i);
    if (!std::isfinite(w)) return kInf;
    out[std::size_t(active_[std::size_t(i)])] = w;
  }
  return std::isfinite(residual) ? residual : kInf;
}

}  // namespace detail
}  // namespace foveart::foveation
