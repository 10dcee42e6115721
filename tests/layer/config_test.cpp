// Config search chain, per-application sections and bad-input warnings.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "config.hpp"

namespace foveart::layer {
namespace {

namespace fs = std::filesystem;

class ConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("foveart_config_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    env_["HOME"] = (root_ / "home").string();
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path write(const fs::path& relative, const std::string& text) {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path;
  }
  GetEnvFn env() const {
    return [this](const char* name) -> std::optional<std::string> {
      auto it = env_.find(name);
      if (it == env_.end()) return std::nullopt;
      return it->second;
    };
  }
  static bool any_warning_contains(const ConfigResult& r, const std::string& needle) {
    for (const auto& w : r.warnings) {
      if (w.find(needle) != std::string::npos) return true;
    }
    return false;
  }

  fs::path root_;
  std::map<std::string, std::string> env_;
};

TEST_F(ConfigTest, NoFileGivesDefaultsWithoutWarnings) {
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  const auto r = load_config("app", env());
  EXPECT_TRUE(r.config.enabled);
  EXPECT_EQ(r.config.k, LayerConfig{}.k);
  EXPECT_TRUE(r.warnings.empty());
}

TEST_F(ConfigTest, FoveartConfigWinsOverXdg) {
  const auto explicit_path = write("explicit.json", R"({"k": 7})");
  write("xdg/foveart/config.json", R"({"k": 9})");
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  env_["FOVEART_CONFIG"] = explicit_path.string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, 7u);
  EXPECT_EQ(r.path, explicit_path.string());
}

TEST_F(ConfigTest, MissingFoveartConfigWarnsAndFallsBackToXdg) {
  write("xdg/foveart/config.json", R"({"k": 9})");
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  env_["FOVEART_CONFIG"] = (root_ / "nope.json").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, 9u);
  EXPECT_TRUE(any_warning_contains(r, "nope.json"));
}

TEST_F(ConfigTest, FoveartConfigThatIsNotAFileWarnsAndFallsBackToXdg) {
  write("xdg/foveart/config.json", R"({"k": 9})");
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  env_["FOVEART_CONFIG"] = root_.string();  // a directory
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, 9u);
  EXPECT_TRUE(any_warning_contains(r, root_.string() + "', which is not a regular file"));
}

TEST_F(ConfigTest, HomeDotConfigWhenXdgUnset) {
  write("home/.config/foveart/config.json", R"({"rays_per_point": 4})");
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.rays_per_point, 4u);
}

TEST_F(ConfigTest, ApplicationSectionOverridesTopLevel) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": 3, "temporal": "image",
      "applications": {"hello_xr": {"k": 12, "temporal": "off"}, "other": {"k": 1}}})").string();
  const auto hello = load_config("hello_xr", env());
  EXPECT_EQ(hello.config.k, 12u);
  EXPECT_EQ(hello.config.temporal, "off");
  const auto unnamed = load_config("someone_else", env());
  EXPECT_EQ(unnamed.config.k, 3u);
  EXPECT_EQ(unnamed.config.temporal, "image");
}

TEST_F(ConfigTest, TemporalIsOneKeyAutoByDefault) {
  EXPECT_EQ(LayerConfig{}.temporal, "auto");
  for (const char* mode : {"off", "image", "rays", "auto"}) {
    env_["FOVEART_CONFIG"] = write("c.json", std::string(R"({"temporal": ")") + mode + R"("})").string();
    const auto r = load_config("app", env());
    EXPECT_EQ(r.config.temporal, mode);
    EXPECT_TRUE(r.warnings.empty()) << mode;
  }
}

// An old config that names a removed key still loads; each removed key is named with what replaced it,
// and the old TAA switch and history are read into "temporal" unless the file names it.
TEST_F(ConfigTest, RemovedKeysWarnWithTheirReplacementAndStillLoad) {
  struct Case {
    const char* text;
    const char* temporal;
  };
  for (const Case& c : {Case{R"({"taa": false, "k": 7})", "off"}, Case{R"({"taa": true, "k": 7})", "image"},
                        Case{R"({"taa": true, "taa_history": "ray_cache", "k": 7})", "rays"},
                        Case{R"({"taa_history": "ray_cache_kept", "k": 7})", "rays"},
                        Case{R"({"taa_history": "reproject", "k": 7})", "image"},
                        Case{R"({"taa": false, "temporal": "rays", "k": 7})", "rays"},
                        Case{R"({"pixel_filter": "bspline2", "taa_mean_while_young": true, "k": 7})", "auto"}}) {
    SCOPED_TRACE(c.text);
    env_["FOVEART_CONFIG"] = write("c.json", c.text).string();
    const auto r = load_config("app", env());
    EXPECT_EQ(r.config.k, 7u) << "the rest of the file still applies";
    EXPECT_EQ(r.config.temporal, c.temporal);
    EXPECT_FALSE(r.warnings.empty());
    for (const RemovedConfigKey& removed : kRemovedConfigKeys) {
      if (std::string(c.text).find("\"" + std::string(removed.key) + "\"") == std::string::npos) continue;
      EXPECT_TRUE(any_warning_contains(r, "'" + std::string(removed.key) + "' was removed; replaced by " +
                                              std::string(removed.replaced_by)))
          << removed.key;
    }
    EXPECT_FALSE(any_warning_contains(r, "unknown key")) << "a removed key is not an unknown one";
  }
}

// "worker_threads" became "threads": an old file keeps its count, with the warning; a file
// that names both keeps "threads".
TEST_F(ConfigTest, RemovedWorkerThreadsIsReadAsThreads) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"worker_threads": 3})").string();
  auto r = load_config("app", env());
  EXPECT_EQ(r.config.threads, 3u);
  EXPECT_TRUE(any_warning_contains(r, "'worker_threads' was removed; replaced by \"threads\"")) << r.warnings.size();
  env_["FOVEART_CONFIG"] = write("c.json", R"({"worker_threads": 3, "threads": 5})").string();
  r = load_config("app", env());
  EXPECT_EQ(r.config.threads, 5u);
}

TEST_F(ConfigTest, BadValueWarnsNamingKeyAndKeepsDefault) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": "many", "density_scale": -1, "interpolation": "cubic",
      "log_level": "loud", "rays_per_point": 1000, "temporal": "yes"})").string();
  const auto r = load_config("app", env());
  const LayerConfig defaults;
  EXPECT_EQ(r.config.k, defaults.k);
  EXPECT_EQ(r.config.density_scale, defaults.density_scale);
  EXPECT_EQ(r.config.interpolation, defaults.interpolation);
  EXPECT_EQ(r.config.log_level, defaults.log_level);
  EXPECT_EQ(r.config.rays_per_point, defaults.rays_per_point);
  EXPECT_EQ(r.config.temporal, defaults.temporal);
  for (const char* key : {"'k'", "'density_scale'", "'interpolation'", "'log_level'", "'rays_per_point'",
                          "'temporal'"}) {
    EXPECT_TRUE(any_warning_contains(r, key)) << key;
  }
}

TEST_F(ConfigTest, UnknownKeyWarns) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"kk": 3})").string();
  const auto r = load_config("app", env());
  EXPECT_TRUE(any_warning_contains(r, "'kk'"));
}

TEST_F(ConfigTest, InvalidJsonWarnsAndUsesDefaults) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": 3,)").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, LayerConfig{}.k);
  EXPECT_TRUE(any_warning_contains(r, "not valid JSON"));
}

// Numbers that do not fit: each key warns with its value and keeps its
// default; the other keys of the file still apply.
TEST_F(ConfigTest, OutOfRangeNumbersWarnNamingKeyAndValueAndKeepOtherKeys) {
  const LayerConfig defaults;
  struct Case {
    const char* key;
    const char* value;
    const char* shown;  // the value in the warning
  };
  for (const Case& c : {Case{"density_scale", "1e400", "1e400"}, Case{"density_scale", "-1e400", "-1e400"},
                        Case{"density_scale", "1e-50", "1e-50"}, Case{"density_scale", "1e39", "1e+39"},
                        Case{"density_scale", "\"dense\"", "\"dense\""},
                        Case{"k", "18446744073709551615", "18446744073709551615"},
                        Case{"k", "4294967301", "4294967301"}, Case{"k", "1e400", "1e400"},
                        Case{"rays_per_point", "9223372036854775808", "9223372036854775808"},
                        Case{"rays_per_point", "\"4\"", "\"4\""},
                        Case{"threads", "18446744073709551616", "1.8446744073709552e+19"},
                        Case{"threads", "-9223372036854775808", "-9223372036854775808"},
                        Case{"threads", "\"8\"", "\"8\""}}) {
    SCOPED_TRACE(std::string(c.key) + ": " + c.value);
    // The other keys are valid non-defaults on both sides of the bad one.
    env_["FOVEART_CONFIG"] = write("c.json", std::string(R"({"temporal": "off", ")") + c.key + "\": " + c.value +
                                                 R"(, "interpolation": "rbf"})")
                                 .string();
    ConfigResult r;
    EXPECT_NO_THROW(r = load_config("app", env()));
    EXPECT_EQ(r.config.density_scale, defaults.density_scale);
    EXPECT_EQ(r.config.k, defaults.k);
    EXPECT_EQ(r.config.rays_per_point, defaults.rays_per_point);
    EXPECT_EQ(r.config.threads, defaults.threads);
    EXPECT_EQ(r.config.temporal, "off");
    EXPECT_EQ(r.config.interpolation, "rbf");
    EXPECT_EQ(r.warnings.size(), 1u);
    if (r.warnings.empty()) continue;
    EXPECT_NE(r.warnings[0].find(std::string("'") + c.key + "'"), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find(std::string("got ") + c.shown + ")"), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("c.json"), std::string::npos) << r.warnings[0];
  }
}

// The same inside an application section: the section's other keys apply.
TEST_F(ConfigTest, OutOfRangeNumberInApplicationSectionKeepsTheSection) {
  env_["FOVEART_CONFIG"] =
      write("c.json", R"({"k": 3, "applications": {"hello_xr": {"density_scale": 1e400, "k": 12}}})").string();
  const auto r = load_config("hello_xr", env());
  EXPECT_EQ(r.config.k, 12u);
  EXPECT_EQ(r.config.density_scale, LayerConfig{}.density_scale);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("'applications.hello_xr.density_scale'"), std::string::npos) << r.warnings[0];
}

// Valid edge values are still read exactly.
TEST_F(ConfigTest, InRangeEdgeValuesAreRead) {
  env_["FOVEART_CONFIG"] =
      write("c.json", R"({"density_scale": 16, "k": 20, "rays_per_point": 64, "threads": 256})").string();
  const auto r = load_config("app", env());
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.config.density_scale, 16.0f);
  EXPECT_EQ(r.config.k, 20u);
  EXPECT_EQ(r.config.rays_per_point, 64u);
  EXPECT_EQ(r.config.threads, 256u);
}

// A syntax error still rejects the whole file, naming it and the position.
TEST_F(ConfigTest, SyntaxErrorNamesFileAndPosition) {
  const auto path = write("c.json", R"({"k": 3, "temporal": tru})");
  env_["FOVEART_CONFIG"] = path.string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.temporal, "auto");
  EXPECT_EQ(r.config.k, LayerConfig{}.k);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find(path.string()), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("byte 25"), std::string::npos) << r.warnings[0];
}

TEST_F(ConfigTest, FoveartDisableWinsOverFile) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"enabled": true})").string();
  env_["FOVEART_DISABLE"] = "1";
  EXPECT_FALSE(load_config("app", env()).config.enabled);
  env_["FOVEART_DISABLE"] = "0";
  EXPECT_TRUE(load_config("app", env()).config.enabled);
}

TEST_F(ConfigTest, LogSettingsAreRead) {
  env_["FOVEART_CONFIG"] =
      write("c.json", R"({"log_level": "debug", "log_file": "/tmp/foveart.log"})").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.log_level, LogLevel::Debug);
  EXPECT_EQ(r.config.log_file, "/tmp/foveart.log");
}

}  // namespace
}  // namespace foveart::layer
