// The temporal columns in the price list's outputs (pricelist_temporal_report.hpp).
#include <eval/pricelist_temporal_report.hpp>

#include <eval/motion_sequence.hpp>
#include <eval/pricelist_report.hpp>
#include <metrics/comparison_json.hpp>

#include <metrics/image_metrics.hpp>

#include <toolkit/plot.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;
constexpr std::size_t kRings = metrics::kRingCount;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double num(const Json& j) { return j.is_number() ? j.get<double>() : kNaN; }

std::string fmt(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

const Json* track(const Json& temporal, const std::string& id) {
  if (!temporal.contains("tracks")) return nullptr;
  for (const Json& t : temporal["tracks"])
    if (t["id"] == id) return &t;
  return nullptr;
}

// obj[key] as a number; NaN when obj is no object or lacks the key (a const
// operator[] on a missing key is undefined behaviour in nlohmann::json).
double field(const Json& obj, const std::string& key) {
  if (!obj.is_object()) return kNaN;
  const auto it = obj.find(key);
  return it == obj.end() ? kNaN : num(*it);
}

// owner[bands_key]'s peripheral band (find_band), or null.
const Json* periphery_of(const Json& owner, const std::string& bands_key) {
  if (!owner.is_object()) return nullptr;
  const auto bands = owner.find(bands_key);
  return bands == owner.end() ? nullptr : find_band(*bands, kPeripheralBand);
}

double settled_value(const Json* band, const char* key) {
  if (band == nullptr) return kNaN;
  const auto settled = band->find("settled");
  return settled == band->end() ? kNaN : field(*settled, key);
}

double ring_value(const Json& t, std::size_t r, const char* key) {
  const auto rings = t.find("rings");
  if (rings == t.end() || !rings->is_array() || r >= rings->size()) return kNaN;
  return field((*rings)[r], key);
}


}  // namespace

std::string peripheral_ratios(const Json& values, const std::string& key, int decimals) {
  std::string out;
  for (std::size_t r = kPeripheralBand.begin; r < kPeripheralBand.end; ++r)
    out += (r > kPeripheralBand.begin ? " / " : "") + fmt(num(values[key][r]), decimals) + "x";
  return out;
}

std::string central_gains_db(const Json& gains) {
  std::string out;
  for (std::size_t r = kCentralBand.begin; r < kCentralBand.end; ++r) {
    const double g = num(gains[r]);
    out += std::string(r > kCentralBand.begin ? " / " : "") + (g >= 0 ? "+" : "") + fmt(g, 1);
  }
  return out;
}

Json temporal_goal(const Json& off, const Json& history) {
  Json g = Json::object();
  for (const char* measure : {"flicker", "flicker_tracked", "flicker_csf"}) {
    const std::string m = measure;
    Json ratio = Json::array();
    for (std::size_t r = 0; r < kRings; ++r)
      ratio.push_back(metrics::number_or_null_json(ring_value(off, r, measure) / ring_value(history, r, measure)));
    bool peripheral = true;
    for (std::size_t r = kPeripheralBand.begin; r < kPeripheralBand.end; ++r)
      peripheral = peripheral && ratio[r].is_number() && ratio[r].get<double>() >= 5.0;
    g[m + "_ratio"] = ratio;
    g[m == "flicker"           ? "peripheral_flicker_5x_lower"
      : m == "flicker_tracked" ? "peripheral_tracked_flicker_5x_lower"
                               : "peripheral_csf_flicker_5x_lower"] = peripheral;
  }
  Json gain = Json::array();
  for (std::size_t r = 0; r < kRings; ++r)
    gain.push_back(metrics::number_or_null_json(ring_value(history, r, "psnr") - ring_value(off, r, "psnr")));
  bool central = true;
  for (std::size_t r = kCentralBand.begin; r < kCentralBand.end; ++r)
    central = central && gain[r].is_number() && gain[r].get<double>() >= 0.0;
  g["psnr_minus_off_db"] = gain;
  g["central_error_no_worse"] = central;
  return g;
}

Json temporal_acceptance(const Json& temporal, const std::string& setting) {
  const Json* off = track(temporal, setting + "_temporal-off");
  const Json* restart = track(temporal, setting + "_temporal-restart");
  const Json* reproject = track(temporal, setting + "_temporal-image");
  if (!off || !restart || !reproject) return nullptr;
  const bool have_control = temporal.contains("reference") && temporal["reference"].is_object();
  Json a = {{"setting", setting}};
  // The image history (the layer's history on the CPU path) against off, and beside it off over restart and
  // off over each control (kSequenceControls): the stable blur (an image that is soft but does not flicker at
  // all), the image history fed the reference (what the history's reprojection costs without noise) and the sample
  // histories (what keeping the rays themselves reaches). The third measure, weighted by what the eye resolves
  // (temporal_metrics.hpp flicker_csf_rms), stands beside the goal, which is set on the plain change.
  const Json goal = temporal_goal(*off, *reproject), restart_goal = temporal_goal(*off, *restart);
  for (const char* measure : {"flicker", "flicker_tracked", "flicker_csf"}) {
    const std::string m = measure;
    for (const SequenceControl& control : kSequenceControls) {
      const std::string key = std::string(control.key) + "_" + m;
      Json ratio_control = Json::array();
      for (std::size_t r = 0; r < kRings; ++r)
        ratio_control.push_back(metrics::number_or_null_json(
            have_control ? ring_value(*off, r, measure) / ring_value(temporal["reference"], r, key.c_str()) : kNaN));
      a[m + "_ratio_off_over_" + control.key] = ratio_control;
    }
    a[m + "_ratio_off_over_image"] = goal[m + "_ratio"];
    a[m + "_ratio_off_over_restart"] = restart_goal[m + "_ratio"];
  }
  for (const char* key :
       {"peripheral_flicker_5x_lower", "peripheral_tracked_flicker_5x_lower", "peripheral_csf_flicker_5x_lower"})
    a[key] = goal[key];
  a["psnr_image_minus_off_db"] = goal["psnr_minus_off_db"];
  a["central_error_no_worse"] = goal["central_error_no_worse"];
  // The render cache (TemporalMode::rays, restarting where the image history restarts) against the same
  // off; absent from runs measured before the price list had it.
  if (const Json* cache = track(temporal, setting + "_temporal-rays")) a["render_cache"] = temporal_goal(*off, *cache);
  // Beside the goal, which pools every frame: the periphery over the frames whose image history has
  // settled (motion_sequence.hpp), without the cold start and the frames after the saccade.
  const Json* off_band = periphery_of(*off, "bands");
  const Json* reproject_band = periphery_of(*reproject, "bands");
  if (off_band != nullptr && reproject_band != nullptr) {
    Json settled = {{"frames", temporal["reference"].value("settled_frames", Json())},
                    {"settle_frames", temporal["reference"].value("settle_frames", Json())}};
    for (const char* measure : {"flicker", "flicker_tracked", "flicker_csf"}) {
      const std::string m = measure;
      const double o = settled_value(off_band, measure);
      settled[m + "_ratio_off_over_image"] = metrics::number_or_null_json(o / settled_value(reproject_band, measure));
      for (const SequenceControl& control : kSequenceControls) {
        const std::string key = control.key;
        const Json* band = have_control ? periphery_of(temporal["reference"], key + "_bands") : nullptr;
        settled[m + "_ratio_off_over_" + key] = metrics::number_or_null_json(o / settled_value(band, measure));
      }
    }
    a["settled_periphery"] = settled;
  }
  return a;
}

Json temporal_sanity(const Json& temporal) {
  Json flicker_margin = Json::array(), error_margin = Json::array(), csf_margin = Json::array();
  const bool have_reference = temporal.contains("reference") && temporal["reference"].is_object();
  bool ok = have_reference, csf_ok = have_reference;
  // The smallest margin (dB) of `measure` over the tracks against the reference's `floor` in ring r.
  const auto margin_db = [&](std::size_t r, const char* measure, const char* floor) {
    double m = std::numeric_limits<double>::infinity();
    for (const Json& t : temporal["tracks"]) {
      const double db = 20.0 * std::log10(ring_value(t, r, measure) / ring_value(temporal["reference"], r, floor));
      if (std::isfinite(db)) m = std::min(m, db);
    }
    return m;
  };
  for (std::size_t r = 0; r < kRings && have_reference; ++r) {
    // The plain floor bounds the tracked flicker (temporal_metrics.hpp); the weighted one has its own.
    const double fm = std::min(margin_db(r, "flicker", "flicker_floor"), margin_db(r, "flicker_tracked", "flicker_floor"));
    const double cm = margin_db(r, "flicker_csf", "flicker_csf_floor");
    double max_psnr = -std::numeric_limits<double>::infinity();
    for (const Json& t : temporal["tracks"])
      if (std::isfinite(ring_value(t, r, "psnr"))) max_psnr = std::max(max_psnr, ring_value(t, r, "psnr"));
    const double em = ring_value(temporal["reference"], r, "psnr_floor") - max_psnr;
    flicker_margin.push_back(metrics::number_or_null_json(fm));
    error_margin.push_back(metrics::number_or_null_json(em));
    csf_margin.push_back(metrics::number_or_null_json(cm));
    if ((std::isfinite(fm) && fm < 10.0) || (std::isfinite(em) && em < 10.0)) ok = false;
    if (!std::isfinite(cm) || cm < 10.0) csf_ok = false;
  }
  return {{"flicker_margin_db", flicker_margin}, {"error_margin_db", error_margin}, {"floor_10db_below", ok},
          {"csf_flicker_margin_db", csf_margin}, {"csf_floor_10db_below", csf_ok}};
}

std::string temporal_headline(const Json& temporal, const Json& a) {
  if (a.is_null()) return "";
  const Json& run = temporal["run"];
  const auto three = [&](const char* key) { return peripheral_ratios(a, key); };
  std::ostringstream h;
  h << "Over the " << run["motion"].get<std::string>() << " motion (" << run["frames"] << " frames from "
    << fmt(num(run["start_s"]), 2) << " s at " << fmt(num(run["fps"]), 0) << " fps, " << run["width"] << "x"
    << run["height"] << ") at equal rays (" << a["setting"].get<std::string>() << "), the image history flickers "
    << three("flicker_ratio_off_over_image") << " less than off at 20-30 / 30-45 / >45 deg at fixed pixels and "
    << three("flicker_tracked_ratio_off_over_image")
    << " along the motion (goal 5x: " << (a["peripheral_flicker_5x_lower"].get<bool>() ? "met" : "not met") << " / "
    << (a.value("peripheral_tracked_flicker_5x_lower", false) ? "met" : "not met")
    << "; the reference blurred [1 2 1]^2, soft but stable, reaches " << three("flicker_ratio_off_over_stable_blur")
    << " at fixed pixels and " << three("flicker_tracked_ratio_off_over_stable_blur")
    << " along the motion; the same history fed the reference itself, without noise, "
    << three("flicker_ratio_off_over_history_on_reference") << " at fixed pixels and "
    << three("flicker_tracked_ratio_off_over_history_on_reference") << " along the motion"
    << "; every ray since the history's last restart kept and traced again (what a history of these rays reaches "
       "without error) "
    << three("flicker_ratio_off_over_sample_history") << " at fixed pixels and "
    << three("flicker_tracked_ratio_off_over_sample_history") << " along the motion, kept through the saccade "
    << three("flicker_ratio_off_over_sample_history_kept") << " and "
    << three("flicker_tracked_ratio_off_over_sample_history_kept")
    << "; a render cache of these rays at equal rays (each kept ray's colour as traced) "
    << three("flicker_ratio_off_over_ray_cache") << " and " << three("flicker_tracked_ratio_off_over_ray_cache")
    << ", kept through the saccade " << three("flicker_ratio_off_over_ray_cache_kept") << " and "
    << three("flicker_tracked_ratio_off_over_ray_cache_kept")
    << "; the image history restarting on every pose change: " << three("flicker_ratio_off_over_restart")
    << "); its error at 0-2.5 / 2.5-5 deg is " << central_gains_db(a["psnr_image_minus_off_db"])
    << " dB against off (goal: no worse: " << (a["central_error_no_worse"].get<bool>() ? "met" : "not met") << ").";
  return h.str();
}

std::string temporal_render_cache_line(const Json& a) {
  if (a.is_null() || !a.contains("render_cache")) return "";
  const Json& g = a["render_cache"];
  const auto met = [&](const char* key) { return g.value(key, false) ? "met" : "not met"; };
  std::ostringstream line;
  line << "The render cache (the layer's \"temporal\": \"rays\": the traced rays kept where they hit, "
          "restarting where the image history restarts) flickers "
       << peripheral_ratios(g, "flicker_ratio") << " less than off at 20-30 / 30-45 / >45 deg at fixed pixels and "
       << peripheral_ratios(g, "flicker_tracked_ratio")
       << " along the motion (goal 5x: " << met("peripheral_flicker_5x_lower") << " / "
       << met("peripheral_tracked_flicker_5x_lower") << "); its error at 0-2.5 / 2.5-5 deg is "
       << central_gains_db(g["psnr_minus_off_db"])
       << " dB against off (goal: no worse: " << met("central_error_no_worse") << ").";
  return line.str();
}

std::string temporal_csf_line(const Json& a) {
  if (a.is_null() || !a.contains("flicker_csf_ratio_off_over_image")) return "";
  std::ostringstream line;
  line << "Weighted by what the eye resolves at each pixel's eccentricity (the change's luma in octave bands, "
          "each weighted by the foveated contrast sensitivity; `flicker_csf`), the image history flickers "
       << peripheral_ratios(a, "flicker_csf_ratio_off_over_image") << " less than off at 20-30 / 30-45 / >45 deg";
  for (const SequenceControl& control : kSequenceControls)
    line << "; `" << control.key << "` " << peripheral_ratios(a, std::string("flicker_csf_ratio_off_over_") + control.key);
  line << ".";
  return line.str();
}

std::string write_temporal_csv(const std::filesystem::path& file, const Json& temporal) {
  std::ofstream f(file);
  f << "id,setting,kind,method,k,scale,pattern,temporal,spp,ms,time_fraction,temporal_resets";
  for (const char* m : {"flicker", "flicker_tracked", "flicker_csf", "psnr"})
    for (std::size_t r = 0; r < kRings; ++r) f << "," << m << "_" << ring_name(r);
  f << "\n";
  const auto cell = [](const Json& j) -> std::string {
    if (j.is_null()) return "";
    if (j.is_string()) return j.get<std::string>();
    if (j.is_number_float()) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", j.get<double>());
      return buf;
    }
    return j.dump();
  };
  for (const Json& t : temporal["tracks"]) {
    f << cell(t["id"]) << "," << cell(t["setting"]) << "," << cell(t["kind"]) << "," << cell(t.value("method", Json()))
      << "," << cell(t.value("k", Json())) << "," << cell(t.value("scale", Json())) << ","
      << cell(t.value("pattern", Json())) << "," << cell(t["temporal"]) << "," << cell(t["spp"]) << "," << cell(t["ms"])
      << "," << cell(t["time_fraction"]) << "," << cell(t["temporal_resets"]);
    for (const char* m : {"flicker", "flicker_tracked", "flicker_csf", "psnr"})
      for (std::size_t r = 0; r < kRings; ++r) f << "," << cell(t["rings"][r].value(m, Json()));
    f << "\n";
  }
  if (!f) return "cannot write " + file.string();
  return "";
}

std::string write_temporal_plots(const std::filesystem::path& dir, const Json& temporal, const Json& a) {
  if (a.is_null()) return "";
  const std::string setting = a["setting"].get<std::string>();
  const Json* ceiling =
      temporal.contains("reference") ? periphery_of(temporal["reference"], "history_on_reference_bands") : nullptr;
  const Json* sample_history =
      temporal.contains("reference") ? periphery_of(temporal["reference"], "sample_history_bands") : nullptr;
  const Json* ray_cache =
      temporal.contains("reference") ? periphery_of(temporal["reference"], "ray_cache_bands") : nullptr;
  const Json* reproject = track(temporal, setting + "_temporal-image");
  // Frame t's value of a per-frame array (t >= 1: a pair), as a series.
  const auto series = [](const std::string& label, const Json* band, const char* key, bool points,
                         const std::vector<int>* only) {
    toolkit::PlotSeries s{label, {}, {}, points};
    if (band == nullptr || !band->contains(key)) return s;
    const Json& values = (*band)[key];
    for (std::size_t t = 1; t < values.size(); ++t) {
      if (only != nullptr && std::find(only->begin(), only->end(), int(t)) == only->end()) continue;
      s.x.push_back(double(t));
      s.y.push_back(num(values[t]));
    }
    return s;
  };
  std::vector<int> resets;
  if (reproject != nullptr && reproject->contains("temporal_reset_frames"))
    resets = (*reproject)["temporal_reset_frames"].get<std::vector<int>>();
  for (const auto& [key, file, title] :
       {std::tuple{"flicker_by_frame", kTemporalPlotFixed, "at fixed pixels"},
        std::tuple{"flicker_tracked_by_frame", kTemporalPlotTracked, "along the motion"}}) {
    std::vector<toolkit::PlotSeries> lines;
    for (const auto& [variant, label] :
         {std::pair{"off", "off"}, std::pair{"restart", "image history restarting on every pose change"},
          std::pair{"image", "image history (reprojected)"}, std::pair{"rays", "render cache (rays)"}}) {
      const Json* t = track(temporal, setting + "_temporal-" + variant);
      if (t == nullptr && std::string(variant) == "rays") continue;  // a run measured before the price list had it
      lines.push_back(series(label, t ? periphery_of(*t, "bands") : nullptr, key, false, nullptr));
    }
    lines.push_back(series("control: the image history fed the reference", ceiling, key, false, nullptr));
    lines.push_back(series("control: every ray since the history's last restart, kept", sample_history, key, false,
                           nullptr));
    lines.push_back(series("control: the same rays' render cache (equal rays)", ray_cache, key, false, nullptr));
    lines.push_back(series("history restart (image history)",
                           reproject ? periphery_of(*reproject, "bands") : nullptr, key, true,
                           &resets));
    if (!toolkit::has_finite_point(lines)) continue;  // no per-frame values (a resumed older run)
    toolkit::PlotSpec spec;
    spec.title = std::string("Flicker beyond 20 deg ") + title + ", frame by frame";
    spec.legend_below = true;
    spec.x_label = "frame t (the change from frame t-1; " + fmt(num(temporal["run"]["fps"]), 0) + " fps)";
    spec.y_label = "flicker RMS (display values)";
    if (std::string e = toolkit::write_plot_png((dir / file).string(), spec, lines); !e.empty()) return e;
  }
  return "";
}

namespace {

// The periphery's flicker over the frames whose history has settled (the analysis `a`), with its plots.
void write_settled_periphery(std::ostream& md, const Json& a) {
  if (a.is_null() || !a.contains("settled_periphery")) return;
  const Json& settled = a["settled_periphery"];
  const auto ratio = [&](const char* key) { return fmt(field(settled, key), 1) + "x"; };
  md << "\n### Frame by frame in the periphery (> 20 deg)\n\n"
     << "![at fixed pixels](" << kTemporalPlotFixed << ")\n\n![along the motion](" << kTemporalPlotTracked
     << ")\n\nThe goal pools every frame, the history's cold start and the frames after the saccade included. "
     << "Pooled over the " << settled["frames"] << " frames whose history has settled (at least "
     << settled["settle_frames"] << " frames, the blend's time constant, since the motion's last restart: the "
     << "first frame, a saccade's or a blink's), image history flickers " << ratio("flicker_ratio_off_over_image")
     << " less than off at fixed pixels and " << ratio("flicker_tracked_ratio_off_over_image")
     << " along the motion; the image history fed the reference "
     << ratio("flicker_ratio_off_over_history_on_reference") << " and "
     << ratio("flicker_tracked_ratio_off_over_history_on_reference")
     << "; every ray since the history's last restart, kept " << ratio("flicker_ratio_off_over_sample_history")
     << " and " << ratio("flicker_tracked_ratio_off_over_sample_history") << "; the same rays' render cache "
     << ratio("flicker_ratio_off_over_ray_cache") << " and " << ratio("flicker_tracked_ratio_off_over_ray_cache")
     << ".\n";
}

}  // namespace

void write_temporal_markdown(std::ostream& md, const Json& temporal, const Json& a, const Json& sanity) {
  const Json& run = temporal["run"];
  md << "## Temporal columns: the " << run["motion"].get<std::string>() << " motion\n\n"
     << run["frames"] << " frames at " << fmt(num(run["fps"]), 0) << " fps from " << fmt(num(run["start_s"]), 2)
     << " s at " << run["width"] << "x" << run["height"] << " (" << run["eye"].get<std::string>()
     << " eye), each against a full render of the same frame at " << run["reference_spp"]
     << " rays per pixel. flicker: RMS over consecutive frames, pixels and channels of the error's change "
        "e_t - e_t-1 (e = I - R: the change beyond the reference's own) at fixed pixels, and along the motion "
        "(e_t - e_t-1 warped to where each pixel's surface was: what an eye that keeps the world still sees); "
        "PSNR: the error against the reference over all frames. The same rays per point without history (one "
        "jitter), restarting on every pose change, reprojecting its history (new jitter each frame), and keeping "
        "the traced rays in a render cache (the layer's \"rays\", restarting with it). Four "
        "controls: the reference blurred [1 2 1]^2, soft but stable by construction; the layer's image "
        "history fed the reference itself in place of the noisy frames: what its reprojection and clip cost without "
        "noise, the part more averaging cannot remove; and one new jittered ray per pixel per frame with every "
        "ray since the history's last restart (or since the first frame) kept where it hit and traced again from "
        "each frame's eye: what a history of these rays reaches when nothing it keeps is wrong.\n\n";
  if (!a.is_null()) md << temporal_headline(temporal, a) << "\n\n";
  if (const std::string line = temporal_render_cache_line(a); !line.empty()) md << line << "\n\n";
  const auto csf_margins = sanity.find("csf_flicker_margin_db");
  if (!a.is_null() && csf_margins != sanity.end() && csf_margins->size() == kRings) {
    md << temporal_csf_line(a) << " Its reference floor lies at least 10 dB below every track's in every ring: "
       << (sanity.value("csf_floor_10db_below", false) ? "yes" : "**no**") << " (margins";
    for (std::size_t r = 0; r < kRings; ++r)
      md << (r ? "," : "") << " " << ring_name(r) << " " << fmt(num((*csf_margins)[r]), 1);
    md << " dB).\n\n";
  }
  md << "Reference floor (its own flicker and error, from its two halves) below the smallest flicker / the best "
        "PSNR of any track per ring:";
  for (std::size_t r = 0; r < kRings; ++r)
    md << " " << ring_name(r) << ": " << fmt(num(sanity["flicker_margin_db"][r]), 1) << " / "
       << fmt(num(sanity["error_margin_db"][r]), 1) << " dB;";
  md << " at least 10 dB in every ring: " << (sanity["floor_10db_below"].get<bool>() ? "yes" : "**no**") << ".\n\n";
  md << "Per ring: flicker along the motion / at fixed pixels / PSNR dB.\n\n| track | time % of full_spp1 | history "
        "restarts |";
  for (std::size_t r = 0; r < kRings; ++r) md << " " << ring_name(r) << " |";
  md << "\n|---|---|---|";
  for (std::size_t r = 0; r < kRings; ++r) md << "---|";
  md << "\n";
  // Per ring of `owner` (a track or the reference): along the motion / at fixed pixels / PSNR.
  const auto cells = [&](const Json& owner, const char* tracked, const char* fixed, const char* psnr) {
    for (std::size_t r = 0; r < kRings; ++r)
      md << " " << fmt(ring_value(owner, r, tracked), 4) << " / " << fmt(ring_value(owner, r, fixed), 4) << " / "
         << fmt(ring_value(owner, r, psnr), 1) << " |";
    md << "\n";
  };
  for (const Json& t : temporal["tracks"]) {
    md << "| " << t["id"].get<std::string>() << " | " << fmt(100.0 * num(t["time_fraction"]), 0) << " | "
       << t["temporal_resets"] << " |";
    cells(t, "flicker_tracked", "flicker", "psnr");
  }
  if (temporal.contains("reference") && temporal["reference"].is_object()) {
    for (const SequenceControl& control : kSequenceControls) {
      const std::string key = control.key;
      md << "| " << control.label << " | - | - |";
      cells(temporal["reference"], (key + "_flicker_tracked").c_str(), (key + "_flicker").c_str(),
            (key + "_psnr").c_str());
    }
    md << "| reference floor | - | - |";
    cells(temporal["reference"], "flicker_tracked_floor", "flicker_floor", "psnr_floor");
  }
  write_settled_periphery(md, a);
  md << "\nEvery track: `temporal.csv` and `pricelist.json` (`temporal`).\n\n";
}

}  // namespace foveart::eval
