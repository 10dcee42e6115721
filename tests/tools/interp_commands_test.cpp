// The contracts of `fovea interpolate` and `fovea reconstruct`: values in
// query order, the renderer's RBF de-ringing clamp by default, clear errors
// with a non-zero exit, finite output for every finite valid input, and the
// JSON keys of reconstruct.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <stb_image_write.h>
#include <unistd.h>

#include "interp_commands.hpp"

namespace foveart::fovea {
namespace {

namespace fs = std::filesystem;

class InterpCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("foveart_interp_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string file(const std::string& name, const std::string& text) {
    const auto p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }

  // Runs interpolate; returns exit code, fills values / error text.
  int run(const std::string& method, int k, const std::string& samples, const std::string& queries,
          std::vector<double>* values = nullptr, std::string* error = nullptr, bool no_constant = false,
          const std::string& rbf_clamp = InterpolateArgs{}.rbf_clamp) {
    InterpolateArgs a;
    a.interpolation = method;
    a.k = k;
    a.samples_file = file("s.csv", samples);
    a.queries_file = file("q.csv", queries);
    a.no_constant = no_constant;
    a.rbf_clamp = rbf_clamp;
    std::ostringstream out, err;
    const int rc = run_interpolate(a, out, err);
    if (values) {
      std::istringstream in(out.str());
      for (double v; in >> v;) values->push_back(v);
    }
    if (error) *error = err.str();
    return rc;
  }

  fs::path dir_;
};

const char* kSquare = "x,y,value\n0,0,1\n1,0,2\n0,1,3\n1,1,4\n";

TEST_F(InterpCommands, ValuesInQueryOrderForEveryMethod) {
  for (const char* m : {"nearest", "msm", "rbf", "rbf-gauss"}) {
    std::vector<double> v;
    ASSERT_EQ(run(m, 4, kSquare, "x,y\n0,0\n1,1\n0.5,0.5\n", &v), 0) << m;
    ASSERT_EQ(v.size(), 3u);
    EXPECT_EQ(v[0], 1.0) << m;  // on a sample
    EXPECT_EQ(v[1], 4.0) << m;
    if (std::string(m) == "nearest") {
      EXPECT_EQ(v[2], 1.0);  // four-way tie: lowest row
    } else {
      EXPECT_NEAR(v[2], 2.5, 1e-12) << m;  // symmetric: the mean
    }
  }
}

TEST_F(InterpCommands, ThesisFormDoesNotReproduceConstants) {
  std::vector<double> a, b, c;
  const char* flat = "0,0,1\n1,0,1\n0,1,1\n1,1,1\n2,0.5,1\n";
  ASSERT_EQ(run("rbf", 5, flat, "0.3,0.6\n", &a, nullptr, false, "off"), 0);
  ASSERT_EQ(run("rbf", 5, flat, "0.3,0.6\n", &b, nullptr, /*no_constant=*/true, "off"), 0);
  EXPECT_NEAR(a[0], 1.0, 1e-12);
  EXPECT_GT(std::abs(b[0] - 1.0), 1e-3);
  // The default de-ringing clamp holds the plain form to the data's range too.
  ASSERT_EQ(run("rbf", 5, flat, "0.3,0.6\n", &c, nullptr, /*no_constant=*/true), 0);
  EXPECT_EQ(c[0], 1.0);
}

// An under-sampled field: values 0.4 / 0.6 alternating faster than the
// samples resolve, on a jittered grid; queries between the samples. The RBF
// weights alone ring far outside [0.4, 0.6]; the renderer's default clamp
// (RbfClamp::block; for scattered queries the taps' range) keeps every value
// inside, and --rbf-clamp off shows the ringing.
TEST_F(InterpCommands, RbfClampKeepsAnUnderSampledFieldInItsRange) {
  std::ostringstream samples, queries;
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x < 12; ++x) {
      const double jx = 0.3 * std::sin(1.7 * x + 2.3 * y), jy = 0.3 * std::cos(2.9 * x - 1.3 * y);
      samples << x + jx << "," << y + jy << "," << (((x + y) % 2 == 0) != (x % 3 == 0) ? 0.6 : 0.4) << "\n";
    }
  }
  for (double y = 3.0; y < 9.0; y += 0.37) {
    for (double x = 3.0; x < 9.0; x += 0.41) queries << x << "," << y << "\n";
  }
  for (const char* m : {"rbf", "rbf-gauss"}) {
    for (int k : {10, 20}) {
      SCOPED_TRACE(std::string(m) + " k=" + std::to_string(k));
      std::vector<double> clamped, taps, off;
      std::string err;
      ASSERT_EQ(run(m, k, samples.str(), queries.str(), &clamped, &err), 0) << err;
      ASSERT_EQ(run(m, k, samples.str(), queries.str(), &taps, &err, false, "taps"), 0) << err;
      ASSERT_EQ(run(m, k, samples.str(), queries.str(), &off, &err, false, "off"), 0) << err;
      ASSERT_EQ(clamped.size(), off.size());
      ASSERT_FALSE(clamped.empty());
      EXPECT_EQ(clamped, taps);  // block is the taps clamp for scattered queries
      EXPECT_GE(*std::min_element(clamped.begin(), clamped.end()), 0.4);
      EXPECT_LE(*std::max_element(clamped.begin(), clamped.end()), 0.6);
      const double off_min = *std::min_element(off.begin(), off.end());
      const double off_max = *std::max_element(off.begin(), off.end());
      EXPECT_TRUE(off_min < 0.39 || off_max > 0.61) << "no ringing to clamp: " << off_min << ".." << off_max;
    }
  }
}

TEST_F(InterpCommands, ErrorsAreClearAndNonZero) {
  struct Case {
    std::string method;
    int k;
    std::string samples, queries, expect;
  };
  const std::vector<Case> cases = {
      {"msm", 2, "", "0,0\n", "no data rows"},
      {"msm", 2, "x,y,value\n", "0,0\n", "no data rows"},
      {"msm", 2, kSquare, "", "no data rows"},
      {"msm", 2, "0,0,1\n1,abc,2\n", "0,0\n", ":2: field 2 'abc' is not a number"},
      {"msm", 2, "0,0,1\n1,0\n", "0,0\n", "expected 3 fields"},
      {"msm", 1, "0,0,1\nnan,0,2\n", "0,0\n", "not finite"},
      {"msm", 1, "0,0,1\n", "inf,0\n", "not finite"},
      {"msm", 1, "0,0,1\n1e999,0,2\n", "0,0\n", "out of the double range"},
      {"msm", 5, kSquare, "0,0\n", "larger than the 4 samples"},
      {"msm", 0, kSquare, "0,0\n", "outside 1..20"},
      {"msm", 21, kSquare, "0,0\n", "outside 1..20"},
      {"cubic", 2, kSquare, "0,0\n", "unknown --interpolation"},
  };
  for (const auto& c : cases) {
    std::string err;
    EXPECT_NE(run(c.method, c.k, c.samples, c.queries, nullptr, &err), 0) << c.expect;
    EXPECT_NE(err.find(c.expect), std::string::npos) << "wanted '" << c.expect << "' in: " << err;
    EXPECT_EQ(err.rfind("fovea interpolate: ", 0), 0u) << err;
  }
  std::string clamp_err;
  EXPECT_NE(run("rbf", 2, kSquare, "0,0\n", nullptr, &clamp_err, false, "sometimes"), 0);
  EXPECT_EQ(clamp_err.rfind("fovea interpolate: unknown --rbf-clamp 'sometimes'", 0), 0u) << clamp_err;
  InterpolateArgs a;
  a.samples_file = (dir_ / "missing.csv").string();
  a.queries_file = a.samples_file;
  std::ostringstream out, err;
  EXPECT_NE(run_interpolate(a, out, err), 0);
  EXPECT_NE(err.str().find("samples file '" + a.samples_file + "': no such file"), std::string::npos) << err.str();
  a.samples_file = dir_.string();
  std::ostringstream dir_out, dir_err;
  EXPECT_NE(run_interpolate(a, dir_out, dir_err), 0);
  EXPECT_NE(dir_err.str().find("samples file '" + a.samples_file + "': a directory, not a file"), std::string::npos)
      << dir_err.str();
}

TEST_F(InterpCommands, HardInputsGiveFiniteOutput) {
  std::ostringstream dup, near, line, lattice, big;
  for (int i = 0; i < 25; ++i) {
    dup << "3,4," << i % 3 << "\n";
    near << 1e-7 * i << "," << -1e-7 * i << "," << i << "\n";
    line << i << "," << 2 * i << "," << i * 0.5 << "\n";
    lattice << i % 5 << "," << i / 5 << "," << (i * 7) % 11 << "\n";
    big << 1e6 + 0.37 * i << "," << 1e6 - 0.11 * (i * i % 7) << "," << std::sin(i) << "\n";
  }
  const std::string queries = "3,4\n0,0\n2.5,2.5\n1e6,1e6\n1000000.5,999999.9\n-50,20\n";
  for (const auto& s : {dup.str(), near.str(), line.str(), lattice.str(), big.str()}) {
    for (const char* m : {"nearest", "msm", "rbf", "rbf-gauss"}) {
      for (int k : {1, 2, 5, 20}) {
        for (bool nc : {false, true}) {
          std::vector<double> v;
          std::string err;
          ASSERT_EQ(run(m, k, s, queries, &v, &err, nc), 0) << err;
          ASSERT_EQ(v.size(), 6u);
          for (double x : v) ASSERT_TRUE(std::isfinite(x)) << m << " k=" << k;
        }
      }
    }
  }
}

TEST_F(InterpCommands, ReconstructReportsEveryKey) {
  // A small image: the display takes its size, so the point set is small.
  const int w = 96, h = 80;
  std::vector<unsigned char> px(std::size_t(w * h * 3));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      unsigned char* p = &px[std::size_t((y * w + x) * 3)];
      p[0] = static_cast<unsigned char>(x * 255 / w);
      p[1] = static_cast<unsigned char>(((x / 8 + y / 8) % 2) * 200);
      p[2] = static_cast<unsigned char>(y * 255 / h);
    }
  }
  const auto in = (dir_ / "in.png").string();
  ASSERT_NE(stbi_write_png(in.c_str(), w, h, 3, px.data(), w * 3), 0);
  ReconstructArgs a;
  a.image = in;
  a.preset = "fove";
  a.gaze = "40,30";
  a.interpolation = "rbf";
  a.k = 10;
  a.rays_per_point = 4;
  a.out = (dir_ / "out.png").string();
  a.json = true;
  a.frames = 3;
  a.jitter = true;
  a.cache_dir = (dir_ / "cache").string();
  std::ostringstream out, err;
  ASSERT_EQ(run_reconstruct(a, out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  for (const char* key : {"points", "pixels", "sample_ms", "interpolate_ms", "temporal_ms", "total_ms", "psnr", "ssim",
                          "rings", "flicker", "flicker_no_history"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["pixels"].get<int>(), w * h);
  EXPECT_GT(j["points"].get<int>(), 0);
  EXPECT_GT(j["psnr"].get<double>(), 10.0);
  ASSERT_EQ(j["rings"].size(), 7u);  // metrics::kRingEdgesDeg: 0, 2.5, 5, 10, 20, 30, 45, open
  EXPECT_EQ(j["rings"][0]["from_deg"].get<double>(), 0.0);
  EXPECT_EQ(j["rings"][1]["from_deg"].get<double>(), 2.5);
  EXPECT_EQ(j["rings"][6]["from_deg"].get<double>(), 45.0);
  EXPECT_TRUE(j["rings"][6]["to_deg"].is_null());
  EXPECT_TRUE(j["rings"][0]["csf_rmse"].is_number());
  EXPECT_TRUE(fs::exists(a.out));
  // Second run: the tables come from the cache.
  std::ostringstream out2, err2;
  ASSERT_EQ(run_reconstruct(a, out2, err2), 0) << err2.str();
  EXPECT_TRUE(nlohmann::json::parse(out2.str())["table_from_cache"].get<bool>());
}

TEST_F(InterpCommands, ReconstructErrors) {
  ReconstructArgs a;
  a.image = (dir_ / "missing.png").string();
  a.no_cache = true;
  std::ostringstream out, err;
  EXPECT_NE(run_reconstruct(a, out, err), 0);
  EXPECT_NE(err.str().find("cannot read image " + a.image + ": no such file"), std::string::npos) << err.str();
  a.image = dir_.string();
  std::ostringstream dir_out, dir_err;
  EXPECT_NE(run_reconstruct(a, dir_out, dir_err), 0);
  EXPECT_NE(dir_err.str().find("cannot read image " + a.image + ": a directory, not a file"), std::string::npos)
      << dir_err.str();
  const std::string bad_png = file("bad.png", "not a png");
  for (auto mutate : std::vector<std::function<void(ReconstructArgs&)>>{
           [](ReconstructArgs& r) { r.interpolation = "bicubic"; }, [](ReconstructArgs& r) { r.k = 0; },
           [](ReconstructArgs& r) { r.rays_per_point = 0; }, [](ReconstructArgs& r) { r.density_scale = -1; },
           [](ReconstructArgs& r) { r.preset = "oculus"; }, [](ReconstructArgs& r) { r.rbf_clamp = "sometimes"; },
           [&](ReconstructArgs& r) { r.image = bad_png; }}) {
    ReconstructArgs b;
    b.image = bad_png;
    b.no_cache = true;
    mutate(b);
    std::ostringstream o, e;
    EXPECT_NE(run_reconstruct(b, o, e), 0);
    EXPECT_EQ(e.str().rfind("fovea reconstruct: ", 0), 0u) << e.str();
  }
}

}  // namespace
}  // namespace foveart::fovea
