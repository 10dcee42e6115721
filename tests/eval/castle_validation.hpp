// The castleCSF human thresholds the perceptual metric is validated against
// (tests/data/castlecsf_achromatic*.csv, tests/data/README.md), the statistics of a
// prediction against them, per eccentricity band, and the reader of tests/data/ CSV files.
#pragma once

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace foveart::test {

struct CastleRow {
  std::string dataset, stimulus;
  double freq_cpd = 0, luminance_cd_m2 = 0, ge_sigma_deg = 0, area_deg2 = 0, ecc_deg = 0, vis_field_deg = 0;
  double sensitivity = 0;  // 1 / RMS cone contrast, as published
  double lum_sensitivity = 0;  // 1 / luminance (L + M) contrast of the same threshold
  double temporal_freq_hz = 0;  // the flicker's frequency (the temporal file's last column; 0: static)
};

// The data rows of a CSV file in tests/data/ (README.md there), header skipped, split at commas.
inline std::vector<std::vector<std::string>> test_data_rows(const std::string& file) {
  std::ifstream in(std::string(FOVEART_TEST_DATA_DIR) + "/" + file);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<std::string>& f = rows.emplace_back();
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
  }
  return rows;
}

// The static rows (castlecsf_achromatic.csv) or the flickering ones (castlecsf_achromatic_temporal.csv).
inline std::vector<CastleRow> load_castle_rows(const std::string& file = "castlecsf_achromatic.csv") {
  std::vector<CastleRow> rows;
  for (const std::vector<std::string>& f : test_data_rows(file)) {
    if (f.size() < 17) continue;
    CastleRow r{f[0], f[1], std::stod(f[2]), std::stod(f[3]), std::stod(f[4]), std::stod(f[5]), std::stod(f[6]),
                std::stod(f[7]), std::stod(f[10])};
    // castleCSF's sensitivity is 1 / (RMS over L, M, S of delta_i / bkg_i); the metric predicts
    // luminance contrast (delta_L + delta_M) / (bkg_L + bkg_M): rescale by their ratio.
    double cc2 = 0;
    for (int i = 0; i < 3; ++i) cc2 += std::pow(std::stod(f[11 + std::size_t(i)]) / std::stod(f[14 + std::size_t(i)]), 2);
    const double lum_c = (std::stod(f[11]) + std::stod(f[12])) / (std::stod(f[14]) + std::stod(f[15]));
    r.lum_sensitivity = r.sensitivity * std::sqrt(cc2 / 3.0) / lum_c;
    if (f.size() > 17) r.temporal_freq_hz = std::stod(f[17]);
    rows.push_back(r);
  }
  return rows;
}

// castleCSF's per-dataset sensitivity adjustment (the scale each lab's procedure gets in the
// model's fit; castleCSF project report "comparison-3", the fit over spatio-temporal
// frequency, luminance, area and eccentricity): data are divided by it before comparing.
inline double castle_dataset_adjustment(const std::string& dataset) {
  static const std::map<std::string, double> k = {
      {"modelfest", 1.019}, {"hdrvdp_csf", 1.351}, {"rovamo1993", 1.664}, {"virsu1979", 1.601},
      {"wright1983", 0.823}, {"colorfest", 0.889}, {"hdr_csf", 1.000}, {"hdr_csf_disc", 1.189},
      {"hansen2009", 1.291}, {"laird2006", 0.873}, {"snowden1995", 1.172}, {"robson1966", 1.097},
      {"virsu1982", 0.965}};
  return k.at(dataset);
}

// The fitting error (dB, 20 log10 of sensitivity) that stelaCSF (Mantiuk et al. 2022), the
// published predecessor of castleCSF, reaches on each dataset (same report, same fit).
inline double stelacsf_error_db(const std::string& dataset) {
  static const std::map<std::string, double> k = {
      {"modelfest", 2.77}, {"hdrvdp_csf", 2.23}, {"rovamo1993", 2.98}, {"virsu1979", 5.80},
      {"wright1983", 2.42}, {"colorfest", 3.42}, {"hdr_csf", 3.59}, {"hdr_csf_disc", 1.65},
      {"hansen2009", 10.17}, {"laird2006", 5.97}, {"snowden1995", 5.74}, {"robson1966", 2.87},
      {"virsu1982", 4.14}};
  return k.at(dataset);
}

// Eccentricity bands of the validation: 0 deg, (0, 10], (10, 30], > 30 deg.
inline constexpr std::array<const char*, 4> kBandNames = {"0 deg", "0-10 deg", "10-30 deg", ">30 deg"};
inline int ecc_band(double ecc_deg) { return ecc_deg <= 0 ? 0 : ecc_deg <= 10 ? 1 : ecc_deg <= 30 ? 2 : 3; }

struct BandStats {
  int rows = 0;
  double sum_d = 0, sum_d2 = 0, sum_tol2 = 0;  // d: log10 predicted - log10 measured
  double rmse() const { return rows ? std::sqrt(sum_d2 / rows) : std::nan(""); }
  double bias() const { return rows ? sum_d / rows : std::nan(""); }
  // Row-weighted RMS of stelaCSF's published error over the band's rows, in log10 units.
  double tolerance() const { return rows ? std::sqrt(sum_tol2 / rows) : std::nan(""); }
};

inline void add_prediction(std::array<BandStats, 4>& bands, const CastleRow& row, double predicted_sensitivity) {
  BandStats& b = bands[std::size_t(ecc_band(row.ecc_deg))];
  const double measured = row.lum_sensitivity / castle_dataset_adjustment(row.dataset);
  const double d = std::log10(predicted_sensitivity) - std::log10(measured);
  const double tol = stelacsf_error_db(row.dataset) / 20.0;
  ++b.rows;
  b.sum_d += d;
  b.sum_d2 += d * d;
  b.sum_tol2 += tol * tol;
}

// What a band's row in the agreement table is: a check that must hold, a known miss printed with
// its numbers (the band misses its tolerance today; the row says by how much), or too few rows to
// assert anything (reported only).
enum class BandCheck { kAsserted, kPrintedMiss, kReportOnly };

inline const char* check_name(BandCheck c) {
  return c == BandCheck::kAsserted ? "asserted" : c == BandCheck::kPrintedMiss ? "MISS, printed" : "reported only";
}

// The agreement table: band, rows, RMSE, bias, tolerance (RMS of the rows' published errors,
// combined in quadrature with margin_log10), the control's RMSE, and what the row is.
inline std::string band_table(const std::string& title, const std::array<BandStats, 4>& bands,
                              const std::array<BandStats, 4>& control, const std::array<BandCheck, 4>& checks,
                              double margin_log10 = 0.0) {
  std::ostringstream os;
  os << "\n" << title << "\n| band | rows | RMSE log10 S | bias log10 S | tolerance | control RMSE | check |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < bands.size(); ++i) {
    char line[200];
    const double tol = std::hypot(bands[i].tolerance(), margin_log10);
    std::snprintf(line, sizeof line, "| %s | %d | %.3f | %+.3f | %.3f | %.3f | %s |\n", kBandNames[i], bands[i].rows,
                  bands[i].rmse(), bands[i].bias(), tol, control[i].rmse(), check_name(checks[i]));
    os << line;
  }
  return os.str();
}

}  // namespace foveart::test
