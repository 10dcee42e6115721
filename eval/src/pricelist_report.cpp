// pricelist.json / .csv / plots / report.md from the measured settings.
#include <eval/pricelist_report.hpp>

#include <eval/cmd_density.hpp>
#include <eval/pricelist_temporal_report.hpp>

#include <metrics/image_metrics.hpp>

#include <toolkit/format.hpp>
#include <toolkit/plot.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;
constexpr std::size_t kRings = metrics::kRingCount;

double num(const Json& j) { return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN(); }
double ring_psnr(const Json& s, std::size_t r) { return num(s["rings"][r]["psnr"]); }
double time_pct(const Json& s) { return 100.0 * num(s["time_fraction"]); }
// Whether a setting has the image history ("temporal": "image"; "off" without).
bool has_history(const Json& s) { return s.value("temporal", std::string("off")) != "off"; }

std::string fmt(double v, int decimals = 1) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

constexpr const char* kEccentricityFamily = "eccentricity only";
constexpr const char* kContentFamily = "content-aware";
constexpr const char* kRaysFamily = "rays per point by content";
constexpr double kGoalRayFraction = 0.10;  // the goal: 10 % of the full render's rays or fewer

// A ring's perceptual metric cell: the share of pixels at P >= 0.5 and the largest P against the
// reference, each the row's and the full render's at its rays per pixel ("row / full"); "-" without it.
std::string p_detect_cell(const Json& ring) {
  const double share = num(ring.value("p_detect_share", Json())), full = num(ring.value("p_detect_full_share", Json()));
  const double max = num(ring.value("p_detect_max", Json())), full_max = num(ring.value("p_detect_full_max", Json()));
  return std::isfinite(share) ? fmt(share, 3) + " / " + fmt(full, 3) + "; " + fmt(max, 2) + " / " + fmt(full_max, 2)
                              : "-";
}

const Json* find(const std::vector<Json>& all, const std::string& id) {
  for (const Json& s : all)
    if (s["id"] == id) return &s;
  return nullptr;
}

// "2.3 dB above" / "1.1 dB below"; "not comparable with" when either PSNR is not finite ("-").
std::string db_above_below(double db) {
  if (!std::isfinite(db)) return "not comparable with";
  return fmt(std::abs(db)) + " dB " + (db >= 0.0 ? "above" : "below");
}

// Every foveated setting's "equal_time_full": per ring its equal-time baseline (equal_time_full) as
// {id, time_fraction, psnr, gain_db}, or null when no full render is that cheap.
void add_equal_time(std::vector<Json>& all) {
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i]["kind"] != "foveated") continue;
    Json rings = Json::array();
    for (std::size_t r = 0; r < kRings; ++r) {
      const std::optional<std::size_t> f = equal_time_full(all, i, r);
      if (!f) {
        rings.push_back(nullptr);
        continue;
      }
      const Json& full = all[*f];
      const double gain = ring_psnr(all[i], r) - ring_psnr(full, r);
      rings.push_back({{"id", full["id"]}, {"time_fraction", full["time_fraction"]}, {"psnr", ring_psnr(full, r)},
                       {"gain_db", std::isfinite(gain) ? Json(gain) : Json(nullptr)}});
    }
    all[i]["equal_time_full"] = std::move(rings);
  }
}

// The headline's fair comparisons in the fovea (ring 0): a foveated setting with the image history
// (the thesis's default with it, else the first measured) against the full render with the same history at the
// same rays; the thesis's default and that setting against the full render at equal time.
std::string fair_headline(const std::vector<Json>& all, const PricelistContext& ctx, const Json* def) {
  std::ostringstream h;
  const Json* fov = find(all, ctx.thesis_default + "_image");
  for (const Json& s : all)
    if (!fov && s["kind"] == "foveated" && has_history(s)) fov = &s;
  const int rays = fov ? (*fov)["spp"].get<int>() : 0;
  const Json* full = fov ? find(all, "full_spp" + std::to_string(rays) + "_image") : nullptr;
  if (full) {
    h << "With the same history (the image history over " << ctx.run.value("history_frames", 0)
      << " frames of new jitter, " << rays << (rays == 1 ? " ray" : " rays") << " per point or pixel) the fovea of "
      << (*fov)["id"].get<std::string>() << " is " << db_above_below(ring_psnr(*fov, 0) - ring_psnr(*full, 0)) << " "
      << (*full)["id"].get<std::string>() << " (" << fmt(ring_psnr(*fov, 0)) << " vs " << fmt(ring_psnr(*full, 0))
      << " dB) at " << fmt(time_pct(*fov), 0) << "% vs " << fmt(time_pct(*full), 0) << "% of the time. ";
  }
  std::vector<std::string> clauses;
  for (const Json* s : {def, fov}) {
    if (!s) continue;
    const Json& e = (*s)["equal_time_full"][0];  // ring 0
    const std::string id = (*s)["id"].get<std::string>() + " (" + fmt(time_pct(*s), 0) + "%";
    if (e.is_null()) {
      clauses.push_back("no full render is as cheap as " + id + ")");
      continue;
    }
    clauses.push_back("the fovea of " + id + ", " + fmt(ring_psnr(*s, 0)) + " dB) is " +
                      db_above_below(num(e["gain_db"])) + " the best full render no slower, " +
                      e["id"].get<std::string>() + " (" + fmt(100.0 * num(e["time_fraction"]), 0) + "%, " +
                      fmt(num(e["psnr"])) + " dB)");
  }
  for (std::size_t i = 0; i < clauses.size(); ++i) h << (i == 0 ? "At equal time " : "; ") << clauses[i];
  if (!clauses.empty()) h << ".";
  std::string text = h.str();
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

std::string ring_name(std::size_t r) {
  char buf[32];
  if (std::isinf(metrics::kRingEdgesDeg[r + 1]))
    std::snprintf(buf, sizeof buf, ">%g", metrics::kRingEdgesDeg[r]);
  else
    std::snprintf(buf, sizeof buf, "%g-%g", metrics::kRingEdgesDeg[r], metrics::kRingEdgesDeg[r + 1]);
  return buf;
}

std::vector<std::size_t> pareto_front(const std::vector<double>& cost, const std::vector<double>& acc) {
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < cost.size(); ++i) {
    if (std::isnan(cost[i]) || std::isnan(acc[i])) continue;
    bool dominated = false;
    for (std::size_t j = 0; j < cost.size() && !dominated; ++j) {
      if (j == i || std::isnan(cost[j]) || std::isnan(acc[j])) continue;
      dominated = cost[j] <= cost[i] && acc[j] >= acc[i] && (cost[j] < cost[i] || acc[j] > acc[i]);
    }
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) { return cost[a] < cost[b]; });
  return front;
}

std::optional<std::size_t> equal_time_full(const std::vector<Json>& all, std::size_t of, std::size_t ring) {
  const double budget = num(all[of]["time_fraction"]);
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Json& s = all[i];
    const double psnr = ring_psnr(s, ring), t = num(s["time_fraction"]);
    if (s["kind"] != "full" || std::isnan(psnr) || !(t <= budget)) continue;
    if (!best) {
      best = i;
      continue;
    }
    const double best_psnr = ring_psnr(all[*best], ring), best_t = num(all[*best]["time_fraction"]);
    if (psnr > best_psnr || (psnr == best_psnr && t < best_t)) best = i;
  }
  return best;
}

namespace {

// A row's largest P per ring, key "p_detect_max" (the row's) or "p_detect_full_max" (its baseline's); NaN: none.
std::vector<double> rings_p(const Json& s, const char* key) {
  std::vector<double> v;
  for (std::size_t r = 0; r < kRings; ++r) v.push_back(num(s["rings"][r].value(key, Json())));
  return v;
}

// The families of the content-aware comparison a row belongs to; none for full renders, rows with
// history and rows without perceptual columns.
std::vector<std::string> families_of(const Json& s) {
  if (s["kind"] != "foveated" || has_history(s) || !s.value("p_detect_max", Json()).is_number()) return {};
  const double contrast = num(s.value("content_contrast", Json(0.0))), rays = num(s.value("content_rays", Json(0.0)));
  if (contrast > 0.0)
    return {kContentFamily, std::string(kContentFamily) + ", contrast " + toolkit::format_g(contrast)};
  if (rays > 0.0) return {std::string(kRaysFamily) + ", contrast " + toolkit::format_g(rays)};
  return {kEccentricityFamily};
}

// The rings where the metric sees a row that it does not see in its full render.
Json rings_seen(const Json& s) {
  const std::vector<double> row = rings_p(s, "p_detect_max"), full = rings_p(s, "p_detect_full_max");
  Json seen = Json::array();
  for (std::size_t r = 0; r < kRings; ++r)
    if (full[r] < 0.5 && !(row[r] < 0.5)) seen.push_back(ring_name(r));
  return seen;
}

Json row_summary(const Json& s) {
  return {{"id", s["id"]}, {"ray_fraction", s.value("ray_fraction", Json())}, {"time_fraction", s["time_fraction"]},
          {"psnr", s["psnr"]}, {"rings_seen", rings_seen(s)}};
}

// One family's count, judged count (a ring to judge), unseen count, smallest unseen ray fraction
// (smallest_unseen) and fewest rays among the judged rows.
Json family_json(const std::string& name, const std::vector<const Json*>& rows) {
  std::vector<UnseenCandidate> candidates;
  std::vector<UnseenCandidate> judged;  // every judged row as unseen: the fewest rays of them
  std::size_t unseen = 0;
  for (const Json* s : rows) {
    const std::optional<bool> verdict = row_unseen(*s);
    candidates.push_back({num(s->value("ray_fraction", Json())), verdict.value_or(false)});
    judged.push_back({candidates.back().ray_fraction, verdict.has_value()});
    unseen += candidates.back().unseen ? 1 : 0;
  }
  const std::optional<std::size_t> best = smallest_unseen(candidates), fewest = smallest_unseen(judged);
  const auto judged_rows = std::count_if(judged.begin(), judged.end(), [](const UnseenCandidate& c) { return c.unseen; });
  return {{"family", name}, {"rows", rows.size()}, {"judged_rows", judged_rows}, {"unseen_rows", unseen},
          {"smallest_unseen", best ? row_summary(*rows[*best]) : Json()},
          {"fewest_rays", fewest ? row_summary(*rows[*fewest]) : Json()}};
}

// The goal: rows at or below kGoalRayFraction, how many of them have a ring to judge and how many
// are unseen, and per ring how many the metric sees.
Json goal_json(const std::vector<Json>& all) {
  std::size_t rows = 0, judged = 0, unseen = 0;
  std::vector<std::size_t> seen(kRings, 0);
  for (const Json& s : all) {
    if (families_of(s).empty() || !(num(s.value("ray_fraction", Json())) <= kGoalRayFraction)) continue;
    ++rows;
    const std::optional<bool> verdict = row_unseen(s);
    judged += verdict ? 1 : 0;
    unseen += verdict.value_or(false) ? 1 : 0;
    for (const Json& ring : rings_seen(s))
      for (std::size_t r = 0; r < kRings; ++r) seen[r] += ring == ring_name(r) ? 1 : 0;
  }
  return {{"ray_fraction", kGoalRayFraction}, {"rows_at_or_below", rows}, {"judged_at_or_below", judged},
          {"unseen_at_or_below", unseen},
          {"met", unseen > 0}, {"rows_seen_per_ring", seen}};
}

}  // namespace

std::optional<bool> row_unseen(const Json& s) {
  if (!s.value("p_detect_max", Json()).is_number() || !s.value("p_detect_full_max", Json()).is_number())
    return std::nullopt;
  const std::vector<double> full = rings_p(s, "p_detect_full_max");
  if (measurable_ring_count(full) == 0) return std::nullopt;
  return unseen_in_every_ring(rings_p(s, "p_detect_max"), full);
}

Json detection_json(std::vector<Json>& all) {
  std::vector<std::string> names;
  std::map<std::string, std::vector<const Json*>> members;
  for (Json& s : all) {
    const std::optional<bool> unseen = row_unseen(s);
    s["p_unseen"] = unseen ? Json(*unseen) : Json();
  }
  for (const Json& s : all)
    for (const std::string& f : families_of(s)) {
      if (!members.count(f)) names.push_back(f);
      members[f].push_back(&s);
    }
  // Eccentricity only first, then content-aware (any contrast, then each), then rays per point by content.
  const auto rank = [](const std::string& n) {
    return n == kEccentricityFamily ? 0 : n.rfind(kContentFamily, 0) == 0 ? 1 : 2;
  };
  std::stable_sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
  Json families = Json::array();
  for (const std::string& f : names) families.push_back(family_json(f, members[f]));
  return {{"rule", "the smallest ray fraction whose largest P stays below 0.5 in every ring where the full render at "
                   "the same rays per pixel stays below 0.5 (fovea-eval density's rule)"},
          {"families", families}, {"goal", goal_json(all)}};
}

namespace {

// The full renders without and with the image history, each by rays per pixel.
struct FullRenders {
  std::vector<const Json*> plain, history;
};

FullRenders full_renders(const std::vector<Json>& all) {
  FullRenders f;
  for (const Json& s : all)
    if (s["kind"] == "full") (has_history(s) ? f.history : f.plain).push_back(&s);
  std::sort(f.plain.begin(), f.plain.end(), [](const Json* a, const Json* b) { return (*a)["spp"] < (*b)["spp"]; });
  return f;
}

// The Pareto front of every ring over every setting (full renders included: a user may pick
// either), each setting's "front_rings" set; cost[i] is setting i's time in percent.
std::vector<std::vector<std::size_t>> mark_fronts(std::vector<Json>& all, std::vector<double>* cost) {
  cost->assign(all.size(), 0.0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    (*cost)[i] = time_pct(all[i]);
    all[i]["front_rings"] = Json::array();
  }
  std::vector<std::vector<std::size_t>> fronts(kRings);
  for (std::size_t r = 0; r < kRings; ++r) {
    std::vector<double> acc(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) acc[i] = ring_psnr(all[i], r);
    fronts[r] = pareto_front(*cost, acc);
    for (std::size_t i : fronts[r]) all[i]["front_rings"].push_back(r);
  }
  return fronts;
}

// Sanity: the full render's error (without history) falls with rays per pixel in every ring;
// the reference's residual is >= 10 dB below the best setting in every ring.
Json sanity_json(const std::vector<Json>& all, const std::vector<const Json*>& full, const PricelistContext& ctx) {
  Json sanity = {{"full_error_falls_with_spp", true}, {"full_error_failures", Json::array()},
                 {"reference_10db_below_best", true}, {"reference_margin_db", Json::array()}};
  for (std::size_t r = 0; r < kRings; ++r) {
    for (std::size_t i = 1; i < full.size(); ++i) {
      const double a = ring_psnr(*full[i - 1], r), b = ring_psnr(*full[i], r);
      if (!std::isnan(a) && !std::isnan(b) && !(b > a)) {
        sanity["full_error_falls_with_spp"] = false;
        sanity["full_error_failures"].push_back("ring " + ring_name(r) + ": " + fmt(a, 2) + " dB at " +
                                                std::to_string((*full[i - 1])["spp"].get<int>()) + " spp, " + fmt(b, 2) +
                                                " dB at " + std::to_string((*full[i])["spp"].get<int>()));
      }
    }
    double best = -std::numeric_limits<double>::infinity();
    for (const Json& s : all)
      if (!std::isnan(ring_psnr(s, r))) best = std::max(best, ring_psnr(s, r));
    const double margin = num(ctx.reference["residual_psnr"][r]) - best;
    sanity["reference_margin_db"].push_back(std::isfinite(margin) ? Json(margin) : Json(nullptr));
    if (std::isfinite(margin) && margin < 10.0) sanity["reference_10db_below_best"] = false;
  }
  return sanity;
}

// The headline's first sentences: the thesis's default against the full render at 1 ray per pixel in
// the fovea, the cheapest setting within 0.5 dB of it inside 10 deg, and the fair comparisons.
std::string still_headline(const std::vector<Json>& all, const PricelistContext& ctx) {
  std::ostringstream h;
  const Json* full1 = find(all, "full_spp1");
  const Json* def = find(all, ctx.thesis_default);
  if (full1 && def) {
    h << "At the thesis's default (" << ctx.thesis_default << ") the fovea (0-2.5 deg) is "
      << fmt(ring_psnr(*full1, 0) - ring_psnr(*def, 0)) << " dB below a full render at 1 ray per pixel ("
      << fmt(ring_psnr(*def, 0)) << " vs " << fmt(ring_psnr(*full1, 0)) << " dB) and costs " << fmt(time_pct(*def), 0)
      << "% of its time; ";
    const Json* cheapest = nullptr;
    for (const Json& s : all) {
      if (s["kind"] != "foveated") continue;
      bool ok = true;
      for (std::size_t r = 0; r < 3; ++r) ok = ok && ring_psnr(s, r) >= ring_psnr(*full1, r) - 0.5;
      if (ok && (!cheapest || time_pct(s) < time_pct(*cheapest))) cheapest = &s;
    }
    if (cheapest)
      h << "the cheapest setting within 0.5 dB of it in every ring inside 10 deg (" << (*cheapest)["id"].get<std::string>()
        << ") costs " << fmt(time_pct(*cheapest), 0) << "%.";
    else
      h << "no foveated setting measured comes within 0.5 dB of it in every ring inside 10 deg.";
  } else {
    h << "(the headline needs full_spp1 and " << ctx.thesis_default << " in the grid)";
  }
  if (const std::string fair = fair_headline(all, ctx, def); !fair.empty()) h << " " << fair;
  return h.str();
}

// The temporal columns read: the acceptance at the layer's defaults (else the first setting with history
// measured) and the reference floor's checks, added to `temporal`; their sentences onto *headline.
struct TemporalReading {
  Json temporal, acceptance, checks;
};

TemporalReading read_temporal(const PricelistContext& ctx, std::string* headline) {
  TemporalReading t{ctx.temporal, {}, {}};
  if (!t.temporal.is_object()) return t;
  std::string setting = kTemporalHeadlineSetting;
  bool measured = false;
  for (const Json& track : t.temporal["tracks"]) measured = measured || track["id"] == setting + "_temporal-off";
  if (!measured)
    for (const Json& track : t.temporal["tracks"])
      if (track["temporal"] == "off") {
        const std::string id = track["id"].get<std::string>();
        setting = id.substr(0, id.size() - std::string("_temporal-off").size());
        break;
      }
  t.acceptance = temporal_acceptance(t.temporal, setting);
  t.checks = temporal_sanity(t.temporal);
  t.temporal["acceptance"] = t.acceptance;
  t.temporal["sanity"] = t.checks;
  if (const std::string line = temporal_headline(t.temporal, t.acceptance); !line.empty()) *headline += " " + line;
  if (const std::string line = temporal_render_cache_line(t.acceptance); !line.empty()) *headline += " " + line;
  return t;
}

std::string csv_cell(const Json& j) {
  if (j.is_null()) return "";
  if (j.is_string()) return j.get<std::string>();
  if (j.is_boolean()) return j.get<bool>() ? "1" : "0";
  if (j.is_number_float()) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", j.get<double>());
    return buf;
  }
  return j.dump();
}

// The perceptual columns, over the image and per ring: the row's and its baseline's against the reference.
constexpr const char* kPerceptualColumns[] = {"p_detect_mean",      "p_detect_share",      "p_detect_max",
                                              "p_detect_full_mean", "p_detect_full_share", "p_detect_full_max"};

// pricelist.csv: one row per setting. False and *error naming the file.
[[nodiscard]] bool write_csv(const std::filesystem::path& file, const std::vector<Json>& all, std::string* error) {
  std::ofstream f(file);
  f << "id,kind,method,k,scale,pattern,temporal,spp,points,rays_primary,rays_shadow,rays_reflection,rays_refraction,"
       "rays_total,ms_select,ms_trace,ms_reconstruct,ms_temporal,ms_total,anchor_full_ms,time_fraction,psnr,ssim,csf_"
       "rmse";
  for (std::size_t r = 0; r < kRings; ++r)
    for (const char* m : {"psnr", "ssim", "csf_psnr", "flicker"}) f << "," << m << "_" << ring_name(r);
  for (std::size_t r = 0; r < kRings; ++r)
    f << ",equal_time_full_" << ring_name(r) << ",equal_time_gain_db_" << ring_name(r);
  f << ",content_contrast,content_rays,ray_fraction,p_detect_against,p_detect_baseline,p_unseen";
  for (const char* k : kPerceptualColumns) f << "," << k;
  for (std::size_t r = 0; r < kRings; ++r)
    for (const char* k : kPerceptualColumns) f << "," << k << "_" << ring_name(r);
  f << "\n";
  for (const Json& s : all) {
    const bool fov = s["kind"] == "foveated";
    f << csv_cell(s["id"]) << "," << csv_cell(s["kind"]) << "," << (fov ? csv_cell(s["method"]) : "") << ","
      << (fov ? csv_cell(s["k"]) : "") << "," << (fov ? csv_cell(s["scale"]) : "") << ","
      << (fov ? csv_cell(s["pattern"]) : "") << "," << csv_cell(s.value("temporal", Json("off"))) << ","
      << csv_cell(s["spp"]) << "," << csv_cell(s["points"]);
    for (const char* k : {"primary", "shadow", "reflection", "refraction", "total"}) f << "," << csv_cell(s["rays"][k]);
    for (const char* k : {"select", "trace", "reconstruct", "temporal", "total"}) f << "," << csv_cell(s["ms"][k]);
    f << "," << csv_cell(s["anchor_full_ms"]) << "," << csv_cell(s["time_fraction"]) << "," << csv_cell(s["psnr"])
      << "," << csv_cell(s["ssim"]) << "," << csv_cell(s["csf_rmse"]);
    for (std::size_t r = 0; r < kRings; ++r)
      for (const char* m : {"psnr", "ssim", "csf_psnr", "flicker"}) f << "," << csv_cell(s["rings"][r][m]);
    for (std::size_t r = 0; r < kRings; ++r) {  // full renders: empty; "none": no full render that cheap
      const Json e = fov ? s["equal_time_full"][r] : Json();
      f << "," << (!fov ? "" : e.is_null() ? "none" : csv_cell(e["id"]));
      f << "," << (e.is_null() ? "" : csv_cell(e["gain_db"]));
    }
    for (const char* k : {"content_contrast", "content_rays"}) f << "," << (fov ? csv_cell(s.value(k, Json(0.0))) : "");
    f << "," << csv_cell(s.value("ray_fraction", Json()));
    for (const char* k : {"p_detect_against", "p_detect_baseline", "p_unseen"}) f << "," << csv_cell(s.value(k, Json()));
    for (const char* k : kPerceptualColumns) f << "," << csv_cell(s.value(k, Json()));
    for (std::size_t r = 0; r < kRings; ++r)
      for (const char* k : kPerceptualColumns) f << "," << csv_cell(s["rings"][r].value(k, Json()));
    f << "\n";
  }
  if (!f) *error = "cannot write " + file.string();
  return static_cast<bool>(f);
}

// The Pareto plot of one ring: time (% of a full frame at 1 ray per pixel) against PSNR. "" or what
// could not be written; nothing is drawn for a ring without a finite PSNR (empty at this size).
std::string plot_ring(const std::filesystem::path& file, const std::string& title, std::size_t r,
                      const std::vector<Json>& all, const FullRenders& full, const std::vector<std::size_t>& front,
                      const std::vector<double>& cost) {
  toolkit::PlotSeries full_curve{"full render 1-16 spp", {}, {}, false};
  toolkit::PlotSeries grid{"foveated, pixel-grid fovea", {}, {}, true};
  toolkit::PlotSeries thesis{"foveated, thesis fovea", {}, {}, true};
  toolkit::PlotSeries with_history{"foveated + image history", {}, {}, true};
  toolkit::PlotSeries history_curve{"full render + image history", {}, {}, true};
  toolkit::PlotSeries front_curve{"Pareto front", {}, {}, false};
  const auto x_of = [](double pct) { return std::log2(pct / 100.0); };
  const auto add = [&](toolkit::PlotSeries& to, const Json& s) {
    to.x.push_back(x_of(time_pct(s)));
    to.y.push_back(ring_psnr(s, r));
  };
  for (const Json* s : full.plain) add(full_curve, *s);
  for (const Json* s : full.history) add(history_curve, *s);
  for (const Json& s : all)
    if (s["kind"] == "foveated") add(has_history(s) ? with_history : (s["pattern"] == "thesis" ? thesis : grid), s);
  for (std::size_t i : front) {
    front_curve.x.push_back(x_of(cost[i]));
    front_curve.y.push_back(ring_psnr(all[i], r));
  }
  toolkit::PlotSpec spec;
  spec.title = title;
  spec.x_label = "log2 (frame time / full frame at 1 ray per pixel): -2 = 25%, 0 = 100%, 3 = 800%";
  spec.y_label = "PSNR against the reference (dB)";
  const std::vector<toolkit::PlotSeries> series = {full_curve, front_curve, grid, thesis, with_history, history_curve};
  return toolkit::has_finite_point(series) ? toolkit::write_plot_png(file.string(), spec, series) : std::string();
}

[[nodiscard]] bool write_plots(const std::filesystem::path& dir, const std::vector<Json>& all, const FullRenders& full,
                               const std::vector<std::vector<std::size_t>>& fronts, const std::vector<double>& cost,
                               std::string* error) {
  for (std::size_t r = 0; r < kRings; ++r) {
    *error =
        plot_ring(dir / ("pareto_ring" + std::to_string(r) + ".png"),
                  "Price list, ring " + ring_name(r) + " deg: time against accuracy", r, all, full, fronts[r], cost);
    if (!error->empty()) return false;
  }
  *error =
      plot_ring(dir / "pricelist.png", "What accuracy costs in the fovea (0-2.5 deg)", 0, all, full, fronts[0], cost);
  return error->empty();
}

// report.md's head: the run, the headline, the reference and the sanity checks.
void write_md_head(std::ostream& md, const PricelistContext& ctx, const std::string& headline, const Json& sanity) {
  md << "# Price list: " << ctx.run["scene"].get<std::string>() << ", " << ctx.run["width"] << "x" << ctx.run["height"]
     << ", gaze (" << fmt(num(ctx.run["gaze"][0]), 0) << ", " << fmt(num(ctx.run["gaze"][1]), 0) << ")\n\n"
     << "Written by `" << ctx.command << "` on " << ctx.run.value("machine", std::string("?")) << ", "
     << ctx.run.value("threads", 0) << " threads, in " << fmt(ctx.run.value("run_s", 0.0), 0)
     << (ctx.run.value("resumed_settings", 0) > 0
             ? " s (resuming: " + std::to_string(ctx.run.value("resumed_settings", 0)) +
                   " settings were measured by earlier runs into the same --out)"
             : std::string(" s"))
     << ". The numbers below are that run's own output; rerun the command to update them.\n\n"
     << headline << "\n\n"
     << "Times are each setting's median frame "
     << "as a percentage of a full frame at 1 ray per pixel rendered interleaved with it. "
     << "`full_sppN_image` is the full render with the foveated settings' image history: the same "
     << ctx.run.value("history_frames", 0) << " frames of new jitter, the same blend; its time is trace + blend.\n\n"
     << "Reference: " << ctx.reference["spp"] << " rays per pixel; residual PSNR per ring (MSE(A,B)/4 of two "
     << "independent halves):";
  for (std::size_t r = 0; r < kRings; ++r)
    md << " " << ring_name(r) << ": " << fmt(num(ctx.reference["residual_psnr"][r])) << " dB;";
  md << " convergence check " << (ctx.reference.value("converged", true) ? "met" : "**not met** (stopped at its cap)")
     << ", counts tried " << ctx.reference["spp_tried"].dump() << ", each doubling lowered the residual by";
  if (ctx.reference.contains("db_per_doubling"))
    for (const Json& d : ctx.reference["db_per_doubling"]) md << " " << fmt(num(d));
  md << " dB per ring on average (3 dB when the 1/N law holds).";
  md << "\n\nSanity: full-render error falls with rays per pixel in every ring: "
     << (sanity["full_error_falls_with_spp"].get<bool>() ? "yes" : "**no**");
  for (const Json& f : sanity["full_error_failures"]) md << "; " << f.get<std::string>();
  md << ". Reference residual >= 10 dB below the best setting in every ring: "
     << (sanity["reference_10db_below_best"].get<bool>() ? "yes" : "**no**") << " (margins";
  for (std::size_t r = 0; r < kRings; ++r) md << " " << fmt(num(sanity["reference_margin_db"][r]));
  md << " dB).\n\n![fovea](pricelist.png)\n\n";
}

// report.md's section of one ring: its front with ms and rays per dB, and each foveated setting on it
// against the full render at equal time. ms_of: a setting's time fraction x full_spp1's ms.
void write_md_ring(std::ostream& md, std::size_t r, const std::vector<Json>& all, const std::vector<std::size_t>& front,
                   const std::function<double(const Json&)>& ms_of) {
  md << "## Ring " << ring_name(r) << " deg\n\n![ring " << ring_name(r) << "](pareto_ring" << r << ".png)\n\n"
     << "| on the front | time % | ms | rays (total) | primary rays % of full | PSNR dB | SSIM | CSF dB | "
        "share P >= 0.5; largest P, vs reference (row / full same spp) | ms per dB | rays per dB |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  const Json* prev = nullptr;
  for (std::size_t i : front) {
    const Json& s = all[i];
    std::string ms_db = "-", rays_db = "-";
    if (prev) {
      const double ddb = ring_psnr(s, r) - ring_psnr(*prev, r);
      if (ddb > 0) {
        ms_db = fmt((ms_of(s) - ms_of(*prev)) / ddb, 2);
        rays_db = fmt((num(s["rays"]["total"]) - num((*prev)["rays"]["total"])) / ddb, 0);
      }
    }
    md << "| " << s["id"].get<std::string>() << " | " << fmt(time_pct(s), 1) << " | " << fmt(ms_of(s)) << " | "
       << s["rays"]["total"] << " | " << fmt(100.0 * num(s.value("ray_fraction", Json(0.0))), 1) << " | "
       << fmt(ring_psnr(s, r), 2) << " | " << fmt(num(s["rings"][r]["ssim"]), 3)
       << " | " << fmt(num(s["rings"][r]["csf_psnr"]), 2) << " | " << p_detect_cell(s["rings"][r]) << " | " << ms_db
       << " | " << rays_db << " |\n";
    prev = &s;
  }
  const bool any_foveated =
      std::any_of(front.begin(), front.end(), [&](std::size_t i) { return all[i]["kind"] == "foveated"; });
  md << "\nAt equal time, ring " << ring_name(r) << " deg:"
     << (any_foveated ? "\n\n| foveated on the front | time % | PSNR dB | full render no slower | its time % | "
                        "its PSNR dB | gain dB |\n|---|---|---|---|---|---|---|\n"
                      : " no foveated setting is on this ring's front.\n");
  for (std::size_t i : front) {
    const Json& s = all[i];
    if (s["kind"] != "foveated") continue;
    const Json& e = s["equal_time_full"][r];
    md << "| " << s["id"].get<std::string>() << " | " << fmt(time_pct(s), 1) << " | " << fmt(ring_psnr(s, r), 2);
    if (e.is_null())
      md << " | none that cheap | - | - | - |\n";
    else
      md << " | " << e["id"].get<std::string>() << " | " << fmt(100.0 * num(e["time_fraction"]), 1) << " | "
         << fmt(num(e["psnr"]), 2) << " | " << fmt(num(e["gain_db"]), 2) << " |\n";
  }
  md << "\n";
}

// "12.3 % (id, time 45 %)" of a family's row summary; "-" for none.
std::string summary_cell(const Json& row) {
  if (row.is_null()) return "- | - | - | -";
  return fmt(100.0 * num(row["ray_fraction"]), 1) + " | " + row["id"].get<std::string>() + " | " +
         fmt(100.0 * num(row["time_fraction"]), 0) + " | " + fmt(num(row["psnr"]), 2);
}

std::string ring_list(const Json& rings) {
  std::string text;
  for (const Json& r : rings) text += (text.empty() ? "" : ", ") + r.get<std::string>();
  return text.empty() ? "none" : text;
}

// report.md's "Content-aware density": per family the smallest unseen ray fraction and the fewest
// rays, eccentricity-only beside content-aware, and where the list lands against the goal.
void write_md_content_density(std::ostream& md, const Json& detection) {
  md << "## Content-aware density\n\nRows without history by family. Unseen: the row's largest P against the "
     << "reference stays below 0.5 in every ring where the full render at the same rays per pixel stays below 0.5 "
     << "(the rule of `fovea-eval density`); judged: rows with such a ring (where the full render is seen in every "
     << "ring the metric cannot tell foveation from its noise); rays % = primary rays over the full render's at the "
     << "same rays per pixel.\n\n"
     << "| family | rows | judged | unseen | smallest unseen: rays % | setting | time % | PSNR dB | fewest rays "
        "judged: rays % | setting | rings seen |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Json& f : detection["families"]) {
    const Json& fewest = f["fewest_rays"];
    md << "| " << f["family"].get<std::string>() << " | " << f["rows"] << " | " << f["judged_rows"] << " | "
       << f["unseen_rows"] << " | " << summary_cell(f["smallest_unseen"]) << " | "
       << (fewest.is_null() ? "- | - | -"
                            : fmt(100.0 * num(fewest["ray_fraction"]), 1) + " | " + fewest["id"].get<std::string>() +
                                  " | " + ring_list(fewest["rings_seen"]))
       << " |\n";
  }
  const Json& goal = detection["goal"];
  const double goal_pct = 100.0 * num(goal["ray_fraction"]);
  md << "\nGoal, unseen at " << fmt(goal_pct, 0) << " % of the full render's rays or fewer: "
     << (goal["met"].get<bool>() ? "**met**" : "**not met**") << " (" << goal["unseen_at_or_below"] << " of "
     << goal["judged_at_or_below"] << " judged rows at or below " << fmt(goal_pct, 0) << " % unseen; "
     << goal["rows_at_or_below"] << " rows there in all";
  if (!goal["met"].get<bool>() && goal["rows_at_or_below"].get<std::size_t>() > 0) {
    md << "; the metric sees them in";
    for (std::size_t r = 0; r < kRings; ++r)
      if (goal["rows_seen_per_ring"][r].get<std::size_t>() > 0)
        md << " " << ring_name(r) << " deg (" << goal["rows_seen_per_ring"][r] << " rows)";
  }
  md << ").\n\n";
}

// report.md's "Detection per ring": every row's rays, time and per ring its largest P beside its
// full render's at the same rays per pixel and its PSNR.
void write_md_detection(std::ostream& md, const std::vector<Json>& all) {
  md << "## Detection per ring\n\nPer ring: largest P against the reference, the row's / the full render's at "
     << "the same rays per pixel, then PSNR dB. Unseen: as above (-: no ring to judge; a full render is its own "
     << "baseline).\n\n"
     << "| setting | rays % of full | time % |";
  for (std::size_t r = 0; r < kRings; ++r) md << " " << ring_name(r) << " |";
  md << " unseen |\n|---|---|---|";
  for (std::size_t r = 0; r < kRings; ++r) md << "---|";
  md << "---|\n";
  for (const Json& s : all) {
    md << "| " << s["id"].get<std::string>() << " | " << fmt(100.0 * num(s.value("ray_fraction", Json())), 1) << " | "
       << fmt(time_pct(s), 1) << " |";
    for (std::size_t r = 0; r < kRings; ++r) {
      const Json& ring = s["rings"][r];
      md << " " << fmt(num(ring.value("p_detect_max", Json())), 2) << " / "
         << fmt(num(ring.value("p_detect_full_max", Json())), 2) << " · " << fmt(num(ring["psnr"]), 1) << " |";
    }
    const Json unseen = s.value("p_unseen", Json());
    md << " " << (unseen.is_boolean() ? (unseen.get<bool>() ? "yes" : "no") : "-") << " |\n";
  }
  md << "\n";
}

// report.md: the head, a section per ring, the temporal columns, and where the rest is.
[[nodiscard]] bool write_md(const std::filesystem::path& file, const PricelistContext& ctx, const std::string& headline,
                            const Json& sanity, const std::vector<Json>& all,
                            const std::vector<std::vector<std::size_t>>& fronts, const Json& detection,
                            const TemporalReading& t, std::string* error) {
  std::ofstream md(file);
  write_md_head(md, ctx, headline, sanity);
  // ms at the pace of the full group's frames: time fraction x full_spp1's ms (the groups ran
  // minutes apart on a shared machine; the fraction is what each measured against its anchor).
  const Json* full1 = find(all, "full_spp1");
  const double full1_ms = full1 ? num((*full1)["ms"]["total"]) : std::numeric_limits<double>::quiet_NaN();
  md << "Columns: time % of a full frame at 1 ray per pixel (measured against the anchor frames interleaved "
     << "with it); ms = that fraction x the full render's " << fmt(full1_ms) << " ms; rays traced in all "
     << "(primary + shadow + reflection + refraction); PSNR, SSIM and the CSF-weighted error (as dB) in the ring "
     << "against the reference; ms per dB and rays per dB from the previous setting on the front. "
     << "At equal time: each foveated setting on the front against the most accurate full render (with or "
     << "without history) that takes no more time, and how many dB it gains on it in the ring.\n\n";
  for (std::size_t r = 0; r < kRings; ++r)
    write_md_ring(md, r, all, fronts[r], [&](const Json& s) { return num(s["time_fraction"]) * full1_ms; });
  write_md_content_density(md, detection);
  write_md_detection(md, all);
  if (t.temporal.is_object()) write_temporal_markdown(md, t.temporal, t.acceptance, t.checks);
  md << "## Every setting\n\nSee `pricelist.csv` (one row per setting) and `pricelist.json`. Error heat map of "
     << ctx.heatmap << ": ![heat map](heatmap.png)\n";
  if (!md) *error = "cannot write " + file.string();
  return static_cast<bool>(md);
}

}  // namespace

bool write_pricelist(const std::filesystem::path& dir, const PricelistContext& ctx, std::vector<Json> all,
                     std::string* headline, std::string* error) {
  std::vector<double> cost;
  const std::vector<std::vector<std::size_t>> fronts = mark_fronts(all, &cost);
  add_equal_time(all);
  const Json detection = detection_json(all);
  const FullRenders full = full_renders(all);
  const Json sanity = sanity_json(all, full.plain, ctx);
  *headline = still_headline(all, ctx);
  const TemporalReading t = read_temporal(ctx, headline);
  Json doc = {{"run", ctx.run}, {"reference", ctx.reference}, {"sanity", sanity}, {"headline", *headline},
              {"rings_deg", Json::array()}, {"detection", detection}, {"settings", all}, {"temporal", t.temporal}};
  for (std::size_t r = 0; r < kRings; ++r) doc["rings_deg"].push_back(ring_name(r));
  if (t.temporal.is_object()) {
    *error = write_temporal_csv(dir / "temporal.csv", t.temporal);
    if (error->empty()) *error = write_temporal_plots(dir, t.temporal, t.acceptance);
    if (!error->empty()) return false;
  }
  {
    std::ofstream f(dir / "pricelist.json");
    f << doc.dump(2) << "\n";
    if (!f) {
      *error = "cannot write " + (dir / "pricelist.json").string();
      return false;
    }
  }
  return write_csv(dir / "pricelist.csv", all, error) && write_plots(dir, all, full, fronts, cost, error) &&
         write_md(dir / "report.md", ctx, *headline, sanity, all, fronts, detection, t, error);
}

}  // namespace foveart::eval
